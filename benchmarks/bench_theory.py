"""Theory kernel speed: trajectories per second per core (CPU kernel, adaptive DP5 and fixed-step
RK4), the scipy reference, and the CUDA kernel when a GPU is present, all measured in one run on
the same random sample of the paper grid.

CPU rates are trajectories per CPU-second of the process (``time.process_time``), i.e. per core,
which stays meaningful on a machine shared with other jobs; wall time is printed beside them.
GPU rates are trajectories per wall second of the whole device (launch + copies included).

Usage: python benchmarks/bench_theory.py [--designs 4] [--weights 31] [--reference 40]
       [--threads 1] [--gpu-designs 0]
``--gpu-designs N`` also times the GPU on N random designs at 121 x 121 weights (a sample big
enough to fill the device) and extrapolates the full sweep's wall time.
"""

from __future__ import annotations

import argparse
import platform
import time
from collections.abc import Callable

import numba
import numpy as np

from morphlearn import grid
from morphlearn.theory import TheoryParams, cpu
from morphlearn.theory import cuda as gpu
from morphlearn.theory.reference import reference_trajectory

FULL = 6561 * 4 * 121**2  # trajectories of the paper grid (3321 designs with mirror symmetry)
CONFIGS = [("dp5 1e-8", TheoryParams()), ("rk4 dt=0.01", TheoryParams(integrator="rk4"))]


def _timed(f: Callable[[], tuple]) -> tuple[tuple, float, float]:
    w0, c0 = time.perf_counter(), time.process_time()
    out = f()
    return out, time.perf_counter() - w0, time.process_time() - c0


def _compare(a: tuple, b: tuple) -> str:
    """Outcome differences between two kernels' (first_time, min_dist, status, steps)."""
    sa, sb = ~np.isnan(a[0]), ~np.isnan(b[0])
    both = sa & sb
    dt = float(np.max(np.abs(a[0][both] - b[0][both]))) if both.any() else 0.0
    dd = float(np.max(np.abs(a[1] - b[1])))
    return (
        f"{int((sa != sb).sum())} success flags differ, {int((a[2] != b[2]).sum())} statuses differ, "
        f"max |dfirst_time| {dt:.2e}, max |dmin_dist| {dd:.2e}"
    )


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--designs", type=int, default=4)
    ap.add_argument("--weights", type=int, default=31)
    ap.add_argument("--reference", type=int, default=40, help="trajectories for scipy")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--threads", type=int, default=1, help="numba threads for the CPU kernel")
    ap.add_argument("--gpu-designs", type=int, default=0, help="extra GPU sample at 121 weights")
    a = ap.parse_args()
    numba.set_num_threads(a.threads)
    rng = np.random.default_rng(a.seed)
    g = grid.DesignGrid(9)
    designs = g.coords(rng.choice(g.size, a.designs, replace=False))
    w = grid.weights(a.weights)
    starts = grid.env_starts(4.0)
    n_traj = len(designs) * 4 * len(w) ** 2
    print(f"# machine: {platform.processor() or platform.machine()}, float64, {a.threads} CPU thread(s)")
    print(
        f"# sample: {len(designs)} random designs of the 9^4 grid (seed {a.seed}) x 4 envs x "
        f"{len(w)}^2 weights = {n_traj} trajectories, T = 500, r = 4"
    )

    rates: dict[str, float] = {}
    cpu_out: dict[str, tuple] = {}
    for name, p in CONFIGS:
        cpu.sweep(designs[:1], w[:2], starts, **p.kernel_kwargs())  # compile / load cache outside the timing
        out, wall, cput = _timed(lambda p=p: cpu.sweep(designs, w, starts, **p.kernel_kwargs()))
        cpu_out[name] = out
        rates[name] = n_traj / cput
        print(
            f"CPU {name:12s}: {rates[name]:9.0f} trajectories/s/core (mean {out[3].mean():.0f} steps "
            f"per trajectory; {cput:.1f} CPU-s, {wall:.1f} s wall)"
        )

    c0 = time.process_time()
    for _ in range(a.reference):
        d = designs[rng.integers(len(designs))]
        reference_trajectory(starts[rng.integers(4)], d[:2], d[2:], *rng.choice(w, 2))
    ref = a.reference / (time.process_time() - c0)
    print(f"scipy DOP853 1e-10: {ref:9.1f} trajectories/s/core ({a.reference} trajectories)")
    for name, r in rates.items():
        print(f"speed-up of CPU {name} over scipy reference: {r / ref:.0f}x per core")
    for name, r in rates.items():
        print(
            f"full sweep estimate, CPU {name}: {FULL / r / 3600:.1f} core-hours "
            f"({FULL / 2 / r / 3600:.1f} with mirror symmetry); sample-dependent"
        )

    if not gpu.available():
        print("# GPU: skipped (numba.cuda.is_available() is False: no CUDA GPU visible)")
        return
    print(f"# GPU: {gpu.device_description()}, float64, one thread per trajectory, refill scheduling")
    for name, p in CONFIGS:
        gpu.sweep(designs[:1], w[:2], starts, **p.kernel_kwargs())  # compile outside the timing
        out, wall, _ = _timed(lambda p=p: gpu.sweep(designs, w, starts, **p.kernel_kwargs()))
        r = n_traj / wall
        print(
            f"GPU {name:12s}: {r:9.0f} trajectories/s ({wall:.2f} s wall); "
            f"{r / rates[name]:.0f}x one CPU core, {r / ref:.0f}x scipy; vs CPU: "
            f"{_compare(out, cpu_out[name])}"
        )
    if a.gpu_designs:
        big = g.coords(rng.choice(g.size, a.gpu_designs, replace=False))
        w121 = grid.weights(121)
        n_big = len(big) * 4 * 121**2
        for name, p in CONFIGS:
            _, wall, _ = _timed(lambda p=p: gpu.sweep(big, w121, starts, **p.kernel_kwargs()))
            print(
                f"GPU {name:12s} on {len(big)} designs x 121^2 ({n_big} trajectories): {wall:.1f} s; "
                f"full sweep estimate {FULL / n_big * wall:.0f} s "
                f"({FULL / 2 / n_big * wall:.0f} s with mirror symmetry)"
            )


if __name__ == "__main__":
    main()
