"""Rule metrics: one row per design, from the merged dataset."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake)  # noqa: F821
from morphlearn import models  # noqa: E402
from morphlearn.workflow import rules  # noqa: E402

model = snakemake.wildcards.model  # noqa: F821
rules.run_metrics(model, models.get(model).thresholds(s), snakemake.input[0], snakemake.output.table)  # noqa: F821
