"""Rule coopt_analysis: the (a)-(e) tables, the landscape table, the summary and the figure's
position map (the figure itself: rule figure_coopt, notebooks/coopt.ipynb).

Settings: the ``coopt`` section (and ``coopt.restart``). Inputs: the theory metrics table
(``coopt.best_metrics``), the landscape JSONs, the runs CSVs (and the restart runs CSVs). Outputs:
runs.csv, summary.csv, landscape.csv, summary.md, position_map.csv (restart_runs.csv,
restart_summary.csv) and their sealed record summary.provenance.json.
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake)  # noqa: F821
from morphlearn.coopt import stage  # noqa: E402

stage.run_analysis(
    s,
    list(snakemake.input.landscapes),  # noqa: F821
    list(snakemake.input.runs),  # noqa: F821
    Path(snakemake.output.md).parent,  # noqa: F821
    list(snakemake.input.restart),  # noqa: F821
)
