"""Rule coopt_landscape: M_L and M_CF of one design's four-weight controller space.

Settings: the ``coopt`` section (``landscape_weights``) and the theory model's parameters.
Input: the theory metrics table whose best designs are landscaped (``coopt.best_metrics``).
Output: one JSON per design (canonical, best_M_L, best_M_CF): its four- and two-weight counts,
M_L and M_CF.
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(snakemake.scriptdir)))  # noqa: F821
from _entry import setup

s = setup(snakemake)  # noqa: F821
from morphlearn.coopt import stage  # noqa: E402

stage.run_landscape(s, snakemake.wildcards.design, snakemake.output[0])  # noqa: F821
