"""Scenarios: reading and validating the file, the simulation plan, the derivations it relies on,
the comparison statistics, and a smoke run of the scenario workflow."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from conftest import ROOT, copy_workflow, job_stats, snakemake

from morphlearn import configure, metrics
from morphlearn import grid as gridmod
from morphlearn import scenarios as sc
from morphlearn.theory import TheoryParams, evaluate


def _file(tmp_path: Path, data: dict) -> Path:
    p = tmp_path / "scenarios.yaml"
    p.write_text(yaml.safe_dump(data))
    return p


@pytest.mark.parametrize(
    ("data", "needle"),
    [
        ({"base": {}, "_x": {}}, "scenario name '_x' is invalid"),
        ({"base": {}, "a": {"results_dir": "x"}}, "key ['results_dir'] cannot be overridden"),
        ({"base": {}, "a": [1]}, "must be a mapping"),
        ({"a": {}}, "no scenario named 'base'"),
        ({"base": {}, "a": {"analysis": {"horizon": 100}}}, "analysis.horizon is set by the planner"),
    ],
)
def test_bad_scenario_file_is_one_line_naming_it(tmp_path: Path, data: dict, needle: str) -> None:
    with pytest.raises(sc.ScenarioError) as e:
        sc.read_file(_file(tmp_path, data))
    assert needle in str(e.value) and "\n" not in str(e.value)


def test_select_adds_base_keeps_file_order_and_refuses_unknown_names() -> None:
    avail = ["base", "a", "b", "c"]
    assert sc.select(avail, "all") == avail
    assert sc.select(avail, "c,a") == ["base", "a", "c"]
    assert sc.select(avail, ["b"]) == ["base", "b"]
    with pytest.raises(sc.ScenarioError, match=r"unknown scenario \['zz'\]; allowed: 'all' or names"):
        sc.select(avail, "a,zz")


def test_override_validated_with_the_config_schema() -> None:
    base = configure.load(ROOT / "config.yaml")
    with pytest.raises(sc.ScenarioError, match=r"scenario 'neg': theory.r = -1.0 is invalid"):
        sc.expand(base, {"base": {}, "neg": {"theory": {"r": -1.0}}}, ["base", "neg"])
    with pytest.raises(sc.ScenarioError, match=r"scenario 'typo': unknown key \['horizn'\] under 'theory'"):
        sc.expand(base, {"base": {}, "typo": {"theory": {"horizn": 1.0}}}, ["base", "typo"])


def test_answers_only_what_stored_arrays_determine() -> None:
    sim = (500.0, 0.2)
    assert sc.answers(sim, (500.0, 0.2)) == sc.HOW_DIRECT
    assert sc.answers(sim, (250.0, 0.2)) == sc.HOW_HORIZON
    assert sc.answers(sim, (500.0, 0.4)) == sc.HOW_RADIUS
    assert sc.answers(sim, (1000.0, 0.2)) is None  # longer horizon: never simulated
    assert sc.answers(sim, (500.0, 0.1)) is None  # smaller radius: the run stopped at 0.2
    assert sc.answers(sim, (250.0, 0.4)) is None  # no time of entry into 0.4 is stored


def test_default_set_needs_five_simulations_for_nine_scenarios() -> None:
    base = configure.load(ROOT / "config.yaml")
    f = sc.read_file(ROOT / "config" / "scenarios.yaml")
    scen = sc.expand(base, f, sc.select(f, "all"))
    p = sc.plan(scen, base.results_dir)
    params = [sim.models["theory"].params for sim in p.sims.values()]
    simulated = {(round(t.r, 9), t.horizon, t.success_radius) for t in params}
    r2 = round(4 * math.sqrt(2), 9)
    # r = 4: (500, 0.2) answers base, T250, radius0.4; (1000, 0.1) answers T1000 (radius) and
    # radius0.1 (horizon); both cost 1500 time units, the tie goes to simulating the base itself.
    assert simulated == {(4.0, 500.0, 0.2), (4.0, 1000.0, 0.1), (2.0, 500.0, 0.2), (8.0, 500.0, 0.2), (r2, 1000.0, 0.2)}
    how = {n: a.how for n, a in p.answers.items()}
    assert how["base"] == how["r4sqrt2_T1000"] == sc.HOW_DIRECT
    assert how["T250"] == how["r4sqrt2"] == how["radius0.1"] == sc.HOW_HORIZON
    assert how["radius0.4"] == how["T1000"] == sc.HOW_RADIUS
    assert p.answers["r4sqrt2"].sim == p.answers["r4sqrt2_T1000"].sim
    # every simulation keeps its designs in the main run's design cache (shared science, shared designs)
    assert {sim.results_dir for sim in p.sims.values()} == {base.results_dir}
    assert p.thresholds("T1000") == metrics.Thresholds(1000.0, 0.2, 1000.0, 0.1)


def test_derived_success_equals_direct_simulation() -> None:
    """What the plan relies on: a shorter horizon from first-success times and a larger radius from
    minimum distances give the success a direct simulation gives (canonical and the paper's best
    design, 11 x 11 weights). The horizon derivation may differ only where the direct run's last
    step, clipped to the shorter horizon, ends: first success within one step of T."""
    g = gridmod.DesignGrid(5)
    designs = g.coords([g.index_of(*gridmod.canonical_design()), g.index_of(*sc.PAPER_BEST_DESIGN)])
    w = gridmod.weights(11)

    def run(t: float, rad: float):
        return evaluate(designs, w, TheoryParams(horizon=t, success_radius=rad))

    long_, short, small, direct = run(300.0, 0.2), run(150.0, 0.2), run(300.0, 0.1), run(300.0, 0.4)
    for lg, sh in zip(long_, short, strict=True):
        derived = metrics.success(lg.first_time, lg.min_dist, metrics.Thresholds(150.0, 0.2, 300.0, 0.2))
        direct_short = metrics.success(sh.first_time, sh.min_dist, metrics.Thresholds(150.0, 0.2, 150.0, 0.2))
        differ = derived != direct_short
        assert derived.sum() > 0 and (~derived).sum() > 0  # the test has both outcomes
        assert np.all(np.abs(np.nan_to_num(lg.first_time[differ], nan=1e9) - 150.0) < 5.0), differ.sum()

    def succ(res, t: float, rad: float, ts: float, rs: float) -> np.ndarray:
        return metrics.success(res.first_time, res.min_dist, metrics.Thresholds(t, rad, ts, rs))

    for sm, lg, d4 in zip(small, long_, direct, strict=True):
        assert np.array_equal(succ(sm, 300.0, 0.2, 300.0, 0.1), succ(lg, 300.0, 0.2, 300.0, 0.2))
        assert np.array_equal(succ(lg, 300.0, 0.4, 300.0, 0.2), succ(d4, 300.0, 0.4, 300.0, 0.4))


def _table(ml: np.ndarray, cf: np.ndarray) -> pd.DataFrame:
    g = gridmod.DesignGrid(3)
    c = g.coords(np.arange(g.size))
    return pd.DataFrame(
        {
            "design": np.arange(g.size),
            "l1x": c[:, 0],
            "l1y": c[:, 1],
            "l2x": c[:, 2],
            "l2y": c[:, 3],
            "M_L": ml,
            "M_CF": cf,
        }
    )


def test_compare_statistics_on_known_tables() -> None:
    g = gridmod.DesignGrid(3)
    n = g.size
    ml = np.linspace(0.0, 0.8, n)
    cf = np.linspace(1.0, 0.2, n)
    canon = g.index_of(*gridmod.canonical_design())
    comp = sc.compare(
        {"base": _table(ml, cf), "same": _table(ml, cf), "rev": _table(ml[::-1], cf[::-1])}, top=10
    ).set_index("scenario")
    assert comp.loc["same", "tau_M_L"] == pytest.approx(1.0)
    assert comp.loc["rev", "tau_M_L"] == pytest.approx(-1.0)
    assert comp.loc["rev", "tau_M_CF"] == pytest.approx(-1.0)
    assert comp.loc["same", "top10_overlap_M_L"] == 10
    assert comp.loc["rev", "top10_overlap_M_L"] == 0  # 81 designs: the top 10 and the bottom 10
    assert comp.loc["base", "canonical_rank_M_L"] == n - canon  # M_L increases with the index
    assert comp.loc["rev", "canonical_rank_M_L"] == canon + 1
    assert comp.loc["base", "best_M_L"] == pytest.approx(0.8)
    # the paper's best design is not on the 3-position grid
    assert math.isnan(comp.loc["base", "paper_best_M_L"]) and not comp.loc["base", "paper_best_in_top10_M_L"]


def test_text_distance_is_zero_at_the_text_values() -> None:
    assert sc.text_distance(0.049, 0.286) == 0.0
    assert sc.text_distance(0.098, 0.286) == pytest.approx(1.0)


def test_generalist_fraction_matches_design_metrics() -> None:
    rng = np.random.default_rng(3)
    ft = np.where(rng.random((3, 4, 6, 6)) < 0.7, rng.uniform(0, 500, (3, 4, 6, 6)), np.nan).astype(np.float32)
    md = np.where(np.isnan(ft), rng.uniform(0.2, 2, ft.shape), 0.1).astype(np.float32)
    for th in (metrics.Thresholds(250.0, 0.2, 500.0, 0.2), metrics.Thresholds(500.0, 0.6, 500.0, 0.2)):
        got = sc.generalist_fraction(ft, md, th)
        want = [metrics.design_metrics(metrics.success(ft[i], md[i], th)).M_L for i in range(3)]
        assert np.allclose(got, want) and len(set(np.round(want, 6))) > 1


def test_scenario_workflow_smoke(tmp_path: Path) -> None:
    """Three scenarios, one simulation: the base at smoke resolution, a shorter horizon and a larger
    radius answered from it; then the comparison. A bad scenario name stops the start (exit 2)."""
    wd = copy_workflow(tmp_path / "wf")
    (wd / "config" / "s.yaml").write_text(
        yaml.safe_dump(
            {
                "base": {},
                "short": {"theory": {"horizon": 200.0}},
                "wide": {"theory": {"success_radius": 0.4}},
            }
        )
    )
    over = ["--configfile", "config/smoke.yaml", "--config", "scenario_file=config/s.yaml"]
    bad = snakemake(wd, "-n", "--cores", "1", *over, "scenarios=base,nope", check=False)
    assert bad.returncode == 2 and "unknown scenario ['nope']" in bad.stderr
    run = snakemake(wd, "--cores", "2", *over, "scenarios=all")
    stats = job_stats(run.stdout + run.stderr)
    assert stats["scenario_merge"] == 1 and stats["scenario_metrics"] == 3
    out = wd / "results" / "scenarios"
    comp = pd.read_csv(out / "comparison.csv").set_index("scenario")
    assert comp.loc["base", "tau_M_L"] == pytest.approx(1.0)
    base = pd.read_csv(out / "base" / "theory" / "metrics.csv")
    short = pd.read_csv(out / "short" / "theory" / "metrics.csv")
    assert (short.generalists <= base.generalists).all()  # a shorter horizon never adds successes
    assert json.loads((out / "wide" / "scenario.json").read_text())["answer"]["how"] == sc.HOW_RADIUS
    assert (out / "comparison.png").stat().st_size > 0
    # a subset re-uses the simulation and the scenarios' metrics: only its comparison is new
    again = snakemake(wd, "-n", "--cores", "1", *over, "scenarios=short")
    assert set(job_stats(again.stdout)) == {"scenario_compare", "scenario_report", "all"}
    # custody (issue 24): an edited scenario table stops the next start, by name, exit 2
    table = out / "short" / "theory" / "metrics.csv"
    table.write_text(table.read_text().replace(",0,", ",1,", 1))
    refused = snakemake(wd, "-n", "--cores", "1", *over, "scenarios=all", check=False)
    assert refused.returncode == 2 and f"{table.relative_to(wd)}: SHA-256" in refused.stderr, refused.stderr[-2000:]
