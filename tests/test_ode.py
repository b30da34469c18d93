"""The ODE model (morphlearn.ode): the authors' robot read back from the engine, the reference
values of the authors' facts (docs/ode.md), determinism and bad input."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
from conftest import CANONICAL_O_11

from morphlearn.grid import weights
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import load_params

core = pytest.importorskip("morphlearn.ode.core")
if not core.available():  # CI and tools/setup.sh install libode-dev; elsewhere say why it skips
    pytest.skip("morphlearn.ode._core not built (no libode-dev)", allow_module_level=True)

from morphlearn.ode.episode import evaluate_design  # noqa: E402

BODY = load_params("config/authors_body.yaml")
WR = 0.260017
CANONICAL = ((0.5, 0.5), (0.5, -0.5))


def test_body_file_holds_the_authors_constants() -> None:
    assert BODY.gravity == 1.0 and BODY.dt == 0.05 and BODY.steps == 2500
    assert BODY.wheel_radius == WR and BODY.body_mass == 999.973 and BODY.wheel_mass == 117.519
    assert BODY.castor_mass == 0.00666004
    assert BODY.max_speed == 0.5 * (2.59115 * math.pi) * (2.59255 * math.pi)  # 0.5 * SPEED * LO_HI
    assert BODY.max_torque == 1.95026 * math.pi
    assert core.success_radius(BODY) == 0.5 + WR + 0.2 + 2.0**-10


def test_built_against_debians_ode_in_double_precision() -> None:
    assert core.core().version() == "0.16.2"  # the pinned libode-dev (tools/setup.sh)
    assert "ODE_double_precision" in core.core().config()


def test_world_read_back_from_the_engine_is_the_authors() -> None:
    f = core.core().facts(core.params_tuple(BODY), (0.5, 0.5, 0.5, -0.5), (4.0, 4.0), 1.0, -0.5)
    assert f["gravity"] == (0.0, 0.0, -1.0) and f["space"] == "hash"
    assert f["erp"] == 0.2  # ODE's defaults, never set
    b = {x["name"]: x for x in f["bodies"]}
    # creation order fixes the constraint rows' order
    assert [x["name"] for x in f["bodies"]] == [
        "light", "chassis", "left_wheel", "right_wheel", "sensor1", "sensor2", "castor"
    ]  # fmt: skip
    assert b["chassis"]["shape"] == "box" and b["chassis"]["size"] == (1.0, 1.0, WR / 2)
    assert b["chassis"]["mass"] == 999.973 and b["chassis"]["position"] == (0.0, 0.0, WR)
    # box inertia of dMassSetBoxTotal: m (ly^2 + lz^2) / 12 about x
    assert b["chassis"]["inertia"][0] == pytest.approx(999.973 * (1 + (WR / 2) ** 2) / 12, rel=1e-12)
    for side, x in (("left_wheel", -0.5), ("right_wheel", 0.5)):
        assert b[side]["shape"] == "sphere" and b[side]["size"] == WR and b[side]["mass"] == 117.519
        assert b[side]["position"] == (x, -0.025, WR)
        assert b[side]["inertia"][0] == pytest.approx(0.4 * 117.519 * WR**2, rel=1e-12)
    assert b["castor"]["size"] == WR and b["castor"]["mass"] == 0.00666004 and b["castor"]["position"] == (0, 0.5, WR)
    # sensors: project (x, y) -> authors' (-y, x), 0.05 spheres of 1 kg at 2 WR + 0.05
    assert b["sensor1"]["position"] == (-0.5, 0.5, 2 * WR + 0.05) and b["sensor1"]["size"] == 0.05
    assert b["sensor2"]["position"] == (0.5, 0.5, 2 * WR + 0.05) and b["sensor2"]["mass"] == 1.0
    # the light: project (4, 4) (45 degrees) -> authors' (-4, 4), a 0.2 sphere of 1 kg at z 0.201
    assert b["light"]["position"] == (-4.0, 4.0, 0.201) and b["light"]["size"] == 0.2 and b["light"]["mass"] == 1.0
    assert [b[n]["group"] for n in ("light", "chassis", "left_wheel", "castor", "sensor1")] == [
        "env", "robot", "robot", "robot", "none"
    ]  # fmt: skip
    j = f["joints"]
    assert [x["bodies"] for x in j] == [
        ("light", None), ("left_wheel", "chassis"), ("right_wheel", "chassis"),
        ("chassis", "sensor1"), ("chassis", "sensor2"), ("castor", "chassis"),
    ]  # fmt: skip
    assert all(x["type"] == "hinge" for x in j)
    for fixed in (j[0], j[3], j[4]):  # the simulator's "fixed" joints
        assert fixed["anchor"] == (0, 0, 0) and fixed["axis"] == (0, 0, 1)
        assert fixed["lo_stop"] == 0 and fixed["hi_stop"] == 0
    assert j[1]["axis"] == (-1, 0, 0) and j[1]["anchor"] == (-0.5, -0.025, WR) and j[1]["lo_stop"] == -math.inf
    assert j[5]["axis"] == (1, 0, 0) and j[5]["fmax"] == 0.0  # the castor rolls freely
    # collision pairs: anything with the ground, robot-env; never sensors with the robot or each other
    pairs = set(f["collides"])
    ground = {("ground", n) for n in b}
    assert pairs == ground | {("light", n) for n in ("chassis", "left_wheel", "right_wheel", "castor")}
    # motor law: velocity 0.5 SPEED LO_HI tanh(w s), force limit TORQUE; sensor 1 -> right wheel
    s = f["step0"]
    d1 = np.subtract((-0.5, 0.5, 2 * WR + 0.05), (-4.0, 4.0, 0.201))
    assert s["s1"] == pytest.approx(1 / (d1 @ d1), rel=1e-14)
    assert s["vel_right"] == BODY.max_speed * math.tanh(1.0 * s["s1"])
    assert s["vel_left"] == BODY.max_speed * math.tanh(-0.5 * s["s2"])
    assert s["fmax_right"] == s["fmax_left"] == BODY.max_torque


def test_canonical_w11_distances_are_the_reference() -> None:
    # the authors' environments 1-4 are the lights at (4,4), (-4,4), (-4,-4), (4,-4) in their frame:
    # ours 315, 45, 135, 225 degrees; reference d_min 0.94728, 0.94728, 0.76128, 0.76128
    ep, _ = core.run(BODY, *CANONICAL, np.ones((4, 2)), np.arange(4), stop_at_success=False)
    assert np.round(ep.min_dist, 5).tolist() == [0.94728, 0.76128, 0.76128, 0.94728]
    assert ep.success.all() and (ep.steps == 2500).all()
    stopped, _ = core.run(BODY, *CANONICAL, np.ones((4, 2)), np.arange(4))
    # stopping at success changes no outcome: the same first step
    assert (stopped.first_step == ep.first_step).all() and (stopped.steps == ep.first_step).all()


@pytest.mark.slow
def test_canonical_11x11_landscape_is_the_reference() -> None:
    r = evaluate_design(*CANONICAL, weights(11), BODY)
    o = (~np.isnan(r.first_time)).sum(axis=0)
    ref = np.array([[int(v) for v in row.split(",")] for row in CANONICAL_O_11.split()])
    assert o.tolist() == ref.tolist()
    assert int((o == 4).sum()) == 1 and o[10, 10] == 4  # the only generalist: w = (1, 1)


def test_episodes_do_not_depend_on_their_batch_order_or_a_rerun() -> None:
    rng = np.random.default_rng(7)
    n = 6
    w = rng.uniform(-1, 1, (n, 2))
    w[0] = (1.0, 1.0)
    env = rng.integers(0, 4, n)
    l1 = rng.choice([-0.5, -0.25, 0.0, 0.25, 0.5], (n, 2))
    l2 = rng.choice([-0.5, 0.0, 0.5], (n, 2))
    batch, _ = core.run(BODY, l1, l2, w, env)
    rerun, _ = core.run(BODY, l1, l2, w, env)
    rev, _ = core.run(BODY, l1[::-1], l2[::-1], w[::-1], env[::-1])
    for f in ("first_step", "min_dist", "steps", "finite"):
        a = getattr(batch, f)
        assert np.array_equal(a, getattr(rerun, f))
        assert np.array_equal(a, getattr(rev, f)[::-1])
        for i in (0, n - 1):  # alone
            one, _ = core.run(BODY, l1[i], l2[i], w[i : i + 1], env[i : i + 1])
            assert np.array_equal(a[i : i + 1], getattr(one, f))


def test_path_records_the_steps_read() -> None:
    ep, path = core.run(BODY, *CANONICAL, [[1.0, 1.0]], [0], path=True)
    k = int(ep.steps[0])
    assert np.isfinite(path[0, : k + 1]).all() and np.isnan(path[0, k + 1 :]).all()
    assert path[0, 0].tolist() == [0.0, 0.0]  # starts at the origin
    light = np.array([4.0, 4.0])
    assert np.linalg.norm(path[0, k] - light) == pytest.approx(ep.min_dist[0], rel=1e-12)


@pytest.mark.parametrize(
    ("kw", "message"),
    [
        ({"w": [[1.5, 0.0]]}, "weight 1.5 is invalid; allowed: finite values in [-1, 1]"),
        ({"w": [[np.nan, 0.0]]}, "weight nan is invalid"),
        ({"l1": (0.6, 0.0)}, "l1 = [0.6, 0.0] is off the body; allowed: finite x, y in [-0.5, 0.5]"),
        ({"l2": (0.0, np.inf)}, "l2 = [0.0, inf] is off the body"),
        ({"env": [4]}, "env [4] invalid; allowed: 0..3"),
    ],
)
def test_bad_input_is_refused_in_one_line(kw: dict, message: str) -> None:
    args = {"l1": (0.5, 0.5), "l2": (0.5, -0.5), "w": [[1.0, 1.0]], "env": [0], **kw}
    with pytest.raises(ValueError) as e:
        core.run(BODY, args["l1"], args["l2"], args["w"], args["env"])
    assert message in str(e.value) and "\n" not in str(e.value)


def test_reach_bound_is_refused() -> None:
    with pytest.raises(ValueError, match=r"early_stop .* not available in the ode model"):
        evaluate_design(*CANONICAL, weights(2), BODY, options=SweepOptions(early_stop=True))


def test_config_refuses_early_stop_and_names_the_key() -> None:
    from morphlearn import config, configure

    base = config.load("config.yaml", ["config/smoke.yaml"])
    with pytest.raises(config.ConfigError, match=r"ode\.early_stop") as e:
        config.validate({**base, "ode": {"enabled": True, "early_stop": True}})
    assert "\n" not in str(e.value)
    # no morphology named: the robot's own body file (the authors')
    assert config.validate({**base, "ode": {"enabled": True}})["ode"]["morphology"] is None
    s = configure.parse({**base, "ode": {"enabled": True, "designs": [[[0.5, 0.5], [0.5, -0.5]]]}})
    assert s.models["ode"].morphology == "config/authors_body.yaml" and s.models["ode"].robot == "authors"
    with pytest.raises(config.ConfigError, match=r"ode\.robot"):
        config.validate({**base, "ode": {"enabled": True, "robot": "project"}})
    with pytest.raises(config.ConfigError, match=r"ode\.morphology = 'a\{b\}' holds"):
        configure.parse({**base, "ode": {"morphology": "a{b}"}})  # the model declares its path keys


def test_missing_library_is_one_line(monkeypatch) -> None:
    """Without the extension (no libode-dev at set-up), choosing the model says what to install."""
    code = (
        "import sys; sys.modules['morphlearn.ode._core'] = None\n"
        "from morphlearn.ode import core\n"
        "try:\n    core.core()\nexcept core.OdeUnavailableError as e:\n    print(e)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.startswith("the ode model needs the Open Dynamics Engine: install Debian's libode-dev")
    assert out.count("\n") == 1


def test_design_cli_runs_the_ode_model() -> None:
    out = subprocess.run(
        [sys.executable, "-m", "morphlearn.apps.cli", "design", "--model", "ode", "--l1", "0.5", "0.5", "--l2", "0.5",
         "-0.5", "--weights", "2"],
        capture_output=True, text=True,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert "model ode" in out.stdout


@pytest.mark.parametrize("adaptive", [False, True])
def test_a_killed_design_resumes_inside_itself_to_the_same_bytes(tmp_path, monkeypatch, adaptive: bool) -> None:
    from morphlearn.ode import episode
    from morphlearn.physics import partial as partial_cells

    monkeypatch.setattr(episode, "CHUNK", 16)
    monkeypatch.setattr(partial_cells, "CHECKPOINT_S", 0.0)
    opts = SweepOptions(adaptive_weights=adaptive)
    w = weights(5)
    whole = evaluate_design(*CANONICAL, w, BODY, options=opts)
    path = tmp_path / "design.partial.npz"

    def kill(done: int, total: int) -> None:
        if done >= 32:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        evaluate_design(*CANONICAL, w, BODY, progress=kill, options=opts, partial=path)
    assert path.is_file()
    ran = []
    real = episode.run
    monkeypatch.setattr(episode, "run", lambda *a, **k: ran.append(len(a[3])) or real(*a, **k))
    resumed = evaluate_design(*CANONICAL, w, BODY, options=opts, partial=path)
    simulated = int((whole.status != 4).sum())
    assert sum(ran) == simulated - 32  # the 32 episodes done before the kill are not run again
    for f in ("first_time", "min_dist", "status"):
        assert np.array_equal(getattr(resumed, f), getattr(whole, f), equal_nan=f != "status")


def test_adaptive_stride_reaches_the_science_record() -> None:
    """adaptive_stride (the coarse lattice's spacing) is a config key; stride 2, the default, is
    recorded as before, so the results made before the key existed keep their digests."""
    from morphlearn import config, configure, models

    base = config.load("config.yaml", ["config/smoke.yaml"])
    on = {"enabled": True, "weights": 9, "designs": [[[0.5, 0.5], [0.5, -0.5]]], "adaptive_weights": True}
    sci = [
        models.get("ode").science(configure.parse({**base, "ode": {**on, **extra}}))["adaptive_weights"]
        for extra in ({}, {"adaptive_stride": 4})
    ]
    assert sci == [{"stride": 2, "near": 4.0}, {"stride": 4, "near": 4.0}]
    with pytest.raises(config.ConfigError, match=r"ode\.adaptive_stride = 1 is invalid"):
        configure.parse({**base, "ode": {**on, "adaptive_stride": 1}})


@pytest.mark.parametrize("adaptive", [False, True])
def test_shard_log_has_a_progress_line_per_design(tmp_path, capsys: pytest.CaptureFixture[str], adaptive: bool) -> None:
    """Issue 59: an ODE shard's log (its stdout) says when each design starts and how far it is,
    'design k/n (index d): e/E episodes', never silent for a whole design; with the adaptive grid
    the count is an upper bound and no time left is guessed."""
    from pathlib import Path

    from morphlearn import config as cfgmod
    from morphlearn import configure
    from morphlearn.workflow import rules

    root = Path(__file__).resolve().parents[1]
    cfg = cfgmod.load(root / "config.yaml", [root / "config/smoke.yaml"])
    over = {
        "results_dir": str(tmp_path),
        "grid": {"positions_per_axis": 5},
        "empirical": {"enabled": False, "results_from": None},
        "ode": {
            "enabled": True,
            "weights": 3,
            "designs": [[[0.5, 0.5], [0.5, -0.5]], [[-0.5, 0.0], [0.5, -0.5]]],
            "include_mirrors": False,
            "adaptive_weights": adaptive,
        },
    }
    s = configure.parse(cfgmod.validate(cfgmod.deep_merge(cfg, over)))
    rules.run_shard(s, "ode", 0, tmp_path / "shard_0.nc")
    out = capsys.readouterr().out
    assert "design 1/2 (index 70): started" in out and "design 2/2 (index 620): started" in out
    end = "done in" if adaptive else "36/36 episodes"
    assert f"design 1/2 (index 70): {end}" in out and f"design 2/2 (index 620): {end}" in out, out
