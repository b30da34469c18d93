"""Rule learners_shard: every learner run of one shard of designs."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake)  # noqa: F821
from morphlearn.learners import experiment  # noqa: E402

experiment.run_shard(s, int(snakemake.wildcards.shard), snakemake.output[0])  # noqa: F821
