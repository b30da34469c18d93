"""The reproduction table's screen rows (config ``screen_from``, issue 56): the paper's best-design
claims over all 6561 designs, answered by the reduced model's map and ODE at its best designs.
The rule is checked on small tables, then on the committed bundles as they are and as an attacker
(or an unlucky refinement) would leave them."""

from __future__ import annotations

import dataclasses

import pandas as pd
import pytest
import yaml
from conftest import ROOT

from morphlearn import config as cfgmod
from morphlearn import configure
from morphlearn.figures import options
from morphlearn.figures.reproduction import build
from morphlearn.figures.reproduction.stages import screen as sc
from morphlearn.figures.reproduction.verdict import NOT_COMPARABLE, REPRODUCED

SCREEN = {"bundle": "results/reduced-paper", "model": "reduced", "refinement": "results/ode-screened-paper"}


def _table(values: dict[int, float]) -> pd.DataFrame:
    """A metrics table of designs -> M_L (M_CF = M_L / 10, so both rank alike)."""
    d = sorted(values)
    return pd.DataFrame({"design": d, "M_L": [values[k] for k in d], "M_CF": [values[k] / 10 for k in d]})


def test_rule_on_small_tables() -> None:
    screen = _table({0: 0.50, 1: 0.48, 2: 0.30, 3: 0.29})
    # the engine at designs 0 and 1: 0.52 and 0.47 -> margin 0.02; design 2's 0.30 + 0.02 < 0.52
    refined = _table({0: 0.52, 1: 0.47})
    r = sc.ruled_out(screen, refined, "M_L")
    assert int(r.best.design) == 0 and r.margin == pytest.approx(0.02) and r.open.empty
    assert int(r.best_outside.design) == 2
    # a larger error at the refined designs leaves design 2 open: 0.30 + 0.25 >= 0.52
    r = sc.ruled_out(screen, _table({0: 0.52, 1: 0.23}), "M_L")
    assert list(r.open.design) == [2, 3][: len(r.open)] and 2 in set(r.open.design)
    # a tie stays open (it could share the best)
    r = sc.ruled_out(_table({0: 0.5, 1: 0.4, 2: 0.5}), _table({0: 0.5, 1: 0.4}), "M_L")
    assert list(r.open.design) == [2]
    # a refinement the screen does not hold is an error, not a silent inner join
    with pytest.raises(ValueError, match="lacks 1 of the refinement's designs"):
        sc.ruled_out(screen, _table({0: 0.5, 9: 0.1}), "M_L")


def _paper() -> dict:
    """config.yaml + config/paper.yaml (the bundles it reads are committed): parsed only, nothing run."""
    return cfgmod.deep_merge(*(yaml.safe_load((ROOT / p).read_text()) for p in ("config.yaml", "config/paper.yaml")))


@pytest.fixture(scope="module")
def bundles() -> tuple:
    s = configure.parse(cfgmod.deep_merge(_paper(), {"screen_from": SCREEN}))
    assert s.screen is not None and s.screen[0].bundle == SCREEN["bundle"]  # config/paper.yaml reads this screen
    return s, build._screen(options.screen_option(s))


def test_committed_screen_answers_the_best_design_claims(bundles: tuple) -> None:
    """ODE at the reduced model's 22 best designs: its best by both metrics is the paper's design (57
    generalists), and every other design is ruled out by the screen (issue 56, docs/results.md)."""
    _, (screen, refined) = bundles
    rows = {r["key"]: r for r in sc.screen_rows(screen, refined, "test")}
    assert set(rows) == {"screen_best_design", "screen_best_on_both"}
    for r in rows.values():
        assert r["verdict"] == REPRODUCED and r["section"] == "paper", r
        assert "stays below" in r["note"] and "reaches" not in r["note"]
    assert rows["screen_best_design"]["ours"].startswith("l1 = (-0.5, 0.125), l2 = (0.5, -0.375): 57 of 14641")


def test_a_refinement_that_misses_contenders_is_not_comparable(bundles: tuple) -> None:
    """Without the screen's 56-generalist designs in ODE (or with the paper's design left out), the
    screen cannot rule them out: the claims are not comparable, never reproduced by default."""
    _, (screen, refined) = bundles
    t = refined.table
    for drop in ({396, 6484}, {478, 6402}):
        cut = dataclasses.replace(refined, table=t[~t.design.isin(drop)].reset_index(drop=True))
        rows = sc.screen_rows(screen, cut, "test")
        assert all(r["verdict"] == NOT_COMPARABLE for r in rows), rows
        assert "cannot rule out" in rows[0]["reason"] and "designs open" in rows[0]["note"]


def test_a_screen_that_understates_a_design_is_caught(bundles: tuple) -> None:
    """A screen table whose value of one outside design is raised to the engine's best: open."""
    _, (screen, refined) = bundles
    t = screen.table.copy()
    outside = t[~t.design.isin(refined.table.design)].index[0]
    t.loc[outside, ["M_L", "M_CF"]] = [float(refined.table.M_L.max()), float(refined.table.M_CF.max())]
    rows = sc.screen_rows(dataclasses.replace(screen, table=t), refined, "test")
    assert all(r["verdict"] == NOT_COMPARABLE for r in rows)


def test_bad_screen_config_is_refused_in_one_line() -> None:
    nine = _paper()
    nine.pop("screen_from")
    cases = {
        r"screen_from\.bundle is set without screen_from\.refinement": {"bundle": SCREEN["bundle"]},
        r"screen_from\.refinement is set without screen_from\.bundle": {"refinement": SCREEN["refinement"]},
        r"screen_from\.model = 'theory' is not a physics model": {**SCREEN, "model": "theory"},
        # the 5-point grid's 625 designs rule out none of the 9-point grid's others
        r"screen_from\.bundle = 'results/reduced-survey' holds 625 designs; allowed: every design": {
            **SCREEN,
            "bundle": "results/reduced-survey",
        },
        r"screen_from\.refinement = 'nowhere': nowhere/bundle\.json is missing": {**SCREEN, "refinement": "nowhere"},
    }
    for message, sec in cases.items():
        with pytest.raises(cfgmod.ConfigError, match=message) as err:
            configure.parse(cfgmod.deep_merge(nine, {"screen_from": sec}))
        assert "\n" not in str(err.value)
    unset = configure.parse(nine)
    assert options.screen_option(unset) is None and options.screen_files(unset) == []
