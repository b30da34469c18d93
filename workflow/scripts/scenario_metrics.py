"""Rule scenario_metrics: a scenario's metrics from its simulation at its own thresholds."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

setup(snakemake)  # noqa: F821
from morphlearn import metrics, scenarios  # noqa: E402

smk = snakemake  # noqa: F821
th = metrics.Thresholds(**smk.params.thresholds)
scenarios.run_metrics(th, smk.input[0], smk.output.table, dict(smk.params.record), smk.output.record)
