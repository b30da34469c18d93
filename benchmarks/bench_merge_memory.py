"""Peak memory of the merge step against the number of designs, at the paper's 121 x 121 weights.

Writes synthetic shards (random outcomes, the real schema) of ``--per-shard`` designs each (30,
as in config/full.yaml) for a growing number of designs, merges each set in a fresh process and
prints that process's peak RSS. The merge holds one shard at a time, so the peak stays flat as
the design count grows; the full config's merge (3321 evaluated designs in 111 shards) is then
estimated by extrapolating the measured slope.

Usage: python benchmarks/bench_merge_memory.py [--designs 60 240 480] [--per-shard 30] [--dir /tmp/x]
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from morphlearn import grid, store
from morphlearn.results import DesignResult

M = 121
G = grid.DesignGrid(9)
SCIENCE = {"benchmark": "merge memory"}


def write_shards(d: Path, n_designs: int, n_shards: int) -> list[np.ndarray]:
    reps = G.representatives()[:n_designs]
    parts = grid.split_shards(reps, n_shards)
    rng = np.random.default_rng(0)
    for i, designs in enumerate(parts):
        res = []
        for _ in designs:
            ft = rng.uniform(0, 500, (4, M, M))
            ft[rng.random((4, M, M)) < 0.8] = np.nan
            res.append(DesignResult(ft, rng.uniform(0, 4, (4, M, M)), np.zeros((4, M, M), dtype=np.int8)))
        store.write_shard(
            d / f"shard_{i}.nc",
            model="theory",
            grid=G,
            weights=grid.weights(M),
            designs=designs,
            results=res,
            science=SCIENCE,
            provenance={},
        )
    return parts


def merge_child(d: str, n_shards: int, n_designs: int) -> None:
    """Run in a fresh process: merge and report peak RSS (MiB) and wall time as JSON."""
    reps = G.representatives()[:n_designs]
    parts = grid.split_shards(reps, n_shards)
    t0 = time.perf_counter()
    store.merge_shards(
        [Path(d) / f"shard_{i}.nc" for i in range(n_shards)],
        Path(d) / "merged.zarr",
        model="theory",
        grid=G,
        weights=grid.weights(M),
        shard_designs=parts,
        science=SCIENCE,
        mirror=False,
        provenance={},
    )
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps({"peak_mib": peak, "wall_s": time.perf_counter() - t0}))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--designs", type=int, nargs="+", default=[60, 240, 480])
    ap.add_argument("--per-shard", type=int, default=30)
    ap.add_argument("--dir", default=None, help="scratch folder (default: a temporary one)")
    a = ap.parse_args()
    per_design = 4 * M * M * (8 + 8 + 1)
    print(
        f"# 121 x 121 weights: {per_design / 2**20:.2f} MiB of outcomes per design; "
        f"{a.per_shard} designs per shard; peak RSS of a fresh merging process"
    )
    rows = []
    with tempfile.TemporaryDirectory(dir=a.dir) as tmp:
        for n in a.designs:
            d = Path(tmp) / f"n{n}"
            d.mkdir()
            shards = -(-n // a.per_shard)
            write_shards(d, n, shards)
            out = subprocess.run(
                [sys.executable, __file__, "--child", str(d), str(shards), str(n)],
                capture_output=True,
                text=True,
                check=True,
            ).stdout
            r = json.loads(out.strip().splitlines()[-1])
            rows.append((n, r["peak_mib"]))
            print(
                f"{n:5d} designs ({n * per_design / 2**30:5.2f} GiB of outcomes): peak RSS "
                f"{r['peak_mib']:7.1f} MiB, merge {r['wall_s']:.1f} s"
            )
    (n0, p0), (n1, p1) = rows[0], rows[-1]
    slope = (p1 - p0) / (n1 - n0)
    print(f"slope: {slope:.3f} MiB per design (in-memory merge would need {per_design / 2**20:.2f})")
    print(
        f"estimated peak for config/full.yaml (3321 designs evaluated): {p1 + slope * (3321 - n1):.0f} MiB "
        f"(holding all outcomes would need {3321 * per_design / 2**30:.1f} GiB)"
    )


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        merge_child(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))
    else:
        main()
