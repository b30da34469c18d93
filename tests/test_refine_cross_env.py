"""The adaptive grid across environments (``adaptive_cross_env``, physics/refine.py): a success in
one of a design's environments is simulated in all four, so a generalist island that one
environment's own region never reaches is found; the sweep's waves equal the vectorised replay."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from morphlearn.grid import weights
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import load_params
from morphlearn.physics.refine import refine_waves, replay_mask

ROOT = Path(__file__).resolve().parents[1]


def test_replay_across_environments_equals_the_waves() -> None:
    rng = np.random.default_rng(11)
    for m, stride, p, nd in ((11, 2, 0.1, 1), (17, 6, 0.15, 2), (13, 3, 0.05, 3)):
        ok, near, first = rng.random((3, 4 * nd, m, m)) < p
        asked: list[np.ndarray] = []

        def sim(
            c: np.ndarray, ok: np.ndarray = ok, near: np.ndarray = near, asked: list = asked
        ) -> tuple[np.ndarray, np.ndarray]:
            asked.append(c)
            return ok[tuple(c.T)], near[tuple(c.T)]

        live = refine_waves(m, 4 * nd, sim, stride, first, group=4)
        cells = np.concatenate(asked)
        assert len(np.unique(cells, axis=0)) == len(cells)  # each cell once
        want = replay_mask(
            (ok | near).reshape(nd, 4, m, m),
            stride,
            first.reshape(nd, 4, m, m),
            across=True,
            success=ok.reshape(nd, 4, m, m),
        )
        np.testing.assert_array_equal(live, want.reshape(4 * nd, m, m))
        # a success anywhere is simulated in every environment of its design
        hit = (ok & live).reshape(nd, 4, m, m).any(axis=1)
        assert live.reshape(nd, 4, m, m)[np.broadcast_to(hit[:, None], (nd, 4, m, m))].all()
        per_env = refine_waves(m, 4 * nd, lambda c, ok=ok, near=near: (ok[tuple(c.T)], near[tuple(c.T)]), stride, first)
        assert (live >= per_env).all()


def test_an_island_one_environment_never_reaches_is_found_from_another() -> None:
    m = 13
    ok = np.zeros((4, m, m), bool)
    ok[:, 3, 3] = True  # a generalist, off the lattice (stride 6), no near miss around it...
    ok[0, 0:6, 0:6] = True  # ...but inside environment 0's region, which holds the lattice cell (0, 0)
    sim = lambda c: (ok[tuple(c.T)], np.zeros(len(c), bool))  # noqa: E731
    assert not refine_waves(m, 4, sim, 6)[1:, 3, 3].any()  # per environment: lost in 1-3
    assert refine_waves(m, 4, sim, 6, group=4)[:, 3, 3].all()
    with pytest.raises(ValueError, match="group = 3 must be >= 1 and divide n_maps = 4"):
        refine_waves(m, 4, sim, 6, group=3)


def test_the_6561_maps_design_keeps_its_7_generalists() -> None:
    """Design (-0.5, -0.375), (0.125, -0.25) of the 9-point grid at 121 x 121 weights: every cell
    gives successes [305, 365, 222, 472], 7 generalists, 1135 solving at least one environment;
    results/reduced-paper (stride 6, near 2.5, per environment) had 0 generalists. Across
    environments the adaptive grid finds every success of it."""
    from morphlearn.reduced.episode import evaluate_design

    p = load_params(ROOT / "config/authors_body.yaml")
    l1, l2, w = (-0.5, -0.375), (0.125, -0.25), weights(121)
    full = ~np.isnan(evaluate_design(l1, l2, w, p).first_time)
    assert full.sum(axis=(1, 2)).tolist() == [305, 365, 222, 472]
    assert int(full.all(axis=0).sum()) == 7 and int(full.any(axis=0).sum()) == 1135
    levers = {"adaptive_weights": True, "stride": 6, "near": 2.5}
    fixed = ~np.isnan(evaluate_design(l1, l2, w, p, options=SweepOptions(**levers)).first_time)
    np.testing.assert_array_equal(fixed, full)
    old = ~np.isnan(evaluate_design(l1, l2, w, p, options=SweepOptions(**levers, cross_env=False)).first_time)
    assert int(old.all(axis=0).sum()) == 0 and int(old.any(axis=0).sum()) == 1135  # the map's counts
