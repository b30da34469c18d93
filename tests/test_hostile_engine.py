"""Hostile input that reached the engines, hung or ended in a traceback (issue 57, D1-D3, D11-D14,
D16): each attack of the issue with its command, refused in one line before anything runs or
handled, never an abort of the interpreter, a hang or a traceback.

The classes and their one root each: every physical parameter has one range (the ``params``
properties of ``config_schema.yaml``, read by :mod:`morphlearn.physics.params` for body files and
by the schema for the config); ODE's messages and errors go through one handler in the C core
(``ode/_core.c``: a message is counted and said once, an error is a one-line failure, never an
abort); the C core guards its own size arithmetic; every manifest or URL value a verb reads is
checked for its shape (file, key, what is allowed). The attacks that aborted or hung the process
on e3d6953 run in a subprocess, so that a regression fails the test rather than the test run. A
wider pass over the same classes (816 instances, about 3 minutes): benchmarks/hostile_engine_pass.py.
"""

from __future__ import annotations

import html
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import ROOT, TEST_COMMIT, copy_workflow

from morphlearn import config, configure
from morphlearn.apps import cli, explore
from morphlearn.bundles import render as bundle_rerender
from morphlearn.ode import core as odecore
from morphlearn.physics import params as paramsmod

AUTHORS = ROOT / "config/authors_body.yaml"
DESIGN = ["design", "--model", "ode", "--l1", "0.5", "0.5", "--l2", "0.5", "-0.5", "--weights", "2"]
needs_ode = pytest.mark.skipif(not odecore.available(), reason="the ODE core is not built (libode-dev)")


@pytest.fixture(autouse=True)
def _at_root(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)


def _body(tmp_path: Path, key: str, value: str) -> Path:
    """``B`` of the issue: the authors' body file with one line changed (floats with a dot)."""
    lines = [f"{key}: {value}" if line.startswith(f"{key}:") else line for line in AUTHORS.read_text().splitlines()]
    out = tmp_path / f"body_{key}.yaml"
    out.write_text("\n".join(lines) + "\n")
    return out


def _ml(*argv: str, timeout: float = 120) -> subprocess.CompletedProcess:
    """``morphlearn ARGV`` in its own process (an abort or a hang must not take the test run)."""
    code = "import sys; from morphlearn.apps.cli import main; sys.exit(main(sys.argv[1:]))"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    return subprocess.run(
        [sys.executable, "-c", code, *argv], cwd=ROOT, capture_output=True, text=True, timeout=timeout, env=env
    )


def _py(code: str, timeout: float = 120) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    return subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=timeout, env=env
    )


def _one_line(proc: subprocess.CompletedProcess, rc: int = 2) -> str:
    assert proc.returncode == rc, (proc.returncode, proc.stdout[-500:], proc.stderr[-1500:])
    assert "Traceback" not in proc.stderr, proc.stderr[-1500:]
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr[-1500:]
    return lines[0]


def _cli(argv: list[str], capsys: pytest.CaptureFixture) -> tuple[int, str, str]:
    try:
        rc = cli.main(argv)
    except SystemExit as e:
        rc = int(e.code or 0)
    out, err = capsys.readouterr()
    return rc, out, err


def _refused(argv: list[str], capsys: pytest.CaptureFixture, *needles: str) -> str:
    rc, out, err = _cli(argv, capsys)
    assert rc == 2 and out == "", (argv, rc, out[-300:], err[-1500:])
    assert len(err.strip().splitlines()) == 1 and "error" in err, err
    for n in needles:
        assert n in err, (n, err)
    return err


# --- D1, D2, D3: body values the engine cannot integrate, refused before it runs ----------------

#: The issue's values (D1, D2, D3): each aborted ODE (exit 134), hung, or flooded stderr.
BEYOND = [
    ("light_distance", "1.0e+10"),
    ("body_mass", "1.0e+308"),
    ("body_mass", "1.0e-308"),
    ("wheel_mass", "1.0e+308"),
    ("castor_mass", "1.0e+300"),
    ("castor_mass", "1.0e-20"),
    ("castor_mass", "5.0e-324"),
    ("gravity", "1.0e+20"),
    ("dt", "1.0e+308"),
    ("light_distance", "1.0e+20"),
    ("light_radius", "1.0e-10"),
    ("wheel_radius", "1.0e-300"),
    ("gravity", "0"),
    ("steps", "1000000000"),
    ("steps", "18446744073709551616"),
]


@needs_ode
@pytest.mark.parametrize(("key", "value"), BEYOND)
def test_design_refuses_body_values_the_engine_cannot_integrate(key: str, value: str, tmp_path: Path) -> None:
    # e3d6953: exit 134 (ODE INTERNAL ERROR), a hang (steps 1e9), a 31-line OverflowError, or
    # 80,000 lines of "LCP internal error" and exit 0 (gravity 0)
    t0 = time.monotonic()
    line = _one_line(_ml(*DESIGN, "--morphology", str(_body(tmp_path, key, value)), timeout=60))
    assert f"{key} = " in line and "out of range; allowed: " in line and len(line) < 300, line
    assert time.monotonic() - t0 < 30


@pytest.mark.parametrize(("key", "value"), BEYOND)
def test_config_refuses_the_same_values_at_load(key: str, value: str) -> None:
    """The same range for ``ode.params`` (and every physics section): the schema's, at config load
    (e3d6953: validation passed and the shard died with SIGABRT)."""
    base = config.read(ROOT / "config.yaml")
    v = yaml.safe_load(value)
    for model in ("ode", "empirical", "mujoco"):
        with pytest.raises(config.ConfigError) as e:
            config.validate(config.deep_merge(base, {model: {"params": {key: v}}}))
        msg = str(e.value)
        assert f"{model}.params.{key} = " in msg and "allowed: " in msg and "\n" not in msg and len(msg) < 400, msg


def test_one_range_per_parameter_from_the_schema() -> None:
    """The body file's check and the config's are the same ranges: the schema's ``params``."""
    props = config.schema()["properties"]["empirical"]["properties"]["params"]["properties"]
    fields = set(paramsmod.EmpiricalParams.__dataclass_fields__)
    assert set(props) == fields == set(paramsmod._RANGES)
    for name, s in props.items():
        assert "maximum" in s and s.get("description"), name  # bounded above, and said why
        _, _, hi, integer = paramsmod._RANGES[name]
        assert hi == s["maximum"] and integer == (s["type"] == "integer")
    for model in ("mujoco", "ode"):  # one range: the physics sections share it
        assert config.schema()["properties"][model]["properties"]["params"]["properties"] == props
    # every committed body is inside it
    for body in (
        "config/authors_body.yaml",
        "config/empirical_morphology.yaml",
        "config/empirical_morphology_body2.yaml",
    ):
        paramsmod.load_params(ROOT / body)


@needs_ode
def test_every_corner_of_the_box_of_ranges_runs_in_ode_cleanly() -> None:
    """The ranges' derivation, checked: at every corner of the box the schema allows (the least
    light distance the contact distance allows, times 1.5), ODE integrates two episodes without an
    error, a message or a non-finite state. (Just outside it, 0.1 g wheels of 1 cm failed ODE's own
    checks at 24 of 2048 corners, and a wheel axle 0.4 in front of the centre made ODE say "LCP
    internal error" at 23 of 2048.)"""
    import itertools

    r = paramsmod._RANGES
    ends = ("body_mass", "wheel_mass", "castor_mass", "wheel_radius", "wheel_setback", "max_speed", "max_torque")
    box: dict[str, tuple[float | None, float | None]] = {
        k: (r[k][0], r[k][2]) for k in (*ends, "light_radius", "gravity", "dt")
    }
    box["light_distance"] = (None, r["light_distance"][2])
    w = np.array([[1.0, -1.0], [0.3, 0.3]])
    odecore.MESSAGES.clear()
    bad = []
    for corner in itertools.product(*box.values()):
        v = dict(zip(box, corner, strict=True))
        if v["light_distance"] is None:
            v["light_distance"] = 1.5 * (0.5 + v["wheel_radius"] + v["light_radius"])
        p = paramsmod.load_params(AUTHORS).replace(**v, steps=100)  # validated: inside the ranges
        try:
            ep, _ = odecore.run(p, (0.5, 0.5), (0.5, -0.5), w, [0, 1], stop_at_success=False)
        except odecore.OdeEngineError as e:
            bad.append((v, str(e)))
            continue
        if not ep.finite.all():
            bad.append((v, "not finite"))
    assert not bad and not odecore.MESSAGES, (len(bad), bad[:3], odecore.MESSAGES)


def test_steps_bound_is_a_cost_a_user_can_wait_for(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    hi = paramsmod._RANGES["steps"][2]
    assert hi == 100_000
    paramsmod.EmpiricalParams(steps=int(hi))
    with pytest.raises(ValueError, match=r"steps = 100001 is out of range; allowed: integer >= 1 and <= 100000"):
        paramsmod.EmpiricalParams(steps=int(hi) + 1)
    # a 5,000-digit integer is named by its size, not printed (nor refused by Python's own limit)
    with pytest.raises(ValueError, match=r"steps = an integer of \d+ bits is out of range") as e:
        paramsmod.EmpiricalParams(steps=10**5000)
    assert len(str(e.value)) < 200


@pytest.fixture(scope="module")
def wf(tmp_path_factory: pytest.TempPathFactory) -> Path:
    wd = copy_workflow(tmp_path_factory.mktemp("hostile_engine") / "wf")
    return wd


@needs_ode
@pytest.mark.parametrize(("key", "value"), [("light_distance", 1.0e10), ("steps", 1_000_000_000), ("steps", 2**64)])
def test_workflow_dry_run_refuses_what_the_engine_cannot_run(wf: Path, key: str, value: int | float) -> None:
    """The issue's workflow attacks: ``ode.params`` that aborted a shard or hung it, refused by
    ``snakemake -n`` at start in one line, nothing written."""
    cfg = {
        "grid": {"positions_per_axis": 3, "weights": 5},
        "empirical": {"enabled": False},
        "figures": {"enabled": False},
        "ode": {"enabled": True, "results_from": None, "designs": [[[0.5, 0.5], [0.5, -0.5]]], "params": {key: value}},
    }
    (wf / "bad.yaml").write_text(yaml.safe_dump(cfg))
    exe = Path(sys.executable).with_name("snakemake")
    proc = subprocess.run(
        [str(exe), "-n", "--cores", "1", "--configfile", "bad.yaml", "--config", "results_dir=results/hostile"],
        cwd=wf,
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "MORPHLEARN_GIT_COMMIT": TEST_COMMIT},
    )
    assert proc.returncode != 0, proc.stdout[-2000:]
    assert f"ode.params.{key} = " in proc.stderr and "allowed" in proc.stderr, proc.stderr[-2000:]
    assert "Traceback" not in proc.stderr
    assert not (wf / "results/hostile").exists()


# --- the C core: its own size arithmetic, ODE's errors and messages through one handler ----------


@needs_ode
def test_run_batch_guards_its_size_arithmetic() -> None:
    # e3d6953: 2 * n * steps overflowed and the process aborted (not reachable through core.run)
    code = """
import numpy as np
from morphlearn.ode import core
from morphlearn.physics.params import load_params
p = list(core.params_tuple(load_params("config/authors_body.yaml")))
p[10] = 2**62
n = 2
z = lambda k, t: np.zeros(k, t)
try:
    core.core().run_batch(tuple(p), n, z(8, float), z(4, float), z(4, float), z(n, np.int64), z(n, float),
                          z(n, np.int64), z(n, np.uint8), True, z(1, float))
except ValueError as e:
    print("refused:", e)
p[10] = 10
p[0] = float("nan")
try:
    core.core().run_batch(tuple(p), n, z(8, float), z(4, float), z(4, float), z(n, np.int64), z(n, float),
                          z(n, np.int64), z(n, np.uint8), True, None)
except ValueError as e:
    print("refused:", e)
"""
    proc = _py(code)
    assert proc.returncode == 0, (proc.returncode, proc.stderr[-1500:])
    out = proc.stdout.splitlines()
    assert out[0].startswith("refused:") and "overflow" in out[0], out
    assert out[1] == "refused: params: every body value must be finite", out


def _unchecked(**changes: float) -> paramsmod.EmpiricalParams:
    """The authors' body with values the validator refuses (to reach the engine's own handler)."""
    p = object.__new__(paramsmod.EmpiricalParams)
    for k, v in {**paramsmod.load_params(AUTHORS).to_dict(), **changes}.items():
        object.__setattr__(p, k, v)
    return p


@needs_ode
def test_an_ode_error_is_a_one_line_failure_and_the_process_goes_on() -> None:
    """Past the validator (a caller of core.run), ODE's own checks end the batch with one
    OdeEngineError naming ODE's message; the process goes on and the next batch is exact."""
    code = """
import numpy as np
from morphlearn.ode import core
from morphlearn.physics.params import load_params
from morphlearn.physics.params import EmpiricalParams
def _unchecked(**changes):
    p = object.__new__(EmpiricalParams)
    for k, v in {**load_params("config/authors_body.yaml").to_dict(), **changes}.items():
        object.__setattr__(p, k, v)
    return p
good = load_params("config/authors_body.yaml").replace(steps=300)
w = np.array([[1.0, -0.5], [0.3, 0.3]])
before, _ = core.run(good, (0.5, 0.5), (0.5, -0.5), w, [0, 1])
for bad in (dict(light_distance=1e10), dict(body_mass=5e-324), dict(wheel_radius=1e-300), dict(dt=1e308)):
    try:
        core.run(_unchecked(**bad, steps=300), (0.5, 0.5), (0.5, -0.5), w, [0, 1])
        print("ran", bad)
    except core.OdeEngineError as e:
        print("error:", e)
after, _ = core.run(good, (0.5, 0.5), (0.5, -0.5), w, [0, 1])
keys = ("first_step", "min_dist", "steps")
print("same" if all(np.array_equal(getattr(before, k), getattr(after, k)) for k in keys) else "differs")
"""
    proc = _py(code)
    assert proc.returncode == 0, (proc.returncode, proc.stderr[-1500:])  # e3d6953: 134 (abort)
    out = proc.stdout.splitlines()
    assert out[-1] == "same", out
    errors = [line for line in out if line.startswith("error:")]
    assert len(errors) >= 3, out
    assert all("ODE" in e and "\n" not in e and len(e) < 400 for e in errors), errors


@needs_ode
def test_an_ode_message_is_counted_and_said_once(capfd: pytest.CaptureFixture) -> None:
    """gravity 0 (past the validator) makes ODE say "LCP internal error" every step: one line on
    stderr for the process, the rest counted (e3d6953: 80,000 lines)."""
    odecore.MESSAGES.clear()
    w = np.array([[1.0, -1.0], [0.5, 0.5]])
    for _ in range(2):
        odecore.run(_unchecked(gravity=0.0, steps=200), (0.5, 0.5), (0.5, -0.5), w, [0, 1])
    _, err = capfd.readouterr()
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("morphlearn: ODE message 3: LCP internal error"), lines
    assert odecore.MESSAGES[3] > 100


def test_cli_says_an_engine_error_in_one_line(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture) -> None:
    from morphlearn.physics import model

    def boom(*_a: object, **_k: object) -> None:
        raise odecore.OdeEngineError("the ODE engine failed on these body values: ODE internal error 1: x")

    monkeypatch.setattr(model.Physics, "evaluate_one", boom)
    rc, out, err = _cli([*DESIGN[:1], "--model", "empirical", *DESIGN[3:]], capsys)
    assert rc == 1 and out == "" and len(err.strip().splitlines()) == 1, err
    assert err.startswith("morphlearn design: engine error: the ODE engine failed") and "Traceback" not in err


# --- D16: the ode model with the project's body; files too large to list ------------------------


@needs_ode
def test_design_ode_refuses_the_project_body_as_the_config_does(capsys: pytest.CaptureFixture) -> None:
    # e3d6953: it ran (the authors' robot with the project's masses, motor and gravity)
    for path in (
        "config/empirical_morphology.yaml",
        "./config/empirical_morphology.yaml",
        str(ROOT / "config/empirical_morphology.yaml"),
    ):
        _refused([*DESIGN, "--morphology", path], capsys, "is the project robot's body file", "allowed")
    with pytest.raises(config.ConfigError, match="is the project robot's body file"):
        base = config.read(ROOT / "config.yaml")
        over = {"ode": {"enabled": True, "results_from": None, "morphology": "config/empirical_morphology.yaml"}}
        configure.parse(config.deep_merge(base, over))


def test_a_hundred_thousand_unknown_keys_are_a_short_error_at_once(
    tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    f = tmp_path / "keys.yaml"
    f.write_text("".join(f"k{i}: {i}\n" for i in range(100_000)))
    t0 = time.monotonic()
    with pytest.raises(config.ConfigError) as e:
        config.load(f)
    msg = str(e.value)
    assert "unknown keys ['k0', 'k1', 'k10', 'k100', 'k1000'] and 99995 more" in msg and len(msg) < 1000, msg[:300]
    # a body file of them: the first named, the rest counted
    err = _refused(
        [
            "design",
            "--l1",
            "0.5",
            "0.5",
            "--l2",
            "0.5",
            "-0.5",
            "--weights",
            "2",
            "--model",
            "empirical",
            "--morphology",
            str(f),
        ],
        capsys,
        "unknown empirical parameter",
        "more",
    )
    assert len(err) < 600
    assert time.monotonic() - t0 < 20  # e3d6953: 27 s and a 989 KB line


def test_a_plain_long_list_is_not_said_to_expand_through_aliases(tmp_path: Path) -> None:
    f = tmp_path / "list.yaml"
    f.write_text("x: [" + ",".join(["0"] * 4_000_000) + "]\n")
    with pytest.raises(ValueError) as e:
        config.yaml_mapping(f)
    assert "holds more than 1000000 values" in str(e.value) and "alias" not in str(e.value), e.value
    g = tmp_path / "bomb.yaml"  # an alias bomb is still called one
    g.write_text("a: &a [" + ",".join(["1"] * 1000) + "]\nb: &b [" + ",".join(["*a"] * 1000) + "]\nc: [*b, *b]\n")
    with pytest.raises(ValueError, match="expands through its aliases"):
        config.yaml_mapping(g)


# --- D11, D12: malformed manifests, one line -----------------------------------------------------

SHAPES = ["[]", '"str"', "123", "null", '{"files": "x"}', '{"files": [1, 2]}', '{"files": {"figures/a.png": 5}}']


@pytest.mark.parametrize("manifest", SHAPES)
def test_render_says_a_malformed_manifest_in_one_line(
    manifest: str, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    # e3d6953: AttributeError traceback; {"files": "x"} "holds no figures"
    b = tmp_path / "b"
    b.mkdir()
    (b / "bundle.json").write_text(manifest)
    err = _refused(["render", str(b)], capsys, f"{b / 'bundle.json'}: ", "allowed: a JSON object whose 'files' maps")
    assert "holds no figures" not in err


def test_render_says_a_deep_manifest_in_one_line(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    b = tmp_path / "b"
    b.mkdir()
    (b / "bundle.json").write_text("[" * 50_000 + "]" * 50_000)
    _refused(["render", str(b)], capsys, "nested deeper than")


@pytest.mark.parametrize(
    "manifest",
    [
        "[]",
        '"str"',
        "null",
        pytest.param("[" * 50_000 + "]" * 50_000, id="50000-deep"),
        '{"run_key": "x"}',
        '{"run_key": "x", "identity": []}',
        '{"run_key": 5, "identity": {}}',
        '{"run_key": "x", "identity": {"design": {"l1": [0.5, 0.5], "l2": [0.5, -0.5]}, "weights": 10000000, '
        '"params": {}}}',
        '{"run_key": "x", "identity": {"design": {"l1": [0.5, 0.5], "l2": [0.5, -0.5]}, "weights": 5, '
        '"params": {"steps": 1e30}}}',
    ],
)
def test_refine_status_says_a_malformed_manifest_in_one_line(
    manifest: str, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    # e3d6953: TypeError ([]) and RecursionError (50,000 deep) tracebacks
    (tmp_path / "manifest.json").write_text(manifest)
    _refused(["refine", "status", str(tmp_path)], capsys, f"{tmp_path / 'manifest.json'}: ", "allowed")


# --- D13: the explorer ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("query", "needle"),
    [
        pytest.param(
            "design=" + "9" * 5000, "URL design='99999999999999999999... (5000 characters)'", id="5000-digits"
        ),
        ("design=²", "URL design='²'"),
        ("w=nan,nan", "URL w='nan,nan': allowed: two finite numbers in [-1, 1]"),
        ("w=inf,-inf", "URL w='inf,-inf'"),
        ("w=1e308,1e308", "URL w='1e308,1e308'"),
        ("w=1.5,0", "URL w='1.5,0'"),
        pytest.param(
            "metric=" + "x" * 5000, "URL metric='xxxxxxxxxxxxxxxxxxxx... (5000 characters)'", id="long-metric"
        ),
    ],
)
def test_explorer_url_values_are_checked(query: str, needle: str) -> None:
    with pytest.raises(explore.ExploreError) as e:
        explore.parse_view(query)
    assert needle in str(e.value) and len(str(e.value)) < 300, e.value
    assert explore.parse_view("design=720&w=-1,1").w == (-1.0, 1.0)


def test_explorer_app_falls_back_with_a_note_on_the_page() -> None:
    import matplotlib

    matplotlib.use("Agg")
    from morphlearn.apps import explore_app

    for query, needle in (("design=" + "7" * 5000, "URL design="), ("w=nan,nan", "URL w='nan,nan'")):
        app = explore_app.App(ROOT / "results", url_query=query)  # e3d6953: ValueError out of App
        assert needle in html.unescape(app.w_info.value) and app.design == app.ex.best("M_L")


def test_explore_starts_voila_with_its_idle_kernels_culled(monkeypatch: pytest.MonkeyPatch) -> None:
    seen: list[list[str]] = []
    monkeypatch.setattr(os, "execv", lambda exe, args: seen.append(args))
    cli.main(["explore"])
    args = seen[0]
    assert "--MappingKernelManager.cull_idle_timeout=60" in args and "--MappingKernelManager.cull_interval=15" in args
    assert "--no-browser" in args


# --- D14: a failed render says why and keeps its log; a killed render's copy is removed ----------


def test_a_failed_render_names_the_rule_and_its_error_and_keeps_the_log(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = tmp_path / ".rerender-b-1-abcdefgh"
    log = target / "logs/figures/fig3.log"
    log.parent.mkdir(parents=True)
    log.write_text("Traceback (most recent call last):\n  File x\nKeyError: 'M_CF'\n")
    stderr = (
        "x" * 3000 + f"\nError in rule fig3:\n    jobid: 4\n    log: {target.name}/logs/figures/fig3.ipynb, "
        f"{target.name}/logs/figures/fig3.log (check log file(s) for error details)\n    shell: ...\n\n"
        "Shutting down, this might take some time.\n"
        "Exiting because a job execution failed. Look above for error message\n"
    )
    monkeypatch.setattr(
        bundle_rerender.subprocess, "run", lambda *a, **k: subprocess.CompletedProcess(a, 1, "", stderr)
    )
    keep = tmp_path / ".render-failed-b.log"  # beside the bundle b, whose working copy failed
    with pytest.raises(bundle_rerender.bundle.BundleError) as e:
        bundle_rerender._render(["snakemake"], tmp_path, target.name)
    msg = str(e.value)
    # e3d6953: the last 1,500 characters of Snakemake's stderr, from mid-word, without the cause
    assert "in rule fig3: KeyError: 'M_CF'" in msg and f"the whole log: {keep}" in msg and "xxx" not in msg, msg
    kept = keep.read_text()
    assert "KeyError: 'M_CF'" in kept and "Error in rule fig3" in kept


def _tiny_bundle(results: Path, name: str = "b") -> Path:
    from morphlearn import provenance

    b = results / name
    b.mkdir(parents=True)
    (b / "a.txt").write_text("a\n")
    (b / "bundle.json").write_text(json.dumps({"files": {"a.txt": provenance.sha256_file(b / "a.txt")}}))
    return b


@pytest.mark.parametrize("name", ["../outside.txt", "/etc/hostname", "a\x00b"])
def test_a_rerender_reads_no_name_outside_the_bundle(
    name: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The render's working copy is made before the render's start check: a manifest that lists a
    name outside the bundle (or one no file can have) is refused first, nothing copied or read."""
    from morphlearn import provenance
    from morphlearn.bundles import make as bundle

    results = tmp_path / "results"
    b = _tiny_bundle(results)
    (results / "outside.txt").write_text("not the bundle's\n")
    (b / "bundle.json").write_text(
        json.dumps({"files": {"a.txt": provenance.sha256_file(b / "a.txt"), name: "0" * 64}})
    )
    monkeypatch.setattr(bundle_rerender, "_render", lambda *_: pytest.fail("rendered"))
    with pytest.raises(
        bundle.BundleError, match=r"^results/b: not re-rendered: bundle\.json lists .*outside the bundle"
    ):
        with bundle_rerender.rendered_copy("results/b", tmp_path, 1):
            pass
    assert not list(results.glob(".rerender-*"))


def test_a_render_that_checks_nothing_at_start_still_refuses_a_missing_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A bundle without figures renders nothing and its start check is skipped: a listed file that is
    missing is said in one line, not a FileNotFoundError."""
    from morphlearn.bundles import make as bundle

    b = _tiny_bundle(tmp_path / "results")
    (b / "a.txt").unlink()
    monkeypatch.setattr(bundle_rerender, "_render", lambda *_: None)
    with pytest.raises(
        bundle.BundleError, match=r"^results/b: not re-rendered: a\.txt: listed in bundle\.json but missing"
    ):
        with bundle_rerender.rendered_copy("results/b", tmp_path, 1):
            pass


def _dead_pid() -> int:
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


def test_a_killed_rerender_copy_is_removed_at_the_next_start_and_never_a_source(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    results = tmp_path / "results"
    b = _tiny_bundle(results)
    for m in ("theory",):
        (b / m).mkdir()
        (b / m / "metrics.csv").write_text("design\n")
    dead = results / f".rerender-b-{_dead_pid()}-abcdefgh"  # kill -9 left it, with its bundle.json
    older = results / ".rerender-b-k2j4_x9q"  # left by the code before the pid was in the name
    live = results / f".rerender-b-{os.getpid()}-zzzzzzzz"  # a render still running
    other = results / ".rerender-b-mujoco-1-abcdefgh"  # bundle b-mujoco's, not b's
    for d in (dead, older, live, other):
        d.mkdir()
        (d / "bundle.json").write_text((b / "bundle.json").read_text())
        (d / "theory").mkdir()
        (d / "theory/metrics.csv").write_text("design\n")
    # e3d6953: the explorer listed the copies as sources
    assert [s.bundle.name for s in explore.sources(results)] == ["b"]
    seen = []
    monkeypatch.setattr(bundle_rerender, "_render", lambda cmd, root, target: seen.append(target))
    with bundle_rerender.rendered_copy("results/b", tmp_path, 1) as (work, _, changed):
        assert work.name.startswith(f".rerender-b-{os.getpid()}-") and changed == {}
    assert not dead.exists() and not older.exists() and live.exists() and other.exists()
    assert not work.exists() and len(seen) == 1


@pytest.mark.parametrize("line", ["[]", '{"row": "x"}', '{"row": 1, "episodes": -5, "wall_s": 1, "cpu_s": 1}', "{"])
def test_refine_status_says_a_malformed_progress_log_in_one_line(
    line: str, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    import shutil

    folder = tmp_path / "f"
    shutil.copytree(ROOT / "results/refine/canonical_121", folder)
    with (folder / "progress.jsonl").open("a") as fh:
        fh.write(line + "\n")
    _refused(
        ["refine", "status", str(folder)], capsys, f"{folder / 'progress.jsonl'}: line ", "is malformed", "allowed"
    )


@pytest.mark.parametrize(
    ("value", "needle"),
    [
        pytest.param(10**5000, "ode.params.steps = an integer of 16610 bits; allowed", id="5000-digit-int"),
        pytest.param([10**5000], "ode.params.steps.0 = an integer of 16610 bits", id="in-a-list"),
        pytest.param("x" * 1_000_000, "is 1000000 characters long; allowed: at most 4096", id="1MB-string"),
        pytest.param("x" * 300, "... (302 characters) is invalid", id="300-char-string"),
    ],
)
def test_a_huge_config_value_is_named_short(value: object, needle: str) -> None:
    """Found in this pass: the schema's messages print the value whole (a 1 MB line for a 1 MB
    string), and an integer of more than 4,300 digits made Python's own ValueError."""
    base = config.read(ROOT / "config.yaml")
    with pytest.raises(config.ConfigError) as e:
        config.validate(config.deep_merge(base, {"ode": {"params": {"steps": value}}}))
    assert needle in str(e.value) and len(str(e.value)) < 700, str(e.value)[:300]
