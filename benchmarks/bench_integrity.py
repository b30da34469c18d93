"""Cost of the merged store's digest checks (issue 13): metrics and render-only reads, before/after.

Merges synthetic shards (random outcomes, the real schema, the paper's 121 x 121 weights) of
``--designs`` designs into one store, then times, best of ``--repeat``:

- metrics: the metrics table over every design, *before* = the unverified block reads the metrics
  used until digests existed (xarray ``isel`` per block of 64 designs), *after* =
  ``metrics.metrics_table`` (every chunk hashed and compared);
- render-only data reads: *before* = open + read ``--figure-designs`` designs unverified (what the
  figures read), *after* = the render-only start check (``store.check_merged_files``: digest
  record, coordinates, every chunk file present) + open + verified reads of the same designs.

The figures' drawing and reference integrations are the same before and after and are not timed
here: the "after" extra is an upper bound on what the digests add to a render-only run.

Usage: python benchmarks/bench_integrity.py [--designs 400] [--repeat 3] [--dir /tmp/x]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pandas as pd

from morphlearn import grid, metrics, store
from morphlearn.results import DesignResult

M = 121
G = grid.DesignGrid(9)
TH = metrics.Thresholds(500.0, 0.2, 500.0, 0.2)


def make_store(d: Path, n: int) -> Path:
    designs = np.arange(n)
    parts = np.array_split(designs, max(1, n // 30))
    rng = np.random.default_rng(0)
    paths = []
    for i, part in enumerate(parts):
        res = []
        for _ in part:
            ft = rng.uniform(0, 500, (4, M, M)).astype(np.float32)
            ft[rng.random((4, M, M)) < 0.7] = np.nan
            res.append(DesignResult(ft, rng.uniform(0, 4, (4, M, M)).astype(np.float32), np.zeros((4, M, M))))
        paths.append(d / f"s{i}.nc")
        store.write_shard(
            paths[-1],
            model="theory",
            grid=G,
            weights=grid.weights(M),
            designs=part,
            results=res,
            science={"b": 1},
            provenance={},
        )
    out = d / "merged.zarr"
    store.merge_shards(
        paths,
        out,
        model="theory",
        grid=G,
        weights=grid.weights(M),
        shard_designs=parts,
        science={"b": 1},
        mirror=False,
        provenance={},
    )
    return out


def metrics_before(path: Path) -> None:
    """metrics.metrics_table as it was before digests (commit 6eb57c1): unverified block reads."""
    ds = store.open_merged(path)
    rows = []
    for a in range(0, ds.sizes["design"], 64):
        part = ds.isel(design=slice(a, a + 64))
        succ = metrics.success(part["first_time"].values, part["min_dist"].values, TH)
        stt = part["status"].values
        for i in range(succ.shape[0]):
            dm = metrics.design_metrics(succ[i], stt[i])
            row = {
                "model": "theory",
                "design": int(part["design"].values[i]),
                **{c: float(part[c].values[i]) for c in ("l1x", "l1y", "l2x", "l2y")},
            }
            row.update({f"n_{ang}": c for ang, c in zip(grid.ENV_ANGLES_DEG, dm.per_env, strict=True)})
            row.update(
                generalists=dm.generalists, at_least_one=dm.at_least_one, M_L=dm.M_L, M_CF=dm.M_CF, flagged=dm.flagged
            )
            rows.append(row)
    pd.DataFrame(rows)


def metrics_after(path: Path) -> None:
    metrics.metrics_table(store.open_merged(path), TH)


def render_before(path: Path, k: int) -> None:
    ds = store.open_merged(path)
    for i in np.linspace(0, ds.sizes["design"] - 1, k).astype(int):
        d = ds.isel(design=int(i))
        _ = (d["first_time"].values, d["min_dist"].values, d["status"].values)


def render_after(path: Path, k: int) -> None:
    store.check_merged_files(path)  # render-only's start check
    ds = store.open_merged(path)
    for i in np.linspace(0, ds.sizes["design"] - 1, k).astype(int):
        store.read_design(ds, int(i))


def best(f: Callable[[], None], repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return min(times)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--designs", type=int, default=400)
    ap.add_argument("--figure-designs", type=int, default=30)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--dir", type=Path, default=None)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory(dir=a.dir) as tmp:
        path = make_store(Path(tmp), a.designs)
        print(f"store: {a.designs} designs x 4 x {M} x {M}, best of {a.repeat}")
        rows = [
            ("metrics", lambda: metrics_before(path), lambda: metrics_after(path)),
            (
                "render-only reads",
                lambda: render_before(path, a.figure_designs),
                lambda: render_after(path, a.figure_designs),
            ),
        ]
        for name, before, after in rows:
            b, c = best(before, a.repeat), best(after, a.repeat)
            print(f"{name:18s} before {b:7.3f} s  after {c:7.3f} s  ({100 * (c - b) / b:+.1f} %, {c - b:+.3f} s)")


if __name__ == "__main__":
    main()
