"""The MuJoCo model (morphlearn.mujoco): MJCF from the parameters, batch independence, levers."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("mujoco")

from morphlearn.grid import weights
from morphlearn.mujoco.episode import BatchRunner, evaluate_design, lower_times
from morphlearn.mujoco.model import MujocoSettings, build_model, mjcf
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import EmpiricalParams, load_params
from morphlearn.physics.reach import ReachBound

CANON = ((0.5, 0.5), (0.5, -0.5))
PARAMS = load_params("config/empirical_morphology.yaml")


@pytest.mark.parametrize(
    "name",
    [
        "body_mass",
        "wheel_mass",
        "castor_mass",
        "wheel_radius",
        "max_speed",
        "max_torque",
        "wheel_setback",
        "wheel_friction",
        "gravity",
        "dt",
    ],
)
def test_mjcf_follows_every_body_parameter(name: str) -> None:
    base = mjcf(PARAMS)
    changed = PARAMS.replace(**{name: getattr(PARAMS, name) * 0.9 + 0.001})
    assert mjcf(changed) != base, name
    assert mjcf(PARAMS) == base  # deterministic text


def test_compiled_model_carries_the_parameters() -> None:
    m = build_model(PARAMS)
    p = PARAMS
    assert m.opt.timestep == p.dt and m.opt.gravity[2] == -p.gravity
    assert m.body("body").mass[0] == pytest.approx(p.body_mass)
    assert m.body("left_wheel").mass[0] == pytest.approx(p.wheel_mass)
    assert m.geom("left_wheel").size[0] == p.wheel_radius
    assert m.body("left_wheel").pos.tolist() == [-p.wheel_setback, 0.5, 0.0]
    assert m.actuator("right").forcerange.tolist() == [-p.max_torque, p.max_torque]
    assert m.actuator("right").ctrlrange.tolist() == [-p.max_speed, p.max_speed]
    assert m.pair("floor_castor").dim[0] == 1  # the castor contact is frictionless
    assert m.pair("floor_left_wheel").friction[:2].tolist() == [p.wheel_friction] * 2
    with pytest.raises(ValueError, match="cone"):
        MujocoSettings(cone="round")


def test_canonical_body_reaches_all_four_lights_with_w_11() -> None:
    ep = BatchRunner(PARAMS).run(*CANON, np.ones((4, 2)), np.arange(4))
    assert ep.success.all(), ep.first_time
    assert (ep.min_dist <= PARAMS.contact_distance).all()
    # mirror images (45 <-> 315, 135 <-> 225) give the same contact times
    assert ep.first_time[0] == ep.first_time[3] and ep.first_time[1] == ep.first_time[2]


def test_episode_does_not_depend_on_its_batch_or_a_rerun() -> None:
    """Bit-identical outcomes alone, inside a large mixed batch (other designs, weights, envs,
    order reversed), and on a rerun; with the early stop on."""
    rng = np.random.default_rng(0)
    n = 300
    l1 = rng.uniform(-0.5, 0.5, (n, 2))
    l2 = rng.uniform(-0.5, 0.5, (n, 2))
    w = rng.choice(weights(11), (n, 2))
    env = rng.integers(0, 4, n)
    runner = BatchRunner(PARAMS.replace(steps=400))
    big = runner.run(l1, l2, w, env, margin=2.0)
    rev = runner.run(l1[::-1], l2[::-1], w[::-1], env[::-1], margin=2.0)
    again = runner.run(l1, l2, w, env, margin=2.0)
    for f in ("first_time", "min_dist", "steps", "hopeless_step", "max_tilt", "max_lift"):
        a = getattr(big, f)
        assert np.array_equal(a, getattr(again, f), equal_nan=True), f
        assert np.array_equal(a, getattr(rev, f)[::-1], equal_nan=True), f
    for k in rng.choice(n, 8, replace=False):
        solo = runner.run(l1[k], l2[k], w[k : k + 1], env[k : k + 1], margin=2.0)
        assert solo.min_dist[0] == big.min_dist[k] and solo.steps[0] == big.steps[k]
        assert np.array_equal(solo.first_time, big.first_time[k : k + 1], equal_nan=True)
    assert big.success.any() and (~big.success).any()  # the sample holds both outcomes


def test_lower_times_equal_the_scalar_bound() -> None:
    rng = np.random.default_rng(1)
    for w_max in (0.0, 0.2, 1.0):
        b = ReachBound(PARAMS, w_max, 0.7, 2.0)
        d = np.concatenate([rng.uniform(0, 8, 500), rng.uniform(60, 80, 20), [b.c, b.c + 1e-9]])
        u = np.concatenate([rng.uniform(0, 3, 300), np.zeros(100), rng.uniform(0, 0.02, 122)])
        expect = [b.lower_time(x, y) for x, y in zip(d, u, strict=True)]
        assert lower_times(b, d, u).tolist() == expect


def test_evaluate_design_levers_keep_the_successes() -> None:
    """Early stop is exact; the adaptive grid infers only failures here (short horizon, 5 x 5)."""
    p = PARAMS.replace(steps=600)
    runner = BatchRunner(p)
    w = weights(5)
    full = evaluate_design(*CANON, w, p, runner=runner)
    stop = evaluate_design(*CANON, w, p, options=SweepOptions(early_stop=True), runner=runner)
    assert np.array_equal(full.first_time, stop.first_time, equal_nan=True)
    adapt = evaluate_design(*CANON, w, p, options=SweepOptions(early_stop=True, adaptive_weights=True), runner=runner)
    sim = adapt.status != 4
    assert np.array_equal(adapt.first_time[sim], full.first_time[sim], equal_nan=True)
    assert full.first_time.shape == (4, 5, 5) and (~np.isnan(full.first_time)).any()


def test_bad_input_says_what() -> None:
    with pytest.raises(ValueError, match="weights must be"):
        BatchRunner(EmpiricalParams(steps=5)).run(*CANON, np.ones((2, 3)), [0, 1])
