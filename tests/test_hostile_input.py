"""Hostile input at the edge (issue 24, part 4): every attack below is refused at start with one line
that names the key or flag, the value and what is allowed (exit 2 on the command line), or, where
the input is legitimate, handled. One rule for the config and the CLI (``settings.check_theory``,
``config.yaml_mapping``, the strict integer type of the schema).

Classes: integers that are floats; physically meaningless settings; unsafe paths; bad YAML files
(duplicate keys, empty, binary, wrong shape); every CLI command's flags; messages that name the
real cause (a run from another folder, a committed bundle as results_dir) and a schema whose
descriptions are not cut short. Most attacks run in-process (``configure.parse``, ``cli.main``); the
few that only the workflow can show run ``snakemake -n`` in one shared copy of the workflow.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest
import yaml
from conftest import ROOT, TEST_COMMIT, copy_workflow, snakemake

from morphlearn import config, configure, scenarios
from morphlearn.apps import cli

SURVEY = ROOT / "results/survey"
#: A small, valid theory-only config (the smoke grid; no file the figures read).
SMALL = {
    "grid": {"positions_per_axis": 3, "weights": 5},
    "sweep": {"shards": 3, "threads": 1},
    "analysis": {"top": 3},
    "empirical": {"enabled": False},
    "figures": {"enabled": False},
}


#: An empirical section that simulates (the body file is read) on SMALL's grid.
PHYSICS = {"enabled": True, "results_from": None, "designs": [[[0.5, 0.5], [0.5, -0.5]]], "shards": 1}


@pytest.fixture(autouse=True)
def _at_root(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)  # config paths (the body file) are relative to the project root


def _base() -> dict:
    return config.deep_merge(config.read(ROOT / "config.yaml"), SMALL)


def _one_line_config_error(patch: dict) -> str:
    with pytest.raises(config.ConfigError) as e:
        configure.parse(config.deep_merge(_base(), patch))
    msg = str(e.value)
    assert "\n" not in msg and "allowed" in msg, msg
    return msg


def _cli(argv: list[str], capsys: pytest.CaptureFixture) -> tuple[int, str, str]:
    """``morphlearn ARGV`` in-process: exit code, stdout, our stderr lines (not pybullet's banner)."""
    try:
        rc = cli.main(argv)
    except SystemExit as e:  # argparse's own refusals exit
        rc = int(e.code or 0)
    out, err = capsys.readouterr()
    ours = [line for line in err.splitlines() if line.startswith("morphlearn")]
    return rc, out, "\n".join(ours)


def _refused(argv: list[str], capsys: pytest.CaptureFixture, *needles: str) -> str:
    rc, out, err = _cli(argv, capsys)
    assert rc == 2 and out == "", (argv, rc, out[-300:], err)
    assert len(err.splitlines()) == 1 and "error" in err, err
    for n in needles:
        assert n in err, (n, err)
    return err


# --- integers are integers (config: schema type; CLI: argparse int) ----------------------------

FLOAT_INTEGERS = [
    ({"grid": {"weights": 5.0}}, "grid.weights = 5.0"),  # crashed the shard (issue 24)
    ({"theory": {"max_steps": 10000.0}}, "theory.max_steps = 10000.0"),  # changed the science digest
    ({"grid": {"positions_per_axis": 3.0}}, "grid.positions_per_axis = 3.0"),
    ({"sweep": {"shards": 3.0}}, "sweep.shards = 3.0"),
    ({"analysis": {"top": 3.0}}, "analysis.top = 3.0"),
    ({"learners": {"seed": 1.0}}, "learners.seed = 1.0"),
    ({"learners": {"max_designs": 4.0}}, "learners.max_designs = 4.0"),
    ({"figures": {"persistence_controllers": 35.0}}, "figures.persistence_controllers = 35.0"),
    ({"empirical": {"weights": 11.0}}, "empirical.weights = 11.0"),
    ({"grid": {"weights": True}}, "grid.weights = True"),  # bool is not an integer either
]


@pytest.mark.parametrize(("patch", "needle"), FLOAT_INTEGERS)
def test_whole_number_floats_refused_where_an_integer_is_meant(patch: dict, needle: str) -> None:
    msg = _one_line_config_error(patch)
    assert needle in msg and "integer" in msg, msg


def test_integers_and_floats_where_numbers_are_meant_still_pass() -> None:
    s = configure.parse(config.deep_merge(_base(), {"theory": {"r": 4, "horizon": 500}, "grid": {"weights": 5}}))
    assert s.grid.weights == 5 and isinstance(s.grid.weights, int)


@pytest.mark.parametrize(
    "argv",
    [
        ["design", "--l1", "0.5", "0.5", "--l2", "0.5", "-0.5", "--weights", "5.0"],
        ["verify", "--merged", "x", "--samples", "2.5"],
        ["compare", "a.csv", "b.csv", "--top", "3.0"],
    ],
)
def test_cli_integer_flags_refuse_floats_in_one_line(argv: list[str], capsys: pytest.CaptureFixture) -> None:
    _refused(argv, capsys, "invalid int value")


# --- physically meaningless settings: one rule (settings.check_theory) for config and CLI --------

PHYSICS_CONFIG = [
    ({"theory": {"r": 0.1}}, "theory.success_radius = 0.2 is not below theory.r = 0.1"),  # light inside
    ({"theory": {"r": 0.2}}, "theory.success_radius = 0.2 is not below theory.r = 0.2"),
    ({"theory": {"success_radius": 5.0}}, "theory.success_radius = 5.0 is not below theory.r = 4.0"),
    (
        {"theory": {"integrator": "rk4", "dt": 600, "max_steps": 10}},
        "theory.dt = 600 is not shorter than theory.horizon = 500.0",
    ),
    (
        {"theory": {"integrator": "rk4", "dt": 50, "horizon": 50, "max_steps": 10}},
        "theory.dt = 50 is not shorter than theory.horizon = 50",
    ),
    ({"theory": {"integrator": "rk4"}}, "theory.max_steps = 10000 is below the 50000 steps"),
    (
        {"empirical": {**PHYSICS, "params": {"light_distance": 0.9}}},
        "empirical.params.light_distance = 0.9 is not beyond the contact distance",
    ),
]


@pytest.mark.parametrize(("patch", "needle"), PHYSICS_CONFIG)
def test_config_refuses_meaningless_physics(patch: dict, needle: str) -> None:
    msg = _one_line_config_error(patch)
    assert needle in msg, msg


def test_meaningful_neighbours_of_the_refused_physics_pass() -> None:
    for ok in (
        {"theory": {"r": 0.21}},
        {"theory": {"integrator": "rk4", "dt": 400, "max_steps": 10}},  # a coarse step, but a step
        {"theory": {"integrator": "dp5", "dt": 600}},  # dt is unused by the adaptive integrator
        {"empirical": {**PHYSICS, "params": {"light_distance": 0.93}}},  # the body's contact: 0.906
    ):
        configure.parse(config.deep_merge(_base(), ok))


@pytest.mark.parametrize(
    ("flags", "needles"),
    [
        (["--r", "0.1"], ("--r = 0.1 is not beyond the success radius 0.2", "allowed: --r > 0.2")),
        (["--r", "0.2"], ("--r = 0.2",)),
        (["--dt", "600"], ("--dt = 600.0 is not shorter than --horizon = 500.0", "allowed: --dt < 500.0")),
        (["--horizon", "1", "--dt", "1"], ("--dt = 1.0 is not shorter than --horizon = 1.0",)),
        (["--horizon", "10", "--dt", "20"], ("--dt = 20.0",)),
    ],
)
def test_cli_design_refuses_what_the_config_refuses(
    flags: list[str], needles: tuple[str, ...], capsys: pytest.CaptureFixture
) -> None:
    # the examples: --r 0.1 reported M_L = 1.0 and --dt 600 reported 0 successes, exit 0
    _refused(["design", "--l1", "0.5", "0.5", "--l2", "0.5", "-0.5", "--weights", "2", *flags], capsys, *needles)


def test_cli_design_accepts_the_neighbour(capsys: pytest.CaptureFixture) -> None:
    rc, out, err = _cli(["design", "--l1", "0.5", "0.5", "--l2", "0.5", "-0.5", "--weights", "2", "--r", "0.3"], capsys)
    assert rc == 0 and "M_L" in out, err


# --- unsafe paths -----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("patch", "needle"),
    [
        ({"results_dir": "res{x}"}, "results_dir = 'res{x}' holds '{' and '}'"),  # a WildcardError
        ({"results_dir": "res}"}, "results_dir = 'res}' holds '}'"),
        ({"results_dir": "a\nb"}, "results_dir = 'a\\nb' holds '\\n'"),
        ({"bundle_dir": "b{w}"}, "bundle_dir = 'b{w}'"),
        ({"empirical": {"morphology": "body{x}.yaml"}}, "empirical.morphology = 'body{x}.yaml'"),
        ({"empirical": {"results_from": "results/{s}"}}, "empirical.results_from = 'results/{s}'"),
    ],
)
def test_unsafe_paths_refused_at_start(patch: dict, needle: str) -> None:
    msg = _one_line_config_error(patch)
    assert needle in msg and "wildcards" in msg, msg


# --- bad files: one reader for configs, scenario files and body files ---------------------------

BAD_FILES = {
    "empty": (b"", "empty (no keys)"),
    "comment_only": (b"# nothing here\n", "empty (no keys)"),
    "binary": (bytes(range(128, 256)) * 2, "not a UTF-8 text file (byte 0x80 at offset 0)"),
    "nul": (b"grid:\x00\n", "not a text file (NUL byte at offset 5)"),
    "control": (b"grid: \x07\n", "not a text file (control character"),
    "duplicate_top": (b"results_dir: a\nresults_dir: b\n", "key 'results_dir' given twice (lines 1 and 2)"),
    "duplicate_nested": (b"grid:\n  weights: 5\n  weights: 7\n", "key 'weights' given twice (lines 2 and 3)"),
    "list": (b"- 1\n- 2\n", "top level is a list, not a mapping"),
    "scalar": (b"42\n", "top level is a number, not a mapping"),
    "malformed": (b"grid: [1, 2\n", "malformed YAML at line 2, column 1"),
    "python_tag": (b"a: !!python/object/apply:os.system [ls]\n", "malformed YAML at line 1"),
}


@pytest.mark.parametrize("kind", sorted(BAD_FILES))
def test_bad_config_file_refused_in_one_line(kind: str, tmp_path: Path) -> None:
    data, needle = BAD_FILES[kind]
    p = tmp_path / f"{kind}.yaml"
    p.write_bytes(data)
    with pytest.raises(config.ConfigError) as e:
        configure.load(p)
    msg = str(e.value)
    assert msg.startswith(f"{p}: ") and needle in msg and "\n" not in msg, msg


@pytest.mark.parametrize("kind", sorted(BAD_FILES))
def test_bad_scenario_file_refused_in_one_line(kind: str, tmp_path: Path) -> None:
    data, needle = BAD_FILES[kind]
    p = tmp_path / "scenarios.yaml"
    p.write_bytes(data)
    with pytest.raises(config.ConfigError) as e:  # the workflow prints it and exits 2
        scenarios.read_file(p)
    assert needle in str(e.value) and "\n" not in str(e.value), str(e.value)


@pytest.mark.parametrize("kind", ["empty", "binary", "duplicate_nested", "list"])
def test_bad_body_file_refused_by_the_cli(kind: str, tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    data, needle = BAD_FILES[kind]
    p = tmp_path / "body.yaml"
    p.write_bytes(data)
    args = ["design", "--model", "empirical", "--l1", "0", "0", "--l2", "0", "0", "--morphology", str(p)]
    _refused(args, capsys, f"--morphology {p}: {needle}")


def test_duplicate_key_in_an_anchor_merge_is_an_override_not_an_error(tmp_path: Path) -> None:
    p = tmp_path / "merge.yaml"
    p.write_text("a: &A {x: 1, y: 2}\nb:\n  <<: *A\n  x: 3\n")
    assert config.yaml_mapping(p) == {"a": {"x": 1, "y": 2}, "b": {"x": 3, "y": 2}}


# --- every command's flags ----------------------------------------------------------------------

T, E = str(SURVEY / "theory/metrics.csv"), str(SURVEY / "empirical/metrics.csv")


def _table(tmp_path: Path, edit: dict[str, object] | None = None, row: int = 3, text: str | None = None) -> str:
    p = tmp_path / "m.csv"
    if text is not None:
        p.write_text(text)
        return str(p)
    import pandas as pd

    t = pd.read_csv(T, comment="#")
    for col, v in (edit or {}).items():
        t[col] = t[col].astype(object)
        t.loc[row, col] = v
    t.to_csv(p, index=False)
    return str(p)


@pytest.mark.parametrize(
    ("make", "flags", "needles"),
    [
        # the examples
        (lambda tp: str(ROOT / "config/empirical_pareto.csv"), [], ("not a metrics table (no columns",)),
        (lambda tp: T, ["--top", "-3"], ("--top = -3", "allowed: an integer >= 1")),
        (lambda tp: T, ["--resamples", "0"], ("--resamples = 0", "allowed: an integer >= 100")),
        (lambda tp: _table(tp, {"M_L": "nan"}), [], ("data row 4: M_L = 'nan'", "allowed: a number in [0, 1]")),
        # variants
        (lambda tp: T, ["--top", "0"], ("--top = 0",)),
        (lambda tp: T, ["--resamples", "99"], ("--resamples = 99",)),
        (lambda tp: _table(tp, {"M_CF": 1.5}), [], ("M_CF = '1.5'",)),
        (lambda tp: _table(tp, {"M_L": "inf"}), [], ("M_L = 'inf'",)),
        (lambda tp: _table(tp, {"design": 2.5}), [], ("design = '2.5'", "an integer >= 0")),
        (lambda tp: _table(tp, {"design": 0}), [], ("design 0 appears twice",)),
        (lambda tp: _table(tp, {"generalists": "many"}), [], ("generalists = 'many'",)),
        (lambda tp: _table(tp, text=""), [], ("not a CSV table (EmptyDataError)",)),
        (lambda tp: _table(tp, text="\x80\x81,\xff\n"), [], ("not a metrics table",)),
        (lambda tp: str(tp / "missing.csv"), [], ("missing.csv: no such file",)),
    ],
)
def test_compare_refuses_bad_tables_and_flags(
    make, flags: list[str], needles: tuple[str, ...], tmp_path, capsys
) -> None:
    _refused(["compare", make(tmp_path), E, *flags], capsys, *needles)


def test_compare_binary_table_refused(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    p = tmp_path / "bin.csv"
    p.write_bytes(bytes(range(128, 256)) * 4)
    _refused(["compare", str(p), E], capsys, "bin.csv: not a")


def test_compare_undefined_rho_is_true_and_json_is_strict(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    import pandas as pd

    t = pd.read_csv(T, comment="#")
    t["M_L"] = 0.25  # every design the same value: rho is undefined, and the text says so truly
    p = tmp_path / "const.csv"
    t.to_csv(p, index=False)
    rc, out, err = _cli(["compare", str(p), E, "--resamples", "100", "--json"], capsys)
    assert rc == 0, err
    lines = out.splitlines()
    assert "M_L: Spearman rho undefined (one model gives every one of the 625 designs the same value)" in lines[0]

    def no_constants(c: str) -> None:
        raise AssertionError(f"bare {c} in --json output")

    rep = json.loads(lines[-1], parse_constant=no_constants)  # strict JSON: no NaN
    assert rep["M_L"]["rho"] is None and rep["M_CF"]["rho"] is not None


@pytest.mark.parametrize(
    ("flags", "needle"),
    [
        (["--samples", "0"], "--samples = 0; allowed: an integer >= 1"),
        (["--samples", "-5"], "--samples = -5"),
        (["--seed", "-1"], "--seed = -1; allowed: an integer >= 0"),
        (["--workers", "0"], "--workers = 0; allowed: an integer >= 1"),
        (["--time-tol", "nan"], "--time-tol = nan must be a finite number > 0"),
        (["--time-tol", "-1"], "--time-tol = -1.0"),
        (["--time-tol", "inf"], "--time-tol = inf"),
    ],
)
def test_verify_flags_range_checked_before_reading(flags: list[str], needle: str, capsys) -> None:
    _refused(["verify", "--merged", "does/not/matter.zarr", *flags], capsys, needle)


@pytest.mark.parametrize("which", ["nonsense", "-5", "1.5", ""])
def test_check_bundle_resimulate_names_checked_before_reading(which: str, capsys) -> None:
    _refused(["check-bundle", str(SURVEY), "--resimulate", which], capsys, f"--resimulate {which!r}")


@pytest.mark.parametrize(
    "argv",
    [
        ["design"],  # required flags missing
        ["frobnicate"],
        ["design", "--l1", "0", "--l2", "0", "0"],
        ["design", "--l1", "0", "0", "--l2", "0", "0", "--model", "nope"],
        ["compare", T],
    ],
)
def test_argparse_refusals_are_one_line(argv: list[str], capsys: pytest.CaptureFixture) -> None:
    _refused(argv, capsys, "--help")


# --- the schema and its generated documentation -------------------------------------------------


def test_schema_has_only_json_schema_keywords_and_the_generator_refuses_others(tmp_path: Path) -> None:
    sys.path.insert(0, str(ROOT / "tools"))
    try:
        import config_docs
    finally:
        sys.path.remove(str(ROOT / "tools"))
    assert config_docs.unknown_keywords(config.schema()) == []
    # the defect: an unquoted comma in a flow mapping makes a key and cuts the description
    bad = yaml.safe_load("properties:\n  enabled: {type: boolean, description: Render the figures, table.}\n")
    assert config_docs.unknown_keywords(bad) == ["enabled: 'table.'"]
    doc = (ROOT / "config/README.md").read_text()
    for full in (
        "Render the figures, table and report inputs.",
        "Runs per design, learner and protocol.",
        "Base seed; a run's seed is (seed, design, learner, protocol, run).",
    ):
        assert full in doc


@pytest.mark.parametrize("kind", ["missing", "empty", "binary", "duplicate_top", "list"])
def test_workflow_start_check_names_a_bad_or_missing_config_yaml(
    kind: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The Snakefile's first check (before Snakemake reads config.yaml): was a WorkflowError or
    traceback, exit 1 (the file is read by Snakemake's own loader)."""
    monkeypatch.chdir(tmp_path)
    if kind != "missing":
        (tmp_path / "config.yaml").write_bytes(BAD_FILES[kind][0])
    with pytest.raises(config.ConfigError) as e:
        config.check_start(tmp_path, ["config.yaml"])
    needle = "cannot read (No such file or directory)" if kind == "missing" else BAD_FILES[kind][1]
    assert str(e.value).startswith("config.yaml: ") and needle in str(e.value), str(e.value)


# --- the workflow: what only Snakemake shows (dry runs in one shared copy) ------------------------


@pytest.fixture(scope="module")
def wf(tmp_path_factory: pytest.TempPathFactory) -> Path:
    wd = copy_workflow(tmp_path_factory.mktemp("hostile") / "wf")
    shutil.rmtree(wd / "results/survey")  # SMALL reads no bundle
    (wd / "small.yaml").write_text(yaml.safe_dump(SMALL))
    return wd


def _start_refusal(wd: Path, *args: str, cwd: Path | None = None) -> str:
    exe = Path(sys.executable).with_name("snakemake")
    proc = subprocess.run(
        [str(exe), "-n", "--cores", "1", *args],
        cwd=cwd or wd,
        capture_output=True,
        text=True,
        timeout=300,
        env={**os.environ, "MORPHLEARN_GIT_COMMIT": TEST_COMMIT},
    )
    ours = [line for line in proc.stderr.splitlines() if line.startswith("morphlearn")]
    assert proc.returncode == 2 and len(ours) == 1, (proc.returncode, proc.stderr[-2000:])
    assert "Traceback" not in proc.stderr
    assert not (wd / "results").exists() or not any((wd / "results").iterdir())
    return ours[0]


def test_workflow_refuses_duplicate_key_and_float_integer(wf: Path) -> None:
    (wf / "dup.yaml").write_text("grid:\n  positions_per_axis: 3\n  weights: 5\n  weights: 7\n")
    line = _start_refusal(wf, "--configfile", "small.yaml", "dup.yaml")
    assert "dup.yaml: key 'weights' given twice (lines 3 and 4)" in line, line


@pytest.mark.parametrize("kind", ["empty", "binary", "list"])
def test_a_bad_configfile_snakemake_reads_first_stops_before_anything_is_written(wf: Path, kind: str) -> None:
    """The limit of the workflow's own check: Snakemake reads the files of ``--configfile`` in its
    command line (snakemake.settings.types.ConfigSettings, before the Snakefile is parsed), so an
    empty, binary, non-mapping or malformed one stops there: exit 1 in Snakemake's words (a
    traceback for a binary file, and no file name), nothing written. Measured here so that the
    README's account stays true; what reaches the Snakefile (a key given twice, a wrong shape under
    a key) is refused in one line, exit 2 (the tests beside this one)."""
    (wf / "bad.yaml").write_bytes(BAD_FILES[kind][0])
    exe = Path(sys.executable).with_name("snakemake")
    before = sorted(p.relative_to(wf) for p in wf.rglob("*"))
    proc = subprocess.run(
        [str(exe), "-n", "--cores", "1", "--configfile", "small.yaml", "bad.yaml"],
        cwd=wf,
        capture_output=True,
        text=True,
        timeout=300,
    )
    said = (proc.stdout + proc.stderr).splitlines()
    first = next((line for line in said if line.strip()), "")
    assert proc.returncode == 1 and not any(ln.startswith("morphlearn") for ln in said), said
    assert first == ("Traceback (most recent call last):" if kind == "binary" else "WorkflowError:"), said
    assert sorted(p.relative_to(wf) for p in wf.rglob("*")) == before  # nothing written


def _morphlearn_run_dry(wf: Path, configfile: str, timeout: int) -> tuple[int, list[str]]:
    """`morphlearn run -n` in ``wf`` with small.yaml and ``configfile``: its exit code and the
    non-empty lines it printed."""
    exe = Path(sys.executable).with_name("morphlearn")
    proc = subprocess.run(
        [str(exe), "run", "-n", "--cores", "1", "--configfile", "small.yaml", configfile],
        cwd=wf,
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    return proc.returncode, [ln for ln in (proc.stdout + proc.stderr).splitlines() if ln.strip()]


@pytest.mark.parametrize("kind", ["empty", "binary", "list"])
def test_morphlearn_run_refuses_a_bad_configfile_in_one_line(wf: Path, kind: str) -> None:
    """`morphlearn run` (snakemake with the same arguments) checks the --configfile files before
    Snakemake reads them: the same file as above is refused in one line naming it, exit 2."""
    (wf / "bad.yaml").write_bytes(BAD_FILES[kind][0])
    before = sorted(p.relative_to(wf) for p in wf.rglob("*"))
    returncode, said = _morphlearn_run_dry(wf, "bad.yaml", timeout=300)
    assert returncode == 2 and len(said) == 1, said
    assert said[0].startswith("morphlearn run: config error: bad.yaml: "), said
    assert sorted(p.relative_to(wf) for p in wf.rglob("*")) == before  # nothing written


def test_morphlearn_run_finds_every_configfile_and_passes_good_ones_to_snakemake(wf: Path) -> None:
    from morphlearn.apps.cli import configfiles_of

    args = ["-n", "--configfile", "a.yaml", "b.yaml", "--cores", "1", "--configfiles=c.yaml", "all", "x"]
    assert configfiles_of(args) == ["a.yaml", "b.yaml", "c.yaml"]
    exe = Path(sys.executable).with_name("morphlearn")
    proc = subprocess.run(
        [str(exe), "run", "-n", "--cores", "1", "--configfile", "small.yaml", "--quiet", "rules"],
        cwd=wf,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0 and "theory_shard" in proc.stdout, proc.stderr[-2000:]


def test_workflow_refuses_a_wildcard_results_dir(wf: Path) -> None:
    line = _start_refusal(wf, "--configfile", "small.yaml", "--config", "results_dir=out{x}")
    assert line.startswith("morphlearn: config error: results_dir = 'out{x}' holds"), line


def test_workflow_from_another_folder_says_so(wf: Path, tmp_path: Path) -> None:
    # was: "'theory' is a required property" (config.yaml not found, skipped silently)
    line = _start_refusal(wf, "-s", str(wf / "Snakefile"), "--configfile", str(wf / "small.yaml"), cwd=tmp_path)
    assert f"the workflow runs from its own folder {wf.resolve()}" in line and "cd " in line, line


def test_results_dir_holding_a_bundle_is_not_advised_to_be_deleted(wf: Path) -> None:
    # a bundle made by another config (here: a store whose science digest is another's)
    b = wf / "bundle"
    (b / "theory/merged.zarr").mkdir(parents=True)
    (b / "theory/merged.zarr/zarr.json").write_text(json.dumps({"attributes": {"science_sha256": "0" * 64}}))
    (b / "bundle.json").write_text("{}")
    try:
        line = _start_refusal(wf, "--configfile", "small.yaml", "--config", "results_dir=bundle")
    finally:
        shutil.rmtree(b)
    assert "holds a results bundle" in line and "render_only" in line and "delete" not in line, line


def test_results_dir_with_a_space_and_quote_reaches_the_figure_commands_whole(wf: Path) -> None:
    """The figure rule's shell command, as Snakemake prints it (dry run), run with the two tools
    replaced by printf: the notebook's output folder arrives as one argument."""
    rd = "results/res ults/it's"  # under results/: the write guard refuses a folder outside it (issue 57)
    (wf / "space.yaml").write_text(yaml.safe_dump({"results_dir": rd, "figures": {"enabled": True}}))
    proc = snakemake(wf, "-n", "-p", "--cores", "1", "--configfile", "small.yaml", "space.yaml")
    cmd = next(line for line in proc.stdout.splitlines() if "jupyter nbconvert" in line and "fig1" in line)
    cmd = cmd.removeprefix("Shell command: ")
    cmd = cmd.replace("papermill ", "true ", 1).replace("jupyter nbconvert", "printf '%s\\n'", 1)
    (wf / rd / "logs/figures").mkdir(parents=True)
    subprocess.run(["bash", "-c", cmd], cwd=wf, check=True)
    args = (wf / rd / "logs/figures/fig1.log").read_text().splitlines()
    assert args[args.index("--output-dir") + 1] == f"{rd}/figures", args
    shutil.rmtree(wf / "results/res ults")


# --- results_dir: never a committed bundle (but to re-render it) nor a project folder (issue 38) ---

#: What a run refused at start says is allowed (config.RESULTS_ALLOWED).
WHERE_RESULTS_GO = "a folder of your own under results/ that is not a bundle"


@pytest.mark.parametrize(
    ("results_dir", "render_only", "needle"),
    [
        ("results/survey", False, "holds a results bundle (bundle.json)"),  # was: 7 min, 254 files in it
        ("./results//survey/", False, "holds a results bundle (bundle.json)"),  # the same folder spelled otherwise
        ("results/survey9-mujoco", False, "holds a results bundle (bundle.json)"),
        ("results/survey/theory", False, "is inside the results bundle"),
        ("results/survey/theory", True, "is inside the results bundle"),  # render-only: the bundle itself only
        (".", False, "is the project folder or one that holds it"),
        ("..", True, "is the project folder or one that holds it"),
        ("docs", False, "is the project's source folder docs/"),
        ("src/morphlearn", True, "is inside the project's source folder src/"),
        ("config", False, "is the project's source folder config/"),
        ("notebooks/out", False, "is inside the project's source folder notebooks/"),
        ("benchmarks", False, "is the project's source folder benchmarks/"),
        ("tools", False, "is the project's source folder tools/"),
        ("tests", False, "is the project's source folder tests/"),
        ("workflow", False, "is the project's source folder workflow/"),
        ("envs", False, "is the project's source folder envs/"),
    ],
)
def test_results_dir_refuses_bundles_and_project_folders(results_dir: str, render_only: bool, needle: str) -> None:
    msg = _one_line_config_error({"results_dir": results_dir, "render_only": render_only})
    assert msg.startswith(f"results_dir = {results_dir!r} {needle}") and WHERE_RESULTS_GO in msg, msg
    assert not any(w in msg.lower() for w in ("delete", "remove", "rm ")), msg


def test_results_dir_allows_a_new_folder_the_default_and_the_re_render_of_a_bundle() -> None:
    for rd, render_only in (("results/my-run", False), ("results", False), ("results/survey", True)):
        patch = {"results_dir": rd, "render_only": render_only, "figures": {"enabled": render_only}}
        assert config.validate(config.deep_merge(_base(), patch))["results_dir"] == rd


def test_bundle_dir_refuses_a_source_folder_and_a_folder_inside_a_bundle() -> None:
    """bundle_dir shares the guard (config.source_folder): an absent folder under src/ was allowed."""
    from morphlearn.bundles import make as bundle

    made = bundle.made_by(["config/smoke.yaml", "config.yaml"], "results")
    for target, needle in (
        ("src/morphlearn/new-bundle", "is inside the project's source folder src/"),
        ("results/survey/new-bundle", "is inside the results bundle"),
    ):
        with pytest.raises(bundle.BundleError) as e:
            bundle.check_target(target, made)
        assert str(e.value).startswith(f"bundle_dir = {target!r} {needle}"), e.value


def test_workflow_refuses_a_committed_bundle_as_results_dir_before_writing(wf: Path) -> None:
    """End to end, as the issue ran it (no render_only): refused at start, nothing written there."""
    b = wf / "results" / "committed"
    b.mkdir(parents=True)
    (b / "bundle.json").write_text("{}")
    try:
        exe = Path(sys.executable).with_name("snakemake")
        proc = subprocess.run(
            [str(exe), "-n", "--cores", "1", "--configfile", "small.yaml", "--config", "results_dir=results/committed"],
            cwd=wf,
            capture_output=True,
            text=True,
            timeout=300,
        )
        ours = [ln for ln in proc.stderr.splitlines() if ln.startswith("morphlearn")]
        assert proc.returncode == 2 and len(ours) == 1 and "Traceback" not in proc.stderr, proc.stderr[-2000:]
        assert ours[0].startswith("morphlearn: config error: results_dir = 'results/committed' holds a results bundle")
        assert sorted(p.name for p in b.iterdir()) == ["bundle.json"]
    finally:
        shutil.rmtree(wf / "results")


# --- unbounded input: size, depth, aliases, devices (issue 38; morphlearn.bounded) ---------------

_LAUGHS = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n" + "".join(
    f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 10)}]\n" for i in range(1, 8)
)
#: name -> (how to make the file in a folder, what the one line says)
UNBOUNDED: dict[str, tuple[Callable[[Path], Path], str]] = {
    "deep_lists": (lambda d: _write(d, "x: " + "[" * 5000 + "]" * 5000), "nested deeper than 100 levels (line 1)"),
    "deep_maps": (
        lambda d: _write(d, "".join(f"{' ' * i}k{i}:\n" for i in range(101)) + " " * 101 + "v: 1"),
        "nested deeper than 100 levels (line 101)",
    ),
    "self_alias": (lambda d: _write(d, "x: &a [*a]"), "the alias *a (line 1) is inside the collection &a"),
    "self_alias_map": (lambda d: _write(d, "grid: &g {weights: 5, again: *g}"), "the alias *g (line 1)"),
    "deep_through_alias": (
        lambda d: _write(d, "a: &a " + "[" * 60 + "]" * 60 + "\nb: " + "[" * 45 + "*a" + "]" * 45),
        "nested deeper than 100 levels (line 2)",
    ),
    "laughs": (lambda d: _write(d, _LAUGHS), "expands through its aliases to more than 1000000 values"),
    "eleven_mb": (lambda d: _write(d, "x: '" + "a" * (11 * 2**20) + "'"), "is larger than 10 MB"),
    "dev_zero": (lambda d: Path("/dev/zero"), "is a device, pipe or socket, not a regular file"),
    "fifo": (lambda d: (os.mkfifo(d / "fifo.yaml"), d / "fifo.yaml")[1], "is a device, pipe or socket"),
    "folder": (lambda d: d, "is a folder, not a regular file"),
}


def _write(d: Path, text: str) -> Path:
    (d / "attack.yaml").write_text(text + "\n")
    return d / "attack.yaml"


@pytest.mark.parametrize("kind", sorted(UNBOUNDED))
def test_unbounded_config_scenario_and_body_files_refused_in_one_line(
    kind: str, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    make, needle = UNBOUNDED[kind]
    p = make(tmp_path)
    for read in (configure.load, scenarios.read_file):
        with pytest.raises(config.ConfigError) as e:
            read(p)
        msg = str(e.value)
        assert msg.startswith(f"{p}: ") and needle in msg and "\n" not in msg, msg
    args = ["design", "--model", "empirical", "--l1", "0", "0", "--l2", "0", "0", "--morphology", str(p)]
    _refused(args, capsys, f"--morphology {p}: {needle}")


def test_aliases_within_the_limits_still_read(tmp_path: Path) -> None:
    """The negative control: an alias of a finished value, nested 100 deep in all, 10**6 values."""
    p = _write(tmp_path, "a: &a " + "[" * 50 + "]" * 50 + "\nb: " + "[" * 49 + "*a" + "]" * 49)
    assert set(config.yaml_mapping(p)) == {"a", "b"}
    p = _write(tmp_path, "".join(_LAUGHS.splitlines(keepends=True)[:5]))  # a4: 10**4 lists of 10 x
    assert len(config.yaml_mapping(p)) == 5


@pytest.mark.parametrize("kind", ["dev_zero", "fifo", "deep_lists", "self_alias"])
def test_morphlearn_run_refuses_an_unbounded_configfile_at_once(wf: Path, kind: str, tmp_path: Path) -> None:
    """Was: /dev/zero read until the machine ran out of memory (23.7 GB); a deep file, 2,995 lines."""
    p = UNBOUNDED[kind][0](tmp_path)
    returncode, said = _morphlearn_run_dry(wf, str(p), timeout=60)
    assert returncode == 2 and len(said) == 1, said
    assert said[0].startswith(f"morphlearn run: config error: {p}: {UNBOUNDED[kind][1]}"), said


def test_workflow_refuses_a_self_alias_snakemake_read_in_one_line(wf: Path) -> None:
    """Snakemake reads the file itself first (a recursive list is valid YAML to it); the Snakefile's
    first check refuses it in one line (was: 990 lines from common.smk)."""
    (wf / "alias.yaml").write_text("x: &a [*a]\n")
    line = _start_refusal(wf, "--configfile", "small.yaml", "alias.yaml")
    assert line.startswith("morphlearn: config error: ") and "alias.yaml: the alias *a (line 1)" in line, line


def test_scenario_file_key_refuses_an_unbounded_file(wf: Path) -> None:
    (wf / "deep_scenarios.yaml").write_text("s: " + "[" * 5000 + "]" * 5000 + "\n")
    line = _start_refusal(
        wf, "--configfile", "small.yaml", "--config", "scenarios=all", "scenario_file=deep_scenarios.yaml"
    )
    assert "deep_scenarios.yaml: nested deeper than 100 levels" in line, line


def _bundle(tmp_path: Path, manifest: str) -> Path:
    b = tmp_path / "b"
    b.mkdir()
    (b / "a.txt").write_text("a\n")
    (b / "bundle.json").write_text(manifest)
    return b


@pytest.mark.parametrize(
    ("manifest", "needle"),
    [
        ('{"files": ' + "[" * 5000 + "]" * 5000 + "}", "bundle.json: unreadable (nested deeper than 100 levels"),
        ('{"files": {}, "made_by": ' + "[" * 200 + "]" * 200 + "}", "bundle.json: unreadable (nested deeper than 100"),
        ('{"files": {"' + "x" * 300 + '.csv": "' + "0" * 64 + '"}}', "(304 characters), a name longer than the file"),
        ('{"files": {"a\\u0000b.csv": "' + "0" * 64 + '"}}', "lists 'a\\x00b.csv', a name with a NUL byte"),
        ('{"files": {"' + "d/" * 2100 + 'f": "' + "0" * 64 + '"}}', "a name longer than the file system allows"),
    ],
)
def test_check_bundle_says_one_line_for_a_hostile_manifest(
    manifest: str, needle: str, tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    b = _bundle(tmp_path, manifest)
    rc, out, err = _cli(["check-bundle", str(b)], capsys)
    assert rc == 1 and err == "" and "Traceback" not in out, (rc, out[-500:], err)
    assert needle in out.splitlines()[0] and len(out.splitlines()[0]) < 400, out[:600]


def test_check_bundle_and_rerender_refuse_a_300_character_folder_name(capsys: pytest.CaptureFixture) -> None:
    for cmd in ("check-bundle", "rerender-bundle"):
        _refused([cmd, "results/" + "y" * 300], capsys, "(308 characters): cannot be read (File name too long)")


def test_a_deep_provenance_record_is_one_custody_error(tmp_path: Path) -> None:
    from morphlearn import provenance

    (tmp_path / "metrics.csv").write_text("design\n0\n")
    (tmp_path / "metrics.provenance.json").write_text("[" * 3000 + "]" * 3000)
    with pytest.raises(provenance.CustodyError, match=r"unreadable provenance record \(nested deeper than 100"):
        provenance.check_derived(tmp_path / "metrics.csv")


# --- messages that say what is allowed (issue 38, item 8) ---------------------------------------


@pytest.mark.parametrize("designs", ["bogus", [[1, 2]], [[[0.5, 0.5]]]])
def test_invalid_empirical_designs_says_what_is_allowed(designs: object) -> None:
    msg = _one_line_config_error({"empirical": {**PHYSICS, "designs": designs}})
    assert msg.startswith("empirical.designs = ") and not msg.rstrip().endswith("allowed:"), msg
    assert 'allowed: "all" (every design of the grid), a list of designs [[x1, y1], [x2, y2]]' in msg, msg
    assert "{top_of: {bundle, model, by, n}}" in msg and "{random: {n, seed}}" in msg, msg


def test_a_nested_config_value_given_on_the_command_line_is_said_to_arrive_as_a_string(wf: Path) -> None:
    line = _start_refusal(wf, "--configfile", "small.yaml", "--config", "grid={positions_per_axis: 3, weights: 7}")
    assert line.startswith("morphlearn: config error: grid."), line
    assert "= '3' is invalid" in line or "= '7' is invalid" in line, line
    assert "nested --config value" in line and "as strings: give them in a --configfile YAML" in line, line


def test_resimulate_an_index_off_the_grid_is_a_usage_error_naming_the_range(capsys: pytest.CaptureFixture) -> None:
    rc, _, err = _cli(["check-bundle", str(SURVEY), "--resimulate", "99999"], capsys)
    assert rc == 2 and len(err.splitlines()) == 1, (rc, err)
    assert "--resimulate '99999': no design 99999 on this bundle's grid; allowed: a design index 0 to 624" in err, err


@pytest.mark.parametrize("cores", ["0", "-1"])
def test_rerender_bundle_refuses_cores_below_one(cores: str, capsys: pytest.CaptureFixture) -> None:
    _refused(
        ["rerender-bundle", "results/survey", "--cores", cores], capsys, f"--cores = {cores}; allowed: an integer >= 1"
    )


def test_design_dt_too_small_is_said_in_a_short_number(capsys: pytest.CaptureFixture) -> None:
    err = _refused(["design", "--l1", "0.5", "0.5", "--l2", "0.5", "-0.5", "--weights", "3", "--dt", "1e-300"], capsys)
    assert "--dt 1e-300 needs 5e+302 RK4 steps" in err and len(err) < 200, err


def test_docs_say_how_a_killed_local_run_resumes() -> None:
    text = " ".join((ROOT / "docs/workflow.md").read_text().split())
    at = text.index("a killed shard resumes")
    assert "--unlock" in text[at : at + 800] and "--rerun-incomplete" in text[at : at + 800]
