import json
import subprocess
import sys

import pytest
from conftest import ROOT

from morphlearn.cli import main

#: What ``morphlearn design --json`` prints: the design and model it evaluated, then the metrics.
DESIGN_JSON_KEYS = {"model", "design", "weights", "per_env", "generalists", "at_least_one", "M_L", "M_CF", "flagged"}
#: a physics model's JSON also names the robot it built (docs/authors_robot.md)
PHYSICS_JSON_KEYS = DESIGN_JSON_KEYS | {"robot"}


def test_design_json_has_exactly_the_documented_keys(capsys: pytest.CaptureFixture) -> None:
    assert main(["design", "--l1", "0.5", "0.5", "--l2", "0.5", "-0.5", "--weights", "5", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == DESIGN_JSON_KEYS
    assert (out["model"], out["design"], out["weights"]) == ("theory", {"l1": [0.5, 0.5], "l2": [0.5, -0.5]}, 5)
    assert len(out["per_env"]) == 4 and all(isinstance(x, int) for x in out["per_env"])
    assert out["M_L"] == out["generalists"] / 25
    # The canonical design is its own mirror image: 45 <-> 315 and 135 <-> 225 match.
    assert out["per_env"][0] == out["per_env"][3] and out["per_env"][1] == out["per_env"][2]


@pytest.mark.parametrize(
    ("args", "msg"),
    [
        (["--l1", "0.5", "0.9", "--l2", "0", "0"], "--l1 y = 0.9 is outside the body"),
        (["--l1", "0", "0", "--l2", "-0.51", "0"], "--l2 x = -0.51 is outside the body"),
        (["--l1", "0", "0", "--l2", "0", "0", "--weights", "1"], "--weights = 1 must be in 2..1001"),
        (["--l1", "0", "0", "--l2", "0", "0", "--horizon", "-1"], "--horizon = -1.0 must be a finite number > 0"),
    ],
)
def test_bad_arguments_exit_2_with_one_line(args: list[str], msg: str) -> None:
    proc = subprocess.run([sys.executable, "-m", "morphlearn.cli", "design", *args], capture_output=True, text=True)
    assert proc.returncode == 2
    assert msg in proc.stderr and proc.stderr.count("\n") == 1
    assert proc.stdout == ""


def test_empirical_design_json_is_clean_stdout() -> None:
    # pybullet prints a banner from C at import; stdout must still be exactly one JSON object.
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "morphlearn.cli",
            "design",
            "--model",
            "empirical",
            "--l1",
            "0.5",
            "0.5",
            "--l2",
            "0.5",
            "-0.5",
            "--weights",
            "2",
            "--json",
        ],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert set(out) == PHYSICS_JSON_KEYS and out["robot"] == "project"
    assert (out["model"], out["design"], out["weights"]) == ("empirical", {"l1": [0.5, 0.5], "l2": [0.5, -0.5]}, 2)
    assert out["generalists"] >= 1  # w = (1, 1) reaches all four lights with the committed body


def test_missing_morphology_file() -> None:
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "morphlearn.cli",
            "design",
            "--model",
            "empirical",
            "--l1",
            "0.5",
            "0.5",
            "--l2",
            "0.5",
            "-0.5",
            "--morphology",
            "nope.yaml",
        ],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert proc.returncode == 2 and "--morphology nope.yaml: no such file" in proc.stderr


def test_run_help_describes_the_verb_before_snakemakes_options() -> None:
    exe = str(__import__("pathlib").Path(sys.executable).with_name("morphlearn"))
    r = subprocess.run([exe, "run", "--help"], capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert r.returncode == 0
    ours, snakemakes = r.stdout.find("Run the workflow: Snakemake"), r.stdout.find("usage: snakemake")
    assert 0 <= ours < snakemakes, r.stdout[:500]


def test_every_verb_has_one_help_line_and_every_option_help_text() -> None:
    from morphlearn.cli import build_parser

    p = build_parser()
    sub = next(a for a in p._actions if a.dest == "cmd")
    assert {"design", "verify", "check-bundle", "render", "explore", "rerender-bundle", "compare", "run"} <= set(
        sub.choices
    )
    helps = {c.dest: c.help for c in sub._choices_actions}
    assert all(helps.get(v) for v in sub.choices), helps
    assert "RE-SEAL" in helps["rerender-bundle"]  # the verb that changes a bundle says so
    for verb, parser in sub.choices.items():
        if verb == "run":
            continue  # Snakemake's options (morphlearn run --help)
        bare = [a.option_strings or a.dest for a in parser._actions if a.help in (None, "") and a.dest != "help"]
        assert not bare, (verb, bare)


@pytest.mark.parametrize(
    ("args", "msg"),
    [
        (["render", "results/nope"], "results/nope: no bundle.json"),
        (["render", "results/ode-paper"], "holds no figures (physics only)"),
        (["render", "results/survey", "--cores", "0"], "--cores = 0; allowed"),
    ],
)
def test_render_refuses_in_one_line(args: list[str], msg: str, capsys: pytest.CaptureFixture) -> None:
    import os

    here = os.getcwd()
    os.chdir(ROOT)
    try:
        assert main(args) == 2
    finally:
        os.chdir(here)
    err = capsys.readouterr().err.strip()
    assert msg in err and "\n" not in err, err


@pytest.mark.slow
def test_render_a_committed_bundle_is_byte_identical(tmp_path) -> None:
    """The reviewer's one command on a clone's copy: the survey bundle re-rendered from its results."""
    from conftest import copy_workflow

    wd = copy_workflow(tmp_path / "clone")
    before = {p: p.read_bytes() for p in (wd / "results" / "survey").rglob("*") if p.is_file()}
    exe = str(__import__("pathlib").Path(sys.executable).with_name("morphlearn"))
    r = subprocess.run([exe, "render", "results/survey"], capture_output=True, text=True, timeout=900, cwd=wd)
    assert r.returncode == 0 and "every file is byte-identical to bundle.json" in r.stdout, r.stdout + r.stderr[-2000:]
    after = {p: p.read_bytes() for p in (wd / "results" / "survey").rglob("*") if p.is_file()}
    assert after == before  # the bundle itself is not touched
