"""Theory kernel speed: trajectories per second per core, adaptive and fixed-step, against the
scipy reference, measured side by side in one run on the same random sample of the paper grid.

Usage: python benchmarks/bench_theory.py [--designs 4] [--weights 31] [--reference 40]
"""

from __future__ import annotations

import argparse
import platform
import time

import numba
import numpy as np

from morphlearn import grid
from morphlearn.theory import TheoryParams, evaluate
from morphlearn.theory.reference import reference_trajectory


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--designs", type=int, default=4)
    ap.add_argument("--weights", type=int, default=31)
    ap.add_argument("--reference", type=int, default=40, help="trajectories for scipy")
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()
    numba.set_num_threads(1)  # per-core figures
    rng = np.random.default_rng(a.seed)
    g = grid.DesignGrid(9)
    designs = g.coords(rng.choice(g.size, a.designs, replace=False))
    w = grid.weights(a.weights)
    n_traj = len(designs) * 4 * len(w) ** 2
    print(f"# machine: {platform.processor() or platform.machine()}, float64, 1 thread")
    print(f"# sample: {len(designs)} random designs of the 9^4 grid x 4 envs x {len(w)}^2 weights "
          f"= {n_traj} trajectories, T = 500, r = 4")  # fmt: skip
    rates = {}
    for name, p in [("dp5 1e-8", TheoryParams()), ("rk4 dt=0.01", TheoryParams(integrator="rk4"))]:
        evaluate(designs[:1], w[:2], p)  # compile / load cache outside the timing
        t0 = time.perf_counter()
        _, steps = evaluate(designs, w, p, return_steps=True)
        dt = time.perf_counter() - t0
        rates[name] = n_traj / dt
        print(f"{name:12s}: {rates[name]:10.0f} trajectories/s/core "
              f"(mean {steps.mean():.0f} steps per trajectory, {dt:.1f} s)")  # fmt: skip
    starts = grid.env_starts(4.0)
    t0 = time.perf_counter()
    for _ in range(a.reference):
        d = designs[rng.integers(len(designs))]
        reference_trajectory(starts[rng.integers(4)], d[:2], d[2:], *rng.choice(w, 2))
    ref = a.reference / (time.perf_counter() - t0)
    print(f"{'scipy DOP853 1e-10':12s}: {ref:10.1f} trajectories/s/core ({a.reference} trajectories)")
    for name, r in rates.items():
        print(f"speed-up of {name} over scipy reference: {r / ref:.0f}x per trajectory")
    full = 6561 * 4 * 121**2
    for name, r in rates.items():
        print(f"full sweep estimate, {name}: {full / r / 3600:.1f} core-hours "
              f"({full / 2 / r / 3600:.1f} with mirror symmetry); sample-dependent")  # fmt: skip


if __name__ == "__main__":
    main()
