"""Reliability: atomic outputs, the merge's shard checks, kill and resume, what a config change
invalidates, bad input, a full disk, and ``morphlearn verify``.

The workflow tests run the theory model only (``empirical.enabled: false``) on the smoke grid
(3 positions per axis, 5 weights) with 6 shards, so that a run can be killed between shards.
"""

from __future__ import annotations

import base64
import errno
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import psutil
import pytest
import xarray as xr
import yaml
from conftest import TEST_COMMIT, copy_workflow, job_stats, snakemake, written_results

from morphlearn import config, configure, grid, models, store
from morphlearn.apps import cli
from morphlearn.provenance import sha256_file
from morphlearn.results import DesignResult

N_SHARDS = 6
REL_CONFIG = {
    "results_dir": "results",
    "grid": {"positions_per_axis": 3, "weights": 5},
    "sweep": {"shards": N_SHARDS, "threads": 1},
    "analysis": {"top": 3},
    "empirical": {"enabled": False},
    "figures": {"enabled": False},  # figure reruns are tested in test_figures.py
}
SNAKEMAKE = str(Path(sys.executable).with_name("snakemake"))
OUTPUTS = (
    "theory/merged.zarr",
    "theory/metrics.csv",
    "theory/metrics.provenance.json",
    "summary.json",
    "summary.md",
    *(f"theory/shards/shard_{i}.nc" for i in range(N_SHARDS)),
)


def workflow_copy(dest: Path) -> Path:
    wd = copy_workflow(dest)
    (wd / "rel.yaml").write_text(yaml.safe_dump(REL_CONFIG))
    return wd


def temporaries(root: Path) -> list[Path]:
    return sorted(p for p in root.rglob(".*.tmp-*"))


@pytest.fixture(scope="module")
def done_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """An uninterrupted run of the 6-shard config: the reference for resume and change tests."""
    wd = workflow_copy(tmp_path_factory.mktemp("reliability") / "done")
    snakemake(wd, "--cores", "2", "--configfile", "rel.yaml")
    return wd


# --- 1, 2: shards are checked before anything is merged ---------------------------------------

G = grid.DesignGrid(3)
W = grid.weights(5)
SCIENCE = models.get("theory").science(
    configure.parse(
        config.deep_merge(yaml.safe_load((Path(__file__).parents[1] / "config.yaml").read_text()), REL_CONFIG)
    )
)
SHARD_DESIGNS = grid.split_shards(G.representatives(), 3)


def _results(designs: np.ndarray, m: int = 5, seed: int = 0) -> list[DesignResult]:
    rng = np.random.default_rng(seed)
    out = []
    for _ in designs:
        ft = rng.uniform(0, 500, (4, m, m))
        ft[rng.random((4, m, m)) < 0.6] = np.nan
        out.append(DesignResult(ft, rng.uniform(0, 4, (4, m, m)), np.zeros((4, m, m))))
    return out


def _write(
    path: Path,
    designs: np.ndarray,
    *,
    science: dict = SCIENCE,
    m: int = 5,
    seed: int = 0,
    results: list[DesignResult] | None = None,
) -> None:
    store.write_shard(
        path,
        model="theory",
        grid=G,
        weights=grid.weights(m),
        designs=designs,
        results=results or _results(designs, m, seed),
        science=science,
        provenance={},
    )


def _shards(d: Path) -> list[Path]:
    paths = [d / f"shard_{i}.nc" for i in range(3)]
    for i, p in enumerate(paths):
        _write(p, SHARD_DESIGNS[i], seed=i)
    return paths


def _merge(paths: list[Path], out: Path) -> None:
    store.merge_shards(
        paths,
        out,
        model="theory",
        grid=G,
        weights=W,
        shard_designs=SHARD_DESIGNS,
        science=SCIENCE,
        mirror=True,
        provenance={},
    )


def test_shard_carries_checksum_and_config_hash(tmp_path: Path) -> None:
    (p,) = _shards(tmp_path)[:1]
    with xr.open_dataset(p, engine="scipy") as ds:
        assert ds.attrs["science_sha256"] == config.digest(SCIENCE)
        assert len(ds.attrs["data_sha256"]) == 64
    assert temporaries(tmp_path) == []
    _merge(_shards(tmp_path), tmp_path / "merged.zarr")
    assert store.open_merged(tmp_path / "merged.zarr").sizes["design"] == G.size
    assert temporaries(tmp_path) == []


def _flip_data_byte(p: Path) -> None:
    """Change one low mantissa byte in the middle of ``min_dist`` (stays a finite number)."""
    data = bytearray(p.read_bytes())
    with xr.open_dataset(p, engine="scipy", mask_and_scale=False) as ds:
        needle = ds["min_dist"].values.astype(">f4").tobytes()
    at = data.find(needle)
    assert at > 0
    data[at + 4 * (len(needle) // 8) + 3] ^= 0x01
    p.write_bytes(bytes(data))


def _damage(kind: str, paths: list[Path]) -> str:
    """Damage shard 1 in one way; return what the refusal must say."""
    p = paths[1]
    if kind == "corrupted bytes":
        _flip_data_byte(p)
        return "data checksum mismatch"
    if kind == "truncated":
        p.write_bytes(p.read_bytes()[: p.stat().st_size * 2 // 3])
        return "unreadable or truncated"
    if kind == "missing":
        p.unlink()
        return "missing"
    if kind == "foreign":
        _write(p, SHARD_DESIGNS[1], science=config.deep_merge(SCIENCE, {"theory": {"horizon": 400.0}}))
        return "different science config (foreign shard)"
    if kind == "wrong designs":
        _write(p, SHARD_DESIGNS[2])
        return "holds designs"
    if kind == "wrong shape":
        _write(p, SHARD_DESIGNS[1], m=4)
        return "has shape"
    if kind == "NaN distance":
        res = _results(SHARD_DESIGNS[1])
        res[0].min_dist[2, 1, 1] = np.nan  # checksum made over the NaN: only the NaN check catches it
        _write(p, SHARD_DESIGNS[1], results=res)
        return "NaN in min_dist"
    if kind == "bad status":
        res = _results(SHARD_DESIGNS[1])
        res[0].status[0, 0, 0] = 7
        _write(p, SHARD_DESIGNS[1], results=res)
        return "status outside [0, 1, 2, 3, 4]"
    raise AssertionError(kind)


@pytest.mark.parametrize(
    "kind",
    [
        "corrupted bytes",
        "truncated",
        "missing",
        "foreign",
        "wrong designs",
        "wrong shape",
        "NaN distance",
        "bad status",
    ],
)
def test_merge_refuses_a_bad_shard_and_writes_nothing(tmp_path: Path, kind: str) -> None:
    paths = _shards(tmp_path)
    why = _damage(kind, paths)
    out = tmp_path / "merged.zarr"
    with pytest.raises(store.ShardError) as e:
        _merge(paths, out)
    msg = str(e.value)
    assert f"shard {paths[1]}:" in msg and why in msg and "\n" not in msg, msg
    assert not out.exists()
    assert temporaries(tmp_path) == []


@pytest.mark.slow
def test_workflow_merge_refuses_a_corrupted_shard(done_run: Path, tmp_path: Path) -> None:
    wd = tmp_path / "corrupt"
    shutil.copytree(done_run, wd, symlinks=True)  # results and .snakemake metadata, mtimes kept
    merged = wd / "results/theory/merged.zarr"
    before = {
        p.relative_to(merged): p.read_bytes()
        for p in merged.rglob("*")
        if p.is_file() and p.name != ".snakemake_timestamp"
    }
    shard = wd / "results/theory/shards/shard_2.nc"
    _flip_data_byte(shard)  # newer than merged.zarr: snakemake re-runs the merge, not the shard
    proc = snakemake(wd, "--cores", "1", "--configfile", "rel.yaml", check=False)
    assert proc.returncode != 0
    assert job_stats(proc.stdout + proc.stderr).get("theory_shard", 0) == 0
    log = (wd / "results/logs/theory/merge.log").read_text()
    assert "shard results/theory/shards/shard_2.nc: data checksum mismatch (damaged)" in log, log[-2000:]
    # The previous good store is still there, byte for byte, and still verifies.
    after = {
        p.relative_to(merged): p.read_bytes()
        for p in merged.rglob("*")
        if p.is_file() and p.name != ".snakemake_timestamp"
    }
    assert after == before
    store.verify_merged(merged)
    assert temporaries(wd / "results") == []


# --- 3: kill in the middle, resume, same bytes ----------------------------------------------------


def _kill_group(proc: subprocess.Popen) -> None:
    """SIGKILL snakemake's process group and every process it started (the running jobs)."""
    try:
        children = psutil.Process(proc.pid).children(recursive=True)
    except psutil.NoSuchProcess:
        children = []
    os.killpg(proc.pid, signal.SIGKILL)
    for c in children:
        try:
            c.kill()
        except psutil.NoSuchProcess:
            pass
    proc.wait(timeout=30)
    psutil.wait_procs(children, timeout=30)


def _incomplete_outputs(wd: Path) -> set[str]:
    """Outputs snakemake had started but not registered as finished (its 'incomplete' markers)."""
    d = wd / ".snakemake/incomplete"
    out = set()
    for f in d.rglob("*") if d.exists() else []:
        if f.is_file() and not f.name.startswith("@"):
            out.add(base64.urlsafe_b64decode(f.name).decode())
    return out


@pytest.mark.slow
def test_kill_mid_run_then_resume_recomputes_only_unfinished_shards(done_run: Path, tmp_path: Path) -> None:
    wd = workflow_copy(tmp_path / "killed")
    shards = [f"results/theory/shards/shard_{i}.nc" for i in range(N_SHARDS)]
    env = dict(os.environ, MORPHLEARN_GIT_COMMIT=TEST_COMMIT)
    log_path = tmp_path / "first.log"
    with log_path.open("w") as log:
        proc = subprocess.Popen(
            [SNAKEMAKE, "--cores", "2", "--configfile", "rel.yaml"],
            cwd=wd,
            env=env,
            stdout=log,
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )
        try:
            deadline = time.monotonic() + 600
            # Kill once snakemake has registered at least one shard as finished (2 cores: 6 shards
            # finish in about three waves, so others are still running or waiting).
            while "(Rule: theory_shard)" not in log_path.read_text():
                assert proc.poll() is None, log_path.read_text()[-3000:]
                assert time.monotonic() < deadline, "no shard finished in time"
                time.sleep(0.05)
        finally:
            _kill_group(proc)
    assert proc.returncode == -signal.SIGKILL
    incomplete = _incomplete_outputs(wd)
    finished = {s for s in shards if (wd / s).exists() and s not in incomplete}
    unfinished = set(shards) - finished
    assert 1 <= len(finished) < N_SHARDS, (finished, log_path.read_text()[-3000:])
    assert not (wd / "results/theory/merged.zarr").exists()
    designs = models.get("theory").shard_designs(
        configure.parse(config.deep_merge(yaml.safe_load((wd / "config.yaml").read_text()), REL_CONFIG))
    )
    for s in finished:  # what looks finished is complete and verifies
        i = int(s.split("_")[-1].split(".")[0])
        store.verify_shard(store.read_shard(wd / s), model="theory", science=SCIENCE, designs=designs[i], m=5)
    # A writer killed mid-write leaves a hidden temporary; plant one so the clean-up is tested
    # whatever moment the kill hit.
    victim = sorted(unfinished)[0]
    stale = (wd / victim).with_name(f".{Path(victim).name}.tmp-999999")
    stale.write_bytes(b"half a shard")
    (wd / "results/theory/.merged.zarr.tmp-999999").mkdir(parents=True)
    before = {s: (wd / s).stat().st_mtime_ns for s in finished}
    bench_before = {
        s: (wd / s.replace("theory/shards/", "benchmarks/theory/").replace(".nc", ".tsv")).stat().st_mtime_ns
        for s in finished
    }

    snakemake(wd, "--unlock")
    proc2 = snakemake(wd, "--cores", "2", "--configfile", "rel.yaml", "--rerun-incomplete")
    recomputed = job_stats(proc2.stdout + proc2.stderr).get("theory_shard", 0)
    print(
        f"\nkilled with {len(finished)} of {N_SHARDS} shards finished; resume recomputed "
        f"{recomputed} shard(s): {sorted(unfinished)}"
    )
    assert recomputed == len(unfinished)
    assert len(re.findall(r"rule theory_shard:", proc2.stderr)) == len(unfinished)
    for s in finished:  # finished shards untouched: same file, benchmark not re-written
        assert (wd / s).stat().st_mtime_ns == before[s], s
        bench = wd / s.replace("theory/shards/", "benchmarks/theory/").replace(".nc", ".tsv")
        assert bench.stat().st_mtime_ns == bench_before[s], s
    assert temporaries(wd / "results") == []
    for rel in OUTPUTS:
        a, b = wd / "results" / rel, done_run / "results" / rel
        assert sha256_file(a) == sha256_file(b), f"{rel} differs from the uninterrupted run"


# --- 4: what a config change invalidates ----------------------------------------------------------

SIM = {"theory_shard": N_SHARDS, "merge": 1, "metrics": 1, "summary": 1, "all": 1}


@pytest.mark.slow
@pytest.mark.parametrize(
    ("change", "expected"),
    [
        ({}, {}),
        ({"theory": {"horizon": 400.0}}, SIM),
        ({"theory": {"success_radius": 0.25}}, SIM),
        ({"grid": {"weights": 7}}, SIM),
        ({"theory": {"dt": 0.02}}, {}),  # dp5 (adaptive) does not use dt: nothing depends on it
        ({"analysis": {"horizon": 250.0}}, {"metrics": 1, "summary": 1, "all": 1}),
        ({"analysis": {"top": 5}}, {"summary": 1, "all": 1}),
        ({"sweep": {"threads": 2}}, {}),
    ],
    ids=lambda v: json.dumps(v, separators=(",", ":")),
)
def test_change_invalidates_exactly_what_depends_on_it(done_run: Path, change: dict, expected: dict) -> None:
    (done_run / "change.yaml").write_text(yaml.safe_dump(change))
    proc = snakemake(done_run, "-n", "--cores", "1", "--configfile", "rel.yaml", "change.yaml")
    assert job_stats(proc.stdout + proc.stderr) == expected, (proc.stdout + proc.stderr)[-3000:]


def test_dt_is_science_only_for_the_fixed_step_integrator() -> None:
    base = config.validate(
        config.deep_merge(yaml.safe_load((Path(__file__).parents[1] / "config.yaml").read_text()), REL_CONFIG)
    )
    rk4 = config.deep_merge(base, {"theory": {"integrator": "rk4", "max_steps": 100_000}})  # horizon / dt steps

    def dig(cfg: dict) -> str:
        return config.digest(models.get("theory").science(configure.parse(cfg)))

    assert dig(rk4) != dig(config.deep_merge(rk4, {"theory": {"dt": 0.02}}))
    assert dig(base) == dig(config.deep_merge(base, {"theory": {"dt": 0.02}}))


# --- 5: bad input -------------------------------------------------------------------------------


def _refused(tmp_path: Path, text: str) -> subprocess.CompletedProcess:
    wd = workflow_copy(tmp_path / "wf")
    (wd / "bad.yaml").write_text(text)
    proc = snakemake(wd, "--cores", "1", "--configfile", "bad.yaml", check=False)
    assert written_results(wd) == []
    assert "Traceback" not in proc.stderr
    return proc


@pytest.mark.parametrize(
    ("override", "needle"),
    [
        ({"sweep": {"shards": 46}}, "sweep.shards = 46 exceeds the 45 designs evaluated; allowed: 1..45"),
        ({"theory": {"success_radius": "wide"}}, "theory.success_radius = 'wide' is invalid"),
        ({"theory": {"r": -4}}, "theory.r = -4 is invalid"),
        ({"analysis": {"tpo": 3}}, "unknown key ['tpo'] under 'analysis'; allowed: ["),
    ],
)
def test_workflow_bad_config_one_line_exit_2(tmp_path: Path, override: dict, needle: str) -> None:
    proc = _refused(tmp_path, yaml.safe_dump(config.deep_merge(REL_CONFIG, override)))
    assert proc.returncode == 2, proc.stderr[-2000:]
    ours = [line for line in proc.stderr.splitlines() if "morphlearn" in line]
    assert len(ours) == 1 and ours[0].startswith("morphlearn: config error: ") and needle in ours[0], ours


def test_workflow_malformed_yaml_is_refused_by_snakemake(tmp_path: Path) -> None:
    """Snakemake parses --configfile before the Snakefile runs, so the workflow cannot word this
    error or choose its exit code: snakemake exits 1 with its own two-line WorkflowError."""
    proc = _refused(tmp_path, "grid: [1, 2\n")
    assert proc.returncode == 1
    assert "Config file is not valid JSON or YAML" in proc.stderr
    # The same file through morphlearn's own loader: one line with the position.
    with pytest.raises(config.ConfigError, match=r"bad.yaml: malformed YAML at line 2, column 1$"):
        config.load(tmp_path / "wf/bad.yaml")


def test_shard_split_larger_than_designs_refused() -> None:
    with pytest.raises(ValueError, match="shards=46 exceeds the 45 designs"):
        grid.split_shards(G.representatives(), 46)


# --- 6: a full disk leaves nothing that looks finished -------------------------------------------


def test_full_disk_during_shard_write_leaves_no_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    real = xr.Dataset.to_netcdf

    def half_then_enospc(self: xr.Dataset, path: Path, *a: object, **k: object) -> None:
        real(self, path, *a, **k)
        Path(path).write_bytes(Path(path).read_bytes()[:1000])  # the part that fitted
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))

    monkeypatch.setattr(xr.Dataset, "to_netcdf", half_then_enospc)
    out = tmp_path / "shards/shard_0.nc"
    with pytest.raises(OSError) as e:
        _write(out, SHARD_DESIGNS[0])
    assert e.value.errno == errno.ENOSPC
    assert not out.exists()
    assert list(out.parent.iterdir()) == []


def test_full_disk_during_merge_keeps_the_previous_dataset(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    paths = _shards(tmp_path)
    _merge(paths, tmp_path / "merged.zarr")
    before = sha256_file(tmp_path / "merged.zarr")
    real, calls = store.chunk_digest, [0]

    def digest_until_full(*a: object) -> str:
        calls[0] += 1
        if calls[0] > 10:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return real(*a)

    monkeypatch.setattr(store, "chunk_digest", digest_until_full)
    with pytest.raises(OSError, match="No space left"):
        _merge(paths, tmp_path / "merged.zarr")
    assert calls[0] > 10  # it failed part-way through writing the new store
    assert sha256_file(tmp_path / "merged.zarr") == before
    assert temporaries(tmp_path) == []


@pytest.mark.skipif(os.geteuid() != 0 or not shutil.which("mount"), reason="needs root to mount a tmpfs")
def test_real_full_tmpfs_leaves_no_file(tmp_path: Path) -> None:
    """A real 64 KiB file system; a 5-design shard at 41 weights needs about 300 KB."""
    d = tmp_path / "tiny"
    d.mkdir()
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(d)]).returncode != 0:
        pytest.skip("cannot mount a tmpfs here")
    try:
        designs = SHARD_DESIGNS[0][:5]
        with pytest.raises(OSError) as e:
            _write(d / "shard_0.nc", designs, m=41)
        assert e.value.errno == errno.ENOSPC, e.value
        assert list(d.iterdir()) == []
    finally:
        subprocess.run(["umount", str(d)], check=True)


def test_stale_temporary_of_a_killed_writer_is_removed(tmp_path: Path) -> None:
    out = tmp_path / "merged.zarr"
    (tmp_path / ".merged.zarr.tmp-999999").mkdir()
    (tmp_path / ".merged.zarr.tmp-999999/junk").write_bytes(b"x" * 100)
    (tmp_path / ".other.nc.tmp-999999").write_bytes(b"not ours")
    _merge(_shards(tmp_path), out)
    assert out.is_dir()
    assert temporaries(tmp_path) == [tmp_path / ".other.nc.tmp-999999"]


# --- 7: morphlearn verify -----------------------------------------------------------------------


@pytest.mark.slow
def test_verify_agrees_with_the_reference(done_run: Path, capsys: pytest.CaptureFixture) -> None:
    merged = done_run / "results/theory/merged.zarr"
    rc = cli.main(["verify", "--merged", str(merged), "--samples", "24", "--seed", "3", "--workers", "2", "--json"])
    out = json.loads(capsys.readouterr().out)
    print(
        f"\nverify: success agreement {out['success_agreement']:.4f} ({out['success_agree']}/"
        f"{out['samples']}), near-boundary {out['disagree_near_boundary']}, unexplained "
        f"{out['disagree_unexplained']}; first-time agreement {out['first_time_agreement']}"
    )
    assert rc == (0 if out["ok"] else 1)
    assert out["samples"] == 24 and out["parameters"]["r"] == 4.0 and out["parameters"]["horizon"] == 500.0
    assert out["parameters"]["success_radius"] == 0.2
    assert out["disagree_unexplained"] == 0, out["disagreements"]
    assert out["success_agreement"] >= 0.9
    assert out["first_time_agreement"] in (None, 1.0)


def test_verify_reports_a_wrong_stored_cell(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    """A dataset whose stored values are nonsense: verify must find unexplained disagreements."""
    paths = []
    for i, d in enumerate(SHARD_DESIGNS):  # every trajectory 'succeeds at t = 1' far from the light
        res = [DesignResult(np.ones((4, 5, 5)), np.full((4, 5, 5), 3.0), np.zeros((4, 5, 5))) for _ in d]
        paths.append(tmp_path / f"s{i}.nc")
        _write(paths[-1], d, results=res)
    _merge(paths, tmp_path / "m.zarr")
    rc = cli.main(["verify", "--merged", str(tmp_path / "m.zarr"), "--samples", "3", "--seed", "1"])
    out = capsys.readouterr().out
    assert rc == 1 and "UNEXPLAINED" in out and "success flags agree: " in out


@pytest.mark.parametrize(
    ("args", "msg"),
    [
        (["--merged", "nowhere.zarr"], "--merged nowhere.zarr: not found"),
        # the lower bounds are checked before the dataset is read; the upper one needs its size
        (["--merged", "{m}", "--samples", "0"], "--samples = 0; allowed: an integer >= 1"),
        (["--merged", "{m}", "--samples", "8101"], "--samples = 8101; allowed: 1..8100"),
        (["--merged", "{m}", "--workers", "0"], "--workers = 0; allowed: an integer >= 1"),
        (["--merged", "{s}"], "not a readable Zarr dataset"),
    ],
)
def test_verify_bad_arguments_exit_2_one_line(tmp_path: Path, args: list[str], msg: str) -> None:
    paths = _shards(tmp_path)
    _merge(paths, tmp_path / "m.zarr")
    args = [a.format(m=tmp_path / "m.zarr", s=paths[0]) for a in args]
    listing = sorted(tmp_path.rglob("*"))
    proc = subprocess.run(
        [sys.executable, "-m", "morphlearn.apps.cli", "verify", *args], cwd=tmp_path, capture_output=True, text=True
    )
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.startswith("morphlearn verify: error: ") and msg in proc.stderr, proc.stderr
    assert proc.stderr.count("\n") == 1 and proc.stdout == ""
    assert sorted(tmp_path.rglob("*")) == listing
