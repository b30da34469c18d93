"""What the theory model's step cap (``theory.max_steps``) costs and what it changes.

Runs a grid of designs once with a generous cap (default 100,000 steps) and, from the step counts
of that run, counts for each smaller cap: the share of the integration steps it would keep (its
cost), the successes it would turn into failures (a success that needed more steps than the cap:
its flips), and the failures that would end at the cap instead of the horizon (they become
flagged ``step_cap``; still failures). Counting from one run is exact: a trajectory under a
smaller cap is the same trajectory, stopped earlier. Usage::

    PYTHONPATH=src python benchmarks/bench_step_cap.py [--positions 5] [--weights 41]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from morphlearn.grid import DesignGrid, env_starts, weights
from morphlearn.theory import TheoryParams, cpu


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--positions", type=int, default=5, help="sensor positions per axis")
    ap.add_argument("--weights", type=int, default=41, help="weights per synapse")
    ap.add_argument("--reference-cap", type=int, default=100_000)
    ap.add_argument("--caps", type=int, nargs="+", default=[5_000, 10_000, 20_000, 50_000])
    a = ap.parse_args()
    p = TheoryParams.from_config({})
    g = DesignGrid(a.positions)
    designs = g.coords(np.arange(g.size))
    t0 = time.perf_counter()
    ft, _, st, n = cpu.sweep(
        designs,
        weights(a.weights),
        env_starts(p.r),
        radius=p.success_radius,
        horizon=p.horizon,
        method=p.method,
        rtol=p.rtol,
        atol=p.atol,
        dt=p.dt,
        max_steps=a.reference_cap,
    )
    wall = time.perf_counter() - t0
    succ = np.isfinite(ft)
    fail = ~succ & (st == 0)  # failures that reached the horizon
    print(
        f"{len(designs)} designs x {a.weights}^2 weights x 4 lights = {succ.size:,} trajectories, "
        f"cap {a.reference_cap:,}: {wall:.1f} s wall"
    )
    print(
        f"successes {succ.sum():,}: steps max {n[succ].max():,}, median {np.median(n[succ]):.0f}; "
        f"at the cap {(st == 2).sum():,}"
    )
    total = n.sum()
    print("cap      steps kept  successes lost  horizon failures ending at the cap")
    for cap in sorted(a.caps):
        print(
            f"{cap:>7,}  {np.minimum(n, cap).sum() / total:>9.1%}  {(succ & (n > cap)).sum():>14,}"
            f"  {(fail & (n > cap)).sum():>10,}"
        )


if __name__ == "__main__":
    main()
