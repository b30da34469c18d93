"""Learners on the theory model (issue 15): kernel for arbitrary weights, losses, protocols,
determinism, and random search against M_L."""

from __future__ import annotations

import math

import numpy as np
import pytest

from morphlearn import config, configure, metrics
from morphlearn.grid import DesignGrid, env_starts, weights
from morphlearn.learners import experiment, protocols
from morphlearn.learners.objective import joint_loss
from morphlearn.settings import Settings
from morphlearn.theory import TheoryParams, evaluate
from morphlearn.theory import cpu as kernel

P = TheoryParams()


def _cfg(**learners) -> Settings:
    base = config.load("config.yaml")
    return configure.parse({**base, "learners": {"enabled": True, **learners}})


def test_points_kernel_equals_grid_kernel_on_grid_points() -> None:
    g = DesignGrid(5)
    designs = g.coords(np.array([99, 312]))
    w = weights(3)
    ft, dm, st, _ = kernel.sweep(
        designs,
        w,
        env_starts(P.r),
        **P.kernel_kwargs(),
    )
    d, e, i, j = (a.ravel() for a in np.indices(ft.shape))
    t2, d2, s2 = kernel.points(
        designs,
        env_starts(P.r),
        d,
        e,
        w[i],
        w[j],
        **P.kernel_kwargs(),
    )
    np.testing.assert_array_equal(t2, ft.ravel())  # same compiled model: bit-identical
    np.testing.assert_array_equal(d2, dm.ravel())
    np.testing.assert_array_equal(s2, st.ravel())


def test_joint_loss_ranks_every_generalist_before_every_non_generalist() -> None:
    rng = np.random.default_rng(0)
    radius_over_r = 0.2 / 4.0
    ok = rng.random((20000, 4)) < 0.6
    loss = np.where(ok, rng.random((20000, 4)), 1.0 + radius_over_r + rng.random((20000, 4)) * (1 - radius_over_r))
    f = joint_loss(loss)
    fails = (~ok).sum(1)
    for k in range(4):  # strictly ordered by the number of environments failed
        assert f[fails == k].max() < f[fails == k + 1].min()


def _feed(run: protocols.Run, script):
    """Drive one run by hand: ``script(env_idx, w)`` returns (loss, success)."""
    req = next(run)
    try:
        while True:
            req = run.send(script(*req))
    except StopIteration as stop:
        return stop.value


class _Fixed:
    """A learner that proposes its points in turn (to test the protocol's bookkeeping)."""

    def __init__(self, pts):
        self.pts, self.k = [np.array(p, float) for p in pts], 0

    def ask(self):
        self.k += 1
        return self.pts[(self.k - 1) % len(self.pts)][None, :]

    def tell(self, x, f):
        pass

    def rescore(self, f):
        pass


def test_sequential_counts_forgetting_and_final_generalist() -> None:
    # Point A solves environments 0, 1; point B solves 1, 2, 3 and scores best on 2 and 3.
    solves = {(0.1, 0.1): {0, 1}, (0.9, 0.9): {1, 2, 3}}

    def script(env, w):
        ok = np.array([e in solves[tuple(np.round(x, 6))] for e, x in zip(env, w, strict=True)])
        loss = np.where(ok, 0.5, 1.5)
        loss[(w[:, 0] > 0.5) & ok] = 0.1  # B is faster where it succeeds
        return loss, ok

    r = _feed(protocols.sequential(_Fixed([(0.1, 0.1), (0.9, 0.9)]), per_phase=2, cycles=1), script)
    # After phase 0 (env 0) the incumbent is A: {0, 1}. Phase 1 (env 1) moves to B (0.1 < 0.5):
    # {1, 2, 3}, env 0 lost (opportunities: env 0, not the trained env 1). Phases 2 and 3 keep B:
    # opportunities {1, 3} and {1, 2}, nothing lost.
    assert (r.forget_events, r.forget_opportunities) == (1, 1 + 2 + 2)
    assert not r.reached and not r.final_generalist and r.evaluations == 8


def test_runs_are_deterministic_and_independent_of_batching() -> None:
    cfg = _cfg(seeds=2, budget=6, cycles=1, per_phase=3)
    alone = experiment.run_designs(cfg, np.array([99]))
    together = experiment.run_designs(cfg, np.array([312, 99]))
    again = experiment.run_designs(cfg, np.array([99]))
    assert alone.equals(again)
    assert alone.reset_index(drop=True).equals(together[together.design == 99].reset_index(drop=True))


@pytest.mark.parametrize("design", [99, 156, 312])
def test_random_search_success_rate_matches_m_l(design: int) -> None:
    """One uniform sample is a generalist with probability = the generalist share of the weight
    square, which the grid's M_L estimates. Tolerance: 4 binomial standard errors plus the share of
    grid cells on the generalist boundary (where the grid cannot say which side the area is on)."""
    n = 1500
    cfg = _cfg(learners=["random"], protocols=["joint"], seeds=n, budget=1)
    p = float(experiment.run_designs(cfg, np.array([design])).p_generalist.iloc[0])
    m = 41
    res = evaluate(DesignGrid(5).coords(np.array([design])), weights(m), P)[0]
    th = metrics.Thresholds(P.horizon, P.success_radius, P.horizon, P.success_radius)
    gen = metrics.success(res.first_time, res.min_dist, th).all(axis=0)
    ml = float(gen.mean())
    pad = np.pad(gen, 1, mode="edge")
    mixed = np.zeros_like(gen)
    for di in (-1, 0, 1):
        for dj in (-1, 0, 1):
            mixed |= pad[1 + di : 1 + di + m, 1 + dj : 1 + dj + m] != gen
    tol = 4 * math.sqrt(max(ml * (1 - ml), 1.0 / n) / n) + 0.5 * float(mixed.mean())
    assert abs(p - ml) <= tol, (p, ml, tol)


def test_config_refuses_more_learner_shards_than_designs() -> None:
    with pytest.raises(config.ConfigError, match=r"learners.shards = 9 exceeds the 3 designs"):
        _cfg(max_designs=3, shards=9)
    with pytest.raises(config.ConfigError, match=r"learners"):
        _cfg(learners=["sgd"])


def test_correlation_among_positive_metric_designs_ignores_the_zero_tie() -> None:
    # 40 designs with M_L = 0 that no learner solves, 40 with M_L > 0 whose success is unrelated to
    # M_L: the whole-table rho is large (the zero tie), the rho among M_L > 0 is not.
    import pandas as pd

    from morphlearn.learners import stats

    rng = np.random.default_rng(1)
    ml = np.r_[np.zeros(40), rng.uniform(0.01, 0.3, 40)]
    p = np.r_[np.zeros(40), rng.uniform(0.2, 1.0, 40)]
    runs = pd.DataFrame({"design": np.arange(80), "learner": "random", "protocol": "joint", "p_generalist": p})
    metrics_table = pd.DataFrame({"design": np.arange(80), "M_L": ml, "M_CF": ml})
    row = stats.correlations(runs, metrics_table, n_boot=500, seed=0).iloc[0]
    assert row.rho_ML_success > 0.7 and row.designs_ML_pos == 40
    assert row.rho_ML_success_pos_lo < 0 < row.rho_ML_success_pos_hi  # no relation among M_L > 0
