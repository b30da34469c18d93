"""The paper's own integration, for a check of a coarse sweep's best designs: ``scipy.integrate.odeint``
(LSODA) on the (x, y, alpha) form over the whole horizon, success tested on its output samples
(the centre within the success radius at a sample), as the paper describes ("10^5 timesteps").

Slow (pure-Python right-hand side), so it runs on a few designs; resumable: each design's cells
are written to a file of their own as it finishes, and a design already written is skipped.

    python -m morphlearn.theory.odeint_check results/theory-text OUT_DIR [--top 50] [--samples 100000]
"""

from __future__ import annotations

import argparse
import math
import sys
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.integrate import odeint

from morphlearn import grid as gridmod
from morphlearn.theory import text_sweep
from morphlearn.theory.reference import velocities

#: odeint's step budget per output interval; the model's singular designs exhaust it (a failure).
MXSTEP = 5000


def _rhs(l1: tuple[float, float], l2: tuple[float, float], w1: float, w2: float):
    def f(z: np.ndarray, _t: float) -> list[float]:
        x, y, a = z[0], z[1], z[2]
        return velocities(x, y, math.cos(a), math.sin(a), l1, l2, w1, w2)

    return f


def first_sample_success(
    start: tuple[float, float],
    l1: tuple[float, float],
    l2: tuple[float, float],
    w1: float,
    w2: float,
    *,
    radius: float,
    horizon: float,
    samples: int,
) -> tuple[float, bool]:
    """(time of the first output sample within ``radius`` of the light (NaN: none), whether odeint
    finished cleanly) for one trajectory from ``start`` facing +x, the light at the origin."""
    t = np.linspace(0.0, horizon, samples + 1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # odeint warns on the singular designs; reported as not clean
        sol, info = odeint(_rhs(l1, l2, w1, w2), [start[0], start[1], 0.0], t, full_output=True, mxstep=MXSTEP)
    clean = info.get("message", "") == "Integration successful."
    d = np.hypot(sol[:, 0], sol[:, 1])
    ok = np.isfinite(d)
    if not clean:  # after a failed step odeint's remaining rows are not a trajectory
        bad = int(np.argmax(~ok)) if not ok.all() else len(d)
        ok[bad:] = False
    hit = np.flatnonzero(ok & (d <= radius))
    return (float(t[hit[0]]) if hit.size else math.nan), clean


def design_cells(
    design: int, g: gridmod.DesignGrid, w: np.ndarray, r: float, radius: float, horizon: float, samples: int
) -> pd.DataFrame:
    """Every (environment, w1, w2) cell of one design by odeint: first sample time and cleanliness."""
    c = g.coords(design)
    l1, l2 = (float(c[0]), float(c[1])), (float(c[2]), float(c[3]))
    rows = []
    for e, start in enumerate(gridmod.env_starts(r)):
        for i, a in enumerate(w):
            for j, b in enumerate(w):
                ft, clean = first_sample_success(
                    (float(start[0]), float(start[1])),
                    l1,
                    l2,
                    float(a),
                    float(b),
                    radius=radius,
                    horizon=horizon,
                    samples=samples,
                )
                rows.append({"design": design, "env": e, "i": i, "j": j, "first_time": ft, "clean": clean})
    return pd.DataFrame(rows)


def summarise(cells: pd.DataFrame, kernel_ft: np.ndarray, horizon: float) -> pd.DataFrame:
    """Per design: generalists, solvers, M_L and M_CF by odeint and by the sweep's kernel."""
    out = []
    for d, part in cells.groupby("design", sort=False):
        ft = np.full(kernel_ft.shape[1:], np.nan)
        ft[part.env, part.i, part.j] = part.first_time
        og, os_ = text_sweep.counts(ft[None], horizon)
        kg, ks = text_sweep.counts(kernel_ft[int(d)][None], horizon)
        cells_n = ft.shape[-1] * ft.shape[-2]
        out.append(
            {
                "design": int(d),
                "odeint_generalists": int(og[0]),
                "odeint_solvers": int(os_[0]),
                "odeint_M_L": og[0] / cells_n,
                "odeint_M_CF": og[0] / os_[0] if os_[0] else 0.0,
                "kernel_generalists": int(kg[0]),
                "kernel_solvers": int(ks[0]),
                "kernel_M_L": kg[0] / cells_n,
                "kernel_M_CF": kg[0] / ks[0] if ks[0] else 0.0,
                "unclean_cells": int((~part.clean.astype(bool)).sum()),
            }
        )
    return pd.DataFrame(out)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("bundle", help="a theory bundle holding every design (results/theory-text)")
    ap.add_argument("out", help="folder for one CSV per design and summary.csv")
    ap.add_argument("--top", type=int, default=50, help="the sweep's best designs by M_L, one of each mirror pair")
    ap.add_argument("--samples", type=int, default=100_000, help="output samples over the horizon")
    ap.add_argument(
        "--summarise", action="store_true", help="only summarise the designs already written (a run stopped early)"
    )
    a = ap.parse_args(argv)
    if a.top < 1 or a.samples < 1:
        print(f"--top and --samples must be >= 1, got {a.top}, {a.samples}", file=sys.stderr)
        return 2
    ft, w, g, science = text_sweep.load_first_times(Path(a.bundle) / "theory" / "merged.zarr")
    th = science["theory"]
    r, radius, horizon = float(th["r"]), float(th["success_radius"]), float(th["horizon"])
    gen, _ = text_sweep.counts(ft, horizon)
    order = np.argsort(-gen, kind="stable")  # best first, ties by index
    wanted: list[int] = [g.index_of(*gridmod.PAPER_BEST_DESIGN), g.index_of(*gridmod.canonical_design())]
    for d in order:
        if len(wanted) >= a.top + 2:
            break
        if int(d) not in wanted and int(g.mirror(int(d))) not in wanted:
            wanted.append(int(d))
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    if a.summarise:  # the designs written so far, in the run's order
        wanted = [d for d in wanted if (out / f"design_{d}.csv").exists()]
    for k, d in enumerate(wanted):
        f = out / f"design_{d}.csv"
        if not f.exists():  # resumable: written whole, once
            tmp = f.with_suffix(".tmp")
            design_cells(d, g, w, r, radius, horizon, a.samples).to_csv(tmp, index=False)
            tmp.replace(f)
        print(f"design {d} done ({k + 1}/{len(wanted)})", flush=True)
    cells = pd.concat([pd.read_csv(out / f"design_{d}.csv") for d in wanted])
    summarise(cells, ft, horizon).to_csv(out / "summary.csv", index=False, float_format="%.6g")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
