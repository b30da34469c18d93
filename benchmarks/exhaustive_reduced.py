"""Exhaustive reduced-model maps of designs of the 9-point grid drawn at random (seeded, none of the
5-point grid's), one ``.npz`` per design (first-success time, closest approach: (4, m, m)) under
``--out``, for replaying the adaptive grid on them (benchmarks/replay_levers.py). Resumable: a
design whose file exists is skipped. Every cell is simulated, each episode to its first success
(as the adaptive sweep runs it, so the replay makes the sweep's choices).

    nice -n 10 python benchmarks/exhaustive_reduced.py --out /work/tmp/exhaustive9 --n 200 --seed 65
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from morphlearn import grid
from morphlearn.physics.params import load_params
from morphlearn.reduced.core import run

BODY = "config/authors_body.yaml"


def drawn(n: int, seed: int) -> np.ndarray:
    """``n`` designs of the 9-point grid, none of the 5-point grid's, in a seeded random order."""
    g9 = grid.DesignGrid(9)
    on5 = (g9.indices(np.arange(g9.size)) % 2 == 0).all(axis=1)  # every 2nd position: the 5-point grid
    pool = np.flatnonzero(~on5)
    return np.random.default_rng(seed).choice(pool, size=n, replace=False)


def exhaustive(design: int, m: int, params) -> dict[str, np.ndarray]:
    """Every (env, w1, w2) episode of ``design`` (9-point grid) at ``m`` weights."""
    c = grid.DesignGrid(9).coords(design)
    w = grid.weights(m)
    e, i, j = np.meshgrid(np.arange(4), np.arange(m), np.arange(m), indexing="ij")
    ep, _ = run(params, (c[0], c[1]), (c[2], c[3]), np.stack([w[i.ravel()], w[j.ravel()]], 1), e.ravel())
    first = np.where(ep.success, ep.first_step * params.dt, np.nan).reshape(4, m, m)
    return {"first_time": first, "min_dist": ep.min_dist.reshape(4, m, m), "finite": ep.finite.reshape(4, m, m)}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--n", type=int, default=200)
    ap.add_argument("--seed", type=int, default=65)
    ap.add_argument("--weights", type=int, default=121)
    a = ap.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    params = load_params(BODY)
    for k, d in enumerate(drawn(a.n, a.seed)):
        path = a.out / f"design{int(d):04d}.npz"
        if path.exists():
            continue
        t0, c0 = time.monotonic(), time.process_time()
        out = exhaustive(int(d), a.weights, params)
        tmp = path.with_suffix(".tmp.npz")
        np.savez_compressed(tmp, design=int(d), **out)
        tmp.rename(path)  # atomic: a killed run leaves no half file
        wall, cpu = time.monotonic() - t0, time.process_time() - c0
        print(f"{k} design {int(d)} wall {wall:.1f} s cpu {cpu:.1f} s", flush=True)


if __name__ == "__main__":
    main()
