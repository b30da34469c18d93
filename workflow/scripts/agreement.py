"""Rule agreement: each engine and robot against ODE with the authors' robot, design by design.

Settings: the ``agreement`` config section (the reference survey and the candidates: committed
bundles and their models). Inputs: their metrics tables (each checked against its bundle's
record) and outcome arrays. Outputs: ``agreement.csv`` (one row per candidate) and
``agreement.json`` (every number the figure and docs/authors_robot.md quote), sealed together in
``agreement.provenance.json``.
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake)  # noqa: F821
from morphlearn.analysis import agreement  # noqa: E402

agreement.write(
    s.agreement,
    snakemake.output.table,  # noqa: F821
    snakemake.output.numbers,  # noqa: F821
)
