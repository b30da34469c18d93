"""A design's finished episodes, kept while it runs, so a killed design resumes inside itself.

A pybullet design on the paper's 121 x 121 weights is hours of one core, too long a unit to lose
to a killed job (SLURM time limit, Ctrl-C, a lost node). The physics sweep
(:func:`morphlearn.physics.sweep.sweep`, every engine's) keeps its episodes done so far in one file
(every ``CHECKPOINT_S`` seconds and when it stops on an error) and reads them back at its start
(:func:`resume`); the design cache (:mod:`morphlearn.physics.design_cache`) says where the file lives and
removes it once the design is stored. The cells already simulated are not
simulated again, and since the adaptive grid chooses cells from outcomes alone, the resumed run
takes the same path and gives the same bytes. The file names the design, weights, body and levers
it was made for and the digest of its arrays; one that does not match is ignored (reported) and
the design starts over.
"""

from __future__ import annotations

import hashlib
import io
import json
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from morphlearn import store
from morphlearn.results import STATUS_OK

#: Seconds between saves of a running design: a killed job loses at most this much of it.
CHECKPOINT_S = 60.0
ARRAYS = ("first_time", "min_dist", "status", "simulated")


@dataclass
class Cells:
    """The (4, m, m) arrays of a design being evaluated, and which cells hold a finished episode."""

    first_time: np.ndarray
    min_dist: np.ndarray
    status: np.ndarray
    simulated: np.ndarray

    @classmethod
    def empty(cls, m: int) -> Cells:
        """No episode done yet, on an m x m weight grid (arrays as the sweep fills them)."""
        return cls(
            first_time=np.full((4, m, m), np.nan),
            min_dist=np.full((4, m, m), np.nan),
            status=np.full((4, m, m), STATUS_OK, dtype=np.int8),
            simulated=np.zeros((4, m, m), bool),
        )


def identity(l1: Any, l2: Any, weights: np.ndarray, params: Any, options: Any) -> str:
    """What the episodes depend on: the design, weights, body and levers (their reprs are exact)."""
    h = hashlib.sha256(repr((tuple(l1), tuple(l2), params, options)).encode())
    h.update(np.ascontiguousarray(weights, dtype=np.float64).tobytes())
    return h.hexdigest()


def _digest(cells: Cells) -> str:
    h = hashlib.sha256()
    for k in ARRAYS:
        h.update(np.ascontiguousarray(getattr(cells, k)).tobytes())
    return h.hexdigest()


def save(path: Path, ident: str, cells: Cells) -> None:
    """Write the cells atomically (a kill during the write leaves the previous save)."""
    buf = io.BytesIO()
    meta = json.dumps({"identity": ident, "sha256": _digest(cells)})
    np.savez(buf, meta=np.array(meta), **{k: getattr(cells, k) for k in ARRAYS})
    with store.atomic_path(path) as tmp:
        tmp.write_bytes(buf.getvalue())


def load(path: Path, ident: str, shape: tuple[int, int, int]) -> Cells | None:
    """The saved cells of this very evaluation, or None (no file, or one that does not match)."""
    if not path.is_file():
        return None
    try:
        with np.load(path, allow_pickle=False) as z:
            meta = json.loads(str(z["meta"]))
            cells = Cells(*(z[k] for k in ARRAYS))
    except (OSError, ValueError, KeyError, zipfile.BadZipFile) as e:  # damaged: its CRC, header or keys
        print(f"partial design {path}: unreadable, not resumed ({e})", flush=True)
        return None
    if meta.get("identity") != ident:
        print(f"partial design {path}: made for another design, weights, body or levers; not resumed", flush=True)
        return None
    if any(getattr(cells, k).shape != shape for k in ARRAYS) or meta.get("sha256") != _digest(cells):
        print(f"partial design {path}: its arrays do not match their digest; not resumed", flush=True)
        return None
    return cells


def resume(path: Path | None, l1: Any, l2: Any, weights: np.ndarray, params: Any, options: Any) -> tuple[str, Cells]:
    """A design's evaluation starts here: its identity and the cells of its partial file (said when
    resumed), or empty cells (no file, or one made for another evaluation)."""
    m = len(weights)
    ident = identity(l1, l2, weights, params, options) if path is not None else ""
    cells = load(path, ident, (4, m, m)) if path is not None else None
    if cells is None:
        return ident, Cells.empty(m)
    print(f"partial design {path}: resumed, {int(cells.simulated.sum())} episodes done", flush=True)
    return ident, cells
