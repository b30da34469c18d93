"""Validate the empirical sweep's levers against full episodes of the current loop.

``run``: simulates every (env, w1, w2) episode of ``--pairs`` mirror pairs of designs (seeded
sample of the 5-positions-per-axis grid, the paper's best theory pair always in it) with the
current loop (stop at contact, no early stop), while the reach bound is asked at every check and
its first "hopeless" step recorded. One ``.npz`` per design in ``OUT`` (resumable: finished
designs are kept), ``--jobs`` processes (one pybullet client each).

``report``: from those files, measures

- early stop (exact lever): success flips = successes whose first contact comes after the
  bound's hopeless step (the early-stopped loop is this loop cut there, so its outcome differs
  exactly then); the share of physics steps it saves;
- adaptive weights (option): successes missed when only the cells the refinement would pick are
  simulated (the refinement is replayed on the exhaustive success maps), and the share of
  episodes and of physics steps it skips;
- mirror derivation (option): flips between a design and its mirror image's derived arrays.

Usage::

    python benchmarks/validate_levers.py run OUT --pairs 21 --jobs 2
    python benchmarks/validate_levers.py run OUT --designs 3,17,40   # chosen designs instead
    python benchmarks/validate_levers.py report OUT [--csv per_design.csv]
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import sys
import time
from pathlib import Path

import numpy as np

from morphlearn.empirical.episode import EpisodeRunner
from morphlearn.grid import ENV_MIRROR, DesignGrid, weights
from morphlearn.physics.params import load_params
from morphlearn.physics.refine import DEFAULT_NEAR, DEFAULT_STRIDE, replay_mask

PAPER_BEST = ((-0.5, -0.25), (0.5, 0.25))
MARGIN = 2.0


def sample_designs(pairs: int, seed: int = 0) -> list[int]:
    g = DesignGrid(5)
    d = np.arange(g.size)
    mir = g.mirror(d)
    reps = d[d < mir]  # one of each true pair (self-mirror designs have none)
    best = min(g.index_of(*PAPER_BEST), int(g.mirror(g.index_of(*PAPER_BEST))))
    rng = np.random.default_rng(seed)
    others = rng.permutation(reps[reps != best])[: pairs - 1]
    chosen = [best, *(int(x) for x in others)]
    return sorted({int(x) for c in chosen for x in (c, int(g.mirror(c)))})


def simulate(args: tuple[int, str, str, int]) -> str:
    design, out, morphology, m = args
    path = Path(out) / f"design_{design}.npz"
    if path.exists():
        return f"design {design}: kept"
    g = DesignGrid(5)
    c = g.coords(design)
    l1, l2 = (float(c[0]), float(c[1])), (float(c[2]), float(c[3]))
    w = weights(m)
    first = np.full((4, m, m), np.nan)
    dist = np.full((4, m, m), np.nan)
    steps = np.zeros((4, m, m), np.int32)
    hopeless = np.full((4, m, m), -1, np.int32)
    t0 = time.process_time()
    with EpisodeRunner(load_params(morphology)) as runner:
        for env in range(4):
            for i in range(m):
                for j in range(m):
                    b = runner.bound(l1, l2, w[i], w[j], MARGIN)
                    ep = runner.run(l1, l2, w[i], w[j], env, bound=b, stop_hopeless=False)
                    first[env, i, j], dist[env, i, j], steps[env, i, j] = ep.first_time, ep.min_dist, ep.steps
                    hopeless[env, i, j] = ep.hopeless_step
    cpu = time.process_time() - t0
    tmp = path.with_suffix(".tmp.npz")
    np.savez(tmp, design=design, first=first, dist=dist, steps=steps, hopeless=hopeless, cpu=cpu)
    tmp.rename(path)  # whole file or none
    return f"design {design}: {4 * m * m} episodes, {cpu:.0f} CPU-s"


def run(a: argparse.Namespace) -> None:
    Path(a.out).mkdir(parents=True, exist_ok=True)
    designs = sample_designs(a.pairs, a.seed) if a.designs is None else sorted(set(a.designs))
    print(f"{len(designs)} designs x {4 * a.weights**2} episodes, {a.jobs} processes", flush=True)
    jobs = [(d, a.out, a.morphology, a.weights) for d in designs]
    with mp.Pool(a.jobs) as pool:
        for k, msg in enumerate(pool.imap_unordered(simulate, jobs), 1):
            print(f"[{k}/{len(jobs)}] {msg}", flush=True)


def report(a: argparse.Namespace) -> None:
    files = sorted(Path(a.out).glob("design_*.npz"))
    if not files:
        sys.exit(f"{a.out}: no design files; run `run` first")
    data = {int(np.load(f)["design"]): dict(np.load(f)) for f in files}
    g = DesignGrid(5)
    n_ep = n_succ = es_flips = 0
    steps_all = steps_es = steps_ad = 0
    ad_missed = ad_sim = 0
    rows = []
    contact = load_params(a.morphology).contact_distance
    for d, r in sorted(data.items()):
        first, steps, hop = r["first"], r["steps"], r["hopeless"]
        succ = np.isfinite(first)
        contact_step = np.where(succ, steps, -1)
        flip = succ & (hop >= 0) & (hop < contact_step)
        es_steps = np.where(hop >= 0, np.minimum(hop, steps), steps)
        near = r["dist"] <= a.near * contact
        mask = replay_mask(succ | near, a.stride)
        missed = succ & ~mask
        n_ep += succ.size
        n_succ += int(succ.sum())
        es_flips += int(flip.sum())
        steps_all += int(steps.sum())
        steps_es += int(es_steps.sum())
        steps_ad += int(es_steps[mask].sum())
        ad_missed += int(missed.sum())
        ad_sim += int(mask.sum())
        rows.append(
            (
                d,
                int(succ.sum()),
                int(flip.sum()),
                int(missed.sum()),
                int(mask.sum()),
                int(steps.sum()),
                int(es_steps.sum()),
                float(r["cpu"]),
            )
        )
    mir_flips = mir_eps = mir_pairs = 0
    for d in data:
        md = int(g.mirror(d))
        if d < md and md in data:
            a_s = np.isfinite(data[d]["first"])
            derived = np.isfinite(data[md]["first"])[list(ENV_MIRROR)].transpose(0, 2, 1)
            mir_flips += int((a_s != derived).sum())
            mir_eps += a_s.size
            mir_pairs += 1
    cpu = sum(r[-1] for r in rows)
    print(
        f"designs {len(data)}; episodes {n_ep:,}; successes {n_succ:,}; CPU {cpu:,.0f} s "
        f"({n_ep / cpu:.2f} episodes/core-s, current loop)"
    )
    print(
        f"early stop (margin {MARGIN}): success flips {es_flips} of {n_succ} successes "
        f"({n_ep:,} episodes); physics steps {steps_es:,} of {steps_all:,} "
        f"({1 - steps_es / steps_all:.1%} saved)"
    )
    print(
        f"adaptive weights (stride {a.stride}, near {a.near}): episodes simulated {ad_sim:,} of {n_ep:,} "
        f"({ad_sim / n_ep:.1%}); successes missed {ad_missed} of {n_succ} "
        f"({ad_missed / max(n_succ, 1):.2%}); steps with early stop {steps_ad:,} "
        f"({steps_ad / steps_all:.1%} of the current loop's)"
    )
    print(
        f"mirror derivation: {mir_flips} success flips in {mir_eps:,} episodes of {mir_pairs} pairs "
        f"({mir_flips / max(mir_eps, 1):.3%})"
    )
    if a.csv:
        import pandas as pd

        cols = [
            "design",
            "successes",
            "early_stop_flips",
            "adaptive_missed",
            "adaptive_simulated",
            "steps_full",
            "steps_early_stop",
            "cpu_s",
        ]
        pd.DataFrame(rows, columns=cols).to_csv(a.csv, index=False, float_format="%.6g")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("out")
    r.add_argument("--pairs", type=int, default=21)
    r.add_argument("--seed", type=int, default=0)
    r.add_argument(
        "--designs",
        type=lambda v: [int(x) for x in v.split(",")],
        help="comma-separated design indices instead of the seeded sample",
    )
    r.add_argument("--jobs", type=int, default=2)
    r.add_argument("--weights", type=int, default=11)
    r.add_argument("--morphology", default="config/empirical_morphology.yaml")
    p = sub.add_parser("report")
    p.add_argument("out")
    p.add_argument("--stride", type=int, default=DEFAULT_STRIDE)
    p.add_argument("--near", type=float, default=DEFAULT_NEAR)
    p.add_argument("--morphology", default="config/empirical_morphology.yaml")
    p.add_argument("--csv")
    a = ap.parse_args()
    run(a) if a.cmd == "run" else report(a)


if __name__ == "__main__":
    main()
