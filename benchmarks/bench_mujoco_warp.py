"""The MuJoCo Warp backend against the CPU MuJoCo batch: throughput and agreement.

Needs the optional group ``gpu`` (``pip install -e '.[gpu]'``). Two parts, both print measured
numbers only:

- throughput (default): for each ``--nworld`` n, n episodes (random designs of the
  5-positions-per-axis grid, random weights in [-1, 1], random environments, a fixed seed; episodes
  stop at contact and with the early stop, as the surveys run) in one MuJoCo Warp batch on
  ``--device``: episodes per second of wall time (after one untimed warm-up batch that compiles or
  loads the kernels; its time is printed too). Then the CPU batch (``mujoco.batch``, one thread)
  on the first ``--cpu-episodes`` of the same episodes: episodes per core-second.
- ``--agree M``: the canonical design's 4 x M x M episodes in both backends
  (``evaluate_design``, early stop on): successes, how many outcomes agree, the largest
  first-contact time difference among the episodes both count as successes, and the cells that
  disagree.

Usage (a GPU machine; Warp's CPU device also runs it, slowly, with ``--device cpu``)::

    python benchmarks/bench_mujoco_warp.py [--device cuda:0] [--nworld 256,4096,16384] [--cpu-episodes 256]
    python benchmarks/bench_mujoco_warp.py --agree 11 [--device cpu]
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np

from morphlearn.grid import DesignGrid, canonical_design, weights
from morphlearn.mujoco.episode import BatchRunner, evaluate_design
from morphlearn.mujoco.mjwarp import WarpBatchRunner, device_name, resolve_device
from morphlearn.physics.options import DEFAULT_MARGIN, SweepOptions
from morphlearn.physics.params import load_params

ROOT = Path(__file__).resolve().parents[1]


def episodes(n: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    c = DesignGrid(5).coords(rng.integers(0, 625, n))
    return c[:, :2], c[:, 2:], rng.uniform(-1.0, 1.0, (n, 2)), rng.integers(0, 4, n)


def throughput(a: argparse.Namespace, params, device: str) -> None:  # type: ignore[no-untyped-def]
    sizes = [int(x) for x in a.nworld.split(",")]
    l1, l2, w, env = episodes(max(sizes), a.seed)
    r = WarpBatchRunner(params, device=device, nworld=max(sizes))
    t = time.perf_counter()
    r.run(l1[:8], l2[:8], w[:8], env[:8], margin=DEFAULT_MARGIN)
    print(f"warm-up (compile or load the kernels, 8 episodes): {time.perf_counter() - t:.1f} s")
    for n in sizes:
        t = time.perf_counter()
        ep = r.run(l1[:n], l2[:n], w[:n], env[:n], margin=DEFAULT_MARGIN)
        s = time.perf_counter() - t
        print(
            f"warp nworld {n}: {n / s:.1f} episodes/s ({s:.2f} s wall, {int(ep.steps.max())} steps for the "
            f"batch, {int(ep.steps.sum())} episode-steps, {int(ep.success.sum())} successes)"
        )
    k = min(a.cpu_episodes, max(sizes))
    cpu = BatchRunner(params)
    t = time.process_time()
    ep = cpu.run(l1[:k], l2[:k], w[:k], env[:k], margin=DEFAULT_MARGIN)
    s = time.process_time() - t
    print(f"cpu batch (one thread): {k / s:.1f} episodes/core-s ({s:.2f} core-s, {int(ep.success.sum())} successes)")


def agree(a: argparse.Namespace, params, device: str) -> None:  # type: ignore[no-untyped-def]
    l1, l2 = canonical_design()
    w = weights(a.agree)
    opt = SweepOptions(early_stop=True)
    t = time.process_time()
    ref = evaluate_design(l1, l2, w, params, options=opt)
    t_cpu = time.process_time() - t
    t = time.perf_counter()
    got = evaluate_design(l1, l2, w, params, options=opt, runner=WarpBatchRunner(params, device=device))
    t_warp = time.perf_counter() - t
    s_ref, s_got = ~np.isnan(ref.first_time), ~np.isnan(got.first_time)
    both = s_ref & s_got
    dt = np.abs(ref.first_time - got.first_time)[both]
    n = s_ref.size
    print(f"canonical design, {a.agree} x {a.agree} weights, 4 environments = {n} episodes, early stop")
    print(f"cpu: {int(s_ref.sum())} successes ({t_cpu:.1f} core-s); warp: {int(s_got.sum())} ({t_warp:.1f} s wall)")
    print(f"same outcome: {int((s_ref == s_got).sum())}/{n}; successes in both: {int(both.sum())}")
    if both.any():
        print(
            f"first-contact time difference among those: max {dt.max():.3g} s, "
            f"{int((dt == 0).sum())} identical, {int((dt <= params.dt).sum())} within one step"
        )
    wv = np.round(w, 3)
    for e, i, j in np.argwhere(s_ref != s_got):
        print(
            f"  differs: env {e}, w = ({wv[i]}, {wv[j]}): cpu {ref.first_time[e, i, j]:.4g} s "
            f"(closest {ref.min_dist[e, i, j]:.4g}), warp {got.first_time[e, i, j]:.4g} s "
            f"(closest {got.min_dist[e, i, j]:.4g})"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--device", default=None, help="Warp device (default: the first CUDA GPU)")
    ap.add_argument("--nworld", default="256,4096,16384", help="batch sizes, comma-separated")
    ap.add_argument("--cpu-episodes", type=int, default=256)
    ap.add_argument("--agree", type=int, default=0, metavar="M", help="agreement on M x M weights instead")
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()
    params = load_params(ROOT / "config" / "empirical_morphology.yaml")
    device = resolve_device(a.device)
    print(f"device {device_name(device)}; {os.cpu_count()} CPU cores")
    if a.agree:
        agree(a, params, device)
    else:
        throughput(a, params, device)


if __name__ == "__main__":
    main()
