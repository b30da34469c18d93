"""Start-up check: results already in ``results_dir`` that another config (or sharding) made.

Snakemake decides what to rerun from its metadata in ``.snakemake/``: a shard made under other
science or sharding is rerun because the rule's params (science and design digests) changed. But
results copied from elsewhere, or whose metadata was cleaned, count as done whatever config made
them, and the merge finds out hours later. This reads only what the files record about themselves
(a shard's NetCDF header and design list, the merged store's attributes; a few ms a shard, at most
``SAMPLE`` shards) and names a stale output that Snakemake has no record of, so that the workflow
stops at start with one clear line.
"""

from __future__ import annotations

import base64
from pathlib import Path
from typing import Any

import numpy as np

from morphlearn import bounded
from morphlearn import config as cfgmod


def _shard_header(path: Path) -> tuple[str | None, np.ndarray]:
    """science_sha256 and design indices of a shard, from its header (the arrays are not read)."""
    from scipy.io import netcdf_file

    with netcdf_file(path, "r", mmap=True) as nc:
        sha = nc._attributes.get("science_sha256")
        designs = np.array(nc.variables["design"][:], dtype=np.int64)
    return (sha.decode() if isinstance(sha, bytes) else sha), designs


#: Shard headers read per model at most (~3 ms each; the empirical full config has 6561 shards).
SAMPLE = 64


def recorded(path: Path) -> bool:
    """Whether Snakemake holds metadata (params, code) for an output: then it reruns a stale one.
    Snakemake names the record after the output path, base64 (urlsafe); names too long for one
    file are split into folders: counted as recorded (no false alarm)."""
    name = base64.urlsafe_b64encode(str(path).encode()).decode()
    return len(name) > 255 or (Path(".snakemake/metadata") / name).exists()


def unrecorded_stale(
    results_dir: str | Path, model: str, science: dict[str, Any], shard_designs: list[np.ndarray]
) -> Path | None:
    """An output of ``model`` made under another science config (or a shard holding other designs
    than this config's sharding) that Snakemake has no record of, else None.

    Up to ``SAMPLE`` shards spread over the range are read; a stale one that the sample misses is
    still refused by the merge's verification of every shard.
    """
    want = cfgmod.digest(science)
    base = Path(results_dir) / model
    meta = base / "merged.zarr" / "zarr.json"
    if meta.is_file() and not recorded(meta.parent):
        try:
            if bounded.json_file(meta).get("attributes", {}).get("science_sha256") != want:
                return meta.parent
        except (ValueError, AttributeError):
            pass
    n = len(shard_designs)
    for i in np.unique(np.linspace(0, n - 1, min(n, SAMPLE)).round().astype(int)):
        p = base / "shards" / f"shard_{i}.nc"
        if not p.is_file() or recorded(p):
            continue
        try:
            sha, held = _shard_header(p)
        except Exception:  # unreadable (truncated): the merge names it; nothing to compare here
            continue
        if sha != want or not np.array_equal(held, shard_designs[i]):
            return p
    return None
