"""Storage: one schema for both models.

Shards are NetCDF-3 files (scipy engine: no timestamps, byte-deterministic) holding, for their
designs, ``first_time``, ``min_dist`` (float32) and ``status`` (int8) over
``(design, env, w1, w2)``. The merged dataset is a Zarr store with one chunk per design, written
shard by shard (bounded memory), and read back with xarray. Every write goes to a temporary name
and is renamed when complete, so a crash never leaves a file that looks finished.

The merged store is verifiable at rest: its ``integrity`` attribute holds a SHA-256 digest of the
decoded bytes of every design's chunk of every variable, of every coordinate array, and one
overall digest of those. Every reader checks what it reads (:func:`open_merged` the coordinates,
:func:`read_design` / :func:`read_blocks` the chunks), so a missing, truncated or altered chunk
stops the run with a message naming the store, the variable and the design.
"""

from __future__ import annotations

import glob
import hashlib
import json
import os
import shutil
import sys
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
from morphlearn.results import STATUS_INFERRED, STATUS_NAMES, DesignResult

VARS = ("first_time", "min_dist", "status")
DIMS = ("design", "env", "w1", "w2")
FILL = {"first_time": np.float32(np.nan), "min_dist": np.float32(np.nan), "status": np.int8(-1)}


class ShardError(ValueError):
    """A shard that must not be merged; the message names it and what is wrong."""


class IntegrityError(ValueError):
    """Merged data that is missing, damaged or not what its digests say; one line naming it."""


COORDS = ("design", "env", "w1", "w2", "l1x", "l1y", "l2x", "l2y")
#: Weights per synapse a store may declare at most (the config schema's ``grid.weights`` maximum):
#: a reader decodes one design's (env, w1, w2) chunk at a time, so this bounds its memory (4 x 1001
#: x 1001 float32: 16 MB a variable). A store declaring more (a forged ``zarr.json``) is refused
#: before anything is read, never a MemoryError.
MAX_WEIGHTS = 1001
#: Where a results folder keeps the physics survey it read from another bundle (``survey_from``):
#: ``survey/<model>/`` beside the models' own folders, the same files as a model's.
SURVEY_DIR = "survey"
#: What the digests are of (recorded with them, so a reader knows what to recompute).
DIGEST_OF = "sha256 of the C-order bytes of each design's decoded (env, w1, w2) chunk, per variable"


def _bytes(a: np.ndarray) -> memoryview:
    """The C-order bytes of an array without copying them (``tobytes`` copies: +50 % hash time)."""
    return memoryview(np.ascontiguousarray(a)).cast("B")


def chunk_digest(a: np.ndarray) -> str:
    return hashlib.sha256(_bytes(a)).hexdigest()


def overall_digest(chunks: dict[str, list[str]], coords: dict[str, str]) -> str:
    """One digest of the whole store: of its per-chunk and coordinate digests."""
    return _digest_json({"chunks": chunks, "coords": coords})


def data_digest(arrays: dict[str, np.ndarray]) -> str:
    h = hashlib.sha256()
    for k in VARS:
        a = np.ascontiguousarray(arrays[k])
        h.update(k.encode() + str(a.dtype).encode() + str(a.shape).encode())
        h.update(_bytes(a))
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
        raise ShardError(
            f"shard {p}: holds designs {shard.designs[:5].tolist()}..., expected "
            f"{designs[:5].tolist()}... ({len(designs)} designs)"
        )
    want = (len(designs), 4, m, m)
    for k in VARS:
        if shard.arrays[k].shape != want:
            raise ShardError(f"shard {p}: {k} has shape {shard.arrays[k].shape}, expected {want}")
    if data_digest(shard.arrays) != shard.attrs.get("data_sha256"):
        raise ShardError(f"shard {p}: data checksum mismatch (damaged)")
    # NaN only where the adaptive weight grid inferred the cell instead of simulating it
    if (np.isnan(shard.arrays["min_dist"]) & (shard.arrays["status"] != STATUS_INFERRED)).any():
        raise ShardError(f"shard {p}: NaN in min_dist of a simulated cell")
    if not np.isin(shard.arrays["status"], list(STATUS_NAMES)).all():
        raise ShardError(f"shard {p}: status outside {sorted(STATUS_NAMES)}")


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
    shards_prov = shard_provenance(paths, provenance.get("git_commit"))
    all_designs = np.unique(np.concatenate(shard_designs))
    if mirror:
        all_designs = np.unique(np.concatenate([all_designs, grid.mirror(all_designs)]))
    pos = {int(d): i for i, d in enumerate(all_designs)}

    def chunks() -> Iterator[tuple[int, dict[str, np.ndarray]]]:
        for p, d in zip(paths, shard_designs, strict=True):
            sh = read_shard(p)  # re-read: keeps one shard in memory at a time
            for i, des in enumerate(d):
                arrays = {k: sh.arrays[k][i] for k in VARS}
                yield pos[int(des)], arrays
                if mirror:
                    md = int(grid.mirror(int(des)))
                    if md != des:
                        yield pos[md], mirror_arrays(arrays)

    attrs = {
        "model": model,
        "science_json": json.dumps(science, sort_keys=True),
        "science_sha256": _digest_json(science),
        "provenance_json": json.dumps(provenance | {"shards": shards_prov}, sort_keys=True),
    }
    with atomic_path(out) as tmp:
        _write_store(tmp, all_designs, grid.coords(all_designs), np.asarray(weights, np.float64), chunks(), attrs)


def shard_provenance(paths: list[Path], merging_commit: str | None) -> dict[str, Any]:
    """Commits, backends and devices that made the shards; a warning when they differ among
    themselves or from the merging commit (recorded, not refused: finished shards stay valid).
    Shards without a backend (made before it was recorded) were made on the CPU."""
    commits: dict[str, int] = {}
    backends: dict[str, int] = {}
    devices: dict[str, int] = {}
    design_commits: dict[str, int] = {}  # designs per commit that computed them (shards that record it)
    for p in paths:
        with xr.open_dataset(p, engine="scipy", mask_and_scale=False) as ds:  # attributes only
            prov = json.loads(ds.attrs.get("provenance_json", "{}"))
        for c, n in prov.get("design_commits", {}).items():
            design_commits[c] = design_commits.get(c, 0) + int(n)
        for d, k in (
            (commits, prov.get("git_commit", "unknown")),
            (backends, prov.get("backend", "cpu")),
            (devices, prov.get("device", "cpu (not recorded)")),
        ):
            d[k] = d.get(k, 0) + 1
    out = {"git_commits": commits, "backends": backends, "devices": devices}
    if design_commits:
        out["design_commits"] = dict(sorted(design_commits.items()))
    notes = []
    if len(commits) > 1:
        notes.append(f"shards come from {len(commits)} git commits {sorted(commits)}")
    elif merging_commit and set(commits) != {merging_commit}:
        notes.append(f"shards were made at commit {next(iter(commits))}, merged at {merging_commit}")
    if len(backends) > 1:
        notes.append(
            f"shards come from {len(backends)} backends {backends} (CPU and CUDA may differ in boundary cases)"
        )
    if notes:
        msg = "merge: " + "; ".join(notes) + " (recorded in the provenance)"
        warnings.warn(msg, stacklevel=2)
        print(f"warning: {msg}", file=sys.stderr)
        out["warnings"] = notes
    return out


def _write_store(
    tmp: Path,
    designs: np.ndarray,
    coords: np.ndarray,
    weights: np.ndarray,
    chunks: Iterable[tuple[int, dict[str, np.ndarray]]],
    attrs: dict[str, Any],
) -> dict[str, Any]:
    """Write a merged store (same bytes for the same input) with its digests; return them."""
    root = zarr.open_group(str(tmp), mode="w", zarr_format=3)
    m = len(weights)
    coord_values = {
        "design": designs.astype(np.int32),
        "env": np.array(ENV_ANGLES_DEG, dtype=np.int32),
        "w1": weights,
        "w2": weights,
        **{c: np.ascontiguousarray(coords[:, i]) for i, c in enumerate(("l1x", "l1y", "l2x", "l2y"))},
    }
    for name, values in coord_values.items():
        _arr(root, name, values, ("design",) if name in ("design", "l1x", "l1y", "l2x", "l2y") else (name,))
    shape = (len(designs), 4, m, m)
    data = {
        k: root.create_array(
            k,
            shape=shape,
            chunks=(1, 4, m, m),
            dtype=FILL[k].dtype,
            fill_value=FILL[k],
            dimension_names=DIMS,
            attributes={"coordinates": "l1x l1y l2x l2y"},
            # Every chunk on disk, also all-fill ones (zarr skips those by default): a missing chunk
            # file then always means damage, and the start check can test existence cheaply.
            config={"write_empty_chunks": True},
        )
        for k in VARS
    }
    digests: dict[str, list[str | None]] = {k: [None] * len(designs) for k in VARS}
    for i, arrays in chunks:
        for k in VARS:
            a = np.ascontiguousarray(arrays[k], dtype=FILL[k].dtype)
            data[k][i] = a
            digests[k][i] = chunk_digest(a)
    missing = sum(d is None for d in digests[VARS[0]])
    if missing:
        raise ShardError(f"merge: {missing} designs missing from the shards")
    coord_digests = {c: chunk_digest(v) for c, v in coord_values.items()}
    integrity = {
        "algorithm": "sha256",
        "of": DIGEST_OF,
        "chunks": digests,
        "coords": coord_digests,
        "overall": overall_digest(digests, coord_digests),
    }
    root.attrs.update({**attrs, "integrity": integrity})
    return integrity


def write_subset(src_merged_path: str | Path, designs: Iterable[int], out_path: str | Path) -> str:
    """A merged store holding only the designs (indices of the design grid) ``designs`` of a
        verified source store: same schema; each chunk's digest re-computed and checked against the
        source's; ``subset_of`` = the full dataset's overall digest (the source's, or the one the source
    was cut from). Returns the subset's overall digest."""
    ds = open_merged(src_merged_path)
    src_int = ds.attrs["integrity"]
    all_designs = ds["design"].values.astype(np.int64)
    want = np.unique(np.asarray(list(designs), dtype=np.int64))
    where = {int(d): i for i, d in enumerate(all_designs)}
    absent = [int(d) for d in want if int(d) not in where]
    if absent:
        raise IntegrityError(f"{src_merged_path}: designs {absent[:5]} are not in the store")
    positions = [where[int(d)] for d in want]
    coords = np.stack([ds[c].values[positions] for c in ("l1x", "l1y", "l2x", "l2y")], axis=-1)

    def chunks() -> Iterator[tuple[int, dict[str, np.ndarray]]]:
        for j, i in enumerate(positions):
            yield j, read_design(ds, i)  # verified against the source's digests

    attrs = {k: v for k, v in ds.attrs.items() if k not in ("integrity", "subset_of", "subset_source_designs")}
    attrs |= {
        # the full dataset's digest, also for a subset of a subset (a bundle of a run that read a
        # bundle): what the metrics tables' records name
        "subset_of": ds.attrs.get("subset_of", src_int["overall"]),
        "subset_source_designs": int(ds.attrs.get("subset_source_designs", len(all_designs))),
    }
    with atomic_path(out_path) as tmp:
        integ = _write_store(tmp, want, coords, np.asarray(ds["w1"].values, np.float64), chunks(), attrs)
        for k in VARS:
            if integ["chunks"][k] != [src_int["chunks"][k][i] for i in positions]:
                raise IntegrityError(f"{out_path}: {k} written differs from the source's digests")
    return integ["overall"]


def _arr(root: zarr.Group, name: str, values: np.ndarray, dims: tuple[str, ...]) -> None:
    a = root.create_array(name, shape=values.shape, dtype=values.dtype, dimension_names=dims)
    a[...] = values


def science_of(ds: xr.Dataset) -> dict[str, Any]:
    """The science config a shard or merged dataset was made with (its ``science_json``)."""
    return json.loads(ds.attrs["science_json"])


def open_merged(path: str | Path) -> xr.Dataset:
    """The merged dataset, lazily, with coordinates; status is not masked. Its digests' record and
    its coordinate arrays are verified here; read data with :func:`read_design` or
    :func:`read_blocks`, which verify each chunk."""
    path = Path(path)
    if not path.exists():
        raise IntegrityError(f"{path}: missing (a merged.zarr made by the workflow)")
    try:
        with warnings.catch_warnings():  # Snakemake marks directory outputs with this file
            warnings.filterwarnings("ignore", message=".*snakemake_timestamp.*")
            ds = xr.open_zarr(str(path), consolidated=False, mask_and_scale=False, chunks=None)
    except Exception as e:  # zarr/xarray raise many kinds
        raise IntegrityError(f"{path}: not a readable Zarr dataset ({type(e).__name__})") from None
    integ = ds.attrs.get("integrity")
    if not isinstance(integ, dict) or "chunks" not in integ:
        raise IntegrityError(f"{path}: no digests (merged before they were recorded): merge it again")
    if overall_digest(integ["chunks"], integ["coords"]) != integ.get("overall"):
        raise IntegrityError(f"{path}: its digest record does not match its overall digest (altered)")
    for c in COORDS:
        try:
            v = ds[c].values
        except Exception as e:
            raise IntegrityError(f"{path}: coordinate {c} unreadable ({type(e).__name__})") from None
        if chunk_digest(v) != integ["coords"].get(c):
            raise IntegrityError(f"{path}: coordinate {c} fails its sha256 digest (damaged or missing)")
    for k in VARS:
        if k not in ds or len(integ["chunks"].get(k, ())) != ds.sizes["design"]:
            raise IntegrityError(f"{path}: variable {k} missing or without a digest per design")
    _check_shape(ds, path)
    ds.encoding["morphlearn_path"] = str(path)
    return ds


def _check_shape(ds: xr.Dataset, path: Path) -> None:
    """What every chunk read decodes is bounded: each variable (design, 4 environments, m, m) with
    m <= :data:`MAX_WEIGHTS`, of its own dtype, in one chunk per design (IntegrityError naming it)."""
    n, m = ds.sizes["design"], ds.sizes.get("w1", 0)
    want = (n, len(ENV_ANGLES_DEG), m, m)
    chunk = (1, *want[1:])
    if not 1 <= m <= MAX_WEIGHTS:
        raise IntegrityError(
            f"{path}: declares {m} weights per synapse; allowed: 1 to {MAX_WEIGHTS} (each design's chunk "
            "is read whole, within a memory bound)"
        )
    for k in VARS:
        v = ds[k]
        got = tuple(v.encoding.get("chunks") or ())
        if v.dims != DIMS or v.shape != want or v.dtype != FILL[k].dtype or got != chunk:
            raise IntegrityError(
                f"{path}: variable {k} declares dims {v.dims}, shape {v.shape}, dtype {v.dtype}, chunks {got}; "
                f"allowed: dims {DIMS}, shape {want}, dtype {FILL[k].dtype}, chunks {chunk} (one design a chunk)"
            )


def _fail(ds: xr.Dataset, k: str, i: int, why: str) -> IntegrityError:
    path = ds.encoding.get("morphlearn_path", "merged store")
    design = int(ds["design"].values[i])
    chunk = Path(path) / k / "c" / str(i) / "0" / "0" / "0"
    if why == "digest" and not chunk.exists():
        why = "its chunk file is missing"
    elif why == "digest":
        why = "fails its sha256 digest (damaged)"
    return IntegrityError(f"{path}: {k} of design {design} (position {i}): {why}")


def read_design(ds: xr.Dataset, i: int) -> dict[str, np.ndarray]:
    """The verified (env, w1, w2) arrays of the design at position ``i`` of a merged store."""
    integ = ds.attrs["integrity"]["chunks"]
    out = {}
    for k in VARS:
        try:
            a = np.asarray(ds[k].variable[i].values)
        except Exception as e:
            raise _fail(ds, k, i, f"chunk unreadable ({type(e).__name__})") from None
        if chunk_digest(a) != integ[k][i]:
            raise _fail(ds, k, i, "digest")
        out[k] = a
    return out


def read_blocks(ds: xr.Dataset, block: int = 64) -> Iterator[tuple[slice, dict[str, np.ndarray]]]:
    """Every design's verified arrays, ``block`` designs at a time (bounded memory)."""
    integ = ds.attrs["integrity"]["chunks"]
    n = ds.sizes["design"]
    for a in range(0, n, block):
        sl = slice(a, min(a + block, n))
        try:
            arrays = {k: np.asarray(ds[k].variable[sl].values) for k in VARS}
        except Exception:  # a chunk unreadable: find which, by name
            for i in range(sl.start, sl.stop):
                read_design(ds, i)
            raise
        for k in VARS:
            for j in range(sl.stop - sl.start):
                if chunk_digest(arrays[k][j]) != integ[k][a + j]:
                    raise _fail(ds, k, a + j, "digest")
        yield sl, arrays


def check_merged_files(path: str | Path) -> None:
    """Cheap start check (render-only): the digest record, the coordinates and that every chunk
    file exists; chunk contents are verified where they are read (:func:`read_design`)."""
    ds = open_merged(path)
    for k in VARS:
        for i in range(ds.sizes["design"]):
            if not (Path(path) / k / "c" / str(i) / "0" / "0" / "0").is_file():
                raise _fail(ds, k, i, "digest")


def verify_merged(path: str | Path) -> str:
    """Read and verify every chunk of a merged store; its overall digest."""
    ds = open_merged(path)
    for _ in read_blocks(ds):
        pass
    return ds.attrs["integrity"]["overall"]
