"""The committed refine folders (``results/refine/*``), read-only: one physics design each on an
exhaustive weight grid, stored row by row.

They were written by the old one-design runner (``tools/refine_design.py``, then
``morphlearn.resumable``; both deleted, issue 58: every result is now made by the workflow's rules
and sealed as a bundle, e.g. ``config/refine_exhaustive.yaml``). What is left is their reader, so
the history stays checkable and usable: every row is verified (run key, row, shapes, dtypes,
SHA-256 of its arrays) before it is read, and a manifest whose identity does not hash to its run key
is refused. Nothing here writes.

Folder layout: ``manifest.json`` (identity: design, weights, params and their digest, levers,
engine version; body file digest, code commit at creation), ``rows/row_{i:03d}.npz`` (one w1
row each: all 4 environments, all w2), ``progress.jsonl`` (one line per row computed: wall and CPU
time, physics steps, commit), ``runs.jsonl`` (one line per start).
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from morphlearn import bounded, metrics
from morphlearn.config import digest
from morphlearn.grid import ENV_MIRROR
from morphlearn.grid import weights as weight_grid
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import EmpiricalParams
from morphlearn.results import DesignResult

Point = tuple[float, float]

FORMAT = "morphlearn.refine_design/1"
#: Status of a cell whose row is not in the folder (partial results only; never in a store).
NOT_RUN = -1
#: The row arrays, their dtypes (those of DesignResult, plus the physics steps for the cost).
CHUNK_VARS: dict[str, np.dtype] = {
    "first_time": np.dtype(np.float32),
    "min_dist": np.dtype(np.float32),
    "status": np.dtype(np.int8),
    "steps": np.dtype(np.int16),
}
#: The identity's keys that say what was simulated; every other key names the engine and its
#: version as recorded when the folder was made (kept as history, never compared with this machine).
CORE_KEYS = frozenset({"format", "design", "weights", "weights_sha256", "params", "levers", "chunk"})
#: The engine of a folder whose manifest names none: folders made before the engine choice existed
#: (a recorded fact of that history, not an engine choice of this code).
UNNAMED_ENGINE = "pybullet"


class RefineError(Exception):
    """A bad folder: a manifest that is missing or malformed, or not its identity's."""


class ChunkError(Exception):
    """A row file that is missing, unreadable, damaged or from another run."""


@dataclass(frozen=True)
class Job:
    """What one folder computed, as its manifest says."""

    l1: Point
    l2: Point
    m: int
    params: EmpiricalParams
    options: SweepOptions
    #: The engine that simulated it (:data:`UNNAMED_ENGINE` when the manifest names none).
    engine: str = UNNAMED_ENGINE
    #: The engine's version and settings as recorded (part of the run key).
    engine_identity: dict[str, Any] = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        for name, v in zip(("l1.x", "l1.y", "l2.x", "l2.y"), (*self.l1, *self.l2), strict=True):
            if not (math.isfinite(v) and -0.5 <= v <= 0.5):
                raise RefineError(f"design {name} = {v!r} is outside the body; allowed: [-0.5, 0.5]")
        if isinstance(self.m, bool) or not isinstance(self.m, int) or self.m < 2:
            raise RefineError(f"weights = {self.m!r} is invalid; allowed: an integer >= 2")

    @property
    def weights(self) -> np.ndarray:
        return weight_grid(self.m)

    def identity(self) -> dict[str, Any]:
        """Everything that determined the rows' numbers (the run key is its digest): rebuilt from
        the parsed fields, so a manifest whose fields and run key disagree is caught."""
        return {
            "format": FORMAT,
            "design": {"l1": [float(v) for v in self.l1], "l2": [float(v) for v in self.l2]},
            "weights": self.m,
            "weights_sha256": hashlib.sha256(self.weights.tobytes()).hexdigest(),
            "params": self.params.to_dict(),
            "levers": self.options.science(),
            "chunk": "one w1 row: all 4 environments x all w2",
            **self.engine_identity,
        }

    def run_key(self) -> str:
        return digest(self.identity())


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
        engine=ident.get("engine", UNNAMED_ENGINE),
        engine_identity={k: v for k, v in ident.items() if k not in CORE_KEYS},
    )


# ---------------------------------------------------------------- row files


def _arrays_sha256(arrays: dict[str, np.ndarray]) -> str:
    h = hashlib.sha256()
    for k in CHUNK_VARS:
        h.update(k.encode() + b"\0" + np.ascontiguousarray(arrays[k]).tobytes())
    return h.hexdigest()


def row_path(folder: Path, row: int) -> Path:
    return folder / "rows" / f"row_{row:03d}.npz"


def read_chunk(folder: Path, row: int, run_key: str, m: int) -> dict[str, np.ndarray]:
    """The arrays of one row, verified; raises ChunkError saying what is wrong."""
    p = row_path(folder, row)
    if not p.is_file():
        raise ChunkError(f"{p}: missing")
    try:
        with np.load(p, allow_pickle=False) as z:
            data = {k: z[k] for k in z.files}
        meta = json.loads(str(data.pop("meta")))
    except Exception as e:  # any unreadable file is a row left out, said through the log
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


def verified_rows(
    folder: Path, key: str, m: int, log: Callable[[str], None] | None = None
) -> dict[int, dict[str, np.ndarray]]:
    """Every row of the folder that verifies; the others are reported through ``log``."""
    out: dict[int, dict[str, np.ndarray]] = {}
    for i in range(m):
        if not row_path(folder, i).exists():
            continue
        try:
            out[i] = read_chunk(folder, i, key, m)
        except ChunkError as e:
            if log:
                log(f"left out: {e}")
    return out


# ---------------------------------------------------------------- manifest


def manifest_path(folder: Path) -> Path:
    return folder / "manifest.json"


#: The most weights per synapse a manifest may name (as grid.weights in the config schema).
MAX_WEIGHTS = 1001
#: What a manifest holds, for the one line that refuses a malformed one.
MANIFEST_SHAPE = (
    "a JSON object with run_key (a string) and identity {design: {l1, l2}, weights, params, levers} "
    "as refine_design wrote it"
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


def assemble(folder: str | Path, log: Callable[[str], None] | None = None) -> Assembled:
    """The verified rows of a folder (damaged ones are left out and reported through ``log``)."""
    folder = Path(folder)
    man = read_manifest(folder)
    job = job_from_manifest(man)
    if job.run_key() != man["run_key"]:
        raise RefineError(f"{manifest_path(folder)}: its identity does not hash to its run key (edited)")
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


def thresholds(params: EmpiricalParams) -> metrics.Thresholds:
    """The physics models' success: touching the light within the episode (as the workflow)."""
    return metrics.Thresholds(params.horizon, params.contact_distance, params.horizon, params.contact_distance)


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
