"""Rule scenario_merge: verify a scenario simulation's shards, stream them into one Zarr store."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake, snakemake.params.cfg)  # noqa: F821
from morphlearn.workflow import rules  # noqa: E402

rules.run_merge(s, "theory", list(snakemake.input), snakemake.output[0])  # noqa: F821
