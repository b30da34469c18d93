"""Rule theory_shard / empirical_shard: evaluate one shard of designs."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

cfg = setup(snakemake)  # noqa: F821
from morphlearn import pipeline  # noqa: E402

model = snakemake.rule.split("_")[0]  # noqa: F821
pipeline.run_shard(cfg, model, int(snakemake.wildcards.shard), snakemake.output[0])  # noqa: F821
