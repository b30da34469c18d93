"""Validate the ODE model's levers (docs/ode.md) against exhaustive runs.

``mirror OUT``: simulates every (env, w1, w2) episode of ``--pairs`` mirror pairs of designs of the
paper's 9-point grid (a seeded sample of designs that are not their own mirror image, the paper's
empirical best design always in it) at ``--m`` x ``--m`` weights, both designs of each pair, and
counts the flips between a design's simulated outcomes and those derived from its mirror image
(environment mirrored, w1 <-> w2): ODE creates the left wheel before the right, so the constraint
rows are not mirror-symmetric and the engine is symmetric only to rounding. One ``.npz`` per design
in OUT (resumable: finished designs are kept).

``adaptive STORE``: replays the adaptive weight grid (:func:`morphlearn.physics.refine.misses`)
on the exhaustive outcomes in a merged store (e.g. ``results/ode-paper-run/ode/merged.zarr``, every
cell simulated) at several ``--near`` values and lattice ``--stride`` values (``adaptive_stride``):
the successes and generalists it would miss and the share of episodes it would simulate.
``--screen SCREEN`` (a merged store of a cheaper model's outcomes of the same designs, e.g.
``results/reduced-ode-paper/reduced/merged.zarr``) replays the grid with ``adaptive_screen``: its
first wave also holds every cell the screen calls a success or a near miss.

``compare NEW OLD``: two metrics tables of the same designs (a re-run with other levers, e.g.
``results/ode-survey-missed/ode/metrics.csv``, against ``results/ode-survey/ode/metrics.csv``):
generalists and controllers solving at least one light, per design, and what changed.

Usage::

    python benchmarks/validate_ode_levers.py mirror OUT [--pairs 20] [--m 11] [--seed 0]
    python benchmarks/validate_ode_levers.py adaptive STORE [--stride 2 4 6] [--screen S]
    python benchmarks/validate_ode_levers.py compare NEW.csv OLD.csv
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from morphlearn.grid import DesignGrid, weights
from morphlearn.physics.params import load_params
from morphlearn.physics.refine import misses, screen_cells
from morphlearn.store import mirror_arrays

ROOT = Path(__file__).resolve().parents[1]
PAPER_BEST = ((-0.5, 0.125), (0.5, -0.375))


def sample(pairs: int, seed: int) -> list[int]:
    g = DesignGrid(9)
    reps = g.representatives()
    reps = reps[g.mirror(reps) != reps]  # not its own mirror image
    best = g.index_of(*PAPER_BEST)
    best = min(best, int(g.mirror(best)))
    rng = np.random.default_rng(seed)
    others = rng.choice(np.setdiff1d(reps, [best]), pairs - 1, replace=False)
    return [best, *sorted(int(d) for d in others)]


def simulate(design: int, m: int, out: Path) -> dict[str, np.ndarray]:
    from morphlearn.ode.episode import evaluate_design

    f = out / f"d{design}_m{m}.npz"
    if f.exists():
        with np.load(f) as z:
            return {k: z[k] for k in z.files}
    c = DesignGrid(9).coords(np.array([design]))[0]
    t = time.process_time()
    r = evaluate_design((c[0], c[1]), (c[2], c[3]), weights(m), load_params(ROOT / "config/authors_body.yaml"))
    arrays = {"first_time": r.first_time, "min_dist": r.min_dist, "cpu_s": np.array(time.process_time() - t)}
    tmp = f.with_suffix(".tmp.npz")
    np.savez(tmp, **arrays)
    tmp.replace(f)  # whole files only: a killed run resumes from the designs it finished
    return arrays


def cmd_mirror(a: argparse.Namespace) -> None:
    a.out.mkdir(parents=True, exist_ok=True)
    g = DesignGrid(9)
    cells = flips = gens = gen_flips = 0
    worst = 0.0
    per = []
    for d in sample(a.pairs, a.seed):
        md = int(g.mirror(d))
        x, y = simulate(d, a.m, a.out), simulate(md, a.m, a.out)
        derived = mirror_arrays({"first_time": x["first_time"], "min_dist": x["min_dist"]})
        s_sim, s_der = ~np.isnan(y["first_time"]), ~np.isnan(derived["first_time"])
        f = int((s_sim != s_der).sum())
        gs, gd = s_sim.all(axis=0), s_der.all(axis=0)
        cells += s_sim.size
        flips += f
        gens += int(gs.sum())
        gen_flips += int((gs != gd).sum())
        same = np.isclose(y["min_dist"], derived["min_dist"], rtol=0, atol=0)
        worst = max(worst, float(np.nanmax(np.abs(y["min_dist"] - derived["min_dist"]))))
        per.append({"design": d, "mirror": md, "flips": f, "bit_identical_min_dist": float(same.mean())})
        print(f"design {d} / mirror {md}: {f} flips of {s_sim.size} cells, generalists {int(gs.sum())}", flush=True)
    report = {
        "pairs": len(per),
        "weights": a.m,
        "cells": cells,
        "success_flips": flips,
        "flip_rate": flips / cells,
        "generalists": gens,
        "generalist_flips": gen_flips,
        "max_abs_min_dist_difference": worst,
        "per_pair": per,
    }
    (a.out / "mirror_report.json").write_text(json.dumps(report, indent=1) + "\n")
    print(json.dumps({k: v for k, v in report.items() if k != "per_pair"}))


def cmd_adaptive(a: argparse.Namespace) -> None:
    from morphlearn import store

    ds = store.open_merged(a.store)
    screen = store.open_merged(a.screen) if a.screen else None
    body = load_params(ROOT / "config/authors_body.yaml")
    rows = []
    for d in ds.design.values:
        sel = ds.sel(design=d)
        first, dist = sel.first_time.values, sel.min_dist.values
        if np.isnan(dist).any():
            raise SystemExit(f"{a.store}: design {int(d)} is not exhaustive (unsimulated cells)")
        if screen is not None and int(d) not in set(screen.design.values.tolist()):
            raise SystemExit(f"{a.screen}: holds no design {int(d)}")
        for stride in a.stride:
            for near in a.near:
                cells = None
                if screen is not None:
                    sc = screen.sel(design=d)
                    cells = screen_cells(sc.first_time.values, sc.min_dist.values, body.contact_distance, near)
                r = misses(~np.isnan(first), dist, body.contact_distance, near, stride, cells)
                rows.append({"design": int(d), "screen": str(a.screen or ""), **r})
                print(json.dumps(rows[-1]))
    if a.json:
        a.json.write_text(json.dumps(rows, indent=1) + "\n")


def cmd_compare(a: argparse.Namespace) -> None:
    import pandas as pd

    new, old = (pd.read_csv(p, comment="#").set_index("design") for p in (a.new, a.old))
    lost = sorted(set(new.index) - set(old.index))
    if lost:
        raise SystemExit(f"{a.old}: holds no design {lost[0]} of {a.new}")
    cols = ["generalists", "at_least_one"]
    both = new[cols].merge(old[cols], left_index=True, right_index=True, suffixes=("", "_old"))
    for c in cols:
        both[f"{c}_change"] = both[c] - both[f"{c}_old"]
    print(both.to_string())
    changed = both[(both.generalists_change != 0) | (both.at_least_one_change != 0)]
    print(
        f"{len(changed)} of {len(both)} designs changed; at_least_one +{int(both.at_least_one_change.sum())}, "
        f"generalists +{int(both.generalists_change.sum())}"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    mp = sub.add_parser("mirror")
    mp.add_argument("out", type=Path)
    mp.add_argument("--pairs", type=int, default=20)
    mp.add_argument("--m", type=int, default=11)
    mp.add_argument("--seed", type=int, default=0)
    mp.set_defaults(func=cmd_mirror)
    ad = sub.add_parser("adaptive")
    ad.add_argument("store", type=Path)
    ad.add_argument("--near", type=float, nargs="+", default=[1.5, 2.0, 3.0, 4.0])
    ad.add_argument("--stride", type=int, nargs="+", default=[2], help="lattice strides (adaptive_stride)")
    ad.add_argument("--json", type=Path)
    ad.add_argument("--screen", type=Path, help="a merged store of a screen's outcomes (adaptive_screen)")
    ad.set_defaults(func=cmd_adaptive)
    cp = sub.add_parser("compare")
    cp.add_argument("new", type=Path)
    cp.add_argument("old", type=Path)
    cp.set_defaults(func=cmd_compare)
    a = ap.parse_args()
    a.func(a)


if __name__ == "__main__":
    main()
