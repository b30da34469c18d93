"""Write config/survey_body2.yaml: the survey repeated on some of its designs with a second body.

The designs: the 13 best by the survey's empirical M_L (ties: M_CF, then index) and 12 more
drawn at random (seed 0) from the rest, each with its mirror image (so 50 or so designs, every
mirror pair complete). Usage: python tools/body2_config.py results/survey/empirical/metrics.csv
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pandas as pd

from morphlearn import metrics
from morphlearn.grid import DesignGrid

HEAD = """# Robustness to the body (issue 12): the survey (config/survey.yaml) repeated on {n} of its designs
# with a second body from the committed Pareto set (config/empirical_morphology_body2.yaml).
# Designs (written by tools/body2_config.py from the survey's empirical metrics): the 13 best by
# M_L and 12 drawn at random (seed 0) from the rest, each with its mirror image.
#   run it:   snakemake results/survey-body2/empirical/metrics.csv --cores 2 \\
#                 --configfile config/survey.yaml config/survey_body2.yaml
#   compare:  morphlearn compare results/survey/empirical/metrics.csv results/survey-body2/empirical/metrics.csv
"""


def main() -> None:
    table = pd.read_csv(sys.argv[1], comment="#")
    g = DesignGrid(5)
    ranked = metrics.rank_designs(table, "M_L").design.to_numpy()
    reps = list(dict.fromkeys(int(min(d, g.mirror(d))) for d in ranked))  # one per pair, best first
    top, rest = reps[:13], reps[13:]
    extra = np.random.default_rng(0).choice(rest, 12, replace=False).tolist()
    chosen = sorted(top + [int(x) for x in extra])
    designs = sorted({int(x) for d in chosen for x in (d, g.mirror(d))})
    lines = [
        HEAD.format(n=len(designs)),
        "results_dir: results/survey-body2",
        "bundle_dir: null",
        "empirical:",
        "  morphology: config/empirical_morphology_body2.yaml",
        "  designs:",
    ]
    for d in chosen:
        c = g.coords(d)
        lines.append(f"    - [[{c[0]:g}, {c[1]:g}], [{c[2]:g}, {c[3]:g}]]")
    lines += ["  include_mirrors: true", "  shards: 2", ""]
    Path("config/survey_body2.yaml").write_text("\n".join(lines))
    print(f"config/survey_body2.yaml: {len(chosen)} designs listed, {len(designs)} with mirror images")


if __name__ == "__main__":
    main()
