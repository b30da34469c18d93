"""Rule learners_analysis: merge the learner shards, correlate with the theory metrics."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake)  # noqa: F821
from morphlearn.learners import experiment  # noqa: E402

inp, out = snakemake.input, snakemake.output  # noqa: F821
experiment.run_analysis(s, list(inp.shards), inp.metrics, out.runs, out.correlations, out.md, out.provenance)
