"""Writes where they must not, unbounded inputs and resources, and the smaller messages, attacked
(a hostile pass over the write guard, the engines' ranges and the cost bound).

- the write guard compares the whole effective config (every ``--config`` override, nested keys
  too) of a render_only run into a bundle with the one its recorded configs give;
- every committed folder under results/ is protected (the ``!results/<name>/`` folders of
  .gitignore): bundles, and the refine, agreement and engine-comparison folders, written only by
  their own config (``results/refine/*`` by none);
- MuJoCo's log goes to the run's results folder, never the working directory;
- a second science config into a results folder stops with one line, Snakemake metadata or not;
- MuJoCo's own ranges, ``verify --workers``, the episodes x steps bound, run kinds that drop work;
- messages: ``²``, a theory screen, the bundles a message suggests, a results-only bundle's render,
  a trailing slash, a bundle outside the project, SIGTERM, the explorer's kernels.

Dry runs and refused starts run at the project root (nothing is written: each test checks
``git status --porcelain results/`` before and after) or in copies."""

from __future__ import annotations

import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import ROOT, TEST_COMMIT, copy_workflow, job_stats

from morphlearn import config as cfgmod
from morphlearn import configure
from morphlearn.apps import cli
from morphlearn.bundles import make as bundle
from morphlearn.bundles import resimulate
from morphlearn.bundles import verify as verifymod
from morphlearn.physics import cost
from morphlearn.physics import params as paramsmod
from morphlearn.workflow import runs

SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))
MORPHLEARN = str(Path(sys.executable).with_name("morphlearn"))
AUTHORS_BODY = ROOT / "config/authors_body.yaml"


@pytest.fixture(autouse=True)
def _at_root(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)


def _git_results() -> str:
    """The committed tree's state under results/ (tracked and untracked, ignored excluded)."""
    proc = subprocess.run(
        ["git", "status", "--porcelain", "--", "results/"], cwd=ROOT, capture_output=True, text=True, timeout=60
    )
    return proc.stdout if proc.returncode == 0 else "no git"


@pytest.fixture
def untouched() -> object:
    """Nothing under results/ changes while the test runs (what git sees)."""
    before = _git_results()
    yield
    assert _git_results() == before


def _cli(argv: list[str], capsys: pytest.CaptureFixture) -> tuple[int, str, str]:
    try:
        rc = cli.main(argv)
    except SystemExit as e:
        rc = int(e.code or 0)
    out, err = capsys.readouterr()
    return rc, out, "\n".join(line for line in err.splitlines() if line.startswith("morphlearn"))


def _refused(argv: list[str], capsys: pytest.CaptureFixture, *needles: str) -> str:
    rc, out, err = _cli(argv, capsys)
    assert rc == 2 and out == "", (argv, rc, out[-300:], err)
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    for n in needles:
        assert n in err, (n, err)
    return err


def _dry(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    return subprocess.run(
        [SNAKEMAKE, "-n", "--cores", "1", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "MORPHLEARN_GIT_COMMIT": TEST_COMMIT},
    )


def _start_refusal(proc: subprocess.CompletedProcess) -> str:
    """A refused start: exit 2, one line of ours, no traceback, no job planned."""
    ours = [ln for ln in proc.stderr.splitlines() if ln.startswith("morphlearn")]
    assert proc.returncode == 2 and len(ours) == 1, (proc.returncode, proc.stderr[-2000:])
    assert "Traceback" not in proc.stderr and not job_stats(proc.stdout + proc.stderr)
    return ours[0]


def _effective(*files: str, **over: object) -> dict:
    """The validated config Snakemake would have: config.yaml, ``files`` merged over it, then
    ``over`` (as --config: top-level keys replaced)."""
    raw = cfgmod.read("config.yaml", list(files))
    raw |= over
    return configure.parse(raw).source


# --- B5: the whole effective config of a render_only run into a bundle ----------------------------

PAPER = ("config/paper.yaml",)
#: --config overrides of a render_only run into results/paper (name -> override, the key named)
RENDER_OVERRIDES = {
    "screen_from_issue": (
        {"screen_from": {"bundle": "results/reduced-paper", "model": "reduced", "refinement": "results/ode-paper"}},
        "screen_from.",
    ),
    "bundle_dir_empty": ({"bundle_dir": None}, "bundle_dir"),
    "bundle_dir_other": ({"bundle_dir": "results/elsewhere"}, "bundle_dir"),
    "design_cache_off": ({"design_cache": False}, "design_cache"),
    "figures_off_top_n": ({"figures": {"enabled": True, "top_n": 2}}, "figures."),
    "theory_horizon": ({"theory": {"horizon": 400.0}}, "theory."),
    "analysis_radius": ({"analysis": {"success_radius": 0.3}}, "analysis."),
    "survey_from_other": ({"survey_from": {"bundle": None, "model": "empirical"}}, "survey_from."),
    "grid_weights": ({"grid": {"weights": 11}}, "grid."),
}


@pytest.mark.parametrize("name", list(RENDER_OVERRIDES))
def test_render_only_into_a_bundle_refuses_any_override_of_its_config(name: str) -> None:
    over, key = RENDER_OVERRIDES[name]
    raw = cfgmod.deep_merge(
        cfgmod.read("config.yaml", list(PAPER)), {"render_only": True, "results_dir": "results/paper"}
    )
    raw |= over  # --config replaces a top-level key
    try:
        v = configure.parse(raw).source
    except cfgmod.ConfigError as e:  # refused by its own validation already: as good
        assert "Traceback" not in str(e) and len(str(e).splitlines()) == 1
        return
    with pytest.raises(cfgmod.ConfigError) as e:
        configure.check_write_guard(v, ["config/paper.yaml", "config.yaml"])
    msg = str(e.value)
    assert msg.startswith("results_dir = 'results/paper' holds a results bundle") and key in msg, msg
    assert "--configfile config/paper.yaml" in msg and len(msg.splitlines()) == 1


RENDERABLE = ["results/paper", "results/survey", "results/learners", "results/reduced-maps", "results/survey-mujoco"]


@pytest.mark.parametrize("b", RENDERABLE)
def test_the_documented_render_of_each_bundle_passes_the_guard(b: str) -> None:
    made = json.loads((ROOT / b / "bundle.json").read_text())["made_by"]["configs"]
    files = [c for c in made if c != "config.yaml"]
    v = _effective(*files, render_only=True, results_dir=b)
    configure.check_write_guard(v, [*files, "config.yaml"])
    # the working copy a render makes beside it holds the same bundle.json: the same config
    assert cfgmod.bundle_holding(b) == (ROOT / b).resolve()


def test_the_issues_render_command_is_refused_before_anything_is_written(untouched: object) -> None:
    """B5 as the issue ran it (here as a dry run: the refusal is at start either way)."""
    proc = _dry(
        "--configfile",
        "config/paper.yaml",
        "--config",
        "render_only=True",
        "results_dir=results/paper",
        "screen_from={bundle: results/reduced-paper, model: reduced, refinement: results/ode-paper}",
        "--forceall",
        "results/paper/reproduction.md",
    )
    line = _start_refusal(proc)
    assert "holds a results bundle and this run's --config sets screen_from." in line, line


# --- B6: committed folders that are no bundle -----------------------------------------------------

COMMITTED_PLAIN = [
    "results/refine",
    *sorted(str(p.relative_to(ROOT)) for p in (ROOT / "results/refine").iterdir() if p.is_dir()),
    "results/agreement",
    "results/agreement/figures",
    "results/mujoco",
    "results/mujoco/figures",
    "results/reduced-agreement-paper",
    "results/reduced-agreement-random",
    "results/reduced-agreement-screened",
    "results/reduced-agreement-survey",
    "results/refine/new-folder",
]


@pytest.mark.parametrize("rd", COMMITTED_PLAIN)
def test_every_committed_folder_is_refused_to_a_config_that_did_not_make_it(rd: str) -> None:
    with pytest.raises(cfgmod.ConfigError) as e:
        cfgmod.check_results_dir(rd, False, ["config.yaml"])
    msg = str(e.value)
    assert msg.startswith(f"results_dir = {rd!r} is") and "committed folder" in msg and len(msg.splitlines()) == 1


@pytest.mark.parametrize(
    ("rd", "own", "other"),
    [
        ("results/agreement", "config/agreement.yaml", "config/reduced_agreement_paper.yaml"),
        ("results/mujoco", "config/engines.yaml", "config/agreement.yaml"),
        ("results/reduced-agreement-paper", "config/reduced_agreement_paper.yaml", "config/agreement.yaml"),
    ],
)
def test_a_committed_folder_is_written_by_its_own_config_alone(rd: str, own: str, other: str) -> None:
    cfgmod.check_results_dir(rd, False, [own, "config.yaml"])
    with pytest.raises(cfgmod.ConfigError, match=f"made by {own} alone"):
        cfgmod.check_results_dir(rd, False, [other, "config.yaml"])
    # and its own config with an override of anything else is a second config
    v = _effective(own, design_cache=False)
    with pytest.raises(cfgmod.ConfigError, match="is a committed folder and this run's --config sets design_cache"):
        configure.check_write_guard(v, [own, "config.yaml"])


def test_the_committed_folders_are_what_git_tracks_under_results() -> None:
    proc = subprocess.run(["git", "ls-files", "results/"], cwd=ROOT, capture_output=True, text=True, timeout=60)
    if proc.returncode != 0:
        pytest.skip("no git here")
    tracked = {Path(*Path(f).parts[:2]) for f in proc.stdout.splitlines() if len(Path(f).parts) > 2}
    assert {(ROOT / t).resolve() for t in tracked} == set(cfgmod.committed_folders())


def test_a_dry_run_into_a_refine_folder_plans_nothing_and_says_why(untouched: object) -> None:
    line = _start_refusal(_dry("--config", "results_dir=results/refine/canonical_121"))
    assert "is inside the committed folder results/refine (in git), which no run writes into" in line, line
    line = _start_refusal(
        _dry("--configfile", "config/reduced_agreement_paper.yaml", "--config", "results_dir=results/agreement")
    )
    assert "made by config/agreement.yaml alone" in line, line


def test_refine_seed_into_a_refine_folder_writes_nothing(tmp_path: Path, untouched: object) -> None:
    x = tmp_path / "x.yaml"
    x.write_text("results_dir: results/refine/canonical_121\n")
    before = sorted(p.relative_to(ROOT) for p in (ROOT / "results/refine/canonical_121").rglob("*"))
    proc = subprocess.run(
        [MORPHLEARN, "refine", "seed", "results/refine/canonical_121", "--configfile", str(x)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 2 and "Traceback" not in proc.stderr, proc.stderr[-2000:]
    assert "committed folder results/refine" in proc.stderr
    assert sorted(p.relative_to(ROOT) for p in (ROOT / "results/refine/canonical_121").rglob("*")) == before


# --- B7: MuJoCo's log -----------------------------------------------------------------------------


def test_mujoco_writes_its_warnings_inside_the_results_folder_only(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture
) -> None:
    from morphlearn.mujoco.authors import AuthorsBatchRunner

    cwd, logs = tmp_path / "cwd", tmp_path / "results/logs/mujoco"
    cwd.mkdir()
    monkeypatch.chdir(cwd)
    monkeypatch.setenv("MORPHLEARN_LOG_DIR", str(logs))
    p = paramsmod.load_params(AUTHORS_BODY).replace(wheel_mass=0.001, steps=100)  # inside the schema's range
    w = np.array([[1.0, -1.0], [0.3, 0.3]])
    ep = AuthorsBatchRunner(p).run((0.5, 0.5), (0.5, -0.5), w, np.array([0, 1]))
    assert not np.asarray(ep.finite).all()  # unstable: MuJoCo warned
    assert list(cwd.iterdir()) == []  # no MUJOCO_LOG.TXT in the working directory
    assert (logs / "MUJOCO_LOG.TXT").is_file()
    err = capsys.readouterr().err
    said = [ln for ln in err.splitlines() if ln.startswith("MuJoCo warning")]
    assert 1 <= len(said) <= 10, err[-2000:]  # once per kind, not once per step


# --- B8: a second config into a results folder ----------------------------------------------------


@pytest.fixture(scope="module")
def run_copy(smoke_run: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A private copy of the smoke run, with Snakemake's metadata."""
    wd = tmp_path_factory.mktemp("guard") / "wd"
    shutil.copytree(smoke_run, wd, symlinks=True, ignore=shutil.ignore_patterns("bundle", "report.html"))
    return wd


@pytest.mark.parametrize(
    "other",
    [
        {"theory": {"horizon": 400.0}},
        {"theory": {"success_radius": 0.3}},
        {"empirical": {"params": {"max_speed": 30.0}}},
    ],
    ids=["theory_horizon", "theory_radius", "empirical_params"],
)
def test_a_second_science_config_into_a_results_folder_stops_with_metadata(run_copy: Path, other: dict) -> None:
    (run_copy / "other.yaml").write_text(yaml.safe_dump(other))
    before = sorted((run_copy / "results").rglob("*.csv"))
    line = _start_refusal(_dry("--configfile", "config/smoke.yaml", "other.yaml", cwd=run_copy))
    assert "was made by another science config (its science record differs" in line, line
    assert sorted((run_copy / "results").rglob("*.csv")) == before


def test_the_first_config_again_still_finds_nothing_to_do(run_copy: Path) -> None:
    proc = _dry("--configfile", "config/smoke.yaml", cwd=run_copy)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr[-2000:]


# --- C9: the engines' own ranges --------------------------------------------------------------------


@pytest.mark.parametrize(
    ("params", "ok"),
    [
        ({"wheel_mass": 0.001}, False),
        ({"wheel_mass": 1.0}, False),
        ({"wheel_mass": 6.0}, False),
        ({"wheel_mass": 10.0}, True),
        ({"dt": 0.1}, False),
        ({"dt": 0.05}, True),
    ],
    ids=["wm_1g", "wm_1kg", "wm_6kg", "wm_10kg", "dt_0.1", "dt_0.05"],
)
def test_mujoco_refuses_what_it_was_measured_not_to_integrate(params: dict, ok: bool, tmp_path: Path) -> None:
    raw = cfgmod.read("config.yaml")
    raw |= {"results_dir": str(tmp_path / "r"), "mujoco": {"enabled": True, "robot": "authors", "params": params}}
    if ok:
        configure.parse(raw)
        return
    with pytest.raises(cfgmod.ConfigError) as e:
        configure.parse(raw)
    msg = str(e.value)
    assert msg.startswith("mujoco.params (or its body file config/authors_body.yaml): ") and "MuJoCo" in msg, msg
    assert "the schema's range is ODE's" in msg and len(msg.splitlines()) == 1


def test_ode_keeps_the_schemas_range(tmp_path: Path) -> None:
    raw = cfgmod.read("config.yaml")
    raw |= {"results_dir": str(tmp_path / "r"), "ode": {"enabled": True, "params": {"wheel_mass": 0.001}}}
    configure.parse(raw)


def test_design_with_mujoco_refuses_a_body_outside_its_range(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    body = yaml.safe_load(AUTHORS_BODY.read_text()) | {"wheel_mass": 1.0}
    (tmp_path / "b.yaml").write_text(yaml.safe_dump(body))
    argv = ["design", "--model", "mujoco", "--robot", "authors", "--l1", "0.5", "0.5", "--l2", "0.5", "-0.5"]
    _refused([*argv, "--weights", "2", "--morphology", str(tmp_path / "b.yaml")], capsys, "wheel_mass = 1 is outside")


# --- C10: verify --workers ---------------------------------------------------------------------------


@pytest.mark.parametrize("workers", ["100000", str(verifymod.available_cores() + 1), "0"])
def test_verify_workers_capped_at_the_cores(workers: str, capsys: pytest.CaptureFixture) -> None:
    argv = ["verify", "--merged", "results/survey/theory/merged.zarr", "--samples", "2", "--workers", workers]
    _refused(argv, capsys, f"--workers = {workers}; allowed: an integer 1..{verifymod.available_cores()}")


def test_verify_library_caps_workers_too() -> None:
    with pytest.raises(verifymod.VerifyError, match="the cores available"):
        verifymod.verify("results/survey/theory/merged.zarr", samples=2, workers=verifymod.available_cores() + 1)


# --- C11: the cost bound -------------------------------------------------------------------------------


def _long_body(tmp_path: Path, steps: int) -> Path:
    body = yaml.safe_load(AUTHORS_BODY.read_text()) | {"steps": steps}
    (tmp_path / "long.yaml").write_text(yaml.safe_dump(body))
    return tmp_path / "long.yaml"


@pytest.mark.parametrize(("weights", "steps"), [(1001, 100000), (501, 10000), (121, 100000)])
def test_design_past_the_bound_asks_for_the_flag_with_the_estimate(
    weights: int, steps: int, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    est = cost.design_estimate(weights, steps)
    argv = ["design", "--model", "ode", "--l1", "0.5", "0.5", "--l2", "0.5", "-0.5", "--weights", str(weights)]
    if est <= cost.DESIGN_BOUND:
        assert cost.refusal("this design", 1, weights, steps, "--allow-long") is None
        return
    _refused(
        [*argv, "--morphology", str(_long_body(tmp_path, steps))], capsys, f"= {est:.3g} episode-steps", "--allow-long"
    )


def test_a_run_past_the_bound_needs_allow_long_run(tmp_path: Path) -> None:
    raw = cfgmod.read("config.yaml")
    raw |= {
        "results_dir": str(tmp_path / "r"),
        "ode": {"enabled": True, "weights": 121, "morphology": str(_long_body(tmp_path, 100000)), "designs": "all"},
    }
    with pytest.raises(cfgmod.ConfigError, match=r"ode: \d+ design\(s\) x 4 x 121 x 121 episodes x 100000 steps"):
        configure.parse(raw)
    configure.parse(raw | {"allow_long_run": True})


@pytest.mark.parametrize("preset", ["config/full.yaml", "config/ode_survey9.yaml", "config/reduced_paper.yaml"])
def test_the_largest_presets_are_under_the_run_bound(preset: str) -> None:
    configure.parse(cfgmod.read("config.yaml", [preset]))


# --- C12: run kinds that drop work ----------------------------------------------------------------------


@pytest.mark.parametrize(
    ("over", "needle"),
    [
        ({"scenarios": "r2", "render_only": True}, "with render_only = true: the scenario stage simulates"),
        ({"agreement": {"enabled": True}, "learners": {"enabled": True}}, "so learners.enabled would be dropped"),
        ({"agreement": {"enabled": True}, "bundle_dir": "results/b"}, "so bundle_dir = 'results/b' would be dropped"),
        ({"engines": {"enabled": True}, "coopt": {"enabled": True}}, "so coopt.enabled would be dropped"),
        ({"scenarios": "r2", "bundle_dir": "results/b"}, "makes the scenarios stage alone"),
    ],
    ids=["scenarios_render_only", "agreement_learners", "agreement_bundle", "engines_coopt", "scenarios_bundle"],
)
def test_run_kinds_that_drop_work_are_refused(over: dict, needle: str) -> None:
    base = cfgmod.read("config.yaml", ["config/agreement.yaml"]) if "agreement" in over else cfgmod.read("config.yaml")
    if "engines" in over:
        base = cfgmod.read("config.yaml", ["config/engines.yaml"])
    raw = cfgmod.deep_merge(base, over) | {"results_dir": "results/guard-test"}
    try:
        s = configure.parse(raw)
    except cfgmod.ConfigError as e:
        pytest.fail(f"refused before the run kind: {e}")
    with pytest.raises(cfgmod.ConfigError) as e:
        runs.run(s)
    assert needle in str(e.value) and len(str(e.value).splitlines()) == 1, e.value


def test_scenarios_with_render_only_plan_no_shard(untouched: object) -> None:
    line = _start_refusal(_dry("--config", "scenarios=r2", "render_only=True"))
    assert "the scenario stage simulates its own sweeps" in line, line


# --- D15: messages ------------------------------------------------------------------------------------


@pytest.mark.parametrize("which", ["reduced:²", "²", "sample:²", "reduced:sample:٣", "theory:١٢"])
def test_resimulate_unicode_digits_refused_in_its_own_words(which: str) -> None:
    with pytest.raises(bundle.BundleError) as e:
        resimulate.parse_which(which, "--resimulate")
    assert str(e.value).startswith(f"--resimulate {which!r}: allowed: [MODEL:]WHICH")


def test_adaptive_screen_with_a_theory_bundle_names_no_none_point_grid() -> None:
    from morphlearn.physics.screen import Screen

    s = Screen("results/theory-paper", "theory", "ode.adaptive_screen")
    with pytest.raises(cfgmod.ConfigError) as e:
        s.check(9, 121, [0])
    assert "None" not in str(e.value) and "records no design grid" in str(e.value), e.value


@pytest.mark.parametrize(
    ("model", "bundle_dir"), [("mujoco", "results/survey"), ("ode", "results/survey"), ("reduced", "results/paper")]
)
def test_results_from_errors_suggest_bundles_that_hold_the_model(model: str, bundle_dir: str) -> None:
    from morphlearn import models

    with pytest.raises(cfgmod.ConfigError) as e:
        models.get(model).check_results_bundle(bundle_dir, 5)
    msg = str(e.value)
    named = msg.split("(e.g. ", 1)[1].split(")", 1)[0].split(", ") if "(e.g. " in msg else []
    assert named, msg
    for b in named:
        assert (ROOT / b / model / "metrics.csv").is_file(), (b, msg)


def test_render_of_a_results_only_bundle_says_so(capsys: pytest.CaptureFixture) -> None:
    err = _refused(["render", "results/theory-paper"], capsys, "holds no figures (results only")
    assert "physics" not in err


def test_a_trailing_slash_results_dir_is_one_folder(untouched: object) -> None:
    proc = _dry("--configfile", "config/paper.yaml", "--config", "render_only=True", "results_dir=results/paper/")
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "MissingInputException" not in proc.stderr and "//" not in proc.stdout
    assert configure.parse(cfgmod.read("config.yaml") | {"results_dir": "results/x/"}).results_dir == "results/x"


@pytest.mark.parametrize("command", ["rerender-bundle", "render"])
def test_a_bundle_outside_the_project_is_refused_by_its_name(
    command: str, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    b = tmp_path / "outb"
    shutil.copytree(ROOT / "results/survey", b)
    err = _refused([command, str(b)], capsys, f"{b}: is not a bundle inside this project's results/ folder")
    assert ".rerender" not in err
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]


# --- D16: SIGTERM --------------------------------------------------------------------------------------


def test_sigterm_to_render_removes_its_working_copy(tmp_path: Path) -> None:
    wd = copy_workflow(tmp_path / "wd")  # it holds the committed survey bundle (the default config reads it)
    proc = subprocess.Popen(
        [MORPHLEARN, "render", "results/survey"], cwd=wd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        end = time.monotonic() + 120
        while not list((wd / "results").glob(".rerender-survey-*")) and time.monotonic() < end:
            assert proc.poll() is None, proc.communicate()
            time.sleep(0.05)
        assert list((wd / "results").glob(".rerender-survey-*")), "no working copy appeared"
        time.sleep(1.0)  # Snakemake started
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 143 and "Traceback" not in err, err[-2000:]
    assert not list((wd / "results").glob(".rerender-survey-*"))


# --- D17: the explorer's kernels ----------------------------------------------------------------------


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_the_explorer_caps_its_kernels(tmp_path: Path) -> None:
    pytest.importorskip("voila")
    import nbformat

    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("x = 1")])
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    nbformat.write(nb, tmp_path / "t.ipynb")
    port = _free_port()
    exe = str(Path(sys.executable).with_name("voila"))
    proc = subprocess.Popen(
        [exe, "t.ipynb", "--no-browser", f"--port={port}", "--Voila.ip=127.0.0.1", *cli.voila_cap(2)],
        cwd=tmp_path,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        end = time.monotonic() + 60
        while time.monotonic() < end:
            with socket.socket() as s:
                if s.connect_ex(("127.0.0.1", port)) == 0:
                    break
            time.sleep(0.2)
        codes = []
        for _ in range(3):
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=60) as r:
                    r.read()
                    codes.append(r.status)
            except urllib.error.HTTPError as e:
                codes.append(e.code)
        assert codes == [200, 200, 503], codes
    finally:
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()
