"""Rule <model>_shard: evaluate one shard of designs of a registered model."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake)  # noqa: F821
from morphlearn.workflow import rules  # noqa: E402

rules.run_shard(s, snakemake.params.model, int(snakemake.wildcards.shard), snakemake.output[0])  # noqa: F821
