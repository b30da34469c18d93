"""Rules coopt_runs and coopt_restart_runs: every run of one setup and learner variant.

Settings: the ``coopt`` section (coopt_restart_runs: with ``coopt.restart``'s learners, setups,
steps and protocols). Input: the theory metrics table whose best designs set up (e) and the
landscape (``coopt.best_metrics``). Output: one CSV, one row per run (coopt.experiment.RUN_COLUMNS).
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake)  # noqa: F821
from morphlearn.coopt import stage  # noqa: E402

stage.run_variant(
    s,
    snakemake.wildcards.setup,  # noqa: F821
    snakemake.wildcards.variant,  # noqa: F821
    snakemake.output[0],  # noqa: F821
    restart=bool(snakemake.params.restart),  # noqa: F821
)
