"""Print the designs to refine at 121 x 121 (issue 26) as a ``designs:`` list for a config.

    python tools/refine_candidates.py --survey mujoco9=results/survey9-mujoco/mujoco/metrics.csv \\
        --survey pybullet5=results/survey/empirical/metrics.csv \\
        --survey mujoco5=results/survey-mujoco/mujoco/metrics.csv \\
        --theory results/paper/theory/metrics.csv --top 10

Settings: ``--top`` designs per metric per survey, ``--positions`` of the refinement grid (9, the
paper's). Inputs: metrics tables (each checked against its provenance record before it is read).
Output: YAML on stdout (logic: :mod:`morphlearn.analysis.candidates`).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))
from morphlearn import grid, provenance
from morphlearn.analysis import candidates


def _table(path: str) -> pd.DataFrame:
    provenance.check_derived(path)  # custody: the table its record names
    return pd.read_csv(path)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--survey", action="append", default=[], metavar="NAME=METRICS_CSV", help="a survey's metrics")
    p.add_argument("--theory", help="the theory's metrics table (its best designs are candidates)")
    p.add_argument("--top", type=int, default=10)
    p.add_argument("--positions", type=int, default=9)
    a = p.parse_args(argv)
    bad = [s for s in a.survey if "=" not in s]
    if bad or a.top < 1:
        p.error(f"--survey takes NAME=METRICS_CSV (got {bad[0]!r})" if bad else f"--top = {a.top}; allowed: >= 1")
    surveys = {name: _table(path) for name, path in (s.split("=", 1) for s in a.survey)}
    g = grid.DesignGrid(a.positions)
    found = candidates.candidates(surveys, _table(a.theory) if a.theory else None, a.top, g)
    sys.stdout.write(candidates.as_yaml(found, g))
    print(f"# {len(found)} designs ({len(found) * 2 - sum(int(g.mirror(d)) == d for d in found)} with mirrors)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
