"""Checking a results bundle against its manifest, and reading one model's results out of it
(the bundle itself: :mod:`morphlearn.bundle`)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from morphlearn import provenance, store
from morphlearn.bundle import MANIFEST, BundleError, bundle_files


def extract_model(bundle_dir: str | Path, model: str, out: dict[str, str | Path]) -> None:
    """Copy one model's results out of a bundle (``out``: metrics, provenance, merged paths),
    after checking the whole bundle against its checksums; nothing is written if it fails."""
    problems = check(bundle_dir)
    if problems:
        raise BundleError(f"{bundle_dir}: {len(problems)} problem(s), first: {problems[0]}")
    src = Path(bundle_dir) / model
    for name, key in (("metrics.csv", "metrics"), ("metrics.provenance.json", "provenance")):
        dst = Path(out[key])
        dst.parent.mkdir(parents=True, exist_ok=True)
        with store.atomic_path(dst) as tmp:
            shutil.copy2(src / name, tmp)
    with store.atomic_path(Path(out["merged"])) as tmp:
        shutil.copytree(src / "merged.zarr", tmp)


def check(out_dir: str | Path) -> list[str]:
    """Problems of a bundle (empty: every file listed, present and unchanged, nothing extra)."""
    out_dir = Path(out_dir)
    mpath = out_dir / MANIFEST
    if not mpath.is_file():
        return [f"{mpath}: missing"]
    try:
        listed = json.loads(mpath.read_text())["files"]
    except (ValueError, KeyError) as e:
        return [f"{mpath}: unreadable ({e})"]
    problems = []
    for rel, digest in listed.items():
        p = out_dir / rel
        if not p.is_file():
            problems.append(f"{p}: listed in {MANIFEST} but missing")
        elif provenance.sha256_file(p) != digest:
            problems.append(f"{p}: checksum differs from {MANIFEST} (changed or damaged)")
    for p in bundle_files(out_dir):
        rel = str(p.relative_to(out_dir))
        rendered = rel.startswith(_RENDERED) or (rel.startswith("figures/") and rel.endswith(".html"))
        if rel not in listed and not rendered:
            problems.append(f"{p}: not listed in {MANIFEST}")
    return problems


#: What a re-render writes beside the bundle's files (logs, benchmarks, and figures/*.html: the
#: executed notebooks).
_RENDERED = ("logs/", "benchmarks/", ".snakemake")
