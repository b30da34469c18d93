"""Shared fixtures: the repository root and a throw-away copy of the workflow to run in."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _head() -> str:
    try:
        out = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return "test"
    return out.stdout.strip() if out.returncode == 0 else "test"


#: The commit the tests' runs and records name (MORPHLEARN_GIT_COMMIT): this checkout's HEAD, so a
#: bundle they make names a commit of this history, as check-bundle requires (issue 57); "test"
#: where there is no git (check-bundle then says it cannot tell).
TEST_COMMIT = os.environ.get("MORPHLEARN_GIT_COMMIT") or _head()
os.environ["MORPHLEARN_GIT_COMMIT"] = TEST_COMMIT  # in-process records too (a dirty worktree: still HEAD)
WORKFLOW_FILES = (
    "Snakefile",
    "config.yaml",
    "config",
    "workflow",
    "src",
    "envs",
    "notebooks",
    "profiles",
    "results/survey",
)


def parse_at_root(cfg: dict) -> object:
    """``configure.parse(cfg)`` run from the repository root: a config's bundle paths (top_of,
    adaptive_screen, results_from) are relative to it, as in the workflow."""
    from morphlearn import configure

    cwd = Path.cwd()
    os.chdir(ROOT)
    try:
        return configure.parse(cfg)
    finally:
        os.chdir(cwd)


def ode_only_config(ode: dict, grid: dict | None = None) -> object:
    """config.yaml with the ODE model alone on (theory, pybullet and figures off) and this ``ode``
    section, parsed at the repository root (:func:`parse_at_root`); ``grid``: another design grid."""
    from morphlearn import config

    cfg = config.read(ROOT / "config.yaml")
    cfg.update(results_dir="results/x", figures={"enabled": False}, empirical={"enabled": False})
    if grid is not None:
        cfg["grid"] = grid
    cfg["theory"] = {**cfg["theory"], "enabled": False}
    cfg["ode"] = {"enabled": True, **ode}
    return parse_at_root(cfg)


def copy_workflow(dest: Path) -> Path:
    """Copy what a user's clone holds (no results but the committed survey bundle, which the
    default config reads) into ``dest``."""
    dest.mkdir(parents=True, exist_ok=True)
    for name in WORKFLOW_FILES:
        src = ROOT / name
        if src.is_dir():
            # src's bytecode is copied (tools/setup.sh compiles it; copy2 keeps the mtimes it is
            # checked against), so the copy's processes do not compile the package from source
            skip = ("*.nbi", "*.nbc") if name == "src" else ("__pycache__", "*.nbi", "*.nbc")
            shutil.copytree(src, dest / name, ignore=shutil.ignore_patterns(*skip))
        elif src.exists():
            shutil.copy2(src, dest / name)
    return dest


def paper_sources() -> list[str]:
    """The committed bundles config/paper.yaml reads besides results/paper itself (its physics at
    121 x 121, the 6561-design survey, the screen and its refinement, the second theory sweep): a
    clone holds them, so a copy that parses that config needs them too."""
    import yaml

    cfg = yaml.safe_load((ROOT / "config/paper.yaml").read_text())
    found = [(sec or {}).get("results_from") for sec in cfg.values() if isinstance(sec, dict)]
    found.append((cfg.get("survey_from") or {}).get("bundle"))
    found += [(cfg.get("screen_from") or {}).get(k) for k in ("bundle", "refinement")]
    found.append(cfg.get("text_sweep_from"))
    return sorted({p for p in found if p and p != "results/paper"})


def copy_paper_sources(dest: Path) -> None:
    """Copy :func:`paper_sources` into the workflow copy ``dest``."""
    for rel in paper_sources():
        shutil.copytree(ROOT / rel, dest / rel, dirs_exist_ok=True)


def written_results(workdir: Path) -> list[Path]:
    """What a run wrote under ``results/`` (the committed bundles a clone holds excluded)."""
    root = workdir / "results"
    kept = {Path(n).name for n in WORKFLOW_FILES if n.startswith("results/")}
    return sorted(p for p in root.iterdir() if p.name not in kept) if root.exists() else []


def snakemake(workdir: Path, *args: str, timeout: int = 900, check: bool = True) -> subprocess.CompletedProcess:
    exe = Path(sys.executable).with_name("snakemake")
    env = dict(os.environ, MORPHLEARN_GIT_COMMIT=TEST_COMMIT)
    proc = subprocess.run([str(exe), *args], cwd=workdir, capture_output=True, text=True, timeout=timeout, env=env)
    if check and proc.returncode != 0:
        raise AssertionError(f"snakemake {' '.join(args)} failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    return proc


def job_stats(output: str) -> dict[str, int]:
    """Job counts per rule from snakemake's 'Job stats' table ({} when nothing is to be done)."""
    m = re.search(r"Job stats:\n(.*?)\n\n", output + "\n\n", re.S)
    if not m:
        return {}
    rows = (line.split() for line in m.group(1).splitlines())
    return {r[0]: int(r[1]) for r in rows if len(r) == 2 and r[1].isdigit() and r[0] != "total"}


@pytest.fixture(scope="session")
def smoke_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One smoke run of the workflow, shared by the tests that only read its results."""
    wd = copy_workflow(tmp_path_factory.mktemp("smoke"))
    snakemake(wd, "--cores", "2", "--configfile", "config/smoke.yaml")
    return wd


#: The longest test groups, longest first (pytest --durations of a CI-equivalent run on a fresh
#: clone, 2-core VM, 2026-11-25 23:25: about 11, 8, 4, 4, 2, 2 and 1.5 minutes); every other group
#: took under a minute.
LONGEST_GROUPS = (
    "smoke_run",
    "test_envs",
    "test_survey",
    "test_paper_bundle",
    "test_reliability",
    "test_design_cache",
    "test_scenarios",
)


@pytest.hookimpl(tryfirst=True)  # before xdist reads the marks into its node ids
class Killed(BaseException):
    """Stands for Ctrl-C or a SIGTERM turned into an exception."""


def counting_runs(
    monkeypatch: pytest.MonkeyPatch, kill_at: int | None = None, at_kill: Callable[[], None] | None = None
) -> list[int]:
    """Count real pybullet episodes (EpisodeRunner.run); raise Killed at episode ``kill_at``
    (1-based) if given, after calling ``at_kill`` (which sees what is on disk before any handler runs)."""
    from morphlearn.empirical import EpisodeRunner

    calls: list[int] = []
    run = EpisodeRunner.run

    def counted(self, *a, **k):
        calls.append(1)
        if kill_at is not None and len(calls) == kill_at:
            if at_kill is not None:
                at_kill()
            raise Killed
        return run(self, *a, **k)

    monkeypatch.setattr(EpisodeRunner, "run", counted)
    return calls


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Under pytest-xdist (``-n N --dist loadgroup``, tools/test.sh) a worker takes whole groups: a
    group is one test file (its module-scoped toy runs made once), and the files that read the
    session's smoke run are one group, so that run is made once, not once per worker."""
    shared = {item.path for item in items if "smoke_run" in item.fixturenames}
    group = {item: "smoke_run" if item.path in shared else item.path.stem for item in items}
    for item in items:
        item.add_marker(pytest.mark.xdist_group(group[item]))
    # The longest groups first (tools/test.sh passes --no-loadscope-reorder, so xdist hands groups
    # out in this order): a long group started last would leave the other workers idle at the end.
    rank = {g: i for i, g in enumerate(LONGEST_GROUPS)}
    items.sort(key=lambda item: rank.get(group[item], len(rank)))


#: The authors' canonical design on 11 x 11 weights: the overlap O (rows w1, columns w2, from -1),
#: from the authors' facts (docs/ode.md); ODE gives it, and its rows w1 = -1 .. -0.4 agree with their
#: published matrix (tests/test_ode.py, tests/test_reduced.py).
CANONICAL_O_11 = """
0,1,2,0,0,0,0,0,0,0,0
1,0,2,0,0,0,0,0,0,0,0
2,2,0,2,0,0,0,0,0,0,0
0,0,2,0,0,0,0,0,0,0,0
0,0,0,0,0,0,0,0,0,0,0
0,0,0,0,0,0,0,0,0,0,0
0,0,0,0,0,0,2,0,0,0,0
0,0,0,0,0,0,0,2,0,0,0
0,0,0,0,0,0,0,0,2,1,0
0,0,0,0,0,0,0,0,1,2,2
0,0,0,0,0,0,0,0,0,2,4
"""
