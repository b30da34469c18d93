"""The 625-design survey (5 positions per axis, 11 x 11 weights) in the MuJoCo model, and its
comparison with the committed pybullet survey (results/survey/empirical/metrics.csv).

    nohup nice -n 10 .venv/bin/python tools/mujoco_survey.py run > /work/runs/mujoco_survey/log 2>&1 &
    .venv/bin/python tools/mujoco_survey.py compare

``run``: one design of each mirror pair is simulated (early stop, exact, and the adaptive weight
grid at near = 4, which missed no success in the pybullet validation: on this 2-core machine shared
with other work the exhaustive grid would not fit the time at hand) and its mirror image derived
(design d with (w1, w2) in env k is mirror(d) with (w2, w1) in ENV_MIRROR[k]). Every
finished design is kept as ``designs/d<index>.npz`` under the output folder and reused (resumable).
``checks``: the flip rate of the mirror derivation and the adaptive grid's misses (:func:`checks`).
``compare``: the metrics table (as the pybullet survey's), Spearman of M_L and M_CF between the
engines with bootstrap 95 % intervals (all designs, and those non-zero in either), top-10 overlap,
the canonical design's rank, the share of designs with a generalist, written as compare.json.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
import pandas as pd

from morphlearn.grid import ENV_MIRROR, DesignGrid, canonical_design, weights
from morphlearn.metrics import design_metrics
from morphlearn.mujoco.episode import BatchRunner, evaluate_design
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import load_params
from morphlearn.physics.refine import DEFAULT_NEAR

ROOT = Path(__file__).resolve().parents[1]
OUT = Path("/work/runs/mujoco_survey")
GRID, M = DesignGrid(5), 11
PYBULLET = ROOT / "results/survey/empirical/metrics.csv"


def design_path(out: Path, d: int) -> Path:
    return out / "designs" / f"d{d:04d}.npz"


def run(out: Path, reverse: bool = False) -> None:
    (out / "designs").mkdir(parents=True, exist_ok=True)
    params = load_params(ROOT / "config/empirical_morphology.yaml")
    runner = BatchRunner(params)
    opts = SweepOptions(early_stop=True, adaptive_weights=True, near=DEFAULT_NEAR)
    w = weights(M)
    reps = GRID.representatives()[::-1] if reverse else GRID.representatives()
    t0 = time.time()
    for n, d in enumerate(reps):
        path = design_path(out, int(d))
        if path.exists():
            continue
        l1, l2 = _points(int(d))
        c0 = time.process_time()
        r = evaluate_design(l1, l2, w, params, options=opts, runner=runner)
        cpu = time.process_time() - c0
        tmp = path.with_suffix(".tmp.npz")
        np.savez(
            tmp,
            first_time=r.first_time,
            min_dist=r.min_dist,
            status=r.status,
            cpu=cpu,
            options=json.dumps(opts.science()),
        )
        tmp.rename(path)
        print(f"{n + 1}/{len(reps)} design {d} cpu {cpu:.2f} s wall {time.time() - t0:.0f} s", flush=True)
    print(f"done: {len(reps)} designs, wall {time.time() - t0:.0f} s", flush=True)


def _points(d: int) -> tuple[tuple[float, float], tuple[float, float]]:
    c = GRID.coords(d)
    return (float(c[0]), float(c[1])), (float(c[2]), float(c[3]))


def load_all(out: Path) -> dict[int, np.ndarray]:
    """Success arrays (4, M, M) of the designs finished so far, mirror images derived (all 625
    when the run is complete; a partial run is compared on what it has, and says so)."""
    succ = {}
    for d in GRID.representatives():
        if not design_path(out, int(d)).exists():
            continue
        z = np.load(design_path(out, int(d)))
        s = ~np.isnan(z["first_time"])
        succ[int(d)] = s
        succ[int(GRID.mirror(int(d)))] = s[list(ENV_MIRROR)].transpose(0, 2, 1)
    return succ


def metrics(out: Path) -> pd.DataFrame:
    succ = load_all(out)
    rows = []
    for d in sorted(succ):
        l1, l2 = _points(d)
        dm = design_metrics(succ[d])
        rows.append(
            {
                "model": "mujoco",
                "design": d,
                "l1x": l1[0],
                "l1y": l1[1],
                "l2x": l2[0],
                "l2y": l2[1],
                **{f"n_{a}": v for a, v in zip((45, 135, 225, 315), dm.per_env, strict=True)},
                "generalists": dm.generalists,
                "at_least_one": dm.at_least_one,
                "M_L": dm.M_L,
                "M_CF": dm.M_CF,
                "flagged": dm.flagged,
            }
        )
    return pd.DataFrame(rows)


def spearman_ci(a: np.ndarray, b: np.ndarray, n_boot: int = 2000, seed: int = 0) -> dict[str, float]:
    from scipy.stats import spearmanr

    rho = float(spearmanr(a, b).statistic)
    rng = np.random.default_rng(seed)
    boots = []
    for _ in range(n_boot):
        k = rng.integers(0, len(a), len(a))
        r = spearmanr(a[k], b[k]).statistic
        if np.isfinite(r):
            boots.append(r)
    lo, hi = np.percentile(boots, [2.5, 97.5])
    return {"rho": rho, "lo": float(lo), "hi": float(hi), "n": len(a)}


def _top_ties(a: np.ndarray, b: np.ndarray, k: int = 10) -> dict[str, int]:
    """Top-k sets that keep every design tied with the k-th value, their sizes and overlap."""
    ta = set(np.flatnonzero(a >= np.sort(a)[::-1][k - 1]))
    tb = set(np.flatnonzero(b >= np.sort(b)[::-1][k - 1]))
    return {"pybullet": len(ta), "mujoco": len(tb), "overlap": len(ta & tb)}


def compare(out: Path) -> dict:
    mj = metrics(out)
    mj.to_csv(out / "metrics.csv", index=False)
    pb = pd.read_csv(PYBULLET).set_index("design").loc[mj["design"]]
    res: dict = {}
    for metric in ("M_L", "M_CF"):
        a, b = pb[metric].to_numpy(float), mj[metric].to_numpy(float)
        nz = (a > 0) | (b > 0)
        top_a = set(np.argsort(-a, kind="stable")[:10])
        top_b = set(np.argsort(-b, kind="stable")[:10])
        entry = {
            "all": spearman_ci(a, b),
            "nonzero_either": spearman_ci(a[nz], b[nz]),
            "top10_overlap": len(top_a & top_b),  # ties at the 10th value broken by design index
            "top10_with_ties": _top_ties(a, b),
            "designs_nonzero": {"pybullet": int((a > 0).sum()), "mujoco": int((b > 0).sum())},
        }
        # rank 1 = best; ties share the best rank of their group
        canon = int(np.flatnonzero(mj["design"].to_numpy() == GRID.index_of(*canonical_design()))[0])
        entry["canonical_rank"] = {"pybullet": int((a > a[canon]).sum()) + 1, "mujoco": int((b > b[canon]).sum()) + 1}
        res[metric] = entry
    res["share_with_generalist"] = {
        "pybullet": float((pb["generalists"] > 0).mean()),
        "mujoco": float((mj["generalists"] > 0).mean()),
    }
    res["designs_compared"] = len(mj)
    cpu = [
        float(np.load(design_path(out, int(d)))["cpu"])
        for d in GRID.representatives()
        if design_path(out, int(d)).exists()
    ]
    res["cpu_s_simulated_designs"] = {"designs": len(cpu), "total": sum(cpu), "mean": float(np.mean(cpu))}
    (out / "compare.json").write_text(json.dumps(res, indent=1) + "\n")
    print(json.dumps(res, indent=1))
    return res


def checks(out: Path, n_mirror: int = 6) -> dict:
    """Two measured checks of the survey's shortcuts.

    - mirror derivation: the ``n_mirror`` representatives with the most successes get their mirror
      image simulated too; outcomes that differ from the derived ones are counted;
    - adaptive grid: designs also simulated exhaustively (``designs_exhaustive/``, the first run
      before the switch to the adaptive grid): successes the adaptive grid inferred as failures.
    """
    params = load_params(ROOT / "config/empirical_morphology.yaml")
    runner = BatchRunner(params)
    opts = SweepOptions(early_stop=True, adaptive_weights=True, near=DEFAULT_NEAR)
    reps = [int(d) for d in GRID.representatives() if int(GRID.mirror(int(d))) != int(d)]
    n_succ = {d: int((~np.isnan(np.load(design_path(out, d))["first_time"])).sum()) for d in reps}
    res: dict = {"mirror": [], "adaptive": []}
    for d in sorted(reps, key=lambda d: -n_succ[d])[:n_mirror]:
        z = np.load(design_path(out, d))
        derived = (~np.isnan(z["first_time"]))[list(ENV_MIRROR)].transpose(0, 2, 1)
        dm = int(GRID.mirror(d))
        l1, l2 = _points(dm)
        r = evaluate_design(l1, l2, weights(M), params, options=opts, runner=runner)
        sim = ~np.isnan(r.first_time)
        res["mirror"].append(
            {
                "design": d,
                "mirror": dm,
                "cells": int(sim.size),
                "successes": int(sim.sum()),
                "flips": int((sim != derived).sum()),
            }
        )
    for p in sorted((out / "designs_exhaustive").glob("d*.npz")):
        d = int(p.stem[1:])
        if not design_path(out, d).exists():
            continue
        ex, ad = np.load(p), np.load(design_path(out, d))
        se, sa = ~np.isnan(ex["first_time"]), ~np.isnan(ad["first_time"])
        res["adaptive"].append(
            {
                "design": d,
                "successes": int(se.sum()),
                "missed": int((se & ~sa).sum()),
                "extra": int((sa & ~se).sum()),  # must be 0: determinism
                "inferred": int((ad["status"] == 4).sum()),
            }
        )
    (out / "checks.json").write_text(json.dumps(res, indent=1) + "\n")
    print(json.dumps(res, indent=1))
    return res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", choices=["run", "compare", "checks"])
    ap.add_argument("--out", type=Path, default=OUT)
    # a second worker from the other end: designs are files written atomically, and a design both
    # workers happen to run gives the same bytes
    ap.add_argument("--reverse", action="store_true")
    a = ap.parse_args()
    if a.what == "run":
        run(a.out, a.reverse)
    else:
        {"compare": compare, "checks": checks}[a.what](a.out)


if __name__ == "__main__":
    main()
