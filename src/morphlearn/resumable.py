"""One empirical design at any weight resolution, resumable inside the design.

A 121 x 121 design in pybullet is 58,564 episodes, hours of one core; the per-design cache
(:mod:`morphlearn.design_cache`) keeps only finished designs, so a killed run would lose them all.
Here the design's (env, w1, w2) grid is cut into chunks, one per w1 row (all 4 environments, all
w2: ``4 m`` episodes, ~1-2 min of one core at m = 121), and each finished chunk is written
atomically to ``{folder}/rows/row_{i:03d}.npz``. A restart verifies every chunk (run key, row,
shapes, dtypes, SHA-256 of its arrays) and computes only the missing or damaged ones; Ctrl-C or a
kill loses at most the chunk in progress.

The episodes are those of :func:`morphlearn.empirical.episode.evaluate_design` on the
exhaustive grid (no adaptive weights) with the given levers (early stop: exact, docs/
empirical_levers.md): same runner, same reach bound, same per-cell call, so the assembled result
equals ``evaluate_design`` bit for bit (tested). Rows run coarse to fine (the 11-point subgrid
first where it exists, then farthest-first), so a partial run is an evenly spread sample of w1.

Folder layout: ``manifest.json`` (identity: design, weights, params and their digest, levers,
pybullet version; body file digest, code commit at creation), ``rows/`` (the chunks: arrays
only, deterministic bytes), ``progress.jsonl`` (one line per chunk computed: wall and CPU time,
physics steps, commit), ``runs.jsonl`` (one line per start).
"""

from __future__ import annotations

import hashlib
import io
import json
import math
import os
import signal
import threading
import time
import zipfile
from collections.abc import Callable
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from morphlearn import bounded, metrics, models, provenance
from morphlearn.config import digest
from morphlearn.grid import ENV_MIRROR
from morphlearn.grid import weights as weight_grid
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import EmpiricalParams
from morphlearn.physics.rows import CHUNK_VARS, Engine
from morphlearn.results import DesignResult

Point = tuple[float, float]

FORMAT = "morphlearn.refine_design/1"
#: Status of a cell whose row is not computed yet (partial results only; never in a store).
NOT_RUN = -1
_ZIP_DATE = (1980, 1, 1, 0, 0, 0)  # fixed, so a chunk's bytes depend on its numbers only


class RefineError(Exception):
    """A bad input or a folder that belongs to another run."""


class ChunkError(Exception):
    """A chunk file that is missing, unreadable, damaged or from another run."""


@dataclass(frozen=True)
class Job:
    """What one folder computes."""

    l1: Point
    l2: Point
    m: int
    params: EmpiricalParams
    options: SweepOptions
    #: ``pybullet`` (the reference engine) or ``mujoco`` (its default ``MujocoSettings``).
    engine: str = "pybullet"

    def __post_init__(self) -> None:
        if self.engine not in ENGINES:
            raise RefineError(f"engine = {self.engine!r} is invalid; allowed: {', '.join(ENGINES)}")
        for name, v in zip(("l1.x", "l1.y", "l2.x", "l2.y"), (*self.l1, *self.l2), strict=True):
            if not (math.isfinite(v) and -0.5 <= v <= 0.5):
                raise RefineError(f"design {name} = {v!r} is outside the body; allowed: [-0.5, 0.5]")
        if isinstance(self.m, bool) or not isinstance(self.m, int) or self.m < 2:
            raise RefineError(f"weights = {self.m!r} is invalid; allowed: an integer >= 2")
        if self.options.adaptive_weights:
            raise RefineError("adaptive_weights is not allowed: this runner is the exhaustive reference grid")

    @property
    def weights(self) -> np.ndarray:
        return weight_grid(self.m)

    def identity(self) -> dict[str, Any]:
        """Everything that determines the chunks' numbers (the run key is its digest)."""
        return {
            "format": FORMAT,
            "design": {"l1": [float(v) for v in self.l1], "l2": [float(v) for v in self.l2]},
            "weights": self.m,
            "weights_sha256": hashlib.sha256(self.weights.tobytes()).hexdigest(),
            "params": self.params.to_dict(),
            "levers": self.options.science(),
            "chunk": "one w1 row: all 4 environments x all w2",
            **ENGINES[self.engine].identity(),
        }

    def runner(self) -> Any:
        """The engine's episode runner (a context manager)."""
        return ENGINES[self.engine].runner(self.params)

    def run_key(self) -> str:
        return digest(self.identity())


def row_order(m: int) -> list[int]:
    """Rows coarse to fine: the 11-point weight subgrid first when ``m - 1`` is a multiple of 10
    (at 121 these rows are the survey's 11 x 11 weights), else the two ends; then repeatedly the
    row farthest from all chosen ones (ties: the smallest index)."""
    seed = list(range(0, m, (m - 1) // 10)) if m > 11 and (m - 1) % 10 == 0 else [0, m - 1]
    chosen = list(dict.fromkeys(seed))
    dist = np.full(m, np.inf)
    for r in chosen:
        dist = np.minimum(dist, np.abs(np.arange(m) - r))
    while len(chosen) < m:
        r = int(np.argmax(dist))  # first maximum: the smallest index
        chosen.append(r)
        dist = np.minimum(dist, np.abs(np.arange(m) - r))
    return chosen


# ---------------------------------------------------------------- chunk files


def _arrays_sha256(arrays: dict[str, np.ndarray]) -> str:
    h = hashlib.sha256()
    for k in CHUNK_VARS:
        h.update(k.encode() + b"\0" + np.ascontiguousarray(arrays[k]).tobytes())
    return h.hexdigest()


def row_path(folder: Path, row: int) -> Path:
    return folder / "rows" / f"row_{row:03d}.npz"


def _atomic_write(path: Path, data: bytes) -> None:
    """Write via a temporary file in the same folder, fsync, rename: a reader sees the old file or
    the whole new one, never a part."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp{os.getpid()}")
    try:
        with tmp.open("wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
    fd = os.open(path.parent, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def write_chunk(folder: Path, row: int, run_key: str, arrays: dict[str, np.ndarray]) -> None:
    """One finished row as an ``.npz`` (readable with ``numpy.load``) with deterministic bytes."""
    arrays = {k: np.ascontiguousarray(arrays[k], dtype=dt) for k, dt in CHUNK_VARS.items()}
    meta = {"format": FORMAT, "run_key": run_key, "row": row, "sha256": _arrays_sha256(arrays)}
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as zf:
        for name, a in [*arrays.items(), ("meta", np.array(json.dumps(meta, sort_keys=True)))]:
            b = io.BytesIO()
            np.lib.format.write_array(b, a, allow_pickle=False)
            zi = zipfile.ZipInfo(f"{name}.npy", date_time=_ZIP_DATE)
            zi.compress_type = zipfile.ZIP_DEFLATED
            zf.writestr(zi, b.getvalue())
    _atomic_write(row_path(folder, row), buf.getvalue())


def read_chunk(folder: Path, row: int, run_key: str, m: int) -> dict[str, np.ndarray]:
    """The arrays of one row, verified; raises ChunkError saying what is wrong."""
    p = row_path(folder, row)
    if not p.is_file():
        raise ChunkError(f"{p}: missing")
    try:
        with np.load(p, allow_pickle=False) as z:
            data = {k: z[k] for k in z.files}
        meta = json.loads(str(data.pop("meta")))
    except Exception as e:  # any unreadable file is just a chunk to recompute
        raise ChunkError(f"{p}: unreadable ({type(e).__name__}: {e})") from None
    if meta.get("run_key") != run_key:
        got = str(meta.get("run_key"))[:12]
        raise ChunkError(f"{p}: from another run (run key {got}..., expected {run_key[:12]}...)")
    if meta.get("row") != row:
        raise ChunkError(f"{p}: holds row {meta.get('row')}, expected {row}")
    for k, dt in CHUNK_VARS.items():
        a = data.get(k)
        if a is None or a.dtype != dt or a.shape != (4, m):
            got = None if a is None else (a.dtype.str, a.shape)
            raise ChunkError(f"{p}: array {k} is {got}, expected ({dt.str}, (4, {m}))")
    if _arrays_sha256(data) != meta.get("sha256"):
        raise ChunkError(f"{p}: checksum mismatch (damaged)")
    return {k: data[k] for k in CHUNK_VARS}


# ---------------------------------------------------------------- manifest


def manifest_path(folder: Path) -> Path:
    return folder / "manifest.json"


#: The most weights per synapse a manifest may name (as grid.weights in the config schema).
MAX_WEIGHTS = 1001
#: What a manifest holds, for the one line that refuses a malformed one.
MANIFEST_SHAPE = (
    "a JSON object with run_key (a string) and identity {design: {l1, l2}, weights, params, levers} "
    "as refine_design writes it"
)


def read_manifest(folder: Path) -> dict[str, Any]:
    """The folder's manifest, read within :mod:`morphlearn.bounded`'s limits (size, nesting) and
    checked for the keys every reader takes from it (a list, a string or a 50,000-deep nesting
    once ended in a TypeError or RecursionError traceback): RefineError, one line naming the file,
    the key and what is allowed."""
    p = manifest_path(folder)
    if not p.exists():
        raise RefineError(f"{p}: missing (not a refine_design folder)")
    try:
        man = bounded.json_file(p)
    except ValueError as e:
        raise RefineError(f"{p}: unreadable ({e}); allowed: {MANIFEST_SHAPE}") from None
    if not isinstance(man, dict):
        kind = {"list": "a list", "str": "a string", "int": "a number", "float": "a number", "NoneType": "null"}
        what = kind.get(type(man).__name__, type(man).__name__)
        raise RefineError(f"{p}: top level is {what}, not an object; allowed: {MANIFEST_SHAPE}")
    if not isinstance(man.get("run_key"), str):
        raise RefineError(f"{p}: run_key = {_short(man.get('run_key'))} is invalid; allowed: {MANIFEST_SHAPE}")
    try:
        job = job_from_manifest(man)
        job.run_key()
    except KeyError as e:
        raise RefineError(f"{p}: the key {_short(e.args[0])} is missing; allowed: {MANIFEST_SHAPE}") from None
    except (TypeError, ValueError, AttributeError, IndexError) as e:
        why = " ".join(str(e).split())[:200]
        raise RefineError(f"{p}: identity is malformed ({why}); allowed: {MANIFEST_SHAPE}") from None
    if not 2 <= job.m <= MAX_WEIGHTS:  # the arrays assembled are 4 x m x m
        raise RefineError(f"{p}: identity.weights = {job.m} is out of range; allowed: 2..{MAX_WEIGHTS}")
    return man


def _short(v: Any) -> str:
    text = repr(v)
    return text if len(text) <= 60 else f"{text[:50]}... ({len(text)} characters)"


def open_folder(folder: Path, job: Job, body_file: str | Path | None) -> str:
    """Create the folder's manifest, or check that an existing one is this job's; the run key."""
    key = job.run_key()
    p = manifest_path(folder)
    if p.exists():
        old = read_manifest(folder)
        if old.get("run_key") != key:
            ident, old_ident = job.identity(), old.get("identity", {})
            diff = sorted(k for k in ident.keys() | old_ident.keys() if ident.get(k) != old_ident.get(k))
            raise RefineError(f"{folder} holds another run (differs in: {', '.join(diff)}); use another --out folder")
        return key
    man = {
        "run_key": key,
        "identity": job.identity(),
        "params_sha256": digest(job.params.to_dict()),
        "body_file": str(body_file) if body_file else None,
        "body_file_sha256": provenance.sha256_file(body_file) if body_file else None,
        "weight_values": job.weights.tolist(),
        "row_order": row_order(job.m),
        "created_utc": _now(),
        "created_commit": provenance.git_commit(),
    }
    _atomic_write(p, (json.dumps(man, indent=1, sort_keys=True) + "\n").encode())
    return key


def _now() -> str:
    return datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ")


def _append(path: Path, record: dict[str, Any]) -> None:
    with path.open("a") as fh:
        fh.write(json.dumps(record, sort_keys=True) + "\n")
        fh.flush()
        os.fsync(fh.fileno())


def verified_rows(
    folder: Path, key: str, m: int, log: Callable[[str], None] | None = None
) -> dict[int, dict[str, np.ndarray]]:
    """Every row of the folder that verifies; the damaged ones are reported through ``log``."""
    out: dict[int, dict[str, np.ndarray]] = {}
    for i in range(m):
        if not row_path(folder, i).exists():
            continue
        try:
            out[i] = read_chunk(folder, i, key, m)
        except ChunkError as e:
            if log:
                log(f"not reused, will recompute: {e}")
    return out


# ---------------------------------------------------------------- running


def compute_row(runner: Any, job: Job, row: int) -> dict[str, np.ndarray]:
    """All 4 x m episodes of w1 row ``row``: the per-cell call of ``evaluate_design``."""
    return ENGINES[job.engine].row(runner, job, row)


#: Engines a folder can be computed with, by engine name: every registered physics model that
#: declares how a row is computed (:meth:`morphlearn.physics.model.Physics.row_engine`; ``pybullet``
#: is the reference engine, ``mujoco`` runs with its default ``MujocoSettings``).
ENGINES: dict[str, Engine] = {
    m.engine: e for m in (models.get(n) for n in models.physics()) if (e := m.row_engine()) is not None
}


def _row_generalists(chunk: dict[str, np.ndarray], th: metrics.Thresholds) -> int:
    succ = metrics.success(chunk["first_time"], chunk["min_dist"], th)
    return int(succ.all(axis=0).sum())


def thresholds(params: EmpiricalParams) -> metrics.Thresholds:
    """The empirical model's success: touching the light within the episode (as the pipeline)."""
    return metrics.Thresholds(params.horizon, params.contact_distance, params.horizon, params.contact_distance)


def run(
    folder: str | Path,
    job: Job,
    *,
    body_file: str | Path | None = None,
    max_rows: int | None = None,
    log: Callable[[str], None] = print,
) -> int:
    """Compute the folder's missing rows in :func:`row_order`; returns the number computed now.

    ``max_rows`` stops after that many new rows (tests, short sessions). SIGTERM is turned into
    KeyboardInterrupt so a kill, like Ctrl-C, only loses the row in progress.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    key = open_folder(folder, job, body_file)
    commit = provenance.git_commit()
    _append(folder / "runs.jsonl", {"started_utc": _now(), "commit": commit, "pid": os.getpid()})
    done = verified_rows(folder, key, job.m, log)
    th = thresholds(job.params)
    gen = sum(_row_generalists(c, th) for c in done.values())
    todo = [r for r in row_order(job.m) if r not in done]
    if max_rows is not None:
        todo = todo[:max_rows]
    n_rows, per_row = job.m, 4 * job.m
    log(
        f"{folder}: run key {key[:12]}, {len(done)}/{n_rows} rows verified and reused, "
        f"{len(todo)} to compute ({len(todo) * per_row} episodes); generalists so far {gen}"
    )
    old = signal.signal(signal.SIGTERM, _raise_interrupt) if _main_thread() else None
    t0, computed = time.monotonic(), 0
    try:
        with job.runner() as runner:
            for row in todo:
                w0, c0 = time.monotonic(), time.process_time()
                chunk = compute_row(runner, job, row)
                write_chunk(folder, row, key, chunk)
                wall, cpu = time.monotonic() - w0, time.process_time() - c0
                computed += 1
                g = _row_generalists(chunk, th)
                gen += g
                _append(
                    folder / "progress.jsonl",
                    {
                        "row": row,
                        "episodes": per_row,
                        "wall_s": round(wall, 3),
                        "cpu_s": round(cpu, 3),
                        "steps": int(chunk["steps"].sum()),
                        "generalists": g,
                        "finished_utc": _now(),
                        "commit": commit,
                    },
                )
                n_done = len(done) + computed
                rate = computed * per_row / (time.monotonic() - t0)
                left = (n_rows - n_done) * per_row / rate
                eta = datetime.fromtimestamp(time.time() + left, UTC).strftime("%H:%M UTC")
                log(
                    f"row {row:3d} (w1 = {job.weights[row]:+.4f}) done: {per_row} episodes in {wall:.0f} s "
                    f"({per_row / wall:.2f}/s, {cpu:.0f} CPU-s); {n_done}/{n_rows} rows ({n_done / n_rows:.1%}); "
                    f"{rate:.2f} episodes/s this session; ~{left / 3600:.2f} h left, ETA {eta}; "
                    f"generalists {g} in this row, {gen} so far"
                )
    except KeyboardInterrupt:
        log(
            f"interrupted: {computed} rows computed in this session; the row in progress is lost; "
            "run the same command to resume"
        )
        raise
    finally:
        if old is not None:
            signal.signal(signal.SIGTERM, old)
    return computed


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


def _raise_interrupt(signum: int, frame: Any) -> None:
    raise KeyboardInterrupt(f"signal {signum}")


# ---------------------------------------------------------------- assembling


@dataclass
class Assembled:
    """A folder's rows as one design's (4, m, m) arrays; ``rows_done[i]`` says whether row i is in.

    Rows not done have NaN times and distances and status ``NOT_RUN`` (-1): a partial result is
    never a ``DesignResult`` of the whole grid (``complete`` says which).
    """

    result: DesignResult
    steps: np.ndarray
    rows_done: np.ndarray
    manifest: dict[str, Any]

    @property
    def complete(self) -> bool:
        return bool(self.rows_done.all())


def job_from_manifest(man: dict[str, Any]) -> Job:
    ident = man["identity"]
    lev = ident.get("levers", {})
    es = lev.get("early_stop")
    opts = SweepOptions(early_stop=es is not None, margin=es["margin"] if es else SweepOptions().margin)
    return Job(
        l1=tuple(ident["design"]["l1"]),
        l2=tuple(ident["design"]["l2"]),
        m=int(ident["weights"]),
        params=EmpiricalParams.from_mapping(ident["params"]),
        options=opts,
        engine=ident.get("engine", "pybullet"),
    )


def assemble(folder: str | Path, log: Callable[[str], None] | None = None) -> Assembled:
    """The verified rows of a folder (damaged ones are left out and reported through ``log``)."""
    folder = Path(folder)
    man = read_manifest(folder)
    job = job_from_manifest(man)
    if job.run_key() != man["run_key"]:
        raise RefineError(
            f"{manifest_path(folder)}: its identity does not hash to its run key "
            "(edited, or written by another engine version)"
        )
    m = job.m
    first = np.full((4, m, m), np.nan, dtype=np.float32)
    dist = np.full((4, m, m), np.nan, dtype=np.float32)
    status = np.full((4, m, m), NOT_RUN, dtype=np.int8)
    steps = np.zeros((4, m, m), dtype=np.int16)
    done = np.zeros(m, dtype=bool)
    for i, c in verified_rows(folder, man["run_key"], m, log).items():
        first[:, i], dist[:, i], status[:, i], steps[:, i] = c["first_time"], c["min_dist"], c["status"], c["steps"]
        done[i] = True
    return Assembled(DesignResult(first, dist, status), steps, done, man)


def mirror_flips(succ: np.ndarray, rows_done: np.ndarray) -> dict[str, int]:
    """For a design that is its own mirror image: cell (env, i, j) against (ENV_MIRROR[env], j, i)
    (the mirror rule of morphlearn.grid.ENV_MIRROR), over the pairs with both rows done; each unordered pair once."""
    mirrored = succ[list(ENV_MIRROR)].transpose(0, 2, 1)
    both = rows_done[:, None] & rows_done[None, :]
    cells = int(both.sum()) * 4
    flips = int(((succ != mirrored) & both[None]).sum())
    return {
        "pairs_compared": cells // 2,
        "pairs_flipped": flips // 2,
        "successes_in_compared": int((succ & both[None]).sum()),
    }


def is_self_mirror(l1: Point, l2: Point) -> bool:
    return (l2[0], -l2[1]) == (l1[0], l1[1]) and (l1[0], -l1[1]) == (l2[0], l2[1])


def summary(a: Assembled) -> dict[str, Any]:
    """Metrics of the rows done (``morphlearn.metrics``), the cost, and the mirror comparison."""
    job = job_from_manifest(a.manifest)
    th = thresholds(job.params)
    d = a.result
    rows = np.flatnonzero(a.rows_done)
    succ = metrics.success(d.first_time, d.min_dist, th)
    dm = metrics.design_metrics(succ[:, rows], d.status[:, rows])
    ep = 4 * len(rows) * job.m
    out: dict[str, Any] = {
        "complete": a.complete,
        "rows_done": len(rows),
        "rows": job.m,
        "fraction_done": len(rows) / job.m,
        "episodes": ep,
        "metrics_over_rows_done": dm.as_dict(),
        "physics_steps": int(a.steps[:, rows].sum()),
        "steps_per_episode": float(a.steps[:, rows].sum() / ep) if ep else math.nan,
        "thresholds": {"horizon": th.horizon, "radius": th.radius},
    }
    if is_self_mirror(job.l1, job.l2):
        out["mirror"] = mirror_flips(succ, a.rows_done)
    return out


def cost(folder: str | Path) -> dict[str, Any]:
    """Wall and CPU time of the rows computed (from progress.jsonl; the last record of a row)."""
    p = Path(folder) / "progress.jsonl"
    recs: dict[int, dict[str, Any]] = {}
    if p.exists():
        try:
            text = bounded.read_bytes(p).decode("utf-8", errors="replace")
        except ValueError as e:
            raise RefineError(f"{p}: {e}") from None
        for n, line in enumerate(text.splitlines(), 1):
            if not line.strip():
                continue
            try:  # one record a line, as refine_design appends them: a malformed one is one line
                r = json.loads(line)
                row = int(r["row"])
                counts = [r[k] for k in ("episodes", "wall_s", "cpu_s")]  # kept as written (int or float)
                if not all(type(v) in (int, float) and math.isfinite(v) and v >= 0 for v in counts):
                    raise ValueError("a negative or non-finite count")
            except (ValueError, TypeError, KeyError, IndexError, RecursionError) as e:
                why = " ".join(str(e).split())[:80]
                raise RefineError(
                    f"{p}: line {n} is malformed ({type(e).__name__}: {why}); allowed: one JSON object a line "
                    "with row, episodes, wall_s and cpu_s >= 0, as refine_design writes them"
                ) from None
            recs[row] = r
    ep = sum(r["episodes"] for r in recs.values())
    wall = sum(r["wall_s"] for r in recs.values())
    cpu = sum(r["cpu_s"] for r in recs.values())
    return {
        "rows_logged": len(recs),
        "episodes": ep,
        "wall_s": round(wall, 1),
        "cpu_s": round(cpu, 1),
        "episodes_per_wall_s": ep / wall if wall else math.nan,
        "episodes_per_cpu_s": ep / cpu if cpu else math.nan,
    }


def check_engine(science: dict[str, Any]) -> None:
    """Refuse (ValueError) to re-simulate a refine bundle's record with another engine version or
    settings than it was simulated with: the re-simulation would not be the recorded run."""
    ref = science["refine"]
    engine = ENGINES.get(ref.get("engine"))
    if engine is None:
        raise ValueError(f"refine engine {ref.get('engine')!r} unknown here; allowed: {', '.join(ENGINES)}")
    here = json.loads(json.dumps(engine.identity()))  # as the record stores it (tuples as lists)
    if here != ref.get("engine_identity"):
        raise ValueError(
            f"the bundle was simulated with {ref.get('engine_identity')}, this machine runs {here}: "
            "a re-simulation here would not be the recorded run"
        )
