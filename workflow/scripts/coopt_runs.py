"""Rule coopt_runs: every run of one setup and learner variant."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake)  # noqa: F821
from morphlearn.coopt import stage  # noqa: E402

stage.run_variant(s, snakemake.wildcards.setup, snakemake.wildcards.variant, snakemake.output[0])  # noqa: F821
