"""Storage: one schema for both models.

Shards are NetCDF-3 files (scipy engine: no timestamps, byte-deterministic) holding, for their
designs, ``first_time``, ``min_dist`` (float32) and ``status`` (int8) over
``(design, env, w1, w2)``. The merged dataset is a Zarr store with one chunk per design, written
shard by shard (bounded memory), and read back with xarray. Every write goes to a temporary name
and is renamed when complete, so a crash never leaves a file that looks finished.
"""

from __future__ import annotations

import glob
import hashlib
import json
import os
import shutil
import warnings
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
import zarr

from morphlearn.grid import ENV_ANGLES_DEG, ENV_MIRROR, DesignGrid
from morphlearn.results import DesignResult

VARS = ("first_time", "min_dist", "status")
DIMS = ("design", "env", "w1", "w2")
FILL = {"first_time": np.float32(np.nan), "min_dist": np.float32(np.nan), "status": np.int8(-1)}


class ShardError(ValueError):
    """A shard that must not be merged; the message names it and what is wrong."""


def data_digest(arrays: dict[str, np.ndarray]) -> str:
    h = hashlib.sha256()
    for k in VARS:
        a = np.ascontiguousarray(arrays[k])
        h.update(k.encode() + str(a.dtype).encode() + str(a.shape).encode())
        h.update(a.tobytes())
    return h.hexdigest()


@contextmanager
def atomic_path(final: str | Path) -> Iterator[Path]:
    """Yield a temporary sibling path; rename it to ``final`` only if the block succeeds."""
    final = Path(final)
    final.parent.mkdir(parents=True, exist_ok=True)
    tmp = final.with_name(f".{final.name}.tmp-{os.getpid()}")
    for stale in final.parent.glob(f".{glob.escape(final.name)}.tmp-*"):
        _remove(stale)  # left by a writer that was killed (SIGKILL, node failure): can be GBs
    try:
        yield tmp
        if final.exists():
            _remove(final)
        os.replace(tmp, final)
    finally:
        _remove(tmp)


def _remove(p: Path) -> None:
    if p.is_dir() and not p.is_symlink():
        shutil.rmtree(p)
    elif p.exists() or p.is_symlink():
        p.unlink()


def write_shard(
    path: str | Path,
    *,
    model: str,
    grid: DesignGrid,
    weights: np.ndarray,
    designs: np.ndarray,
    results: list[DesignResult],
    science: dict[str, Any],
    provenance: dict[str, Any],
) -> None:
    arrays = {k: np.stack([getattr(r, k) for r in results]) for k in VARS}
    coords = grid.coords(designs)
    ds = xr.Dataset(
        {k: (DIMS, arrays[k]) for k in VARS},
        coords={
            "design": ("design", np.asarray(designs, dtype=np.int32)),
            "env": ("env", np.array(ENV_ANGLES_DEG, dtype=np.int32)),
            "w1": ("w1", np.asarray(weights, dtype=np.float64)),
            "w2": ("w2", np.asarray(weights, dtype=np.float64)),
            **{c: ("design", coords[:, i]) for i, c in enumerate(("l1x", "l1y", "l2x", "l2y"))},
        },
        attrs={
            "model": model,
            "science_json": json.dumps(science, sort_keys=True),
            "science_sha256": _digest_json(science),
            "data_sha256": data_digest(arrays),
            "provenance_json": json.dumps(provenance, sort_keys=True),
        },
    )
    for k in VARS:
        ds[k].encoding["_FillValue"] = None
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, engine="scipy", format="NETCDF3_64BIT")


def _digest_json(obj: Any) -> str:
    return hashlib.sha256(json.dumps(obj, sort_keys=True, separators=(",", ":")).encode()).hexdigest()


@dataclass
class Shard:
    path: Path
    designs: np.ndarray
    arrays: dict[str, np.ndarray]
    attrs: dict[str, Any]


def read_shard(path: str | Path) -> Shard:
    path = Path(path)
    if not path.is_file():
        raise ShardError(f"shard {path}: missing")
    try:
        with xr.open_dataset(path, engine="scipy", mask_and_scale=False) as ds:
            arrays = {k: ds[k].values for k in VARS}
            return Shard(path, ds["design"].values.astype(np.int64), arrays, dict(ds.attrs))
    except ShardError:
        raise
    except Exception as e:
        raise ShardError(f"shard {path}: unreadable or truncated ({type(e).__name__}: {e})") from None


def verify_shard(shard: Shard, *, model: str, science: dict[str, Any], designs: np.ndarray, m: int) -> None:
    """Refuse a shard that is foreign, incomplete or damaged."""
    p = shard.path
    if shard.attrs.get("model") != model:
        raise ShardError(f"shard {p}: model {shard.attrs.get('model')!r}, expected {model!r}")
    if shard.attrs.get("science_sha256") != _digest_json(science):
        raise ShardError(f"shard {p}: made with a different science config (foreign shard)")
    if not np.array_equal(shard.designs, designs):
        raise ShardError(f"shard {p}: holds designs {shard.designs[:5].tolist()}..., expected "
                         f"{designs[:5].tolist()}... ({len(designs)} designs)")  # fmt: skip
    want = (len(designs), 4, m, m)
    for k in VARS:
        if shard.arrays[k].shape != want:
            raise ShardError(f"shard {p}: {k} has shape {shard.arrays[k].shape}, expected {want}")
    if data_digest(shard.arrays) != shard.attrs.get("data_sha256"):
        raise ShardError(f"shard {p}: data checksum mismatch (damaged)")
    if np.isnan(shard.arrays["min_dist"]).any():
        raise ShardError(f"shard {p}: NaN in min_dist")
    if ((shard.arrays["status"] < 0) | (shard.arrays["status"] > 3)).any():
        raise ShardError(f"shard {p}: status outside 0..3")


def mirror_arrays(arrays: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Arrays (env, w1, w2) of a design -> those of its mirror image: env mirrored, w1<->w2."""
    return {k: np.ascontiguousarray(v[list(ENV_MIRROR)].transpose(0, 2, 1)) for k, v in arrays.items()}


def merge_shards(
    shard_paths: Iterable[str | Path],
    out: str | Path,
    *,
    model: str,
    grid: DesignGrid,
    weights: np.ndarray,
    shard_designs: list[np.ndarray],
    science: dict[str, Any],
    mirror: bool,
    provenance: dict[str, Any],
) -> None:
    """Verify every shard, then stream them into one Zarr store (nothing written on failure)."""
    paths = [Path(p) for p in shard_paths]
    m = len(weights)
    for p, d in zip(paths, shard_designs, strict=True):  # verify all before writing anything
        verify_shard(read_shard(p), model=model, science=science, designs=d, m=m)
    all_designs = np.unique(np.concatenate(shard_designs))
    if mirror:
        all_designs = np.unique(np.concatenate([all_designs, grid.mirror(all_designs)]))
    with atomic_path(out) as tmp:
        root = zarr.open_group(str(tmp), mode="w", zarr_format=3)
        coords = grid.coords(all_designs)
        _arr(root, "design", all_designs.astype(np.int32), ("design",))
        _arr(root, "env", np.array(ENV_ANGLES_DEG, dtype=np.int32), ("env",))
        _arr(root, "w1", np.asarray(weights, np.float64), ("w1",))
        _arr(root, "w2", np.asarray(weights, np.float64), ("w2",))
        for i, c in enumerate(("l1x", "l1y", "l2x", "l2y")):
            _arr(root, c, coords[:, i], ("design",))
        shape = (len(all_designs), 4, m, m)
        data = {
            k: root.create_array(
                k,
                shape=shape,
                chunks=(1, 4, m, m),
                dtype=FILL[k].dtype,
                fill_value=FILL[k],
                dimension_names=DIMS,
                attributes={"coordinates": "l1x l1y l2x l2y"},
            )
            for k in VARS
        }
        pos = {int(d): i for i, d in enumerate(all_designs)}
        written = np.zeros(len(all_designs), dtype=bool)
        for p, d in zip(paths, shard_designs, strict=True):
            sh = read_shard(p)  # re-read: keeps one shard in memory at a time
            for i, des in enumerate(d):
                arrays = {k: sh.arrays[k][i] for k in VARS}
                _put(data, pos[int(des)], arrays, written)
                if mirror:
                    md = int(grid.mirror(int(des)))
                    if md != des:
                        _put(data, pos[md], mirror_arrays(arrays), written)
        if not written.all():
            raise ShardError(f"merge: {int((~written).sum())} designs missing from the shards")
        root.attrs.update({
            "model": model,
            "science_json": json.dumps(science, sort_keys=True),
            "science_sha256": _digest_json(science),
            "provenance_json": json.dumps(provenance, sort_keys=True),
        })  # fmt: skip


def _arr(root: zarr.Group, name: str, values: np.ndarray, dims: tuple[str, ...]) -> None:
    a = root.create_array(name, shape=values.shape, dtype=values.dtype, dimension_names=dims)
    a[...] = values


def _put(data: dict[str, zarr.Array], i: int, arrays: dict[str, np.ndarray], written: np.ndarray) -> None:
    for k in VARS:
        data[k][i] = arrays[k]
    written[i] = True


def open_merged(path: str | Path) -> xr.Dataset:
    """The merged dataset, lazily, with coordinates; status is not masked."""
    with warnings.catch_warnings():  # Snakemake marks directory outputs with this file
        warnings.filterwarnings("ignore", message=".*snakemake_timestamp.*")
        return xr.open_zarr(str(path), consolidated=False, mask_and_scale=False)
