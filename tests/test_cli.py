import json
import subprocess
import sys

import pytest
from conftest import ROOT

from morphlearn.cli import main


def test_design_json_has_exactly_the_documented_keys(capsys: pytest.CaptureFixture) -> None:
    assert main(["design", "--l1", "0.5", "0.5", "--l2", "0.5", "-0.5", "--weights", "5", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == {"per_env", "generalists", "at_least_one", "M_L", "M_CF", "flagged"}
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
    assert set(out) == {"per_env", "generalists", "at_least_one", "M_L", "M_CF", "flagged"}
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
