"""The designs refined at 121 x 121 (issue 26): candidates from surveys and the theory."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from morphlearn import grid
from morphlearn.analysis import candidates

ROOT = Path(__file__).resolve().parents[1]


def _table(g: grid.DesignGrid, ml: dict[int, float], mcf: dict[int, float]) -> pd.DataFrame:
    c = g.coords(np.arange(g.size)).reshape(-1, 4)
    t = pd.DataFrame({"design": np.arange(g.size), "l1x": c[:, 0], "l1y": c[:, 1], "l2x": c[:, 2], "l2y": c[:, 3]})
    t["M_L"] = [ml.get(d, 0.0) for d in t.design]
    t["M_CF"] = [mcf.get(d, 0.0) for d in t.design]
    return t


def test_candidates_are_the_canonical_the_tops_and_the_theory_best_one_per_mirror_pair() -> None:
    g3, g5 = grid.DesignGrid(3), grid.DesignGrid(5)
    a, b = 12, int(g3.mirror(12))  # a mirror pair (12, 46), best by M_L in the survey
    survey = _table(g3, {a: 0.5, b: 0.5, 20: 0.1}, {20: 0.9, a: 0.2, b: 0.2})
    theory = _table(g5, {7: 1.0}, {7: 1.0})
    found = candidates.candidates({"s": survey}, theory, 2, g5)
    canon = g5.index_of(*grid.canonical_design())
    on5 = {d: g5.index_of(*map(tuple, np.asarray(g3.coords(d)).reshape(2, 2))) for d in (a, b, 20)}
    rep = lambda d: min(d, int(g5.mirror(d)))  # noqa: E731
    assert next(iter(found)) == canon and found[canon] == ["canonical"]
    assert found[rep(on5[a])] == ["s #1 by M_L", "s #2 by M_L", "s #2 by M_CF"]  # the pair once, both ranks said
    assert "s #1 by M_CF" in found[rep(on5[20])]
    assert found[rep(7)] == ["theory best by M_L", "theory best by M_CF"]
    assert all(d == rep(d) for d in found)
    text = candidates.as_yaml(found, g5)
    assert text.startswith("designs:") and text.count("\n  - [[") == len(found)


def test_tool_prints_the_list_for_the_committed_surveys() -> None:
    proc = subprocess.run(
        [
            sys.executable,
            str(ROOT / "tools/refine_candidates.py"),
            "--survey",
            "pb=results/survey/empirical/metrics.csv",
            "--top",
            "3",
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    )
    assert proc.stdout.startswith("designs:") and "canonical" in proc.stdout and "pb #1 by M_L" in proc.stdout
    bad = subprocess.run(
        [sys.executable, str(ROOT / "tools/refine_candidates.py"), "--survey", "x"], capture_output=True, text=True
    )
    assert bad.returncode == 2 and "NAME=METRICS_CSV" in bad.stderr
