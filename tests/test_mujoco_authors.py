"""The authors' robot in MuJoCo (morphlearn.mujoco.authors, ``mujoco.robot: authors``): its world
against the one the ODE model builds (the authors' facts, read back from ODE), its outcomes against
ODE's, determinism, and the config key."""

from __future__ import annotations

import numpy as np
import pytest

from morphlearn.config import ConfigError
from morphlearn.grid import light_positions
from morphlearn.physics import authors as robot
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import load_params

mujoco = pytest.importorskip("mujoco")
core = pytest.importorskip("morphlearn.ode.core")
if not core.available():
    pytest.skip("morphlearn.ode._core not built (no libode-dev): the reference engine", allow_module_level=True)

from morphlearn.mujoco.authors import AuthorsBatchRunner, evaluate_design  # noqa: E402

BODY = load_params("config/authors_body.yaml")
CANONICAL = ((0.5, 0.5), (0.5, -0.5))
PAPER_BEST = ((-0.5, 0.125), (0.5, -0.375))


def _project(p: tuple[float, float, float]) -> tuple[float, float, float]:
    """The authors' frame -> the project's: x = y_a, y = -x_a."""
    return (p[1], -p[0], p[2])


def test_bodies_are_the_ones_ode_builds() -> None:
    f = core.core().facts(core.params_tuple(BODY), (0.5, 0.5, 0.5, -0.5), (4.0, 4.0), 1.0, -0.5)
    ode = {b["name"]: b for b in f["bodies"]}
    m = AuthorsBatchRunner(BODY).model(*CANONICAL)
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    for name in ("chassis", "left_wheel", "right_wheel", "castor", "sensor1", "sensor2"):
        b = m.body(name)
        geom = m.geom(name if name != "chassis" else "box")
        assert b.mass[0] == pytest.approx(ode[name]["mass"], rel=1e-12), name
        assert d.body(name).xpos == pytest.approx(_project(ode[name]["position"]), abs=1e-12), name
        size = ode[name]["size"]
        want = size if isinstance(size, float) else (size[1] / 2, size[0] / 2, size[2] / 2)  # box: half lengths
        assert geom.size[: 1 if isinstance(size, float) else 3] == pytest.approx(want, rel=1e-12), name
    # the wheels' and castor's inertia as ODE's spheres (2/5 m r^2); the chassis box's about its axes
    assert m.body("left_wheel").inertia == pytest.approx([0.4 * 117.519 * BODY.wheel_radius**2] * 3, rel=1e-9)
    assert m.body("chassis").inertia[1] == pytest.approx(ode["chassis"]["inertia"][0], rel=1e-9)  # authors' x = our y
    assert m.opt.gravity == pytest.approx([0, 0, -1.0]) and m.opt.timestep == 0.05
    # the first step's sensor readings: 3D, sphere centres to the light's centre (ODE's facts)
    light = np.array([4.0, 4.0, robot.LIGHT_Z])  # project (4, 4) is the authors' (-4, 4)
    s = [1.0 / np.sum((d.body(f"sensor{i}").xpos - light) ** 2) for i in (1, 2)]
    assert s == pytest.approx([f["step0"]["s1"], f["step0"]["s2"]], rel=1e-12)
    assert robot.success_radius(BODY) == core.params_tuple(BODY)[-1]


def test_light_need_not_be_a_body() -> None:
    # every part of the robot that collides with the light reaches less far than the success radius
    assert robot.reach(BODY) + BODY.light_radius < robot.success_radius(BODY)


def test_canonical_design_agrees_with_ode() -> None:
    # the 11 x 11 diagonal and w = (1, 1) in all four environments. Measured on the whole 11 x 11
    # grid (484 episodes, this commit): 482 cells as ODE for the canonical design, 483 for the
    # paper's best; here 44 episodes each, at most 2 may differ.
    ws = np.linspace(-1, 1, 11)
    w = np.repeat(np.stack([ws, ws], 1), 4, 0)
    env = np.tile(np.arange(4), 11)
    for design in (CANONICAL, PAPER_BEST):
        mj = AuthorsBatchRunner(BODY).run(*design, w, env)
        od, _ = core.run(BODY, *design, w, env)
        same = int(((~np.isnan(mj.first_time)) == od.success).sum())
        assert same >= 42, (design, same)
    # the canonical design's only generalist (the paper's w = (1, 1)) succeeds in every environment
    mj = AuthorsBatchRunner(BODY).run(*CANONICAL, np.ones((4, 2)), np.arange(4))
    assert (~np.isnan(mj.first_time)).all()
    assert (mj.min_dist <= robot.success_radius(BODY)).all()


def test_episodes_do_not_depend_on_their_batch() -> None:
    w = np.array([[1.0, 1.0], [0.6, 0.6], [-0.2, 0.4], [1.0, 0.8]])
    env = np.array([0, 3, 1, 2])
    short = BODY.replace(steps=300)
    a = AuthorsBatchRunner(short).run(*CANONICAL, w, env)
    b = AuthorsBatchRunner(short).run(*CANONICAL, w[::-1], env[::-1])
    for f in ("first_time", "min_dist", "steps", "finite"):
        np.testing.assert_array_equal(getattr(a, f), getattr(b, f)[::-1])
    lights = light_positions(short.light_distance)
    assert np.all(a.min_dist <= np.hypot(*lights[env].T))  # never farther than the start


def test_bad_input_and_levers() -> None:
    r = AuthorsBatchRunner(BODY)
    with pytest.raises(ValueError, match="weights must be"):
        r.run(*CANONICAL, np.zeros((2, 3)), [0, 1])
    with pytest.raises(ValueError, match=r"env in 0\.\.3"):
        r.run(*CANONICAL, np.zeros((1, 2)), [4])
    with pytest.raises(ValueError, match="early_stop"):
        evaluate_design(*CANONICAL, np.linspace(-1, 1, 3), BODY, options=SweepOptions(early_stop=True))


def _settings(section: dict) -> object:
    from morphlearn import config, configure

    cfg = config.read("config.yaml")  # config.yaml with a one-design MuJoCo section
    cfg.update(results_dir="results/x", figures={"enabled": False}, empirical={"enabled": False})
    cfg["theory"] = {**cfg["theory"], "enabled": False}
    sec = {"enabled": True, "weights": 3, "designs": [[[0.5, 0.5], [0.5, -0.5]]], "early_stop": False}
    cfg["mujoco"] = {**sec, **section}
    return configure.parse(cfg)


def test_robot_key() -> None:
    from morphlearn import models

    mj = models.get("mujoco")
    s = _settings({"robot": "authors"})
    e = mj.settings(s)
    assert e.robot == "authors" and e.morphology == "config/authors_body.yaml" and e.params == BODY
    assert e.science["robot"] == "authors"
    assert mj.thresholds(s).radius == robot.success_radius(BODY)
    # the project's robot keeps the science record it had (no robot key): its digests hold
    p = mj.settings(_settings({}))
    assert p.robot == "project" and "robot" not in p.science and p.morphology == "config/empirical_morphology.yaml"
    with pytest.raises(ConfigError, match=r"mujoco.robot = 'ours' is invalid"):
        _settings({"robot": "ours"})
    with pytest.raises(ConfigError, match="builds the project's robot only"):
        _settings({"robot": "authors", "backend": "warp"})


def test_evaluate_design_runs_the_sweep() -> None:
    short = BODY.replace(steps=200)
    r = evaluate_design(*CANONICAL, np.linspace(-1, 1, 3), short)
    assert r.first_time.shape == (4, 3, 3) and np.isnan(r.first_time).all()  # 10 s: too short to arrive
    assert np.isfinite(r.min_dist).all()


def test_design_command_takes_the_robot(capsys: pytest.CaptureFixture) -> None:
    import json

    from morphlearn.apps import cli

    args = ["design", "--l1", "0.5", "0.5", "--l2", "0.5", "-0.5", "--weights", "2", "--json"]
    assert cli.main([*args, "--model", "mujoco", "--robot", "authors"]) in (0, None)
    out = json.loads(capsys.readouterr().out)
    assert out["model"] == "mujoco" and out["robot"] == "authors"
    assert cli.main([*args, "--model", "ode", "--robot", "project"]) == 2
    err = capsys.readouterr().err
    assert "--robot project: the ode model builds authors" in err and len(err.splitlines()) == 1
    assert cli.main([*args, "--model", "theory", "--robot", "authors"]) == 2
    err = capsys.readouterr().err
    assert "--robot: option of the empirical, mujoco, ode and reduced models; the theory model takes" in err
