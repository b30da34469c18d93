"""Rule engines_numbers: the engines figure's table and statistics.

Settings: the ``engines`` config section (the three tables' paths). Inputs: the pybullet survey's,
the MuJoCo survey's and the theory's metrics tables (each checked against its record). Outputs:
``engines.csv`` (one row per design: each model's M_L, M_CF and ranks) and ``engines.json``
(Spearman's rho with bootstrap intervals, each model's best design; docs/results.md quotes it).
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake)  # noqa: F821
from morphlearn.analysis import engines as engine_compare  # noqa: E402

engine_compare.write_numbers(
    s.engines,
    snakemake.output.table,  # noqa: F821
    snakemake.output.numbers,  # noqa: F821
)
