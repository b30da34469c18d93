"""The resumable one-design runner (morphlearn.resumable) and ``morphlearn refine``:
resume skips verified rows, damaged rows are recomputed, the assembled result is evaluate_design's;
the committed refine folders assemble to their committed summaries."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pybullet")

from morphlearn import metrics
from morphlearn import resumable as rz
from morphlearn.empirical import evaluate_design
from morphlearn.grid import canonical_design
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import load_params

BODY = Path(__file__).resolve().parents[1] / "config" / "empirical_morphology.yaml"
_REAL_COMPUTE_ROW = rz.compute_row
STEPS = 300  # 15 s: long enough for the w = (1, 1) contacts at 45 and 315 deg (9.05 s), short for a test


def _job(m: int = 3, steps: int = STEPS) -> rz.Job:
    l1, l2 = canonical_design()
    return rz.Job(
        l1=l1, l2=l2, m=m, params=load_params(BODY).replace(steps=steps), options=SweepOptions(early_stop=True)
    )


class _Spy:
    """Wraps compute_row: records the rows computed; raises KeyboardInterrupt at call ``stop_at``."""

    def __init__(self, stop_at: int | None = None) -> None:
        self.rows: list[int] = []
        self.stop_at = stop_at

    def __call__(self, runner, job, row):  # type: ignore[no-untyped-def]
        if self.stop_at is not None and len(self.rows) == self.stop_at:
            raise KeyboardInterrupt("simulated kill")
        self.rows.append(row)
        return _REAL_COMPUTE_ROW(runner, job, row)


def _quiet(msg: str) -> None:
    pass


def test_assembled_equals_evaluate_design_bit_for_bit(tmp_path: Path) -> None:
    job = _job()
    assert rz.run(tmp_path, job, body_file=BODY, log=_quiet) == 3
    a = rz.assemble(tmp_path)
    ref = evaluate_design(job.l1, job.l2, job.weights, job.params, options=job.options)
    assert a.complete
    for k in ("first_time", "min_dist", "status"):
        got, want = getattr(a.result, k), getattr(ref, k)
        assert got.dtype == want.dtype and got.tobytes() == want.tobytes(), k
    th = rz.thresholds(job.params)
    succ = metrics.success(ref.first_time, ref.min_dist, th)
    assert succ.any(), "the check needs successes to mean something"
    # the early stop took part: some failed episode stopped before the horizon
    assert ((a.steps < STEPS) & ~succ).any()
    assert rz.summary(a)["metrics_over_rows_done"] == metrics.design_metrics(succ, ref.status).as_dict()


def test_interrupted_run_resumes_with_only_the_missing_rows(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    job = _job(m=5)
    spy = _Spy(stop_at=2)
    monkeypatch.setattr(rz, "compute_row", spy)
    with pytest.raises(KeyboardInterrupt):
        rz.run(tmp_path, job, body_file=BODY, log=_quiet)
    first = spy.rows
    assert first == rz.row_order(5)[:2]
    assert sorted(p.name for p in (tmp_path / "rows").iterdir()) == [f"row_{r:03d}.npz" for r in sorted(first)]
    before = {r: rz.row_path(tmp_path, r).read_bytes() for r in first}
    partial = rz.assemble(tmp_path)
    assert not partial.complete and partial.rows_done.sum() == 2
    assert (partial.result.status[:, ~partial.rows_done] == rz.NOT_RUN).all()

    spy2 = _Spy()
    monkeypatch.setattr(rz, "compute_row", spy2)
    assert rz.run(tmp_path, job, body_file=BODY, log=_quiet) == 3
    assert sorted(spy2.rows) == sorted(set(range(5)) - set(first))
    assert all(rz.row_path(tmp_path, r).read_bytes() == before[r] for r in first)
    assert rz.assemble(tmp_path).complete
    assert len((tmp_path / "runs.jsonl").read_text().splitlines()) == 2


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


@pytest.mark.parametrize("damage", [_damage_flip_byte, _damage_values, lambda p: p.write_bytes(b"")])
def test_damaged_row_is_detected_and_recomputed(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, damage) -> None:  # type: ignore[no-untyped-def]
    job = _job()
    rz.run(tmp_path, job, body_file=BODY, log=_quiet)
    good = rz.row_path(tmp_path, 1).read_bytes()
    damage(rz.row_path(tmp_path, 1))
    with pytest.raises(rz.ChunkError):
        rz.read_chunk(tmp_path, 1, job.run_key(), 3)
    said: list[str] = []
    assert rz.assemble(tmp_path, log=said.append).rows_done.tolist() == [True, False, True]
    assert len(said) == 1 and "row_001" in said[0]
    spy = _Spy()
    monkeypatch.setattr(rz, "compute_row", spy)
    assert rz.run(tmp_path, job, body_file=BODY, log=_quiet) == 1
    assert spy.rows == [1]
    assert rz.row_path(tmp_path, 1).read_bytes() == good  # deterministic bytes: the same file again


def test_row_from_another_run_is_not_reused(tmp_path: Path) -> None:
    a, b = tmp_path / "a", tmp_path / "b"
    rz.run(a, _job(), body_file=BODY, log=_quiet, max_rows=1)
    rz.run(b, _job(steps=STEPS - 100), body_file=BODY, log=_quiet, max_rows=0)
    row = rz.row_order(3)[0]
    (b / "rows").mkdir()
    rz.row_path(b, row).write_bytes(rz.row_path(a, row).read_bytes())
    with pytest.raises(rz.ChunkError, match="another run"):
        rz.read_chunk(b, row, _job(steps=STEPS - 100).run_key(), 3)


def test_folder_of_another_job_is_refused(tmp_path: Path) -> None:
    rz.run(tmp_path, _job(m=3), body_file=BODY, log=_quiet, max_rows=0)
    with pytest.raises(rz.RefineError, match="weights"):
        rz.run(tmp_path, _job(m=4), body_file=BODY, log=_quiet, max_rows=0)
    man = json.loads((tmp_path / "manifest.json").read_text())
    assert man["body_file_sha256"] and man["identity"]["weights"] == 3


def test_bad_inputs_say_what_is_allowed() -> None:
    p = load_params(BODY)
    with pytest.raises(rz.RefineError, match=r"l2.y = -0.7 .*\[-0.5, 0.5\]"):
        rz.Job(l1=(0.5, 0.5), l2=(0.5, -0.7), m=3, params=p, options=SweepOptions())
    with pytest.raises(rz.RefineError, match="weights = 1"):
        rz.Job(l1=(0.5, 0.5), l2=(0.5, -0.5), m=1, params=p, options=SweepOptions())
    with pytest.raises(rz.RefineError, match="adaptive_weights"):
        rz.Job(l1=(0.5, 0.5), l2=(0.5, -0.5), m=3, params=p, options=SweepOptions(adaptive_weights=True))


def test_row_order() -> None:
    o = rz.row_order(121)
    assert sorted(o) == list(range(121))
    assert o[:11] == list(range(0, 121, 12))  # the 11 x 11 survey's weights first
    assert rz.row_order(5) == [0, 4, 2, 1, 3]


def test_mirror_flips_counts_each_pair_once() -> None:
    rng = np.random.default_rng(0)
    succ = rng.random((4, 4, 4)) < 0.3
    sym = succ | succ[[3, 2, 1, 0]].transpose(0, 2, 1)  # symmetric under the mirror rule
    done = np.ones(4, dtype=bool)
    assert rz.mirror_flips(sym, done)["pairs_flipped"] == 0
    assert rz.mirror_flips(sym, done)["pairs_compared"] == 32
    bad = sym.copy()
    bad[0, 1, 2] = not bad[0, 1, 2]
    assert rz.mirror_flips(bad, done)["pairs_flipped"] == 1
    done[1] = False  # the flipped cell's row is not done: not compared
    assert rz.mirror_flips(bad, done) == {
        "pairs_compared": 18,
        "pairs_flipped": 0,
        "successes_in_compared": int((bad & (done[:, None] & done)[None]).sum()),
    }


#: A killed one-design run in its own process (the runner turns SIGTERM into KeyboardInterrupt).
_RUN_SCRIPT = """
import sys
from pathlib import Path
from morphlearn.physics.params import load_params
from morphlearn import resumable as rz
from morphlearn.physics.options import SweepOptions
body = Path(sys.argv[2])
job = rz.Job(l1=(0.5, 0.5), l2=(0.5, -0.5), m=7, params=load_params(body).replace(steps=400),
             options=SweepOptions(early_stop=True))
try:
    rz.run(Path(sys.argv[1]), job, body_file=body, log=print)
except KeyboardInterrupt:
    print("interrupted", flush=True)
    sys.exit(130)
"""


def test_killed_with_sigterm_resumes(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A real kill of a run in its own process: the rows written verify, no temporary file is
    left, and the resumed run computes exactly the others."""
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "run"
    proc = subprocess.Popen(
        [sys.executable, "-c", _RUN_SCRIPT, str(out), str(BODY)],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    deadline = time.monotonic() + 120
    while not list((out / "rows").glob("row_*.npz")) and time.monotonic() < deadline:
        time.sleep(0.05)
    proc.send_signal(signal.SIGTERM)
    text = proc.communicate(timeout=60)[0]
    assert proc.returncode == 130, text
    assert "interrupted" in text
    assert not [p for p in (out / "rows").iterdir() if not p.name.endswith(".npz")]  # no temporary file
    job = rz.job_from_manifest(rz.read_manifest(out))
    kept = rz.verified_rows(out, job.run_key(), 7)
    assert 1 <= len(kept) < 7
    spy = _Spy()
    monkeypatch.setattr(rz, "compute_row", spy)
    assert rz.run(out, job, log=_quiet) == 7 - len(kept)
    assert sorted(spy.rows) == sorted(set(range(7)) - set(kept))


def _refine(*args: str) -> subprocess.CompletedProcess[str]:
    """``morphlearn refine ARGS`` in its own process (as a user runs it)."""
    import sys

    return subprocess.run([sys.executable, "-m", "morphlearn.cli", "refine", *args], capture_output=True, text=True)


def test_export_of_a_partial_run_is_a_run_folder(tmp_path: Path) -> None:
    src, dest = tmp_path / "src", tmp_path / "bundle"
    job = _job()
    rz.run(src, job, body_file=BODY, log=_quiet, max_rows=2)
    r = _refine("export", str(src), str(dest))
    assert r.returncode == 0, r.stderr
    assert "PARTIAL" in (dest / "README.md").read_text()
    a, b = rz.assemble(src), rz.assemble(dest)
    assert (a.rows_done == b.rows_done).all() and a.result.first_time.tobytes() == b.result.first_time.tobytes()
    assert json.loads((dest / "summary.json").read_text())["rows_done"] == 2
    assert rz.run(dest, job, log=_quiet) == 1  # the bundle resumes like the run folder
    # exported in place (the run folder is the bundle): the rows stay, the README follows them
    r = _refine("export", str(dest), str(dest))
    assert r.returncode == 0, r.stderr
    assert rz.assemble(dest).complete and "complete" in (dest / "README.md").read_text()
    # status reads the export; a folder that is not one is refused in one line, exit 2
    r = _refine("status", str(dest))
    assert r.returncode == 0 and "rows 3/3 (100.0%)" in r.stdout and "complete" in r.stdout, r.stderr
    r = _refine("status", str(tmp_path))
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "not a refine folder" in r.stderr, r.stderr
    # an export never overwrites a folder that is not an export
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "keep.txt").write_text("mine")
    r = _refine("export", str(src), str(tmp_path / "other"))
    assert r.returncode == 2 and (tmp_path / "other" / "keep.txt").read_text() == "mine", r.stderr


def test_mujoco_rows_equal_mujoco_evaluate_design_bit_for_bit(tmp_path: Path) -> None:
    pytest.importorskip("mujoco")
    from morphlearn.mujoco import evaluate_design as mujoco_evaluate_design

    job = rz.Job(**{**_job().__dict__, "engine": "mujoco"})
    assert rz.run(tmp_path, job, body_file=BODY, log=_quiet) == 3
    a = rz.assemble(tmp_path)
    ref = mujoco_evaluate_design(job.l1, job.l2, job.weights, job.params, options=job.options)
    for k in ("first_time", "min_dist", "status"):
        got, want = getattr(a.result, k), getattr(ref, k)
        assert got.dtype == want.dtype and got.tobytes() == want.tobytes(), k
    assert metrics.success(ref.first_time, ref.min_dist, rz.thresholds(job.params)).any()
    # a MuJoCo folder is not a pybullet one: resuming it with the other engine is refused
    with pytest.raises(rz.RefineError, match="engine"):
        rz.run(tmp_path, _job(), body_file=BODY, log=_quiet, max_rows=0)


def test_engine_choice_keeps_pybullet_run_keys_and_refuses_unknown_engines() -> None:
    job = _job()
    # pybullet folders made before the engine choice existed keep their run keys
    assert "engine" not in job.identity() and "pybullet" in job.identity()
    with pytest.raises(rz.RefineError, match="engine = 'bullet3' is invalid; allowed: pybullet, mujoco"):
        rz.Job(**{**job.__dict__, "engine": "bullet3"})


def test_adaptive_replay_equals_an_adaptive_run(tmp_path: Path) -> None:
    """The adaptive grid's misses are measured by replaying it on an exhaustive folder: the cells
    the replay picks are the cells a real adaptive run simulates."""
    pytest.importorskip("mujoco")
    from morphlearn.mujoco import evaluate_design as mujoco_evaluate_design
    from morphlearn.physics.refine import misses, replay_mask
    from morphlearn.results import STATUS_INFERRED

    job = rz.Job(**{**_job(m=5).__dict__, "engine": "mujoco"})
    rz.run(tmp_path, job, body_file=BODY, log=_quiet)
    r = rz.assemble(tmp_path).result
    succ = metrics.success(r.first_time, r.min_dist, rz.thresholds(job.params))
    near = 1.5
    opts = SweepOptions(early_stop=True, adaptive_weights=True, near=near)
    run = mujoco_evaluate_design(job.l1, job.l2, job.weights, job.params, options=opts)
    seeds = succ | (r.min_dist <= near * job.params.contact_distance)
    mask = replay_mask(seeds)
    assert not mask.all(), "the check needs cells the adaptive grid skips"
    assert (mask == (run.status != STATUS_INFERRED)).all()
    m = misses(succ, r.min_dist, job.params.contact_distance, near)
    assert m["successes"] == int(succ.sum()) > 0 and 0 < m["simulated_share"] <= 1
    got = metrics.success(run.first_time, run.min_dist, rz.thresholds(job.params))
    assert m["successes_missed"] == int((succ & ~got).sum())


def test_adaptive_cost_without_early_stop_equals_a_run_without_it(tmp_path: Path) -> None:
    """`morphlearn refine adaptive` derives the no-lever cost from the early-stopped folder (a failure
    runs the whole horizon, a success stops at contact): its step count equals a real run's."""
    pytest.importorskip("mujoco")
    base = _job(m=5).__dict__
    stopped = rz.Job(**{**base, "engine": "mujoco"})
    full = rz.Job(**{**base, "engine": "mujoco", "options": SweepOptions(early_stop=False)})
    rz.run(tmp_path / "es", stopped, body_file=BODY, log=_quiet)
    rz.run(tmp_path / "full", full, body_file=BODY, log=_quiet)
    proc = _refine("adaptive", str(tmp_path / "es"), "--near", "4")
    assert proc.returncode == 0, proc.stderr
    cost = json.loads(proc.stdout)["cost"]
    real = rz.assemble(tmp_path / "full", log=_quiet).steps.astype(np.int64).sum()
    es = rz.assemble(tmp_path / "es", log=_quiet).steps.astype(np.int64).sum()
    assert cost["exhaustive_no_early_stop"]["steps"] == real
    assert cost["exhaustive_early_stop"]["steps"] == es < real  # the early stop saved steps here
    assert 0 < cost["adaptive_near_4_early_stop"]["steps"] <= es


COMMITTED = sorted((Path(__file__).resolve().parents[1] / "results" / "refine").glob("*/manifest.json"))


@pytest.mark.parametrize("folder", [p.parent for p in COMMITTED], ids=[p.parent.name for p in COMMITTED])
def test_committed_folders_assemble_to_their_summaries(folder: Path) -> None:
    """Every committed refine folder's rows verify, and ``morphlearn refine assemble`` gives its
    committed summary.json byte for byte (the old tool wrote it with the same numbers)."""
    r = _refine("assemble", str(folder))
    assert r.returncode == 0, r.stderr
    assert r.stdout == (folder / "summary.json").read_text()


def test_survey_check_gives_the_committed_check() -> None:
    """``morphlearn refine survey-check`` of the canonical folder against the committed pybullet
    survey gives the committed survey_check.json: every shared cell bit-identical."""
    root = Path(__file__).resolve().parents[1]
    folder = root / "results" / "refine" / "canonical_121"
    r = _refine("survey-check", str(folder), str(root / "results" / "survey" / "empirical" / "merged.zarr"))
    assert r.returncode == 0, r.stderr
    assert r.stdout == (folder / "survey_check.json").read_text()
    got = json.loads(r.stdout)
    assert got["bit_identical_there"]["status"] == got["survey_simulated_with_bit_equal_weights"] > 0
