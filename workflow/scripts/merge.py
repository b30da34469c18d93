"""Rule merge: verify every shard, then stream them into one Zarr dataset."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake)  # noqa: F821
from morphlearn.workflow import rules  # noqa: E402

rules.run_merge(s, snakemake.wildcards.model, list(snakemake.input), snakemake.output[0])  # noqa: F821
