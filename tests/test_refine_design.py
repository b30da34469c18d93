"""The committed refine folders (morphlearn.refine.folder: read-only history) and ``morphlearn
refine``: every row is verified before it is read, a damaged, foreign or edited row or manifest is
refused or left out (said), and the committed folders assemble to their committed summaries."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from refine_folders import write_folder

from morphlearn import metrics
from morphlearn.grid import canonical_design
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import load_params
from morphlearn.refine import folder as rf
from morphlearn.results import STATUS_NONFINITE, STATUS_OK

ROOT = Path(__file__).resolve().parents[1]
BODY = ROOT / "config" / "empirical_morphology.yaml"
STEPS = 300
COMMITTED = sorted((ROOT / "results" / "refine").glob("*/manifest.json"))


def _job(m: int = 3, steps: int = STEPS, **kw) -> rf.Job:  # type: ignore[no-untyped-def]
    l1, l2 = canonical_design()
    return rf.Job(
        l1=l1,
        l2=l2,
        m=m,
        params=load_params(BODY).replace(steps=steps),
        options=SweepOptions(early_stop=True),
        **{"engine_identity": {"pybullet": "test"}, **kw},
    )


def _arrays(job: rf.Job, seed: int = 0) -> dict[str, np.ndarray]:
    """Made-up outcomes (no physics): a cell succeeds with probability 0.5 (contact in the horizon)."""
    rng = np.random.default_rng(seed)
    shape = (4, job.m, job.m)
    ok = rng.random(shape) < 0.5
    return {
        "first_time": np.where(ok, rng.uniform(1, job.params.horizon, shape), np.nan).astype(np.float32),
        "min_dist": np.where(ok, 0.0, rng.uniform(0.5, 3.0, shape)).astype(np.float32),
        "status": np.where(rng.random(shape) < 0.05, STATUS_NONFINITE, STATUS_OK).astype(np.int8),
        "steps": rng.integers(10, job.params.steps, shape).astype(np.int16),
    }


def _refine(*args: str) -> subprocess.CompletedProcess[str]:
    """``morphlearn refine ARGS`` in its own process (as a user runs it)."""
    return subprocess.run(
        [sys.executable, "-m", "morphlearn.apps.cli", "refine", *args], capture_output=True, text=True
    )


def test_assembled_is_the_rows_bit_for_bit_and_a_partial_folder_says_so(tmp_path: Path) -> None:
    job = _job(m=5)
    arr = _arrays(job)
    write_folder(tmp_path, job, arr, rows=[0, 4, 2], body_file=BODY)
    a = rf.assemble(tmp_path)
    assert not a.complete and a.rows_done.tolist() == [True, False, True, False, True]
    done = a.rows_done
    for k in ("first_time", "min_dist", "status"):
        got = getattr(a.result, k)
        assert got.dtype == arr[k].dtype and got[:, done].tobytes() == arr[k][:, done].tobytes(), k
    assert (a.result.status[:, ~done] == rf.NOT_RUN).all() and np.isnan(a.result.first_time[:, ~done]).all()
    succ = metrics.success(arr["first_time"], arr["min_dist"], rf.thresholds(job.params))[:, done]
    want = metrics.design_metrics(succ, arr["status"][:, done]).as_dict()
    assert want["at_least_one"] > 0  # the comparison means something
    s = rf.summary(a)
    assert s["metrics_over_rows_done"] == want and (s["rows_done"], s["episodes"]) == (3, 60)
    assert s["physics_steps"] == int(arr["steps"][:, done].sum())


def _damage_flip_byte(p: Path) -> None:
    b = bytearray(p.read_bytes())
    b[len(b) // 2] ^= 0xFF
    p.write_bytes(bytes(b))


def _damage_values(p: Path) -> None:
    """A readable npz whose values changed but whose recorded checksum did not."""
    with np.load(p) as z:
        d = {k: z[k] for k in z.files}
    d["min_dist"] = d["min_dist"] + np.float32(1.0)
    np.savez(p, **d)


def _damage_row(p: Path) -> None:
    """Another row's file under this row's name (its own checksum holds)."""
    p.write_bytes(p.with_name("row_000.npz").read_bytes())


@pytest.mark.parametrize("damage", [_damage_flip_byte, _damage_values, _damage_row, lambda p: p.write_bytes(b"")])
def test_damaged_row_is_left_out_and_said(tmp_path: Path, damage) -> None:  # type: ignore[no-untyped-def]
    job = _job()
    write_folder(tmp_path, job, _arrays(job))
    damage(rf.row_path(tmp_path, 1))
    with pytest.raises(rf.ChunkError):
        rf.read_chunk(tmp_path, 1, job.run_key(), 3)
    said: list[str] = []
    assert rf.assemble(tmp_path, log=said.append).rows_done.tolist() == [True, False, True]
    assert len(said) == 1 and "row_001" in said[0]


def test_row_from_another_run_is_not_read(tmp_path: Path) -> None:
    a, b = tmp_path / "a", tmp_path / "b"
    write_folder(a, _job(), _arrays(_job()))
    write_folder(b, _job(steps=STEPS - 100), _arrays(_job()), rows=[0])
    rf.row_path(b, 2).write_bytes(rf.row_path(a, 2).read_bytes())
    with pytest.raises(rf.ChunkError, match="another run"):
        rf.read_chunk(b, 2, _job(steps=STEPS - 100).run_key(), 3)
    assert rf.assemble(b).rows_done.tolist() == [True, False, False]


def test_edited_manifest_is_refused(tmp_path: Path) -> None:
    """An identity edited without its run key is refused; edited with it, no row is read (the rows
    carry the run key they were made under)."""
    job = _job()
    write_folder(tmp_path, job, _arrays(job))
    man = json.loads(rf.manifest_path(tmp_path).read_text())
    man["identity"]["params"]["steps"] = STEPS + 1
    rf.manifest_path(tmp_path).write_text(json.dumps(man))
    with pytest.raises(rf.RefineError, match="does not hash to its run key"):
        rf.assemble(tmp_path)
    man["run_key"] = rf.job_from_manifest(man).run_key()
    rf.manifest_path(tmp_path).write_text(json.dumps(man))
    said: list[str] = []
    assert not rf.assemble(tmp_path, log=said.append).rows_done.any()
    assert len(said) == 3 and all("from another run" in s for s in said)


def test_the_recorded_engine_version_is_history_not_this_machines(tmp_path: Path) -> None:
    """A folder records the engine version that made it; it reads whatever is installed here."""
    job = _job(engine_identity={"pybullet": "0.0-not-installed"})
    write_folder(tmp_path, job, _arrays(job))
    a = rf.assemble(tmp_path)
    assert a.complete and rf.job_from_manifest(a.manifest).engine_identity == {"pybullet": "0.0-not-installed"}


def test_bad_inputs_say_what_is_allowed() -> None:
    p = load_params(BODY)
    with pytest.raises(rf.RefineError, match=r"l2.y = -0.7 .*\[-0.5, 0.5\]"):
        rf.Job(l1=(0.5, 0.5), l2=(0.5, -0.7), m=3, params=p, options=SweepOptions())
    with pytest.raises(rf.RefineError, match="weights = 1"):
        rf.Job(l1=(0.5, 0.5), l2=(0.5, -0.5), m=1, params=p, options=SweepOptions())


def test_mirror_flips_counts_each_pair_once() -> None:
    rng = np.random.default_rng(0)
    succ = rng.random((4, 4, 4)) < 0.3
    sym = succ | succ[[3, 2, 1, 0]].transpose(0, 2, 1)  # symmetric under the mirror rule
    done = np.ones(4, dtype=bool)
    assert rf.mirror_flips(sym, done)["pairs_flipped"] == 0
    assert rf.mirror_flips(sym, done)["pairs_compared"] == 32
    bad = sym.copy()
    bad[0, 1, 2] = not bad[0, 1, 2]
    assert rf.mirror_flips(bad, done)["pairs_flipped"] == 1
    done[1] = False  # the flipped cell's row is not done: not compared
    assert rf.mirror_flips(bad, done) == {
        "pairs_compared": 18,
        "pairs_flipped": 0,
        "successes_in_compared": int((bad & (done[:, None] & done)[None]).sum()),
    }


def test_status_reads_a_folder_and_refuses_what_is_not_one(tmp_path: Path) -> None:
    job = _job(m=5)
    write_folder(tmp_path / "f", job, _arrays(job), rows=[0, 4])
    r = _refine("status", str(tmp_path / "f"))
    assert r.returncode == 0 and "rows 2/5 (40.0%)" in r.stdout and "PARTIAL" in r.stdout, r.stderr
    r = _refine("status", str(tmp_path))
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "not a refine folder" in r.stderr, r.stderr
    # the writers are gone: refine folders are history; the workflow's bundle rule is the export
    for gone in (["export", str(tmp_path / "f"), str(tmp_path / "e")], ["assemble", "--write", str(tmp_path / "f")]):
        assert _refine(*gone).returncode == 2
    assert not (tmp_path / "e").exists() and not (tmp_path / "f" / "result.npz").exists()


def test_adaptive_replay_equals_an_adaptive_run(tmp_path: Path) -> None:
    """The adaptive grid's misses are measured by replaying it on an exhaustive folder: the cells
    the replay picks are the cells a real adaptive run simulates."""
    pytest.importorskip("mujoco")
    from morphlearn.mujoco import evaluate_design as mujoco_evaluate_design
    from morphlearn.physics.refine import misses, replay_mask
    from morphlearn.results import STATUS_INFERRED

    job = _job(m=5, engine="mujoco", engine_identity={"engine": "mujoco", "mujoco": "test"})
    ex = mujoco_evaluate_design(job.l1, job.l2, job.weights, job.params, options=job.options)
    arr = {k: getattr(ex, k) for k in ("first_time", "min_dist", "status")}
    write_folder(tmp_path, job, {**arr, "steps": np.zeros((4, 5, 5), np.int16)})
    r = rf.assemble(tmp_path).result
    succ = metrics.success(r.first_time, r.min_dist, rf.thresholds(job.params))
    near = 1.5
    opts = SweepOptions(early_stop=True, adaptive_weights=True, near=near)
    run = mujoco_evaluate_design(job.l1, job.l2, job.weights, job.params, options=opts)
    seeds = succ | (r.min_dist <= near * job.params.contact_distance)
    mask = replay_mask(seeds)
    assert not mask.all(), "the check needs cells the adaptive grid skips"
    assert (mask == (run.status != STATUS_INFERRED)).all()
    m = misses(succ, r.min_dist, job.params.contact_distance, near)
    assert m["successes"] == int(succ.sum()) > 0 and 0 < m["simulated_share"] <= 1
    got = metrics.success(run.first_time, run.min_dist, rf.thresholds(job.params))
    assert m["successes_missed"] == int((succ & ~got).sum())


def test_adaptive_cost_without_early_stop(tmp_path: Path) -> None:
    """`morphlearn refine adaptive` derives the no-lever cost from the early-stopped folder: a
    failure runs the whole horizon, a success (or a non-finite episode) stops where it stopped."""
    job = _job(m=5)
    arr = _arrays(job, seed=2)
    folder = write_folder(tmp_path / "f", job, arr)
    (folder / "summary.json").write_text(json.dumps({"cost": {"cpu_s": 10.0}}))
    proc = _refine("adaptive", str(folder), "--near", "4")
    assert proc.returncode == 0, proc.stderr
    cost = json.loads(proc.stdout)["cost"]
    succ = metrics.success(arr["first_time"], arr["min_dist"], rf.thresholds(job.params))
    steps = arr["steps"].astype(np.int64)
    horizon = round(job.params.horizon / job.params.dt)
    stopped = succ | (arr["status"] != STATUS_OK)
    assert (~stopped).any() and stopped.any()  # both kinds of cell take part
    assert cost["exhaustive_no_early_stop"]["steps"] == int(steps[stopped].sum()) + horizon * int((~stopped).sum())
    assert cost["exhaustive_early_stop"]["steps"] == int(steps.sum())
    assert cost["cpu_s_per_step"] == 10.0 / int(steps.sum())
    assert 0 < cost["adaptive_near_4_early_stop"]["steps"] <= int(steps.sum())


@pytest.mark.parametrize("folder", [p.parent for p in COMMITTED], ids=[p.parent.name for p in COMMITTED])
def test_committed_folders_assemble_to_their_summaries(folder: Path) -> None:
    """Every committed refine folder's rows verify, and ``morphlearn refine assemble`` gives its
    committed summary.json byte for byte (the old tool wrote it with the same numbers)."""
    r = _refine("assemble", str(folder))
    assert r.returncode == 0, r.stderr
    assert r.stdout == (folder / "summary.json").read_text()
    assert rf.assemble(folder).complete == ("d120_121" != folder.name)  # the one partial folder


def test_a_damaged_committed_folder_is_caught(tmp_path: Path) -> None:
    """The committed history under attack: a flipped byte in a row, and the summary no longer holds."""
    folder = tmp_path / "canonical_121"
    shutil.copytree(ROOT / "results" / "refine" / "canonical_121", folder)
    _damage_values(rf.row_path(folder, 60))
    r = _refine("assemble", str(folder))
    assert r.returncode == 0 and "row_060" in r.stderr and "checksum mismatch" in r.stderr, r.stderr
    assert r.stdout != (folder / "summary.json").read_text() and '"complete": false' in r.stdout


def test_survey_check_gives_the_committed_check() -> None:
    """``morphlearn refine survey-check`` of the canonical folder against the committed pybullet
    survey gives the committed survey_check.json: every shared cell bit-identical."""
    folder = ROOT / "results" / "refine" / "canonical_121"
    r = _refine("survey-check", str(folder), str(ROOT / "results" / "survey" / "empirical" / "merged.zarr"))
    assert r.returncode == 0, r.stderr
    assert r.stdout == (folder / "survey_check.json").read_text()
    got = json.loads(r.stdout)
    assert got["bit_identical_there"]["status"] == got["survey_simulated_with_bit_equal_weights"] > 0
