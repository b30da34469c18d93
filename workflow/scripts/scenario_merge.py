"""Rule scenario_merge: verify a scenario simulation's shards, stream them into one Zarr store."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

setup(snakemake)  # noqa: F821
from morphlearn import config as cfgmod  # noqa: E402
from morphlearn import pipeline  # noqa: E402

cfg = cfgmod.validate(dict(snakemake.params.cfg))  # noqa: F821
pipeline.run_merge(cfg, "theory", list(snakemake.input), snakemake.output[0])  # noqa: F821
