"""Issue 57, build items 2 and 3 attacked: a forger who reads the code and keeps every digest
consistent (check-bundle checks what a bundle means, not only its bytes), and writers that must
not write into a bundle, the source tree or a system folder (one write guard,
:func:`morphlearn.config.write_refusal`). Each attack is the issue's command, on a copy: no
committed bundle byte changes (checked at the end of each test that could touch one)."""

from __future__ import annotations

import contextlib
import io
import json
import os
import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from conftest import ROOT, copy_workflow

from morphlearn import config, metrics, models, provenance, store
from morphlearn.apps import cli
from morphlearn.bundles import check as bundle_check
from morphlearn.bundles import make as bundle
from morphlearn.bundles import resimulate

ODE_PAPER = ROOT / "results" / "ode-paper"
SURVEY = ROOT / "results" / "survey"


def _check(*args: str) -> tuple[int, str]:
    """``morphlearn check-bundle ARGS``: exit code and what it printed (stdout)."""
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        rc = cli.main(["check-bundle", *args])
    return rc, buf.getvalue()


def _manifest(b: Path) -> dict:
    return json.loads((b / bundle.MANIFEST).read_text())


def _edit_manifest(b: Path, change: Callable[[dict], None]) -> None:
    m = _manifest(b)
    change(m)
    (b / bundle.MANIFEST).write_text(json.dumps(m, indent=1, sort_keys=True) + "\n")


def _reseal(b: Path) -> None:
    """What the forger does last: bundle.json lists exactly the files there, with their digests."""
    files = {
        p.relative_to(b).as_posix(): provenance.sha256_file(p)
        for p in sorted(b.rglob("*"))
        if p.is_file() and not p.is_symlink() and p.name != bundle.MANIFEST
    }
    _edit_manifest(b, lambda m: m.update(files=files))


def _edit_row(b: Path, model: str, design: int, **values: object) -> None:
    path = b / model / "metrics.csv"
    t = pd.read_csv(path)
    for k, v in values.items():
        t.loc[t.design == design, k] = v
    t.to_csv(path, index=False, float_format=metrics.CSV_FLOAT_FORMAT)


def _digests(root: Path) -> dict[str, str]:
    return {p.relative_to(root).as_posix(): provenance.sha256_file(p) for p in sorted(root.rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def committed() -> dict[str, dict[str, str]]:
    """The digests of the committed bundles these attacks copy, before them."""
    return {b.name: _digests(b) for b in (ODE_PAPER, SURVEY)}


@pytest.fixture
def ode(tmp_path: Path) -> Path:
    """``cp -a results/ode-paper ../nc`` (the issue's copy; its store holds all 10 designs' arrays)."""
    b = tmp_path / "nc"
    shutil.copytree(ODE_PAPER, b, symlinks=True)
    assert bundle_check.check(b) == []
    return b


def _unchanged(committed: dict[str, dict[str, str]]) -> None:
    for b in (ODE_PAPER, SURVEY):
        assert _digests(b) == committed[b.name], f"{b}: a committed byte changed"


# -- D4: every chunk a store declares is present and readable, within a memory bound -----------


def test_deleted_chunks_are_missing_not_skipped(ode: Path, committed: dict) -> None:
    """rm -rf ../nc/ode/merged.zarr/{first_time,min_dist,status}/c, the vanished files dropped from
    bundle.json: was exit 0; then design 6552's row edited to 2 generalists and re-sealed."""
    for k in store.VARS:
        shutil.rmtree(ode / f"ode/merged.zarr/{k}/c")
    _reseal(ode)
    rc, out = _check(str(ode))
    assert rc == 1 and "first_time of design 160 (position 0): its chunk file is missing" in out, out
    _edit_row(ode, "ode", 6552, generalists=2, M_L=float(metrics.CSV_FLOAT_FORMAT % (2 / 121**2)))
    t = pd.read_csv(ode / "ode/metrics.csv").set_index("design").loc[6552]
    _edit_row(ode, "ode", 6552, M_CF=float(metrics.CSV_FLOAT_FORMAT % (2 / t.at_least_one)))
    _reseal(ode)
    rc, out = _check(str(ode))
    assert rc == 1 and "its chunk file is missing" in out and "Traceback" not in out, out
    _unchanged(committed)


@pytest.mark.parametrize("chunks", [True, False], ids=["chunks kept", "no chunks"])
def test_a_store_declaring_40000_weights_is_refused_not_read(ode: Path, chunks: bool) -> None:
    """zarr.json declaring 40000 x 40000 weights (own dimension names, so xarray opens it beside
    the 121 weights of the coordinates), with or without chunks: the MemoryError of reading one
    chunk was swallowed and it passed. Now refused before a chunk is read."""
    z = ode / "ode/merged.zarr"
    for name in store.VARS:
        meta = json.loads((z / name / "zarr.json").read_text())
        meta["shape"] = [10, 4, 40000, 40000]
        meta["chunk_grid"]["configuration"]["chunk_shape"] = [1, 4, 40000, 40000]
        meta["dimension_names"] = ["design", "env", "a", "b"]
        (z / name / "zarr.json").write_text(json.dumps(meta))
        if not chunks:
            shutil.rmtree(z / name / "c")
    _reseal(ode)
    rc, out = _check(str(ode))
    assert rc == 1 and "declares dims ('design', 'env', 'a', 'b'), shape (10, 4, 40000, 40000)" in out, out
    assert "Traceback" not in out, out


def test_open_merged_bounds_what_a_chunk_read_decodes(tmp_path: Path) -> None:
    """The bound itself: a store with digests, consistent, but 1002 weights per synapse (one
    more than the schema allows) is refused by every reader (store.open_merged)."""
    m = store.MAX_WEIGHTS + 1
    arrays = {k: np.full((4, m, m), store.FILL[k]) for k in store.VARS}
    store._write_store(tmp_path / "big.zarr", np.array([0]), np.zeros((1, 4)), np.linspace(-1, 1, m), [(0, arrays)], {})
    with pytest.raises(store.IntegrityError, match=f"declares {m} weights per synapse; allowed: 1 to 1001"):
        store.open_merged(tmp_path / "big.zarr")


# -- D5: every column the arrays determine agrees, required columns exist ----------------------


def test_flagged_is_checked_against_the_arrays(ode: Path) -> None:
    _edit_row(ode, "ode", 722, flagged=int(pd.read_csv(ode / "ode/metrics.csv").set_index("design").flagged[722]) + 5)
    _reseal(ode)
    rc, out = _check(str(ode))
    assert rc == 1 and "design 722: its row's counts differ from the merged store's arrays" in out, out


@pytest.mark.parametrize("columns", [["l1x", "l1y", "l2x", "l2y"], ["model"], ["flagged"], ["l2y"]])
def test_a_table_without_a_required_column_is_refused(ode: Path, columns: list[str]) -> None:
    path = ode / "ode/metrics.csv"
    pd.read_csv(path).drop(columns=columns).to_csv(path, index=False, float_format=metrics.CSV_FLOAT_FORMAT)
    _reseal(ode)
    rc, out = _check(str(ode))
    assert rc == 1 and f"no column {columns[0]!r} (a metrics table has model, design, l1x" in out, out
    assert out.count(f"no column {columns[0]!r}") == 1, out  # said once, not by each check


# -- D6: sample:K drawn afresh, the seed printed, the chance stated ----------------------------


def _draw(b: Path, which: str, monkeypatch: pytest.MonkeyPatch, seed: int | None = None) -> list[str]:
    """What ``--resimulate WHICH`` says of its draw (the simulation itself stubbed out)."""

    def no_simulation(*_: object) -> list:
        raise NotImplementedError("stubbed in this test")

    monkeypatch.setattr(models.get(models.REFERENCE), "resimulate", no_simulation)
    said: list[str] = []
    resimulate.resimulate(b, [which], seed=seed, say=said.append)
    return said


def test_a_sample_is_drawn_afresh_with_its_seed_and_chance_printed(monkeypatch: pytest.MonkeyPatch) -> None:
    """Seeded with 0, survey sample:10 was always {10, 25, 46, 109, 166, 190, 315, 393, 508, 523}:
    a forger avoided them. Now each run draws anew, prints the seed that replays it and the
    chance that K rows catch a forgery of one design."""
    first, second = (_draw(SURVEY, "sample:10", monkeypatch) for _ in range(2))
    assert first != second, (first, second)
    (line,) = first
    assert "theory sample:10: designs [" in line and "chance 10/625 = 0.016" in line, line
    seed = int(line.split("seed ")[1].split(" ")[0])
    assert _draw(SURVEY, "sample:10", monkeypatch, seed=seed) == first  # replayed exactly
    assert "[10, 25, 46, 109, 166, 190, 315, 393, 508, 523]" in _draw(SURVEY, "sample:10", monkeypatch, seed=0)[0]


def test_check_bundle_prints_the_seed_and_refuses_a_bad_one(capsys: pytest.CaptureFixture) -> None:
    rc = cli.main(["check-bundle", str(ODE_PAPER), "--resimulate", "ode:sample:1", "--seed", "-1"])
    err = capsys.readouterr().err
    assert rc == 2 and "--seed = -1; allowed: an integer 0 to" in err, err


# -- D7: bundle.json's commits, command and subsets are what made it ---------------------------


def _attack_manifest(name: str, change: Callable[[dict], None], want: str) -> Callable[[Path], str]:
    def attack(b: Path) -> str:
        _edit_manifest(b, change)
        return want

    attack.__name__ = name
    return attack


def _sim(m: dict) -> dict:
    return m["subsets"]["ode"]["simulated_by"]


MANIFEST_FORGERIES = [
    _attack_manifest(
        "made_by commit 0123...4567",
        lambda m: m["made_by"].update(git_commit="0123456789abcdef0123456789abcdef01234567"),
        "made_by.git_commit names commit 0123456789abcdef0123456789abcdef01234567, which is not in this repository",
    ),
    _attack_manifest(
        "simulated_by commits ffff",
        lambda m: _sim(m).update(git_commits={"f" * 40: sum(_sim(m)["git_commits"].values())}),
        f"subsets.ode.simulated_by.git_commits names commit {'f' * 40}, which is not in this repository",
    ),
    _attack_manifest(
        "made_by commit not a hash",
        lambda m: m["made_by"].update(git_commit="v1.0"),
        "made_by.git_commit names 'v1.0', not a commit",
    ),
    _attack_manifest(
        "subsets.designs [1, 2, 3]",
        lambda m: m["subsets"]["ode"].update(designs=[1, 2, 3]),
        "subsets.ode.designs 1, 2, 3 are not the designs ode/merged.zarr holds",
    ),
    _attack_manifest(
        "subsets.of",
        lambda m: m["subsets"]["ode"].update(of=6561),
        "subsets.ode.of = 6561, but ode/metrics.csv has 10 rows",
    ),
    _attack_manifest("command rm -rf /", lambda m: m["made_by"].update(command="rm -rf /"), "not a snakemake command"),
    _attack_manifest(
        "command with a shell",
        lambda m: m["made_by"].update(command="snakemake --cores 2; curl x | sh"),
        "not a snakemake command of plain words",
    ),
    _attack_manifest(
        "command of other configs",
        lambda m: m["made_by"].update(command="snakemake --cores 2 --configfile config/paper.yaml"),
        "its configs ['config/ode_paper.yaml', 'config.yaml'] give "
        "'snakemake --cores 2 --configfile config/ode_paper.yaml'",
    ),
    _attack_manifest(
        "configs outside config/",
        lambda m: m["made_by"].update(configs=["/etc/passwd"]),
        "made_by.configs = \"['/etc/passwd']\"; allowed",
    ),
    _attack_manifest(
        "configs that do not exist",
        lambda m: m["made_by"].update(
            configs=["config/nothing.yaml", "config.yaml"],
            command="snakemake --cores 2 --configfile config/nothing.yaml",
        ),
        "names the config file config/nothing.yaml, which this repository does not hold",
    ),
    _attack_manifest("no made_by", lambda m: m.pop("made_by"), "no made_by record"),
]


@pytest.mark.parametrize("attack", MANIFEST_FORGERIES, ids=lambda f: f.__name__)
def test_check_bundle_checks_what_bundle_json_records(ode: Path, attack: Callable[[Path], str]) -> None:
    want = attack(ode)
    rc, out = _check(str(ode))
    assert rc == 1 and want in out and "Traceback" not in out, out


def test_subsets_must_be_the_designs_its_configs_keep(tmp_path: Path) -> None:
    """The survey bundle keeps the drawn designs of its every-design theory table (analysis.top
    10 of config/survey.yaml at its commit): a forger who drops the best design's arrays from the
    store (re-cut, digests right) and from subsets, to forge its row, is caught."""
    b = tmp_path / "survey"
    shutil.copytree(SURVEY, b, ignore=shutil.ignore_patterns("logs", "benchmarks", "*.html", ".snakemake*"))
    shutil.copy2(SURVEY / "reproduction.html", b / "reproduction.html")
    held = _manifest(b)["subsets"]["theory"]["designs"]
    keep = held[1:]
    shutil.rmtree(b / "theory/merged.zarr")
    store.write_subset(SURVEY / "theory/merged.zarr", keep, b / "theory/merged.zarr")
    _edit_manifest(b, lambda m: m["subsets"]["theory"].update(designs=keep))
    _reseal(b)
    rc, out = _check(str(b))
    assert rc == 1 and "subsets.theory.designs are not the designs its configs keep" in out, out
    assert f"they differ in design {held[0]}" in out, out


def test_a_shallow_clone_says_it_cannot_tell(ode: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A commit the history lacks in a shallow clone is not called forged: a note says so."""
    monkeypatch.setattr(provenance, "in_history", lambda c, cwd=None: False)
    monkeypatch.setattr(provenance, "is_shallow", lambda cwd=None: True)
    rc, out = _check(str(ode))
    assert rc == 0 and "note: cannot tell whether 1 commit(s) it names" in out and "shallow clone" in out, out


# -- D15: unlisted links of any kind ----------------------------------------------------------


@pytest.mark.parametrize(
    ("name", "target"),
    [("etcdir", "/etc"), ("loop", "."), ("ode2", "ode"), ("ode/up", ".."), ("dangling", "nowhere"), ("f", "README.md")],
)
def test_unlisted_links_of_any_kind_are_reported(ode: Path, name: str, target: str) -> None:
    os.symlink(target, ode / name)
    rc, out = _check(str(ode))
    assert rc == 1 and f"{ode / name}: a symbolic link (to '{target}'), not listed in bundle.json" in out, out


def test_a_pipe_in_a_bundle_is_reported(ode: Path) -> None:
    os.mkfifo(ode / "ode/pipe")
    rc, out = _check(str(ode))
    assert rc == 1 and "ode/pipe: neither a file nor a folder" in out, out


# -- D8-D10: one write guard -----------------------------------------------------------------


@pytest.fixture
def project(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A project folder to write into (as a clone): the survey bundle, a refine folder, source
    folders and a .git folder; the commands run from it."""
    p = tmp_path / "clone"
    for rel in ("results/survey", "results/refine/canonical_121"):
        shutil.copytree(ROOT / rel, p / rel)
    for rel in ("src/morphlearn", "tools", ".git", ".venv", ".snakemake"):
        (p / rel).mkdir(parents=True)
    (p / "Snakefile").write_text("")
    monkeypatch.chdir(p)
    return p


@pytest.mark.parametrize(
    ("dest", "needle"),
    [
        ("results/survey/x", "is inside the results bundle"),
        ("results/survey/theory/y", "is inside the results bundle"),
        ("results/survey", "holds a results bundle"),
        ("src/morphlearn/x", "is inside the project's source folder src/"),
        ("tools/x", "is inside the project's source folder tools/"),
        (".git/x", "has the hidden folder '.git' in it"),
        (".venv", "has the hidden folder '.venv' in it"),
        ("results/.x", "has the hidden folder '.x' in it"),
        ("/proc/morphlearn-x", "is outside the project's results/ folder"),  # not /etc: main wrote there
        ("elsewhere", "is outside the project's results/ folder"),
        ("results/../x", "is outside the project's results/ folder"),
        ("results/link/x", "is a symbolic link out of results/"),
    ],
)
def test_the_write_guard_refuses_where_no_writer_may_write(project: Path, dest: str, needle: str) -> None:
    """The guard of every writer (config.write_refusal: results_dir, bundle_dir; once also
    ``morphlearn refine export``, which exited 0 and wrote into a committed bundle, src/, tools/ and
    .git/): each of those places is refused, saying why."""
    from morphlearn.config import write_refusal

    os.symlink("/proc", project / "results/link")  # not /etc: main wrote through it (as root)
    why = write_refusal(dest)
    assert why is not None and needle in why, why
    assert write_refusal("results/my-export") is None  # a folder of your own under results/ is allowed


@pytest.mark.parametrize(
    ("rd", "needle"),
    [
        (".git", "has the hidden folder '.git' in it"),
        (".venv", "has the hidden folder '.venv' in it"),
        (".snakemake", "has the hidden folder '.snakemake' in it"),
        ("results/.snakemake", "has the hidden folder '.snakemake' in it"),
        ("/etc", "is outside the project's results/ folder"),
        ("/etc/morphlearn", "is outside the project's results/ folder"),
        ("/usr/local/x", "is outside the project's results/ folder"),
        ("results/x", "is a symbolic link out of results/ (to /etc)"),
        ("results/x/y", "is a symbolic link out of results/"),
    ],
)
def test_results_dir_refuses_hidden_system_and_linked_folders(project: Path, rd: str, needle: str) -> None:
    os.symlink("/etc", project / "results/x")
    with pytest.raises(config.ConfigError) as e:
        config.check_results_dir(rd)
    msg = str(e.value)
    assert msg.startswith(f"results_dir = {rd!r} {needle}"), msg
    assert "allowed: a folder of your own under results/ that is not a bundle" in msg, msg


def test_results_dir_allows_its_own_folders(project: Path, tmp_path: Path) -> None:
    for rd in ("results", "results/my-run", "results/a/b", str(project / "results/new"), str(tmp_path / "scratch")):
        config.check_results_dir(rd)


@pytest.mark.parametrize("target", ["results/survey", "results/c"])
def test_render_only_refuses_a_bundle_without_its_own_configs(project: Path, target: str) -> None:
    """cp -a results/survey results/c; render_only=True results_dir=results/c without
    --configfile config/survey.yaml rewrote reproduction.csv/.md/.html with the wrong config; the
    same with results_dir=results/survey passed the guard. With its own configs it re-renders."""
    if target == "results/c":
        shutil.copytree(project / "results/survey", project / target)
    for configs in (["config.yaml"], ["config/paper.yaml", "config.yaml"], []):
        with pytest.raises(config.ConfigError, match="holds a results bundle made by configs"):
            config.check_results_dir(target, True, configs)
    config.check_results_dir(target, True, ["config/survey.yaml", "config.yaml"])
    config.check_results_dir(target, True, ["config.yaml", "./config/survey.yaml"])  # spelled otherwise
    work = project / "results/.rerender-survey-abc"  # morphlearn render's working copy
    shutil.copytree(project / "results/survey", work)
    config.check_results_dir(str(work.relative_to(project)), True, ["config/survey.yaml", "config.yaml"])
    with pytest.raises(config.ConfigError, match="holds a results bundle"):  # a run that is no re-render
        config.check_results_dir(str(work.relative_to(project)), False)
    shutil.rmtree(work)
    work.mkdir()  # not a bundle: then its hidden name refuses it
    with pytest.raises(config.ConfigError, match=r"has the hidden folder '\.rerender-survey-abc'"):
        config.check_results_dir(str(work.relative_to(project)), False)


def _dry_run(wd: Path, *args: str) -> subprocess.CompletedProcess:
    exe = Path(sys.executable).with_name("snakemake")
    return subprocess.run([str(exe), "-n", "--cores", "1", *args], cwd=wd, capture_output=True, text=True, timeout=600)


def test_the_workflow_refuses_them_before_planning_a_job(tmp_path: Path, committed: dict) -> None:
    """End to end, as the issue ran them (dry runs: they planned jobs): one line, exit 2; the
    bundle's own render with its configs still plans."""
    wd = copy_workflow(tmp_path / "wf")
    shutil.copytree(wd / "results/survey", wd / "results/c")
    os.symlink("/etc", wd / "results/x")
    before = _digests(wd / "results")
    for args, needle in (
        (("--config", "render_only=True", "results_dir=results/c", "--forceall"), "would re-render the bundle"),
        (("--config", "render_only=True", "results_dir=results/survey"), "would re-render the bundle"),
        (("--config", "results_dir=.snakemake"), "has the hidden folder '.snakemake'"),
        (("--config", "results_dir=/etc"), "is outside the project's results/ folder"),
        (("--config", "results_dir=results/x"), "is a symbolic link out of results/"),
    ):
        proc = _dry_run(wd, *args)
        ours = [ln for ln in proc.stderr.splitlines() if ln.startswith("morphlearn")]
        assert proc.returncode == 2 and len(ours) == 1 and needle in ours[0], (args, proc.stderr[-2000:])
        assert "Traceback" not in proc.stderr
    proc = _dry_run(wd, "--configfile", "config/survey.yaml", "--config", "render_only=True", "results_dir=results/c")
    assert proc.returncode == 0 and "reproduction" in proc.stdout, proc.stderr[-2000:]
    assert _digests(wd / "results") == before
    _unchanged(committed)


@pytest.mark.parametrize("out", ["src/morphlearn/b", "tools/b", ".git/b", "/proc/b", "results/link/b"])
def test_the_other_bundle_writers_share_the_guard(project: Path, out: str, capsys: pytest.CaptureFixture) -> None:
    """Any other writer: a scenario bundle's folder (one guard)."""
    from morphlearn.bundles import scenario as scenario_bundle

    os.symlink("/proc", project / "results/link")
    assert scenario_bundle.main(["build", "results/scenarios", out]) == 2
    assert "nothing was written" in capsys.readouterr().out
    assert not Path(out).exists()
