"""The co-optimisation stage (issue 27): setups, determinism, censoring, config refusals."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from morphlearn import config, configure, provenance, settings
from morphlearn.coopt import experiment as ex
from morphlearn.coopt.landscape import landscape
from morphlearn.coopt.setups import CANONICAL, decode, paper_setups
from morphlearn.theory import TheoryParams
from morphlearn.workflow import rules

ROOT = Path(__file__).resolve().parents[1]
BEST = (-0.5, -0.375, 0.5, 0.375)
TINY = settings.CooptSettings(
    enabled=True,
    setups=("a", "d"),
    learners=("random", "one_plus_one", "cmaes"),
    sigmas=(0.5, 0.15),
    protocols=("joint", "sequential"),
    budgets=(6, 12),
    cycles=3,
    seeds=2,
    seed=0,
    landscape_weights=3,
    best_metrics="results/paper/theory/metrics.csv",
    bootstrap=100,
)


def test_decode_maps_the_box_onto_the_body_square_and_pads_two_weights() -> None:
    a, b, c, d, _ = paper_setups(BEST)
    assert (a.dim, b.dim, c.dim, d.dim) == (2, 4, 6, 8)
    coords, w = decode(a, np.array([[0.3, -0.2]]))
    assert coords.tolist() == [list(CANONICAL)] and w.tolist() == [[0.3, -0.2, 0.0, 0.0]]
    coords, w = decode(d, np.array([[1, -1, 0.5, 0, 0.1, 0.2, 0.3, 0.4]]))
    assert coords.tolist() == [[0.5, -0.5, 0.25, 0.0]] and w.tolist() == [[0.1, 0.2, 0.3, 0.4]]


def test_runs_are_deterministic_given_seeds_and_independent_of_batch_neighbours() -> None:
    p = TheoryParams()
    setup = paper_setups(BEST)[3]
    one = ex.run_setup(TINY, setup, 3, p)
    two = ex.run_setup(TINY, setup, 3, p)
    pd.testing.assert_frame_equal(one, two)
    solo = ex.run_setup(replace(TINY, seeds=1), setup, 3, p)
    pd.testing.assert_frame_equal(solo.reset_index(drop=True), one[one.seed == 0].reset_index(drop=True))
    joint = one[one.protocol == "joint"]
    assert set(joint.budget) == {12}  # joint runs once at the largest budget
    assert all(len(x.split()) == 8 for x in one.x)  # the incumbent: 4 positions + 4 weights


def test_summary_counts_censored_runs_at_the_budget() -> None:
    """Three runs reach a generalist (after 5, 20 and 70 evaluations), one never does: at budget 60
    P = 2/4 and the restricted mean is (5 + 20 + 60 + 60) / 4; the 70 counts only at 240."""
    runs = pd.DataFrame(
        {
            "setup": "a",
            "learner": "random",
            "sigma0": math.nan,
            "protocol": "joint",
            "budget": 240,
            "seed": range(4),
            "reached": [True, True, True, False],
            "evals_to_generalist": [5.0, 20.0, 70.0, math.nan],
            "final_generalist": [True, True, True, False],
            "forget_events": 0,
            "forget_opportunities": 0,
            "x": "",
        }
    )
    s = replace(TINY, budgets=(60, 240), bootstrap=200)
    out = ex.summarise(runs, s).set_index("budget")
    assert out.loc[60, "p_generalist"] == 0.5
    assert out.loc[60, "evals_restricted_mean"] == (5 + 20 + 60 + 60) / 4
    assert out.loc[240, "p_generalist"] == 0.75
    assert out.loc[240, "evals_restricted_mean"] == (5 + 20 + 70 + 240) / 4
    assert out.loc[240, "evals_km_median"] == 20.0


def test_wilson_interval() -> None:
    # 0 of 30: the upper limit is z^2 / (n + z^2)
    lo, hi = ex.wilson(0, 30)
    assert lo == 0.0 and hi == pytest.approx(1.959964**2 / (30 + 1.959964**2))
    lo, hi = ex.wilson(15, 30)
    assert lo == pytest.approx(1 - hi)


def test_landscape_contains_the_two_weight_slice() -> None:
    """With m = 3 the two-weight slice (u = 0) is a 3 x 3 grid; its counts cannot exceed the
    four-weight space's."""
    land = landscape(np.array(BEST), 3, TheoryParams())
    assert land.controllers == 81 and land.generalists_2w <= land.generalists
    assert land.at_least_one_2w <= land.at_least_one
    assert 0.0 <= land.m_l <= 1.0 and 0.0 <= land.m_cf_2w <= 1.0
    with pytest.raises(ValueError, match="odd"):
        landscape(np.array(BEST), 4, TheoryParams())


@pytest.mark.parametrize(
    ("section", "match"),
    [
        ({"budgets": [60, 100]}, r"coopt.budgets = \[60, 100\]: 100 is not a multiple of coopt.cycles = 3"),
        ({"sigmas": [0]}, r"coopt.sigmas.0 = 0 is invalid"),
        ({"landscape_weights": 20}, r"coopt.landscape_weights = 20 is even"),
        ({"setups": ["f"]}, r"coopt.setups.0 = 'f' is invalid"),
        ({"seeds": 0}, r"coopt.seeds = 0"),
    ],
)
def test_bad_coopt_config_is_refused(section: dict, match: str) -> None:
    cfg = config.read("config.yaml")
    with pytest.raises(config.ConfigError, match=match):
        configure.parse(cfg | {"coopt": section})


def test_stage_end_to_end_on_a_tiny_config(tmp_path) -> None:
    """The stage's three steps (landscape, runs, analysis) in process, on a tiny config: the
    tables, summary and figure are written; the summary has the landscape and the (a)-(e) table."""
    import json

    from morphlearn.coopt import stage

    cfg = config.read("config.yaml") | {
        "results_dir": str(tmp_path),
        "coopt": {
            "enabled": True,
            "setups": ["a", "c"],
            "learners": ["random", "cmaes"],
            "sigmas": [0.5],
            "budgets": [3, 6],
            "seeds": 2,
            "landscape_weights": 3,
            "bootstrap": 100,
        },
    }
    s = configure.parse(cfg)
    assert stage.variant_names(s.coopt) == ["random", "cmaes-0.5"]
    land = [tmp_path / f"{d}.json" for d in stage.LANDSCAPE_DESIGNS]
    for d, p in zip(stage.LANDSCAPE_DESIGNS, land, strict=True):
        stage.run_landscape(s, d, p)
    assert json.loads(land[0].read_text())["coords"] == [0.5, 0.5, 0.5, -0.5]
    csvs = []
    for st in s.coopt.setups:
        for v in stage.variant_names(s.coopt):
            csvs.append(tmp_path / f"{st}_{v}.csv")
            stage.run_variant(s, st, v, csvs[-1])
    stage.run_analysis(s, [str(p) for p in land], [str(p) for p in csvs], tmp_path / "out")
    md = (tmp_path / "out" / "summary.md").read_text()
    assert "| canonical | (0.5, 0.5, 0.5, -0.5) |" in md and "| learner | protocol | budget | (a) | (c) |" in md
    runs = pd.read_csv(tmp_path / "out" / "runs.csv")
    assert len(runs) == 2 * 2 * 2 * 3  # setups x variants x seeds x (joint at 6, sequential at 3 and 6)
    # the figure is the registered notebook's (test below); the analysis writes its background
    pmap = pd.read_csv(tmp_path / "out" / "position_map.csv")
    assert len(pmap) == 2 * 9 * 9 and list(pmap.columns) == ["sensor", "x", "y", "M_L"]
    from morphlearn.coopt import analysis
    from morphlearn.figures import output

    fig = analysis.figure(pd.read_csv(tmp_path / "out" / "summary.csv"), runs, pmap, 0.5)
    assert output.readability_problems(fig) == []
    # custody (issue 24): the analysis is sealed; an edit of any of its files is refused at start
    rules.check_custody([], [tmp_path / "out" / "summary.csv"])
    with (tmp_path / "out" / "summary.md").open("a") as f:
        f.write("edited\n")
    with pytest.raises(provenance.CustodyError, match=r"summary\.md: SHA-256 .* differs"):
        rules.check_custody([], [tmp_path / "out" / "summary.csv"])


def test_position_map_is_the_best_m_l_with_the_sensor_there() -> None:
    """Recomputed by a plain loop over the paper bundle's designs, not by groupby."""
    from morphlearn.coopt import analysis

    m = pd.read_csv(ROOT / "results/paper/theory/metrics.csv")
    pmap = analysis.position_map(ROOT / "results/paper/theory/metrics.csv")
    for sensor, x, y in ((1, 0.5, 0.5), (2, -0.5, 0.0), (1, 0.0, -0.25)):
        cx, cy = ("l1x", "l1y") if sensor == 1 else ("l2x", "l2y")
        want = max(r.M_L for r in m.itertuples() if getattr(r, cx) == x and getattr(r, cy) == y)
        got = pmap[(pmap.sensor == sensor) & (pmap.x == x) & (pmap.y == y)].M_L
        assert got.tolist() == [want]
    m1, m2 = analysis.map_arrays(pmap)
    assert m2.shape == (9, 9)
    assert m1.shape == (9, 9) and m1[8, 8] == pmap[(pmap.sensor == 1) & (pmap.x == 0.5) & (pmap.y == 0.5)].M_L.iloc[0]


def test_restart_runs_give_the_committed_rows_and_summary(tmp_path) -> None:
    """The restart runs (coopt.restart, rule coopt_restart_runs) of config/coopt.yaml: a run is a
    function of its identity, so the first two seeds of setup (a)'s restarting (1+1)-ES, run here
    alone, are the committed restart_runs.csv rows; the committed restart_summary.csv is the
    analysis of the committed rows (the stage's seed, budgets and bootstrap)."""
    import io

    from morphlearn.coopt import analysis, experiment, stage
    from morphlearn.metrics import CSV_FLOAT_FORMAT

    full = configure.load(ROOT / "config.yaml", [ROOT / "config/coopt.yaml"])
    r = stage.restart_settings(full)
    assert r is not None and r.learners == ("one_plus_one_restart", "cmaes_restart") and r.setups == ("a", "e")
    assert stage.variant_names(r) == ["one_plus_one_restart-0.5", "cmaes_restart-0.5"]
    assert stage.restart_settings(configure.load(ROOT / "config.yaml")) is None  # off by default
    cfg = config.read(ROOT / "config.yaml", [ROOT / "config/coopt.yaml"])
    cfg["coopt"]["seeds"] = 2
    out = tmp_path / "a.csv"
    stage.run_variant(configure.parse(cfg), "a", "one_plus_one_restart-0.5", out, restart=True)
    committed = pd.read_csv(ROOT / "results/coopt/restart_runs.csv", keep_default_na=False, dtype=str)
    mine = pd.read_csv(out, keep_default_na=False, dtype=str)
    want = committed[(committed.setup == "a") & (committed.learner == "one_plus_one_restart")]
    want = want[want.seed.isin(["0", "1"])].reset_index(drop=True)
    assert len(mine) == 2 and mine.equals(want[list(mine.columns)])
    # the summary: the analysis's, of the committed rows
    runs = pd.read_csv(ROOT / "results/coopt/restart_runs.csv")
    buf = io.StringIO()
    analysis.sort_summary(experiment.summarise(runs, r)).to_csv(buf, index=False, float_format=CSV_FLOAT_FORMAT)
    assert buf.getvalue() == (ROOT / "results/coopt/restart_summary.csv").read_text()


def test_committed_bundle_figure_renders_from_the_bundle_alone_to_the_same_bytes(tmp_path) -> None:
    """notebooks/coopt.ipynb on a copy of results/coopt (the project root elsewhere): every file,
    the figure's PNG, PDF and caption included, matches the committed bundle.json."""
    import shutil

    from morphlearn.coopt import bundle

    copy = tmp_path / "results" / "coopt"
    shutil.copytree(ROOT / "results" / "coopt", copy, ignore=shutil.ignore_patterns("logs"))
    for f in bundle.FIGURE:
        (copy / f).unlink()
    seconds, problems = bundle.render(copy, ROOT)
    assert problems == [], problems
    print(f"coopt figure re-rendered in {seconds:.1f} s")


def test_one_plus_one_restart_draws_a_new_parent_when_its_step_collapses() -> None:
    from morphlearn.learners import algorithms

    plain = algorithms.make("one_plus_one", np.random.default_rng(1), 0.5, 3)
    lr = algorithms.make("one_plus_one_restart", np.random.default_rng(1), 0.5, 3)
    for a in (plain, lr):
        a.tell(a.ask(), np.array([1.0]))  # the parent's own value
    x0 = lr.x.copy()
    restarted = False
    for _ in range(200):
        for a in (plain, lr):
            a.tell(a.ask(), np.array([2.0]))  # every offspring worse
        restarted = restarted or not np.array_equal(lr.x, x0)
    assert plain.sigma == plain.SIGMA_MIN and np.array_equal(plain.x.shape, (3,))
    assert restarted and lr.x.shape == (3,) and lr.sigma > lr.SIGMA_MIN


def _wilson(k: int, n: int) -> tuple[float, float]:
    """The Wilson score interval written out again here (z for 95 %), not coopt.experiment's."""
    z = 1.959963985
    centre = (k + z * z / 2) / (n + z * z)
    half = z * math.sqrt(k * (n - k) / n + z * z / 4) / (n + z * z)
    return centre - half, centre + half


def test_reproduction_rows_match_the_committed_runs_and_landscape_counts() -> None:
    """The coopt rows of the reproduction table (beyond the paper) from the committed bundle's
    summary and landscape tables, against values recomputed from runs.csv (reached per run) and
    from the landscape's generalist counts."""
    import re

    from morphlearn.figures.reproduction.claims import BEYOND_COOPT
    from morphlearn.figures.reproduction.table import reproduction_table

    b = ROOT / "results" / "coopt"
    summary, land = pd.read_csv(b / "summary.csv"), pd.read_csv(b / "landscape.csv")
    table = reproduction_table(None, None, None, "coopt.yaml", 0.1, coopt=(summary, land, 0.5))
    rows = table[table.key.str.startswith("coopt_")].set_index("key")
    assert (rows.paper == BEYOND_COOPT).all() and len(rows) == 5 * 2 + 2
    runs = pd.read_csv(b / "runs.csv")
    top = runs[(runs.budget == runs.budget.max()) & (runs.sigma0.isna() | (runs.sigma0 == 0.5))]
    names = {"random": "random search", "one_plus_one": "(1+1)-ES (step 0.5)", "cmaes": "CMA-ES (step 0.5)"}
    for (setup, protocol), g in top.groupby(["setup", "protocol"]):
        cell = rows.loc[f"coopt_{setup}_{protocol}_P_generalist", "ours"]
        for learner, h in g.groupby("learner"):
            k, n = int(h.reached.sum()), len(h)
            lo, hi = _wilson(k, n)
            assert n == 30
            assert f"{names[learner]} {k / n:.2f} [{lo:.2f}, {hi:.2f}]" in cell, (setup, protocol, learner, cell)
    canon = land[land["name"] == "canonical"].iloc[0]
    m = int(canon.m)
    want = {
        "M_L": (canon.generalists / m**4, canon.generalists_2w / m**2),
        "M_CF": (canon.generalists / canon.at_least_one, canon.generalists_2w / canon.at_least_one_2w),
    }
    for metric, (four, two) in want.items():
        got = re.findall(r"[0-9.]+(?= \()", rows.loc[f"coopt_canonical_{metric}_4w_vs_2w", "ours"])
        assert [float(x) for x in got] == pytest.approx([four, two], rel=1e-3), (metric, got)
    # the paper's claim this stage answers: four weights make the canonical design more learnable
    assert want["M_L"][0] > want["M_L"][1]
