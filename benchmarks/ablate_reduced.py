"""What moves the optimum: the reduced model with one physical feature at a time taken toward the
theory (issue 56, docs/reduced.md). Each variant is the reduced model's own step with one constant
changed (never a fitted one); for each, over the 625 designs of the 5-point grid at 11 x 11 weights
and 4 lights (302,500 episodes, every cell):

- Spearman of the cells each design solves with ODE's (the committed results/authors-engines, the
  authors' robot in ODE at the same cells) and with the theory's (the committed results/survey:
  the theory at 41 x 41; the share of controllers a design solves does not depend on the grid's
  density, its rank order is what is compared);
- the share of cells with ODE's outcome;
- the best design by cells solved and its rank in ODE and in the theory.

The variants (toward the theory; the theory model: docs/model.md):

- ``reduced``: the model as built (docs/reduced.md);
- ``planar sensors``: the sensors at the light's height (2D distances, as the theory reads them);
- ``no slip``: every contact's slip 1e-6 instead of 0.01. The authors' castor is a sphere on a
  fixed hinge, not a swivel: without slip the robot cannot turn at all;
- ``free castor``: the castor as an ideal swivel (no force from its contact), the wheels as built;
- ``no wheel slip``: the wheels' contacts stiff (slip 1e-6), the castor as built;
- ``rolling drive``: no wheel slip and a free castor: the theory's differential drive, with the
  robot's inertia and motors;
- ``no inertia``: every mass and inertia x 1e-6 (velocities follow the motors at once);
- ``no torque cap``: the motors reach their targets at once (cap x 1e6);
- ``linear motor law``: the target proportional to w s, without tanh or a speed limit (the theory's
  law; emulated exactly to O(eps^2) by max_speed / eps and weights x eps, eps = 1e-4);
- ``kinematic``: planar sensors, the rolling drive, no inertia, no torque cap and the linear law at
  once (what is left of the theory's world: the body's size and success radius, the light's
  distance and the horizon, as the authors' robot has them).

Usage::

    python benchmarks/ablate_reduced.py [--m 11] [--only reduced "planar sensors"]
    python benchmarks/ablate_reduced.py --plot docs/reduced_ablation.png

``--plot``: the figure of docs/results.md, drawn from the measured table in docs/reduced.md (its one
record): each variant's Spearman with ODE against its Spearman with the theory.
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.stats import spearmanr

from morphlearn.grid import DesignGrid, light_positions, weights
from morphlearn.physics import authors
from morphlearn.physics.params import EmpiricalParams, load_params
from morphlearn.reduced import body as bodymod
from morphlearn.reduced.cpu import run_batch

ROOT = Path(__file__).resolve().parents[1]
EPS = 1e-4


@dataclasses.dataclass(frozen=True)
class Variant:
    name: str
    params: Callable[[EmpiricalParams], EmpiricalParams] = lambda p: p
    slip: float = authors.SLIP  # the wheels' contacts
    castor_slip: float | None = authors.SLIP  # None: a free swivel (no force)
    mass_scale: float = 1.0
    torque_scale: float = 1.0  # the motors' cap (given to the kernel: the body file's range stops at 1e4)
    planar: bool = False
    linear: bool = False


VARIANTS = [
    Variant("reduced"),
    Variant("planar sensors", planar=True),
    Variant("no slip", slip=1e-6, castor_slip=1e-6),
    Variant("free castor", castor_slip=None),
    Variant("no wheel slip", slip=1e-6),
    Variant("rolling drive", slip=1e-6, castor_slip=None),
    Variant("no inertia", mass_scale=1e-6),
    Variant("no torque cap", torque_scale=1e6),
    Variant("linear motor law", linear=True),
    Variant(
        "kinematic",
        torque_scale=1e6,
        slip=1e-6,
        castor_slip=None,
        mass_scale=1e-6,
        planar=True,
        linear=True,
    ),
]


def constants(v: Variant, p: EmpiricalParams, l1: tuple[float, float], l2: tuple[float, float]) -> bodymod.Body:
    """The step's constants of ``v``: body.body's derivation with the variant's slips, masses and
    sensor height (the model itself where ``v`` changes none of them)."""
    if (v.slip, v.castor_slip, v.mass_scale, v.planar) == (authors.SLIP, authors.SLIP, 1.0, False):
        return bodymod.body(p, l1, l2)
    m, s = bodymod.mass_matrix(p, l1, l2)
    j = bodymod.contact_jacobian(p)
    # rows: left wheel x, y, right wheel x, y, castor x, y; each a damper of 1 / slip
    c = np.array([1 / v.slip] * 4 + ([0.0, 0.0] if v.castor_slip is None else [1 / v.castor_slip] * 2))
    dz = 0.0 if v.planar else authors.sensor_height(p) - authors.LIGHT_Z
    return bodymod.constants(p.dt, m * v.mass_scale, s * v.mass_scale, p.dt * j.T @ np.diag(c) @ j, dz)


def solved_cells(v: Variant, base: EmpiricalParams, m: int) -> tuple[np.ndarray, np.ndarray, float]:
    """(625,) cells each design solves, (625, 4, m, m) successes, CPU seconds."""
    p = v.params(base)
    g = DesignGrid(5)
    w = weights(m)
    e, i, j = np.meshgrid(np.arange(4), np.arange(m), np.arange(m), indexing="ij")
    ww = np.ascontiguousarray(np.stack([w[i.ravel()], w[j.ravel()]], 1))
    vmax = p.max_speed
    if v.linear:
        ww, vmax = ww * EPS, vmax / EPS
    lights = np.ascontiguousarray(light_positions(p.light_distance)[e.ravel()])
    n = len(ww)
    succ = np.zeros((g.size, 4, m, m), bool)
    t = time.process_time()
    for d in range(g.size):
        c = g.coords(d)
        b = constants(v, p, (c[0], c[1]), (c[2], c[3]))
        first, dmin, steps, ok = np.empty(n, np.int64), np.empty(n), np.empty(n, np.int64), np.empty(n, np.bool_)
        tmax = p.max_torque * v.torque_scale
        run_batch(
            b.g, b.hm, b.kk, b.cen, p.dt, p.steps, vmax, tmax, authors.success_radius(p), b.dz2,
            lights, np.ascontiguousarray(c, dtype=np.float64), ww, True, first, dmin, steps, ok,
        )  # fmt: skip
        succ[d] = (first >= 0).reshape(4, m, m)
    return succ.sum(axis=(1, 2, 3)), succ, time.process_time() - t


def ode_cells(m: int) -> tuple[np.ndarray, dict[int, np.ndarray]]:
    """ODE's cells solved per design and its successes (results/authors-engines, all designs)."""
    from morphlearn.analysis.agreement import Source, read, solved

    ref = read(Source("results/authors-engines", "ode"))
    if int(ref.science["weights"]) != m:
        raise SystemExit(f"results/authors-engines is at {ref.science['weights']} weights; run with --m 11")
    return solved(ref.table.set_index("design").sort_index()).to_numpy(), ref.success


def _rank(x: np.ndarray, d: int) -> int:
    """Design ``d``'s rank by ``x`` (ties share a rank)."""
    return int((x > x[d]).sum()) + 1


def measured_table(doc: Path = ROOT / "docs/reduced.md") -> pd.DataFrame:
    """The variants' rows of the table in ``doc`` that have both Spearman values."""
    rows = []
    for line in doc.read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 8 and cells[1][:1].isdigit() and cells[2][:1].isdigit():
            rows.append({"variant": cells[0], "ode": float(cells[1]), "theory": float(cells[2])})
    if not rows:
        raise SystemExit(f"{doc}: no variant rows with both Spearman values")
    return pd.DataFrame(rows)


def plot(out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = measured_table()
    fig, ax = plt.subplots(figsize=(7.5, 5.2))
    ax.scatter(t.ode, t.theory, color="tab:blue", zorder=3)
    near_ode = 0  # the variants that keep ODE's ranking sit in one spot: their labels stacked above it
    for _, r in t.sort_values("ode").iterrows():
        label = r.variant.split(" (")[0]
        if r.ode > 0.95:
            xy, ha = (-10, 14 + 13 * near_ode), "right"
            near_ode += 1
        else:
            xy, ha = (5, 4), "left"
        ax.annotate(label, (r.ode, r.theory), textcoords="offset points", xytext=xy, fontsize=8, ha=ha,
                    arrowprops={"arrowstyle": "-", "color": "0.6", "lw": 0.6} if r.ode > 0.95 else None)  # fmt: skip
    ax.set_xlabel("Spearman with ODE (cells each design solves, 625 designs)")
    ax.set_ylabel("Spearman with the theory")
    ax.set_title("What moves the optimum: the reduced model, one feature at a time toward the theory", fontsize=10)
    ax.set_xlim(0.55, 1.02)
    ax.set_ylim(0.5, 0.9)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=130, metadata={"Software": None})
    print(f"wrote {out} ({len(t)} variants from docs/reduced.md)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--m", type=int, default=11)
    ap.add_argument("--only", nargs="+")
    ap.add_argument("--plot", type=Path, help="draw the measured table of docs/reduced.md to this PNG and stop")
    a = ap.parse_args()
    if a.plot:
        plot(a.plot)
        return
    base = load_params(ROOT / "config/authors_body.yaml")
    ode, ode_succ = ode_cells(a.m)
    th = pd.read_csv(ROOT / "results/survey/theory/metrics.csv").sort_values("design")
    theory = th[[c for c in th.columns if c.startswith("n_")]].sum(axis=1).to_numpy()
    print(f"625 designs x 4 lights x {a.m} x {a.m} weights; ODE: results/authors-engines; theory: results/survey")
    print(
        "| variant | rho with ODE | rho with theory | cells as ODE | best (cells) | rank in ODE | in theory | CPU s |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for v in VARIANTS:
        if a.only and v.name not in a.only:
            continue
        cells, succ, cpu = solved_cells(v, base, a.m)
        same = np.mean([(succ[d] == ode_succ[d]).mean() for d in range(len(cells))])
        best = int(np.argmax(cells))
        print(
            f"| {v.name} | {spearmanr(cells, ode).statistic:.3f} | {spearmanr(cells, theory).statistic:.3f} | "
            f"{100 * same:.2f} % | {best} ({cells[best]}) | {_rank(ode, best)} | {_rank(theory, best)} | {cpu:.0f} |",
            flush=True,
        )


if __name__ == "__main__":
    main()
