"""Rule scenario_shard: one shard of a scenario simulation (rules.run_shard, its own config)."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake, snakemake.params.cfg)  # noqa: F821
from morphlearn.workflow import rules  # noqa: E402

rules.run_shard(s, "theory", int(snakemake.wildcards.shard), snakemake.output[0])  # noqa: F821
