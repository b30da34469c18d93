"""Rule metrics: one row per design, from the merged dataset."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

cfg = setup(snakemake)  # noqa: F821
from morphlearn import pipeline  # noqa: E402

pipeline.run_metrics(cfg, snakemake.wildcards.model, snakemake.input[0], snakemake.output.table)  # noqa: F821
