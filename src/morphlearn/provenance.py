"""Provenance records: package version, git commit, config subset, input checksums."""

from __future__ import annotations

import hashlib
import os
import platform
import subprocess
from importlib import metadata
from pathlib import Path
from typing import Any

from morphlearn import __version__

_LIBS = ("numpy", "scipy", "numba", "xarray", "zarr", "pybullet", "pandas", "snakemake")


def git_commit(cwd: str | Path | None = None) -> str:
    """HEAD commit of the project, with ``-dirty`` if tracked files differ; 'unknown' outside git.

    ``MORPHLEARN_GIT_COMMIT`` overrides it (e.g. on cluster nodes without the repository).
    """
    env = os.environ.get("MORPHLEARN_GIT_COMMIT")
    if env:
        return env
    where = Path(cwd) if cwd else Path(__file__).resolve().parent
    try:
        head = subprocess.run(
            ["git", "rev-parse", "HEAD"], cwd=where, capture_output=True, text=True, check=True, timeout=10
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no"],
            cwd=where,
            capture_output=True,
            text=True,
            timeout=10,
        ).stdout
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return head + ("-dirty" if dirty.strip() else "")


def sha256_file(path: str | Path) -> str:
    """SHA-256 of a file, or of a directory tree (relative names and contents, sorted)."""
    p = Path(path)
    h = hashlib.sha256()
    if p.is_dir():
        for f in sorted(q for q in p.rglob("*") if q.is_file()):
            h.update(str(f.relative_to(p)).encode() + b"\0")
            h.update(sha256_file(f).encode())
        return h.hexdigest()
    with p.open("rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def library_versions() -> dict[str, str]:
    out = {"python": platform.python_version()}
    for lib in _LIBS:
        try:
            out[lib] = metadata.version(lib)
        except metadata.PackageNotFoundError:
            pass
    return out


def record(config_subset: dict[str, Any], inputs: list[str | Path] = ()) -> dict[str, Any]:
    """A provenance record. Deliberately without timestamps or host names: the same inputs and
    code give the same bytes."""
    return {
        "package": "morphlearn",
        "version": __version__,
        "git_commit": git_commit(),
        "libraries": library_versions(),
        "config": config_subset,
        "inputs": {str(p): sha256_file(p) for p in inputs},
    }
