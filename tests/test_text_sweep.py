"""The second theory sweep's quantities and table rows: the text values counted from first-success
times at a horizon, the verdict of a set-up inferred from the paper's numbers, and its note."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from morphlearn import config as cfgmod
from morphlearn import configure
from morphlearn import grid as gridmod
from morphlearn.figures.reproduction import writers
from morphlearn.figures.reproduction.claims import CLAIMS
from morphlearn.figures.reproduction.stages import text_sweep as stage
from morphlearn.figures.reproduction.verdict import DIFFERS, INFERRED, NOT_COMPARABLE, REPRODUCED, inferred
from morphlearn.theory import text_sweep


def _times() -> tuple[np.ndarray, gridmod.DesignGrid]:
    """A 5-point grid at 3 x 3 weights: the canonical design has 2 generalists (one succeeding only
    at t = 700) and one controller solving one environment; one other design solves only its
    generalists (M_CF = 1)."""
    g = gridmod.DesignGrid(5)
    ft = np.full((g.size, 4, 3, 3), np.nan)
    can = g.index_of(*gridmod.canonical_design())
    ft[can, :, 0, 0] = 100.0
    ft[can, :, 1, 1] = [100.0, 100.0, 100.0, 700.0]
    ft[can, 2, 2, 2] = 50.0
    ft[7, :, 0, 1] = 10.0
    return ft, g


def test_text_values_count_generalists_and_solvers_at_the_horizon() -> None:
    ft, g = _times()
    late = text_sweep.text_values(ft, g, 1000.0, 4.0)
    assert (late.canonical_generalists, late.canonical_solvers) == (2, 3)
    assert math.isclose(late.canonical_ml, 2 / 9) and math.isclose(late.canonical_mcf, 2 / 3)
    assert late.best_design == int(g.index_of(*gridmod.canonical_design()))
    assert late.cf1_designs == 1 and math.isclose(late.cf1_best_ml, 1 / 9)  # design 7
    early = text_sweep.text_values(ft, g, 500.0, 4.0)  # (1, 1) not yet a generalist, still a solver
    assert (early.canonical_generalists, early.canonical_solvers) == (1, 3)
    none = text_sweep.text_values(ft, g, 5.0, 4.0)
    assert none.cf1_designs == 0 and math.isnan(none.cf1_best_ml)


def test_a_reproduction_by_an_inferred_set_up_has_its_own_verdict() -> None:
    assert inferred(REPRODUCED) == INFERRED
    assert inferred(DIFFERS) == DIFFERS and inferred(NOT_COMPARABLE) == NOT_COMPARABLE


def _table(verdicts: list[str]) -> pd.DataFrame:
    rows = [
        {"key": f"k{i}", "section": "paper", "model": "theory", "quantity": "q", "paper": "1", "source": "s"}
        | {"ours": "1", "verdict": v, "reason": "", "anchor": "", "config": "c", "note": ""}
        for i, v in enumerate(verdicts)
    ]
    return pd.DataFrame(rows)


def test_the_inferred_verdict_is_defined_and_counted_only_where_it_is_used() -> None:
    with_it = writers.to_markdown(_table([REPRODUCED, INFERRED]), "c")
    assert writers.INFERRED_RULE in with_it and f"1 reproduced, 1 {INFERRED}, 0 differ" in with_it
    without = writers.to_markdown(_table([REPRODUCED]), "c")
    assert writers.INFERRED_RULE not in without and "1 reproduced, 0 differ, 0 not comparable" in without
    assert INFERRED not in writers.to_html(_table([REPRODUCED]), "c")


def test_the_horizon_note_names_the_spans_where_the_verdict_holds() -> None:
    claim = next(c for c in CLAIMS if c.key == "theory_canonical_M_L")
    scan = [(500.0, False), (510.0, True), (520.0, True), (530.0, False), (540.0, True)]
    assert stage._horizons_note(claim, scan).endswith("gives the paper's 0.049 at 510-520, 540")
    assert stage._horizons_note(claim, [(500.0, False)]).endswith("at none")


def test_the_persistence_note_states_the_thresholds_that_give_the_papers_count() -> None:
    claim = next(c for c in CLAIMS if c.key == "theory_persistence_canonical")  # "2 of 6"
    text, value, note = stage._persistence_row(claim, 0, 6, [2.5, 2.6, 9.9, 11.0, 12.0, 13.0], 1.0)
    assert (text, value) == ("0 of 6", 0.0)
    assert "2 of 6 stay near for every threshold from 2.6 to below 9.9" in note


def test_text_sweep_from_refuses_a_missing_bundle_in_one_line(tmp_path) -> None:
    cfg = cfgmod.read("config.yaml")
    cfg["text_sweep_from"] = str(tmp_path / "none")
    with pytest.raises(cfgmod.ConfigError, match=r"^text_sweep_from = .*bundle\.json is missing; allowed: .*$"):
        configure.parse(cfg)
