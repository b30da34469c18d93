"""The adaptive grid's screen (``adaptive_screen``, morphlearn.physics.screen; issue 56 item 5): its
first wave also simulates the cells a cheaper model calls a success or a near miss, so an isolated
success no lattice cell touches is found; the replay equals the live refinement; its refusals."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import ode_only_config, parse_at_root

from morphlearn.config import ConfigError
from morphlearn.grid import weights
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import load_params
from morphlearn.physics.refine import refine_waves, replay_mask, screen_cells

ROOT = Path(__file__).resolve().parents[1]
SCREEN = {"bundle": "results/reduced-ode-paper", "model": "reduced"}  # 10 designs, 9-point grid, 121 weights


def test_a_lone_success_is_found_only_through_the_screen() -> None:
    m = 13
    success = np.zeros((4, m, m), bool)
    success[2, 3, 5] = True  # off the lattice (stride 6), no neighbour near the light
    promising = np.zeros_like(success)
    sim = lambda c: (success[tuple(c.T)], promising[tuple(c.T)])  # noqa: E731
    assert not refine_waves(m, 4, sim, 6)[2, 3, 5]
    assert not replay_mask(success, 6)[2, 3, 5]
    screen = np.zeros_like(success)
    screen[2, 3, 5] = True
    live = refine_waves(m, 4, sim, 6, screen)
    assert live[2, 3, 5] and np.array_equal(live, replay_mask(success, 6, screen))
    # a screen cell next to a success region grows it as a lattice cell would
    success[1, 7:10, 8:11] = True
    screen[1, 8, 9] = True
    live = refine_waves(m, 4, sim, 6, screen)
    assert live[1, 6:11, 7:12].all() and np.array_equal(live, replay_mask(success, 6, screen))


def test_replay_with_a_screen_equals_the_live_refinement() -> None:
    rng = np.random.default_rng(5)
    for m, stride, p in ((11, 2, 0.1), (17, 6, 0.2), (13, 3, 0.05)):
        ok, near, first = rng.random((3, 4, m, m)) < p
        live = refine_waves(m, 4, lambda c, ok=ok, near=near: (ok[tuple(c.T)], near[tuple(c.T)]), stride, first)
        np.testing.assert_array_equal(live, replay_mask(ok | near, stride, first))
        assert live[first].all()


def test_screen_cells_are_successes_and_near_misses_and_skip_unsimulated() -> None:
    first = np.array([1.0, np.nan, np.nan, np.nan])
    dist = np.array([0.1, 2.0, 9.0, np.nan])
    assert list(screen_cells(first, dist, contact=1.0, near=2.5)) == [True, True, False, False]


def test_the_sweep_simulates_what_the_screen_flags() -> None:
    """The reduced model screening itself at 11 x 11 (stride 10: the lattice is the corners, nothing
    near): every cell the exhaustive run calls a success is simulated and kept."""
    from morphlearn.reduced.episode import evaluate_design

    p = load_params(ROOT / "config/authors_body.yaml")
    l1, l2, w = (0.5, 0.5), (0.5, -0.5), weights(11)
    full = evaluate_design(l1, l2, w, p)
    succ = ~np.isnan(full.first_time)
    assert succ.any()
    opts = SweepOptions(adaptive_weights=True, stride=10, near=0.01)
    bare = evaluate_design(l1, l2, w, p, options=opts)
    flagged = screen_cells(full.first_time, full.min_dist, p.contact_distance, 0.01)
    screened = evaluate_design(l1, l2, w, p, options=opts, screen=flagged)
    assert (~np.isnan(screened.first_time)).sum() == succ.sum() > (~np.isnan(bare.first_time)).sum()
    np.testing.assert_array_equal(screened.first_time[succ], full.first_time[succ])


def _ode(**sec: object) -> object:
    ode = {
        "weights": 121,
        "designs": [[[-0.5, 0.125], [0.5, -0.375]]],  # the paper's best design (478), held by the screen
        "adaptive_weights": True,
        "adaptive_stride": 6,
        "adaptive_near": 2.5,
        "include_mirrors": False,  # the screen holds the design, not its mirror image
        **sec,
    }
    return ode_only_config(ode, grid={"positions_per_axis": 9, "weights": 11})


def test_config_records_the_screen_and_refuses_bad_ones() -> None:
    from morphlearn import models

    pytest.importorskip("morphlearn.ode._core")
    e = models.get("ode").settings(_ode(adaptive_screen=SCREEN))
    assert e.options.screen == (SCREEN["bundle"], SCREEN["model"])
    assert e.science["adaptive_weights"] == {"stride": 6, "near": 2.5, "screen": SCREEN}
    assert SweepOptions.from_science(e.science) == e.options
    # without a screen the record is as before (old results' digests hold)
    assert models.get("ode").settings(_ode()).science["adaptive_weights"] == {"stride": 6, "near": 2.5}
    with pytest.raises(ConfigError, match=r"^ode\.adaptive_screen = \{bundle: results/nowhere, model: reduced\}: "):
        _ode(adaptive_screen={**SCREEN, "bundle": "results/nowhere"})
    with pytest.raises(ConfigError, match=r"^ode\.adaptive_screen is set with ode\.adaptive_weights = false"):
        _ode(adaptive_screen=SCREEN, adaptive_weights=False)
    with pytest.raises(ConfigError, match=r"does not hold design \d+ \(1 of the 1 this run simulates\)"):
        _ode(adaptive_screen=SCREEN, designs=[[[0.5, 0.5], [-0.5, 0.5]]])
    with pytest.raises(ConfigError, match=r"holds 121 weights per synapse; allowed: this run's \(11\)"):
        _ode(adaptive_screen=SCREEN, weights=11)
    with pytest.raises(ConfigError, match=r"ode\.adaptive_screen"):
        _ode(adaptive_screen={"bundle": "results/reduced-ode-paper"})  # no model: the schema's line


def test_an_engine_without_the_layers_sweep_refuses_a_screen() -> None:
    from morphlearn import config

    cfg = config.read(ROOT / "config.yaml")
    cfg["empirical"] = {**cfg["empirical"], "enabled": True, "results_from": None, "adaptive_weights": True}
    cfg["empirical"]["adaptive_screen"] = SCREEN
    with pytest.raises(ConfigError, match=r"^empirical\.adaptive_screen is set, but the empirical model's sweep"):
        parse_at_root(cfg)
