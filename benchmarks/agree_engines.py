"""Agreement of the two engines, cell by cell, and the committed body's w = (1, 1) check.

1. The canonical design with w = (1, 1) in the four environments, both engines: contact times,
   closest approach, largest tilt and lift (does the committed body reach all four lights?).
2. Success matrices on 11 x 11 weights (exhaustive, early stop: exact) for the canonical design and
   ``--designs`` others of the 5-positions grid, both engines: per-environment successes,
   generalists, and in how many of the 4 x 121 cells the two engines agree.

Writes ``--out``/agree.json and ``--out``/<design>.npz (both engines' first-contact times).
Usage::

    python benchmarks/agree_engines.py [--out /work/runs/mujoco_agree] [--designs 620 120 48 91 300]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from morphlearn.empirical import EpisodeRunner
from morphlearn.empirical import evaluate_design as evaluate_pybullet
from morphlearn.grid import ENV_ANGLES_DEG, DesignGrid, canonical_design, weights
from morphlearn.metrics import design_metrics
from morphlearn.mujoco.episode import BatchRunner
from morphlearn.mujoco.episode import evaluate_design as evaluate_mujoco
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import load_params

ROOT = Path(__file__).resolve().parents[1]


def w11(params) -> dict:  # type: ignore[no-untyped-def]
    l1, l2 = canonical_design()
    out: dict = {"pybullet": {}, "mujoco": {}}
    with EpisodeRunner(params) as r:
        for e, a in enumerate(ENV_ANGLES_DEG):
            ep = r.run(l1, l2, 1.0, 1.0, e)
            out["pybullet"][a] = {
                "contact_s": ep.first_time,
                "min_dist": ep.min_dist,
                "max_tilt_deg": float(np.degrees(ep.max_tilt)),
                "max_lift_m": ep.max_lift,
            }
    ep = BatchRunner(params).run(l1, l2, np.ones((4, 2)), np.arange(4))
    for e, a in enumerate(ENV_ANGLES_DEG):
        out["mujoco"][a] = {
            "contact_s": float(ep.first_time[e]),
            "min_dist": float(ep.min_dist[e]),
            "max_tilt_deg": float(np.degrees(ep.max_tilt[e])),
            "max_lift_m": float(ep.max_lift[e]),
        }
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("/work/runs/mujoco_agree"))
    ap.add_argument("--designs", type=int, nargs="+", default=[620, 120, 48, 91, 300])
    ap.add_argument("--m", type=int, default=11)
    a = ap.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    params = load_params(ROOT / "config/empirical_morphology.yaml")
    res: dict = {"w11_canonical": w11(params), "designs": {}}
    print(json.dumps(res["w11_canonical"], indent=1), flush=True)
    g, w, opts = DesignGrid(5), weights(a.m), SweepOptions(early_stop=True)
    for d in a.designs:
        c = g.coords(d)
        l1, l2 = (float(c[0]), float(c[1])), (float(c[2]), float(c[3]))
        t0 = time.process_time()
        pb = evaluate_pybullet(l1, l2, w, params, options=opts)
        t1 = time.process_time()
        mj = evaluate_mujoco(l1, l2, w, params, options=opts)
        t2 = time.process_time()
        sp, sm = ~np.isnan(pb.first_time), ~np.isnan(mj.first_time)
        np.savez(a.out / f"d{d:04d}.npz", pybullet=pb.first_time, mujoco=mj.first_time)
        mp, mm = design_metrics(sp), design_metrics(sm)
        both = sp & sm
        entry = {
            "l1": l1,
            "l2": l2,
            "cells": int(sp.size),
            "agree": int((sp == sm).sum()),
            "success_both": int(both.sum()),
            "only_pybullet": int((sp & ~sm).sum()),
            "only_mujoco": int((~sp & sm).sum()),
            "per_env": {"pybullet": mp.per_env, "mujoco": mm.per_env},
            "generalists": {"pybullet": mp.generalists, "mujoco": mm.generalists},
            "M_L": {"pybullet": mp.M_L, "mujoco": mm.M_L},
            "M_CF": {"pybullet": mp.M_CF, "mujoco": mm.M_CF},
            "generalist_cells_agree": int(((sp.all(0)) == (sm.all(0))).sum()),
            "median_abs_contact_diff_s": float(np.median(np.abs(pb.first_time - mj.first_time)[both]))
            if both.any()
            else None,
            "cpu_s": {"pybullet": t1 - t0, "mujoco": t2 - t1},
        }
        res["designs"][d] = entry
        print(d, json.dumps(entry), flush=True)
        (a.out / "agree.json").write_text(json.dumps(res, indent=1) + "\n")


if __name__ == "__main__":
    main()
