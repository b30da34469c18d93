import json
import subprocess
import sys

import pytest
from conftest import ROOT

from morphlearn.apps.cli import main

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
    proc = subprocess.run(
        [sys.executable, "-m", "morphlearn.apps.cli", "design", *args], capture_output=True, text=True
    )
    assert proc.returncode == 2
    assert msg in proc.stderr and proc.stderr.count("\n") == 1
    assert proc.stdout == ""


def test_empirical_design_json_is_clean_stdout() -> None:
    # pybullet prints a banner from C at import; stdout must still be exactly one JSON object.
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "morphlearn.apps.cli",
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
            "morphlearn.apps.cli",
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


def test_run_help_is_morphlearns_own_and_points_to_snakemakes() -> None:
    # issue 59: not ~1,000 lines of Snakemake's help appended; its examples, and where the rest is
    exe = str(__import__("pathlib").Path(sys.executable).with_name("morphlearn"))
    r = subprocess.run([exe, "run", "--help"], capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert r.returncode == 0 and r.stderr == ""
    assert r.stdout.startswith("usage: morphlearn run") and "Run the workflow: Snakemake" in r.stdout
    assert "snakemake --help" in r.stdout and "usage: snakemake" not in r.stdout
    assert len(r.stdout.splitlines()) < 40


def test_design_help_has_a_description_and_an_example(capsys: pytest.CaptureFixture) -> None:
    with pytest.raises(SystemExit):
        main(["design", "--help"])
    out = capsys.readouterr().out
    assert "Evaluate one sensor placement" in out and "examples:" in out
    assert "morphlearn design --model ode --l1" in out and "CPU-s" in out


def test_refine_help_is_plain_text_for_a_terminal(capsys: pytest.CaptureFixture) -> None:
    with pytest.raises(SystemExit):
        main(["refine", "--help"])
    out = capsys.readouterr().out
    assert "morphlearn refine ACTION FOLDER" in out
    assert "``" not in out and ":mod:" not in out and ":func:" not in out


def test_weights_below_two_is_refused_without_a_memory_note() -> None:
    proc = subprocess.run(
        [sys.executable, "-m", "morphlearn.apps.cli", "design", "--l1", "0", "0", "--l2", "0", "0", "--weights", "1"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2 and "span [-1, 1]" in proc.stderr and "GiB" not in proc.stderr


@pytest.mark.parametrize(
    ("model", "says"),
    [("theory", "simulated by: the theory"), ("ode", "simulated by: engine ODE, robot authors")],
)
def test_design_text_names_what_simulated_it(model: str, says: str) -> None:
    args = ["design", "--model", model, "--l1", "0.5", "0.5", "--l2", "0.5", "-0.5", "--weights", "2"]
    proc = subprocess.run(
        [sys.executable, "-m", "morphlearn.apps.cli", *args], capture_output=True, text=True, cwd=ROOT
    )
    assert proc.returncode == 0, proc.stderr
    assert says in proc.stdout, proc.stdout


def test_compare_counts_shared_top_designs_by_coordinates_across_grids(capsys: pytest.CaptureFixture) -> None:
    # issue 59: a 9-point theory run beside the 5-point ODE survey are joined by coordinates; the
    # top-10 count intersected the two grids' design indices (1 shared by M_CF; by coordinates 0)
    args = ["compare", str(ROOT / "results/paper/theory/metrics.csv"), str(ROOT / "results/ode-survey/ode/metrics.csv")]
    assert main([*args, "--resamples", "100", "--json"]) == 0
    out = json.loads(capsys.readouterr().out.splitlines()[-1])
    assert out["designs"] == 625
    assert (out["M_L"]["top_shared"], out["M_CF"]["top_shared"]) == (0, 0)


def test_every_verb_has_one_help_line_and_every_option_help_text() -> None:
    from morphlearn.apps.cli import build_parser

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
