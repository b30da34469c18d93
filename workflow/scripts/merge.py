"""Rule merge: verify every shard, then stream them into one Zarr dataset."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

cfg = setup(snakemake)  # noqa: F821
from morphlearn import pipeline  # noqa: E402

pipeline.run_merge(cfg, snakemake.wildcards.model, list(snakemake.input), snakemake.output[0])  # noqa: F821
