"""The workflow on a real one-node SLURM cluster.

Starts Debian's slurm-wlm + munge on this machine with tools/slurm/start_local_slurm.sh
(session fixture; stopped at the end if this session started it), then

- runs the smoke config through SLURM (profiles/slurm-test) and locally (--cores 2) in two
  scratch copies of the workflow and compares the merged results bit for bit;
- checks that resuming resubmits only what is missing (dry runs after the SLURM run);
- checks that a failing SLURM job is reported with its SLURM log path and the rule's log;
- dry-runs the full sweep with profiles/slurm and checks the shard count and resources.

Needs root and apt-get (or SLURM + munge already installed). Otherwise the tests skip, or
fail when MORPHLEARN_REQUIRE_SLURM=1. Run with:  pytest -m slurm -s tests/test_slurm.py
Every Snakemake run is bounded by `timeout -s KILL` (Snakemake ignores SIGTERM while jobs
run), followed by `snakemake --unlock`; MORPHLEARN_SLURM_TIMEOUT sets the bound (600 s).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import pytest
import yaml
from conftest import TEST_COMMIT

pytestmark = pytest.mark.slurm

REPO = Path(__file__).resolve().parents[1]
START = REPO / "tools" / "slurm" / "start_local_slurm.sh"
STOP = REPO / "tools" / "slurm" / "stop_local_slurm.sh"
PROFILE_TEST = REPO / "profiles" / "slurm-test"
PROFILE_REAL = REPO / "profiles" / "slurm"
SMOKE = "config/smoke.yaml"
FULL = "config/full.yaml"
# Left out of a workflow copy (the package itself is imported from the installed venv).
SKIP_TOP = {".git", ".venv", ".snakemake", "results", "build", ".whl", ".gl", "tests"}
SKIP_ANY = ("__pycache__", ".snakemake", ".pytest_cache", ".ruff_cache", "*.egg-info")
# The merged results that must not depend on where the shards ran.
MERGED = (
    "results/theory/merged.zarr",
    "results/theory/metrics.csv",
    "results/empirical/merged.zarr",
    "results/empirical/metrics.csv",
    "results/summary.json",
    "results/reproduction.csv",
)
SHARD_RULES = ("theory_shard", "empirical_shard")

RUN_TIMEOUT_S = int(os.environ.get("MORPHLEARN_SLURM_TIMEOUT", "600"))
REQUIRE = os.environ.get("MORPHLEARN_REQUIRE_SLURM") == "1"


def _unavailable(reason: str) -> None:
    if REQUIRE:
        pytest.fail(f"MORPHLEARN_REQUIRE_SLURM=1 but {reason}", pytrace=False)
    pytest.skip(reason)


def _say(request: pytest.FixtureRequest, msg: str) -> None:
    """Print past pytest's capture (timings belong in the test log)."""
    reporter = request.config.pluginmanager.get_plugin("terminalreporter")
    if reporter is not None:
        reporter.write_line(f"[slurm] {msg}")
    else:
        print(f"[slurm] {msg}", file=sys.__stderr__)


def _env() -> dict[str, str]:
    """Clean environment: the venv first on PATH, no inherited SLURM job or profile."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("SLURM_", "SNAKEMAKE_", "MORPHLEARN_SLURM_"))}
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    return env


@dataclass
class Run:
    rc: int
    output: str
    seconds: float


def snakemake(cwd: Path, *args: str, timeout_s: int = RUN_TIMEOUT_S, env: dict[str, str] | None = None) -> Run:
    """Run Snakemake in `cwd`, killed after `timeout_s`, then unlocked if it was killed."""
    cmd = [sys.executable, "-m", "snakemake", *args]
    t0 = time.monotonic()
    proc = subprocess.run(
        ["timeout", "-s", "KILL", str(timeout_s), *cmd],
        cwd=cwd,
        env={**_env(), **(env or {})},
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        check=False,
    )
    seconds = time.monotonic() - t0
    if proc.returncode in (124, 137):
        subprocess.run([*cmd, "--unlock"], cwd=cwd, env=_env(), capture_output=True, check=False)
    return Run(proc.returncode, proc.stdout, seconds)


def _tail(text: str, n: int = 60) -> str:
    return "\n".join(text.splitlines()[-n:])


def _require_ok(run: Run, what: str) -> None:
    if run.rc in (124, 137):
        pytest.fail(f"{what} killed after {RUN_TIMEOUT_S} s\n{_tail(run.output)}")
    assert run.rc == 0, f"{what} failed (rc {run.rc})\n{_tail(run.output)}"


def job_counts(output: str) -> dict[str, int]:
    """Parse Snakemake's 'Job stats' table (the first one) into {rule: count}."""
    match = re.search(r"Job stats:\n(.*?)\n\s*\n", output, re.S)
    assert match, f"no 'Job stats' table in the output\n{_tail(output)}"
    counts = {}
    for line in match.group(1).splitlines():
        parts = line.split()
        if len(parts) == 2 and parts[1].isdigit():
            counts[parts[0]] = int(parts[1])
    return counts


def copy_workflow(dest: Path) -> Path:
    """A scratch copy of the repository's workflow (no results, venv or git)."""
    skip_any = shutil.ignore_patterns(*SKIP_ANY)

    def ignore(directory: str, names: list[str]) -> set[str]:
        skipped = set(skip_any(directory, names))
        if Path(directory) == REPO:
            skipped |= SKIP_TOP & set(names)
        return skipped

    shutil.copytree(REPO, dest, ignore=ignore, dirs_exist_ok=True)
    (dest / "results").mkdir(exist_ok=True)
    committed = REPO / "results" / "committed"
    if committed.is_dir():  # tracked reference results a rule may read
        shutil.copytree(committed, dest / "results" / "committed")
    return dest


def _need_workflow(*configs: str) -> None:
    missing = [p for p in ("Snakefile", *configs) if not (REPO / p).exists()]
    if missing:
        pytest.skip(f"workflow not in the repository yet: {', '.join(missing)}")


def tree_bytes(root: Path, rel: str) -> dict[str, bytes]:
    """Every file under root/rel (a file or a directory) -> its bytes, by relative path."""
    base = root / rel
    if base.is_file():
        return {rel: base.read_bytes()}
    return {str(p.relative_to(root)): p.read_bytes() for p in sorted(base.rglob("*")) if p.is_file()}


def _first_difference(a: bytes, b: bytes, context: int = 40) -> str:
    i = next((k for k, (x, y) in enumerate(zip(a, b, strict=False)) if x != y), min(len(a), len(b)))
    lo = max(0, i - context)
    return (
        f"{len(a)} vs {len(b)} bytes, first difference at byte {i}: "
        f"SLURM {a[lo : i + context]!r} / local {b[lo : i + context]!r}"
    )


# --------------------------------------------------------------------------------------
# The cluster
# --------------------------------------------------------------------------------------


@pytest.fixture(scope="session")
def slurm_cluster(request: pytest.FixtureRequest):
    """A running one-node SLURM cluster; stopped at the end if this session started it."""
    if os.geteuid() != 0:
        _unavailable("not root: the local SLURM cluster needs root (apt-get, daemons)")
    have_slurm = all(
        shutil.which(c) or Path("/usr/sbin", c).exists() for c in ("slurmctld", "slurmd", "munged", "sbatch")
    )
    if not have_slurm and not shutil.which("apt-get"):
        _unavailable("SLURM/munge are not installed and there is no apt-get to install them")
    if not shutil.which("timeout"):
        _unavailable("coreutils `timeout` is missing")
    t0 = time.monotonic()
    proc = subprocess.run(
        ["timeout", "-s", "KILL", "600", str(START)],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        check=False,
    )
    seconds = time.monotonic() - t0
    if proc.returncode != 0:
        _unavailable(f"{START.relative_to(REPO)} failed (rc {proc.returncode}):\n{_tail(proc.stdout, 30)}")
    started_here = "already running" not in proc.stdout
    timing = [line for line in proc.stdout.splitlines() if "timing:" in line]
    _say(
        request,
        f"cluster ready in {seconds:.1f} s ({timing[0].split('timing: ')[1] if timing else 'was already running'})",
    )
    yield proc.stdout
    if started_here:
        subprocess.run([str(STOP)], capture_output=True, check=False, timeout=120)


def test_start_script_refuses_non_root():
    """Without root the start script stops at once with a clear message (exit 2)."""
    if os.geteuid() != 0 or not shutil.which("setpriv"):
        pytest.skip("needs root and setpriv to try the script as an unprivileged user")
    proc = subprocess.run(
        ["setpriv", "--reuid=nobody", "--regid=nogroup", "--clear-groups", "bash", str(START)],
        capture_output=True,
        text=True,
        check=False,
        timeout=30,
    )
    assert proc.returncode == 2, proc.stdout + proc.stderr
    assert "must run as root" in proc.stderr


# --------------------------------------------------------------------------------------
# Smoke config: SLURM vs local, bit for bit
# --------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def smoke_runs(slurm_cluster, smoke_run, tmp_path_factory, request):
    """The smoke config's merged results made through SLURM, beside the shared local smoke run
    (conftest's ``smoke_run``, made with ``--cores 2``): the figures are local rules either way,
    so only the targets that shards feed are asked of SLURM."""
    _need_workflow(SMOKE)
    on_slurm = copy_workflow(tmp_path_factory.mktemp("smoke-slurm"))
    # Results record the git commit; the shared local run pins it to TEST_COMMIT (conftest), so
    # this run does too (it travels to the SLURM jobs via sbatch --export=ALL).
    env = {"MORPHLEARN_GIT_COMMIT": TEST_COMMIT}
    slurm_run = snakemake(on_slurm, *MERGED, "--profile", str(PROFILE_TEST), "--configfile", SMOKE, env=env)
    _require_ok(slurm_run, "SLURM smoke run")
    _say(request, f"smoke run's merged results through SLURM: {slurm_run.seconds:.1f} s")
    return {"slurm": (on_slurm, slurm_run), "local": (smoke_run, None)}


@pytest.mark.slow
def test_smoke_shards_ran_as_slurm_jobs(smoke_runs):
    _, run = smoke_runs["slurm"]
    counts = job_counts(run.output)
    submitted = re.findall(r"submitted with SLURM jobid \d+ \(log: \S*/rule_([A-Za-z0-9_]+)/", run.output)
    shards = {rule: counts.get(rule, 0) for rule in SHARD_RULES}
    assert sum(shards.values()) > 0, f"no shard jobs in the plan: {counts}"
    for rule, n in shards.items():
        assert submitted.count(rule) == n, f"{n} {rule} jobs planned but {submitted.count(rule)} submitted to SLURM"
    # merge/metrics/summary/all are cheap: they should run on the head node (localrules).
    others = sorted(set(submitted) - set(SHARD_RULES))
    assert not others, f"non-shard rules went to SLURM (add them to localrules?): {others}"


@pytest.mark.slow
def test_smoke_slurm_matches_local_bit_for_bit(smoke_runs):
    slurm_dir, _ = smoke_runs["slurm"]
    local_dir, _ = smoke_runs["local"]
    for rel in MERGED:
        assert (local_dir / rel).exists(), f"local run did not write {rel}"
        assert (slurm_dir / rel).exists(), f"SLURM run did not write {rel}"
        a, b = tree_bytes(slurm_dir, rel), tree_bytes(local_dir, rel)
        assert sorted(a) == sorted(b), (
            f"{rel}: different files\n only SLURM: {sorted(set(a) - set(b))}\n only local: {sorted(set(b) - set(a))}"
        )
        differing = [path for path in a if a[path] != b[path]]
        assert not differing, f"{rel}: files differ between SLURM and local:\n" + "\n".join(
            f"  {path}: {_first_difference(a[path], b[path])}" for path in differing
        )


@pytest.mark.slow
def test_resume_resubmits_only_missing_outputs(smoke_runs):
    workdir, _ = smoke_runs["slurm"]
    args = (*MERGED, "--profile", str(PROFILE_TEST), "--configfile", SMOKE, "-n")
    again = snakemake(workdir, *args, timeout_s=120)
    _require_ok(again, "dry run after a finished run")
    assert "Nothing to be done" in again.output, _tail(again.output)

    # An interrupted run: every shard but one finished, nothing downstream of them exists.
    # (Snakemake does not rebuild a missing intermediate when the final targets are up to
    # date, so everything after the shards is moved aside, not only the merge.)
    results = workdir / "results"
    shards = sorted(results.glob("theory/shards/*"))
    assert shards, "no shard outputs found under results/theory/shards/"
    keep = {"shards", "logs", "benchmarks"}
    moved = [shards[0]]
    for top in results.iterdir():
        if top.name in keep:
            continue
        if top.is_dir() and (top / "shards").is_dir():
            moved += [p for p in top.iterdir() if p.name not in keep]
        else:
            moved.append(top)
    aside = workdir / "aside"
    places = {path: aside / f"{i}_{path.name}" for i, path in enumerate(moved)}
    aside.mkdir()
    for path, place in places.items():
        path.rename(place)
    try:
        plan = snakemake(workdir, *args, timeout_s=120)
        _require_ok(plan, "dry run with one shard and everything after the shards missing")
        counts = job_counts(plan.output)
        assert counts.get("theory_shard") == 1, counts
        models = [top for top in results.iterdir() if (top / "shards").is_dir()]  # theory, empirical
        assert counts.get("merge") == len(models), counts  # every merged dataset was moved aside
    finally:
        for path, place in places.items():
            place.rename(path)
        aside.rmdir()


# --------------------------------------------------------------------------------------
# A failing job is reported with its logs
# --------------------------------------------------------------------------------------

FAILING_SNAKEFILE = """\
rule all:
    input: "out/ok.txt", "out/bad.txt"

rule ok:
    output: "out/ok.txt"
    shell: "echo ok > {output}"

rule bad:
    output: "out/bad.txt"
    log: "logs/bad.log"
    shell: "echo 'deliberate failure MORPHLEARN-MARKER' > {log}; exit 3"
"""


@pytest.mark.slow
def test_failing_job_reported_with_log_path(slurm_cluster, tmp_path, request):
    (tmp_path / "Snakefile").write_text(FAILING_SNAKEFILE)
    run = snakemake(tmp_path, "--profile", str(PROFILE_TEST))
    _say(request, f"failing toy workflow through SLURM: {run.seconds:.1f} s")
    assert run.rc not in (0, 124, 137), f"rc {run.rc}\n{_tail(run.output)}"
    assert "Error in rule bad:" in run.output, _tail(run.output)
    logs = re.findall(r"(/\S+/slurm_logs/rule_bad/\d+\.log)", run.output)
    assert logs, f"no SLURM log path reported for the failed job\n{_tail(run.output)}"
    assert Path(logs[-1]).is_file(), f"reported SLURM log {logs[-1]} does not exist"
    assert "logs/bad.log" in run.output
    assert "MORPHLEARN-MARKER" in run.output, "the failed rule's log is not shown"
    assert (tmp_path / "out" / "ok.txt").is_file(), "keep-going: the good job should finish"


# --------------------------------------------------------------------------------------
# The full sweep plans with the real-cluster profile (no cluster needed)
# --------------------------------------------------------------------------------------


def test_full_sweep_dry_run_with_cluster_profile(tmp_path, request):
    _need_workflow(FULL)
    import yte

    workdir = copy_workflow(tmp_path / "wf")
    run = snakemake(workdir, "--profile", str(PROFILE_REAL), "--configfile", FULL, "-n", timeout_s=300)
    _require_ok(run, "dry run of the full sweep")
    counts = job_counts(run.output)
    full = yaml.safe_load((REPO / FULL).read_text())
    expected = full["sweep"]["shards"]
    _say(
        request,
        f"full sweep dry run: {counts.get('total')} jobs "
        f"({', '.join(f'{k} {v}' for k, v in counts.items() if k != 'total')})",
    )
    assert counts.get("theory_shard") == expected, counts

    # The profile's per-rule resources reach the shard jobs.
    with (PROFILE_REAL / "config.yaml").open() as fh:
        profile = yte.process_yaml(fh, require_use_yte=True)
    want = profile["set-resources"]["theory_shard"]
    shard_jobs = re.findall(r"rule theory_shard:\n(?:    .*\n)*?    resources: (.*)", run.output)
    assert len(shard_jobs) == expected
    for key, value in want.items():
        assert all(f"{key}={value}" in r.split(", ") for r in shard_jobs), (key, shard_jobs[0])
