"""The empirical sweep's levers: the reach bound (early stop), the adaptive weight grid, the
status of inferred cells, and the comparison of the two models per design. ~20 s on one core."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy import integrate

from morphlearn import configure, metrics
from morphlearn.analysis import compare
from morphlearn.empirical import EpisodeRunner, evaluate_design
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import EmpiricalParams, load_params
from morphlearn.physics.reach import ReachBound, centre_factor
from morphlearn.physics.refine import lattice, refine_waves, replay_mask
from morphlearn.results import STATUS_INFERRED, STATUS_NONFINITE, STATUS_OK

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def params() -> EmpiricalParams:
    return load_params(ROOT / "config" / "empirical_morphology.yaml")


# --- the reach bound -------------------------------------------------------------------------


def _exact_time(p: EmpiricalParams, w_max: float, rho: float, margin: float, d: float, u: float) -> float:
    """The integral the table bounds, by adaptive quadrature: time from d to c at speed
    max(margin u, margin 1.05 V tanh(w / (x - rho)^2))."""
    k = margin * centre_factor(p) * p.max_speed * p.wheel_radius

    def inv(x: float) -> float:
        v = max(margin * u, k * math.tanh(w_max / max(x - rho, 1e-9) ** 2))
        return 1.0 / v

    return integrate.quad(inv, p.contact_distance, d, limit=200)[0]


@pytest.mark.parametrize(("w_max", "rho", "u"), [(1.0, 0.707, 0.0), (0.4, 0.25, 0.05), (1.0, 0.0, 0.3)])
def test_reach_bound_is_a_lower_bound_and_close(params: EmpiricalParams, w_max: float, rho: float, u: float) -> None:
    b = ReachBound(params, w_max, rho, margin=2.0)
    for d in (1.0, 3.0, 5.66, 12.0, 40.0, 90.0):  # 90 m: past the table
        exact = _exact_time(params, w_max, rho, 2.0, d, u)
        lb = b.lower_time(d, u)
        assert lb <= exact * (1 + 1e-12), (d, lb, exact)
        if d < ReachBound.EXTENT:  # left sums at 1 cm: not much below (past the table: looser)
            assert lb >= exact * 0.97 - 0.05, (d, lb, exact)


def test_reach_bound_monotone_and_edge_cases(params: EmpiricalParams) -> None:
    b = ReachBound(params, 1.0, 0.5)
    times = [b.lower_time(d, 0.0) for d in np.linspace(0.5, 30, 300)]
    assert bool(np.all(np.diff(times) >= 0))
    assert b.lower_time(params.contact_distance, 5.0) == 0.0
    # faster now -> it could get there sooner
    assert b.lower_time(8.0, 1.0) < b.lower_time(8.0, 0.0)
    still = ReachBound(params, 0.0, 0.5)  # w = 0: the wheels are held still
    assert still.hopeless(5.66, 0.0, 125.0)
    assert not still.hopeless(5.66, 1.0, 125.0)  # unless the body is moving
    with pytest.raises(ValueError, match="margin"):
        ReachBound(params, 1.0, 0.5, margin=0.5)


def test_early_stop_changes_no_outcome(params: EmpiricalParams) -> None:
    """The early-stopped loop is the full loop cut where the bound says "hopeless": same contact
    times, and it does cut (a short horizon keeps this fast; the 20,328-episode validation is
    benchmarks/validate_levers.py)."""
    p = params.replace(steps=600)
    cases = [
        ((0.5, 0.5), (0.5, -0.5), 1.0, 1.0, 0),
        ((0.5, 0.5), (0.5, -0.5), -1.0, -0.6, 2),
        ((-0.5, -0.25), (0.5, 0.25), 0.6, -0.8, 1),
        ((0.0, 0.25), (0.25, 0.0), 0.0, 0.0, 3),
        ((-0.5, -0.25), (0.5, 0.25), -0.8, 0.6, 0),
        ((0.5, 0.5), (0.5, -0.5), 0.2, 0.2, 1),
    ]
    stopped = 0
    with EpisodeRunner(p) as runner:
        for l1, l2, w1, w2, env in cases:
            full = runner.run(l1, l2, w1, w2, env)
            b = runner.bound(l1, l2, w1, w2, 2.0)
            shadow = runner.run(l1, l2, w1, w2, env, bound=b, stop_hopeless=False)
            early = runner.run(l1, l2, w1, w2, env, bound=b)
            assert repr(full.first_time) == repr(early.first_time) == repr(shadow.first_time)
            assert (full.steps, full.min_dist) == (shadow.steps, shadow.min_dist)  # checking alone changes nothing
            if early.hopeless_step >= 0:
                stopped += 1
                assert early.steps == early.hopeless_step == shadow.hopeless_step < full.steps
                assert early.min_dist >= full.min_dist  # closest approach up to the stop
            else:
                assert (early.steps, early.min_dist) == (full.steps, full.min_dist)
    assert stopped >= 1


# --- the adaptive weight grid ----------------------------------------------------------------


def refine_mask(success: np.ndarray, promising: np.ndarray, stride: int = 2) -> np.ndarray:
    """The adaptive grid as physics/refine.py's docstring states it, one cell at a time on one
    exhaustive (m, m) map (the reference the sweep's wave-at-once :func:`refine_waves` and the
    vectorised :func:`replay_mask` are checked against): the cells it simulates."""
    m = success.shape[0]
    done = np.zeros((m, m), bool)
    wave = [tuple(int(v) for v in ij) for ij in np.argwhere(lattice(m, stride))]
    while wave:
        for i, j in wave:
            done[i, j] = True
        nxt: set[tuple[int, int]] = set()
        for i, j in wave:
            if success[i, j] or promising[i, j]:  # its unsimulated 8-neighbours are the next wave
                nxt |= {
                    (a, b) for a in range(max(i - 1, 0), min(i + 2, m)) for b in range(max(j - 1, 0), min(j + 2, m))
                }
        wave = sorted(c for c in nxt if not done[c])
    return done


def test_lattice_and_refinement_replay() -> None:
    assert lattice(11, 2).sum() == 36 and lattice(11, 2)[10, 10] and not lattice(11, 2)[1, 0]
    assert lattice(10, 3).sum() == 16  # 0, 3, 6, 9
    none = np.zeros((11, 11), bool)
    assert (refine_mask(none, none) == lattice(11, 2)).all()  # nothing found: the lattice only
    blob = np.zeros((11, 11), bool)
    blob[6:9, 7:10] = True  # touches the lattice at (6, 8), (8, 8)
    mask = refine_mask(blob, none)
    assert mask[blob].all()  # the whole region, found from one lattice cell
    assert mask[5:10, 6:11].all()  # and its one-cell fringe
    lone = np.zeros((11, 11), bool)
    lone[3, 5] = True  # off the lattice, no neighbour succeeds: missed...
    assert not refine_mask(lone, none)[3, 5]
    near = np.zeros((11, 11), bool)
    near[4, 4] = True  # ...unless a lattice neighbour came near the light
    assert refine_mask(lone, near)[3, 5]


def test_vectorised_replay_equals_the_refinement() -> None:
    rng = np.random.default_rng(3)
    for m, stride, p in ((11, 2, 0.15), (13, 3, 0.3), (9, 2, 0.05)):
        succ, near = rng.random((2, 6, m, m)) < p
        want = np.stack([refine_mask(s, n, stride) for s, n in zip(succ, near, strict=True)])
        np.testing.assert_array_equal(replay_mask(succ | near, stride), want)


def test_refine_waves_simulates_the_cells_refine_does() -> None:
    """The sweep's adaptive grid (every map's wave in one call) simulates, per map, the cells of
    the grid simulated one cell at a time, and each cell once."""
    rng = np.random.default_rng(2)
    m = 11
    ok = rng.random((3, m, m)) < 0.08
    near = rng.random((3, m, m)) < 0.1
    asked: list[np.ndarray] = []
    got = refine_waves(m, 3, lambda c: asked.append(c) or (ok[tuple(c.T)], near[tuple(c.T)]), 2)
    for e in range(3):
        np.testing.assert_array_equal(got[e], refine_mask(ok[e], near[e]))
    cells = np.concatenate(asked)
    assert len(cells) == int(got.sum()) == len(np.unique(cells, axis=0))


def test_adaptive_design_marks_inferred_cells(params: EmpiricalParams) -> None:
    """Cells the refinement skips are stored as inferred failures (NaN, status 4); the simulated
    ones equal the full sweep's bit for bit; the metrics do not count inferred cells as flagged."""
    p = params.replace(steps=400)
    w = np.linspace(-1.0, 1.0, 5)
    design = ((0.5, 0.5), (0.5, -0.5))
    full = evaluate_design(*design, w, p)
    calls: list[tuple[int, int]] = []
    ada = evaluate_design(*design, w, p, lambda d, t: calls.append((d, t)), options=SweepOptions(adaptive_weights=True))
    inferred = ada.status == STATUS_INFERRED
    assert inferred.any() and calls[-1] == (100, 100)
    assert np.isnan(ada.first_time[inferred]).all() and np.isnan(ada.min_dist[inferred]).all()
    np.testing.assert_array_equal(ada.first_time[~inferred], full.first_time[~inferred])
    np.testing.assert_array_equal(ada.min_dist[~inferred], full.min_dist[~inferred])
    succ = np.isfinite(ada.first_time)
    dm = metrics.design_metrics(succ, ada.status)
    assert dm.flagged == 0
    st = np.full((4, 2, 2), STATUS_OK, np.int8)
    st[0, 0, 0], st[1, 0, 0] = STATUS_INFERRED, STATUS_NONFINITE
    assert metrics.design_metrics(np.zeros((4, 2, 2), bool), st).flagged == 1


def test_options_enter_the_science_record_only_when_on() -> None:
    from morphlearn import config as cfgmod
    from morphlearn import models

    def science(cfg: dict) -> dict:
        return models.get("empirical").science(configure.parse(cfg))

    base = cfgmod.read(ROOT / "config.yaml")
    off = cfgmod.deep_merge(base, {"empirical": {"early_stop": False, "adaptive_weights": False, "results_from": None}})
    sci_off = science(off)
    assert "early_stop" not in sci_off and "adaptive_weights" not in sci_off
    on = science(cfgmod.deep_merge(off, {"empirical": {"early_stop": True, "adaptive_weights": True}}))
    assert on["early_stop"] == {"margin": 2.0, "check_every": 10}
    assert on["adaptive_weights"] == {"stride": 2, "near": 4.0}
    survey = cfgmod.read(ROOT / "config.yaml", [ROOT / "config/survey.yaml"])
    assert science(survey)["adaptive_weights"]["near"] == 1.5  # its bundle's record
    refine = cfgmod.read(ROOT / "config.yaml", [ROOT / "config/refine_pybullet.yaml"])
    assert science(refine)["adaptive_weights"]["near"] == 4.0  # the 121 x 121 bundle's record
    assert science(refine)["early_stop"] == {"margin": 2.0, "check_every": 10}


# --- theory against physics ------------------------------------------------------------------


def _table(values_l: np.ndarray, values_cf: np.ndarray) -> pd.DataFrame:
    n = len(values_l)
    axis = np.linspace(-0.5, 0.5, 3)
    idx = np.arange(n)
    return pd.DataFrame(
        {
            "design": idx,
            "l1x": axis[idx % 3],
            "l1y": axis[(idx // 3) % 3],
            "l2x": 0.5,
            "l2y": -0.5,
            "generalists": (values_l * 100).astype(int),
            "M_L": values_l,
            "M_CF": values_cf,
        }
    )


def test_rank_agreement_and_sensor_use() -> None:
    x = np.linspace(0, 1, 30)
    t = _table(x, x**2)
    same = compare.joined(t, _table(x**3, x))  # monotone in both metrics
    a = compare.agreement(same, n_resamples=200)
    assert a["M_L"].rho == pytest.approx(1.0) and a["M_L"].low == pytest.approx(1.0)
    rev = compare.joined(t, _table(1 - x, 1 - x))
    r = compare.agreement(rev, n_resamples=200)["M_CF"]
    assert r.rho == pytest.approx(-1.0) and r.high == pytest.approx(-1.0)
    noisy = compare.joined(t, _table(np.random.default_rng(0).permutation(x), x))
    n = compare.agreement(noisy, n_resamples=300)["M_L"]
    assert n.low < n.rho < n.high and n.low < 0.5
    assert compare.agreement(noisy, n_resamples=300)["M_L"] == n  # seeded: same interval
    flat = compare.joined(t, _table(np.zeros(30), np.zeros(30)))
    assert "undefined" in compare.agreement(flat, n_resamples=50)["M_L"].text()
    # one to four designs in both (a physics run of a few refined designs): no rank correlation
    # (rho = +-1 by chance with probability 2 / n!: 8 % at 4), said in words, not a bootstrap error
    assert compare.MIN_DESIGNS == 5
    for k in (1, 2, 3, 4):
        few = compare.agreement(compare.joined(t.head(k), _table(x[:k], x[:k])), n_resamples=200)["M_L"]
        assert np.isnan(few.rho) and few.n == k and f"only {k} design" in few.text()
        assert "needs 5 to tell agreement from chance" in few.text()
    five = compare.agreement(compare.joined(t.head(5), _table(x[:5], x[:5])), n_resamples=200)["M_L"]
    assert five.n == 5 and five.rho == pytest.approx(1.0) and "5 designs" in five.text()
    assert same.rank_M_L_theory.tolist() == list(range(30, 0, -1))  # best (largest) ranks 1
    use = compare.sensor_use(t, 4)
    assert use["count"].sum() == 8 and len(use) == 9  # 4 designs x 2 sensors on the 3 x 3 positions
    with pytest.raises(ValueError, match="different grids"):
        compare.joined(t, t.assign(l1x=t.l1x + 0.1))


def _grid_table(n: int, m_l: np.ndarray) -> pd.DataFrame:
    """A metrics table of every design of the ``n``-point grid."""
    from morphlearn import grid

    g = grid.DesignGrid(n)
    c = g.coords(np.arange(g.size))
    cols = dict(zip(compare.COORDS, c.T, strict=True))
    return pd.DataFrame({"design": np.arange(g.size), **cols, "generalists": 0, "M_L": m_l, "M_CF": m_l / 2})


def test_joined_pairs_a_subgrid_survey_by_coordinates() -> None:
    """A survey of the 3-point grid beside a 5-point run (the 5-point ODE survey beside the paper's
    9-point theory): paired on the 81 designs they share, by position, not by index."""
    from morphlearn import grid

    fine, coarse = grid.DesignGrid(5), grid.DesignGrid(3)
    assert grid.is_subgrid(3, 5) and grid.is_subgrid(5, 9) and not grid.is_subgrid(4, 9) and not grid.is_subgrid(9, 5)
    rng = np.random.default_rng(1)
    a = _grid_table(5, rng.random(fine.size))
    b = _grid_table(3, rng.random(coarse.size))
    both = compare.joined(a, b)
    assert len(both) == coarse.size
    # each coarse design sits at the fine index of its own coordinates, with its own values
    at = fine.flat(2 * coarse.indices(np.arange(coarse.size)))  # every other position
    want = pd.DataFrame({"design": at, "M_L_b": b.M_L}).sort_values("design").reset_index(drop=True)
    got = both.rename(columns={f"M_L_{compare.PAIR[1]}": "M_L_b"})
    assert got.design.tolist() == want.design.tolist() and np.allclose(got.M_L_b, want.M_L_b)
    assert np.allclose(both[f"M_L_{compare.PAIR[0]}"], a.M_L.to_numpy()[both.design])
    assert not np.array_equal(both.design, np.arange(coarse.size))  # not paired by index
    with pytest.raises(ValueError, match="different grids"):
        compare.joined(a, b.assign(l1x=b.l1x + 0.01))


def test_compare_cli(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from morphlearn.apps.cli import main

    x = np.linspace(0, 1, 20)
    _table(x, x).to_csv(tmp_path / "a.csv", index=False)
    _table(x[::-1], x).to_csv(tmp_path / "b.csv", index=False)
    assert main(["compare", str(tmp_path / "a.csv"), str(tmp_path / "b.csv"), "--resamples", "100", "--top", "3"]) == 0
    out = capsys.readouterr().out
    assert "M_L: Spearman rho -1.000" in out and "M_CF: Spearman rho 1.000" in out
    assert "top 3 by M_L shared: 0" in out and "top 3 by M_CF shared: 3" in out
    assert main(["compare", str(tmp_path / "nope.csv"), str(tmp_path / "b.csv")]) == 2
    assert "nope.csv: no such file" in capsys.readouterr().err
