"""Numbers the generated texts once stated misleadingly: the reproduction table's shares, its
persistence note's design, and the run summary's weight grid for a physics model at its own."""

from __future__ import annotations

import pandas as pd

from morphlearn.analysis import summary
from morphlearn.figures.reproduction.claim_values import _persistence, best_label
from morphlearn.figures.reproduction.text import frac


def test_a_share_keeps_its_significant_digits() -> None:
    """1 of 14641 once read "0.01 %" beside the paper's "0.0068 %" for the same value."""
    assert frac(1, 14641) == "1 of 14641 (0.00683 %)"
    assert frac(57, 14641) == "57 of 14641 (0.389 %)"
    assert frac(2243, 14641) == "2243 of 14641 (15.3 %)"


def test_the_best_designs_persistence_is_the_papers_design() -> None:
    """Note 7 once named the best-by-M_L design's 2,254 generalists for the paper's design (2,243)."""
    pers = pd.DataFrame(
        {"design": ["best_M_L"] * 2 + ["paper_best"] * 2, "generalists": [2254] * 2 + [2243] * 2, "stays_near": True}
    )
    assert best_label(pers) == "paper_best"
    assert best_label(pers[pers.design == "best_M_L"]) == "best_M_L"
    ours = _persistence(pers, best_label(pers), "rule", None)  # type: ignore[arg-type]
    assert "of its 2243 generalists" in ours.note and "2254" not in ours.note


def test_the_summary_names_a_models_own_weight_grid() -> None:
    """A reduced-model run at 121 x 121 beside the default 41 x 41 theory grid once said "41 weights
    per synapse" for both."""
    s = {"positions_per_axis": 5, "weights": 41}
    line = summary.grid_line(s, {"reduced": 121})
    assert "reduced 121" in line and "41 weights per synapse" not in line
    assert summary.grid_line(s, {"theory": 41}) == "Grid: 5 positions per axis per sensor, 41 weights per synapse."
