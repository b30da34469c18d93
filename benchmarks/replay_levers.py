"""The adaptive grid replayed on exhaustive reduced-model maps (benchmarks/exhaustive_reduced.py's
``.npz`` files): per design and lever (per environment, the grid before ``adaptive_cross_env``;
across environments, the sweep's default), the generalists, ``at_least_one`` controllers and
successes it would lose, the share of episodes and of steps it simulates (a failure runs the whole
horizon, a success to its first success step: the adaptive run's cost), with no new simulation
(:func:`morphlearn.physics.refine.misses`). Prints the per-design table as CSV to ``--csv`` and
the totals as JSON.

    python benchmarks/replay_levers.py /work/tmp/exhaustive9 --stride 6 --near 2.5 --csv replay.csv
    python benchmarks/replay_levers.py /work/tmp/exhaustive9 --time 20   # also the sweeps' CPU time

``--variants``: also two costlier rules of sharing (what one environment finds joins every
environment's first wave): its near misses as well as its successes (``share_seeds``), and one mask
for all four (``share_mask``: a seed in any environment grows its neighbours in all).

``--time N``: the reduced model's adaptive sweep of the first N designs run for real with each
lever (one thread: NUMBA_NUM_THREADS=1), its CPU seconds per design, after checking that its
successes are the replay's.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
import pandas as pd

from morphlearn.physics.params import load_params
from morphlearn.physics.refine import lattice, misses, replay_mask, simulated_mask

BODY = "config/authors_body.yaml"


def shared_first_wave(seeds: np.ndarray, share: np.ndarray, stride: int) -> np.ndarray:
    """The replay of a grid where a simulated cell of ``share`` (4, m, m) in one environment joins
    every environment's first wave: the least fixed point, as :func:`replay_mask` reaches it."""
    start = np.broadcast_to(lattice(seeds.shape[-1], stride), seeds.shape).copy()
    while True:
        mask = replay_mask(seeds, stride, start)
        grown = start | (mask & share).any(axis=0, keepdims=True)
        if np.array_equal(grown, start):
            return mask
        start = grown


def replay(
    path: Path, stride: int, near: float, contact: float, steps: int, dt: float, variants: bool = False
) -> list[dict]:
    z = np.load(path)
    first, dist = z["first_time"], z["min_dist"]
    succ = ~np.isnan(first)
    # steps an episode runs to its first success (first_time = first_step dt), the horizon otherwise
    cost = np.where(succ, np.rint(np.nan_to_num(first) / dt) + 1, steps)
    rows = []
    for lever, across in (("per_env", False), ("cross_env", True)):
        r = misses(succ, dist, contact, near, stride, across=across)
        sim = simulated_mask(succ, dist, contact, near, stride, across=across)
        r.update(design=int(z["design"]), lever=lever, step_share=float(cost[sim].sum() / cost.sum()))
        rows.append(r)
    if variants:
        seeds = succ | (dist <= near * contact)
        masks = {"share_seeds": shared_first_wave(seeds, seeds, stride)}
        masks["share_mask"] = np.broadcast_to(replay_mask(seeds.any(axis=0), stride), succ.shape)
        for lever, sim in masks.items():
            kept = succ & sim
            rows.append(
                {
                    "design": int(z["design"]),
                    "lever": lever,
                    "generalists": int(succ.all(axis=0).sum()),
                    "generalists_missed": int((succ.all(axis=0) & ~kept.all(axis=0)).sum()),
                    "at_least_one": int(succ.any(axis=0).sum()),
                    "at_least_one_missed": int((succ.any(axis=0) & ~kept.any(axis=0)).sum()),
                    "successes_missed": int((succ & ~sim).sum()),
                    "simulated_share": float(sim.mean()),
                    "step_share": float(cost[sim].sum() / cost.sum()),
                }
            )
    return rows


def timed(files: list[Path], stride: int, near: float) -> dict[str, float]:
    """CPU seconds per design of the reduced model's adaptive sweep with each lever (its
    successes checked against the exhaustive map's kept by the replay)."""
    from morphlearn import grid
    from morphlearn.physics.options import SweepOptions
    from morphlearn.reduced.episode import evaluate_design

    p = load_params(BODY)
    w = grid.weights(121)
    c = grid.DesignGrid(9).coords(int(np.load(files[0])["design"]))
    evaluate_design((c[0], c[1]), (c[2], c[3]), w[:13], p)  # compile outside the clock
    out: dict[str, float] = {}
    for lever, across in (("per_env", False), ("cross_env", True)):
        opts = SweepOptions(adaptive_weights=True, stride=stride, near=near, cross_env=across)
        spent = 0.0
        for f in files:
            z = np.load(f)
            c = grid.DesignGrid(9).coords(int(z["design"]))
            t = time.process_time()
            r = evaluate_design((c[0], c[1]), (c[2], c[3]), w, p, options=opts)
            spent += time.process_time() - t
            succ = ~np.isnan(z["first_time"])
            sim = simulated_mask(succ, z["min_dist"], p.contact_distance, near, stride, across=across)
            if not np.array_equal(~np.isnan(r.first_time), succ & sim):
                raise SystemExit(f"{f}: the sweep's successes are not the replay's ({lever})")
        out[f"{lever}_cpu_s_per_design"] = round(spent / len(files), 3)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("folder", type=Path)
    ap.add_argument("--stride", type=int, default=6)
    ap.add_argument("--near", type=float, default=2.5)
    ap.add_argument("--csv", type=Path)
    ap.add_argument("--variants", action="store_true", help="also the costlier sharing rules")
    ap.add_argument("--time", type=int, default=0, help="also time the sweep on the first N designs")
    a = ap.parse_args()
    p = load_params(BODY)
    files = sorted(a.folder.glob("design*[0-9].npz"))
    rows = [r for f in files for r in replay(f, a.stride, a.near, p.contact_distance, p.steps, p.dt, a.variants)]
    t = pd.DataFrame(rows)
    if a.csv:
        t.to_csv(a.csv, index=False)
    out = {"designs": len(files), "stride": a.stride, "near": a.near}
    for lever, g in t.groupby("lever"):
        out[lever] = {
            "generalists": int(g.generalists.sum()),
            "generalists_missed": int(g.generalists_missed.sum()),
            "designs_missing_generalists": int((g.generalists_missed > 0).sum()),
            "at_least_one": int(g.at_least_one.sum()),
            "at_least_one_missed": int(g.at_least_one_missed.sum()),
            "designs_missing_at_least_one": int((g.at_least_one_missed > 0).sum()),
            "successes_missed": int(g.successes_missed.sum()),
            "simulated_share_mean": round(float(g.simulated_share.mean()), 4),
            "step_share_mean": round(float(g.step_share.mean()), 4),
        }
    if a.time:
        out["timed_designs"] = min(a.time, len(files))
        out.update(timed(files[: a.time], a.stride, a.near))
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
