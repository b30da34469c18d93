"""The adaptive weight grid, validated on the theory model (where the exhaustive answer is known).

Replays the refinement (``morphlearn.physics.refine``, vectorised replay) on every design's
exhaustive success maps of a merged theory store, optionally on a coarser sub-grid of its
weights (``--every 12`` turns 121 weights into the 11 of the empirical survey), and reports the
cells it would simulate, the successes it would miss and what that does to the metrics.
"Promising" = closest approach within ``--near`` success radii (the empirical sweep uses 1.5
contact distances). Usage::

    python benchmarks/validate_adaptive_theory.py results/paper-run/theory/merged.zarr --every 12
"""

from __future__ import annotations

import argparse

import numpy as np
from scipy import stats

from morphlearn import metrics, store
from morphlearn.physics.refine import DEFAULT_NEAR, DEFAULT_STRIDE, replay_mask


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("merged")
    ap.add_argument("--every", type=int, default=1, help="use every k-th weight (sub-grid)")
    ap.add_argument("--stride", type=int, default=DEFAULT_STRIDE)
    ap.add_argument("--near", type=float, default=DEFAULT_NEAR)
    ap.add_argument("--design-step", type=int, default=1, help="use every k-th design of the store")
    a = ap.parse_args()
    ds = store.open_merged(a.merged)
    radius = float(store.science_of(ds)["theory"]["success_radius"])
    sel = slice(None, None, a.every)
    cells = sim = succ_n = missed = 0
    ml_full, ml_ad, cf_full, cf_ad = [], [], [], []
    for sl, arr in store.read_blocks(ds, 64):
        for i in range(0, sl.stop - sl.start, a.design_step):
            ft = arr["first_time"][i][:, sel, sel]
            md = arr["min_dist"][i][:, sel, sel]
            succ = np.isfinite(ft)
            mask = replay_mask(succ | (md <= a.near * radius), a.stride)
            got = succ & mask
            cells += mask.size
            sim += int(mask.sum())
            succ_n += int(succ.sum())
            missed += int((succ & ~mask).sum())
            f, g = metrics.design_metrics(succ), metrics.design_metrics(got)
            ml_full.append(f.M_L)
            ml_ad.append(g.M_L)
            cf_full.append(f.M_CF)
            cf_ad.append(g.M_CF)
    ml_full, ml_ad, cf_full, cf_ad = map(np.array, (ml_full, ml_ad, cf_full, cf_ad))
    m = ds.sizes["w1"] // a.every + (1 if ds.sizes["w1"] % a.every else 0)
    print(
        f"{a.merged}: {len(ml_full)} designs, {m} x {m} weights (every {a.every}), stride {a.stride}, "
        f"near {a.near} x radius {radius}"
    )
    print(f"cells simulated: {sim:,} of {cells:,} ({sim / cells:.1%})")
    print(f"successes missed: {missed:,} of {succ_n:,} ({missed / max(succ_n, 1):.3%})")
    changed = ml_full != ml_ad
    print(
        f"designs whose M_L changes: {int(changed.sum())} of {len(ml_full)}; largest |dM_L| "
        f"{np.abs(ml_full - ml_ad).max():.4g}; whose M_CF changes: {int((cf_full != cf_ad).sum())}, "
        f"largest |dM_CF| {np.abs(cf_full - cf_ad).max():.4g}"
    )
    print(
        f"Spearman(M_L exhaustive, M_L adaptive) = {stats.spearmanr(ml_full, ml_ad).statistic:.6f}; "
        f"M_CF: {stats.spearmanr(cf_full, cf_ad).statistic:.6f}; best design by M_L unchanged: "
        f"{int(np.argmax(ml_full)) == int(np.argmax(ml_ad))}"
    )


if __name__ == "__main__":
    main()
