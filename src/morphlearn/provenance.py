"""Provenance records: package version, git commit, config subset, input checksums."""

from __future__ import annotations

import hashlib
import json
import os
import platform
import re
import subprocess
from collections.abc import Sequence
from importlib import metadata
from pathlib import Path
from typing import Any

from morphlearn import __version__, bounded

#: Libraries every record names; a model adds its own (``Model.libraries``: numba, pybullet, ...).
_LIBS = ("numpy", "scipy", "xarray", "zarr", "pandas", "snakemake")


#: What a commit reads as when the code that made something is not a commit.
UNCOMMITTED = ("-dirty", "unknown")


def uncommitted(commit: str) -> bool:
    """A commit record that names no commit: a worktree with uncommitted changes, or no git."""
    return commit.endswith(UNCOMMITTED[0]) or commit == UNCOMMITTED[1]


def git_commit(cwd: str | Path | None = None) -> str:
    """HEAD commit of the project, with ``-dirty`` if tracked files outside ``results/`` differ;
    'unknown' outside git.

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
        # results/ holds outputs, not code: a rule re-making a committed result (results/agreement,
        # a bundle) overwrites tracked files there, which must not make its own record call the code
        # that made it dirty. What a record read is named by digest (its inputs; bundles' SHA-256s).
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no", "--", ":/", ":(top,exclude)results/"],
            cwd=where,
            capture_output=True,
            text=True,
            timeout=10,
        ).stdout
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return head + ("-dirty" if dirty.strip() else "")


def in_history(commit: str, cwd: str | Path | None = None) -> bool | None:
    """Whether ``commit`` is the project's HEAD or an ancestor of it; None where no repository
    answers (a copy of the project without ``.git``: nothing to check against). A record can name
    any commit through ``MORPHLEARN_GIT_COMMIT``; this is how a reader tells one that made it.
    Only a hash names a commit in a record: a ref (``HEAD``) or an option (``--help``) is not one."""
    where = Path(cwd) if cwd else Path(__file__).resolve().parent
    try:
        repo = subprocess.run(["git", "rev-parse", "--git-dir"], cwd=where, capture_output=True, timeout=10)
        if repo.returncode != 0:
            return None
        if not re.fullmatch(r"[0-9a-f]{7,64}", commit):
            return False
        ask = ["git", "merge-base", "--is-ancestor", commit, "HEAD"]  # 1: not an ancestor; 128: unknown
        return subprocess.run(ask, cwd=where, capture_output=True, timeout=10).returncode == 0
    except (OSError, subprocess.SubprocessError):
        return None


def is_shallow(cwd: str | Path | None = None) -> bool:
    """Whether the project's repository is a shallow clone (its history cut: a commit it lacks
    may still be an ancestor of HEAD)."""
    where = Path(cwd) if cwd else Path(__file__).resolve().parent
    try:
        ask = ["git", "rev-parse", "--is-shallow-repository"]
        out = subprocess.run(ask, cwd=where, capture_output=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return False
    return out.stdout.strip() == b"true"


def file_at(commit: str, path: str, cwd: str | Path | None = None, limit: int = 1 << 20) -> str | None:
    """The text of the project's file ``path`` (relative to its root) at ``commit``; None where the
    repository cannot say (no git, an unknown commit, no such file then, or larger than ``limit``)."""
    where = Path(cwd) if cwd else Path(__file__).resolve().parent
    if not re.fullmatch(r"[0-9a-f]{7,64}", commit) or not re.fullmatch(r"[\w./-]+", path) or ".." in path:
        return None
    try:
        out = subprocess.run(["git", "show", f"{commit}:{path}"], cwd=where, capture_output=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return None
    if out.returncode != 0 or len(out.stdout) > limit:
        return None
    try:
        return out.stdout.decode("utf-8")
    except UnicodeDecodeError:
        return None


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


def library_versions(extra: Sequence[str] = ()) -> dict[str, str]:
    """Versions of the libraries every record names and of ``extra`` (a model's own)."""
    out = {"python": platform.python_version()}
    for lib in dict.fromkeys([*_LIBS, *extra]):
        try:
            out[lib] = metadata.version(lib)
        except metadata.PackageNotFoundError:
            pass
    return out


def record(
    config_subset: dict[str, Any], inputs: list[str | Path] = (), libraries: Sequence[str] = ()
) -> dict[str, Any]:
    """A provenance record. Deliberately without timestamps or host names: the same inputs and
    code give the same bytes."""
    return {
        "package": "morphlearn",
        "version": __version__,
        "git_commit": git_commit(),
        "libraries": library_versions(libraries),
        "config": config_subset,
        "inputs": {str(p): sha256_file(p) for p in inputs},
    }


# ---------------------------------------------------------------------------------------------
# Custody: a derived file's record names its own digest and is sealed by a digest of itself, so
# every consumer can tell an edited table or an edited record before it reads them.

#: The record's digest of itself (of the record without this key, canonical JSON).
SEAL = "record_sha256"
#: The digests of the files the record describes, by file name (a bundle copy keeps them valid).
OUTPUTS = "outputs"
#: A bundle's manifest (morphlearn.bundles.make.MANIFEST; here to keep this module free of imports).
_MANIFEST = "bundle.json"


class CustodyError(ValueError):
    """A derived file or its record was edited, damaged or has no record; the message names it."""


def _canonical(rec: dict[str, Any]) -> bytes:
    return json.dumps({k: v for k, v in rec.items() if k != SEAL}, sort_keys=True, separators=(",", ":")).encode()


def seal(rec: dict[str, Any], outputs: list[str | Path] = ()) -> dict[str, Any]:
    """``rec`` with the digests of ``outputs`` (the files it describes) and its own digest."""
    out = {k: v for k, v in rec.items() if k != SEAL}
    if outputs:
        out[OUTPUTS] = {Path(p).name: sha256_file(p) for p in outputs}
    out[SEAL] = hashlib.sha256(_canonical(out)).hexdigest()
    return out


def write_sealed(path: str | Path, rec: dict[str, Any], outputs: list[str | Path]) -> None:
    """Write a derived file's sealed record (``rec`` plus the outputs' digests) atomically."""
    from morphlearn import store

    with store.atomic_path(path) as tmp:
        tmp.write_text(json.dumps(seal(rec, outputs), indent=1, sort_keys=True) + "\n")


def sidecar_of(path: str | Path) -> Path:
    """Where a derived file's record lives: ``metrics.csv`` -> ``metrics.provenance.json``."""
    return Path(path).with_suffix(".provenance.json")


def read_record(path: str | Path) -> dict[str, Any]:
    """A provenance record, its seal checked when it has one (CustodyError naming the file)."""
    path = Path(path)
    try:
        rec = bounded.json_file(path)
    except ValueError as e:
        raise CustodyError(f"{path}: unreadable provenance record ({e})") from None
    if not isinstance(rec, dict):
        raise CustodyError(f"{path}: a provenance record is a JSON object, found {type(rec).__name__}")
    if SEAL in rec and hashlib.sha256(_canonical(rec)).hexdigest() != rec[SEAL]:
        raise CustodyError(f"{path}: edited or damaged (its content no longer matches its own {SEAL})")
    return rec


def check_derived(path: str | Path, merged: Any = None, record: str | Path | None = None) -> dict[str, Any]:
    """Check a derived file (a metrics table) against its record before reading it; the record.

    A sealed record must name the file's SHA-256; an older, unsealed record is accepted only
    inside a bundle whose ``bundle.json`` lists both files with their digests (the committed
    bundles). ``merged``: the merged store (xarray Dataset) read beside the table, which must be
    the one the table was computed from. ``record``: the record, when it is not the file's own
    sidecar (``persistence.csv`` is sealed in ``reproduction.provenance.json``).
    """
    path = Path(path)
    side = Path(record) if record is not None else sidecar_of(path)
    if not side.is_file():
        raise CustodyError(f"{path}: no provenance record {side.name} beside it, so nothing vouches for it")
    rec = read_record(side)
    digest = sha256_file(path)
    if SEAL in rec:
        outputs = rec.get(OUTPUTS) if isinstance(rec.get(OUTPUTS), dict) else {}
        for name in sorted({path.name, *(n for n in outputs if (path.parent / n).is_file())}):
            # the file, and the others the record describes beside it (summary.md with summary.json)
            got = digest if name == path.name else sha256_file(path.parent / name)
            want = outputs.get(name)
            if want != got:
                raise CustodyError(
                    f"{path.parent / name}: SHA-256 {got[:12]} differs from the {(want or 'none')[:12]} that "
                    f"{side.name} recorded when the file was written (edited or damaged since)"
                )
    else:
        _check_in_bundle(path, side, digest)
    made_from = rec.get("config", {}).get("merged_sha256_overall") if isinstance(rec.get("config"), dict) else None
    held = merged_digests(merged) if merged is not None else set()
    if held and made_from is not None and made_from not in held:
        raise CustodyError(
            f"{path}: computed from the merged store {str(made_from)[:12]} ({side.name}) but the store "
            f"beside it is {min(held)[:12]}"
        )
    return rec


def _check_in_bundle(path: Path, side: Path, digest: str) -> None:
    root = path.parent.parent
    if not (root / _MANIFEST).is_file():
        raise CustodyError(
            f"{side}: records no digest of {path.name} (written before custody records, or by hand), "
            f"so nothing vouches for {path}; move it aside and the metrics rule re-makes it"
        )
    check_listed(root, [(path, digest), (side, sha256_file(side))])


def check_listed(root: str | Path, files: list[tuple[Path, str]]) -> None:
    """Each (file, its SHA-256) of ``files`` is listed with that digest in the ``bundle.json`` of
    the bundle ``root`` (CustodyError naming the first that is not): what vouches for a committed
    bundle's files that were written before they had a sealed record."""
    manifest = Path(root) / _MANIFEST
    try:
        listed = dict(bounded.json_file(manifest)["files"])
    except (ValueError, KeyError, TypeError) as e:
        raise CustodyError(f"{manifest}: unreadable ({e})") from None
    for p, d in files:
        rel = Path(p).relative_to(root).as_posix()
        if listed.get(rel) != d:
            raise CustodyError(f"{p}: SHA-256 {d[:12]} differs from {_MANIFEST} (edited or damaged)")


def merged_source(ds: Any) -> str:
    """The digest of the full merged dataset a store holds or was cut from (the same for a run's
    store and for a bundle's subset of it)."""
    return ds.attrs.get("subset_of") or ds.attrs["integrity"]["overall"]


def merged_digests(ds: Any) -> set[str]:
    """Digests a merged store answers to: its own, and that of the store it was cut from (a
    bundle's subset, or a subset of a run that read a bundle's)."""
    return {d for d in (ds.attrs.get("subset_of"), ds.attrs.get("integrity", {}).get("overall")) if d}
