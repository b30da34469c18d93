"""A refine folder in the committed format (morphlearn.refine.folder), written for tests only: the
project no longer writes refine folders (issue 58), but its reader and seeding must still refuse
damaged or foreign ones, so tests forge them: a design's outcome arrays cut into w1 rows."""

from __future__ import annotations

import io
import json
import zipfile
from pathlib import Path

import numpy as np

from morphlearn import provenance
from morphlearn.refine import folder as rf

_ZIP_DATE = (1980, 1, 1, 0, 0, 0)


def write_row(folder: Path, row: int, run_key: str, arrays: dict[str, np.ndarray]) -> None:
    """One w1 row as the old runner stored it: an ``.npz`` with its arrays and a ``meta`` record
    (run key, row, SHA-256 of the arrays)."""
    arrays = {k: np.ascontiguousarray(arrays[k], dtype=dt) for k, dt in rf.CHUNK_VARS.items()}
    meta = {"format": rf.FORMAT, "run_key": run_key, "row": row, "sha256": rf._arrays_sha256(arrays)}
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as zf:
        for name, a in [*arrays.items(), ("meta", np.array(json.dumps(meta, sort_keys=True)))]:
            b = io.BytesIO()
            np.lib.format.write_array(b, a, allow_pickle=False)
            zf.writestr(zipfile.ZipInfo(f"{name}.npy", date_time=_ZIP_DATE), b.getvalue())
    rf.row_path(folder, row).parent.mkdir(parents=True, exist_ok=True)
    rf.row_path(folder, row).write_bytes(buf.getvalue())


def write_folder(
    folder: Path,
    job: rf.Job,
    arrays: dict[str, np.ndarray],
    *,
    rows: list[int] | None = None,
    body_file: Path | None = None,
    commit: str = "test",
) -> Path:
    """``arrays`` (each ``(4, m, m)``: first_time, min_dist, status, steps) as a refine folder
    holding the w1 rows ``rows`` (all by default), with its manifest and progress log."""
    key = job.run_key()
    rows = list(range(job.m)) if rows is None else rows
    folder.mkdir(parents=True, exist_ok=True)
    man = {
        "run_key": key,
        "identity": job.identity(),
        "body_file": str(body_file) if body_file else None,
        "body_file_sha256": provenance.sha256_file(body_file) if body_file else None,
        "weight_values": job.weights.tolist(),
        "created_commit": commit,
    }
    rf.manifest_path(folder).write_text(json.dumps(man, indent=1, sort_keys=True) + "\n")
    log = {"commit": commit, "episodes": 4 * job.m, "wall_s": 1.0, "cpu_s": 1.0}
    (folder / "progress.jsonl").write_text("".join(json.dumps({"row": r, **log}) + "\n" for r in rows))
    for r in rows:
        write_row(folder, r, key, {k: np.asarray(v)[:, r] for k, v in arrays.items()})
    return folder
