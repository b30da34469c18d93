"""Per-design figure of the two physics engines (issue 25), from the committed tables only:

    .venv/bin/python tools/mujoco_figure.py            # writes results/mujoco/engines.{png,pdf,caption.md,json}

- ``results/survey/empirical/metrics.csv``: pybullet, 625 designs, 11 x 11 weights;
- ``results/mujoco/survey_metrics.csv``: MuJoCo, the same designs and weights;
- ``results/survey/theory/metrics.csv``: the theory model, the same designs, 41 x 41 weights.

Panels: pybullet against MuJoCo (M_L, M_CF), and each engine's M_L against the theory's. Every
Spearman rho carries its bootstrap 95 % interval (:func:`morphlearn.compare.spearman_ci`, seeded);
the numbers drawn are also written to ``engines.json`` (docs/results.md quotes them). An engine's
M_L takes only 9 values (0 to 8 generalists of 121 controllers), so its points get a small seeded
jitter of at most +-0.3 generalist to show how many designs share a value; the statistics use the
unjittered values.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
from matplotlib.axes import Axes

from morphlearn.compare import joined, spearman_ci
from morphlearn.figures.output import save, use_style
from morphlearn.grid import DesignGrid, canonical_design

ROOT = Path(__file__).resolve().parents[1]
PYBULLET = ROOT / "results/survey/empirical/metrics.csv"
MUJOCO = ROOT / "results/mujoco/survey_metrics.csv"
THEORY = ROOT / "results/survey/theory/metrics.csv"
OUT = ROOT / "results/mujoco"
CELLS = 121  # controllers per design in both engine surveys (11 x 11)
TOP = 10
NAME = {"pybullet": "pybullet", "mujoco": "MuJoCo", "theory": "theory"}
JITTER = 0.3  # generalists


def tables() -> pd.DataFrame:
    """One row per design: M_L, M_CF of pybullet, MuJoCo and theory, with each one's ranks."""
    pb, mj, th = (pd.read_csv(p) for p in (PYBULLET, MUJOCO, THEORY))
    engines = joined(pb, mj, names=("pybullet", "mujoco"))
    ranks = joined(th, pb, names=("theory", "pybullet"))[["design", "M_L_theory", "M_CF_theory", "rank_M_L_theory"]]
    both = engines.merge(ranks, on="design", validate="one_to_one")
    if len(both) != len(pb) or len(both) != len(mj):
        raise ValueError(
            f"the tables do not cover the same designs: {len(pb)} pybullet, {len(mj)} mujoco, {len(both)} in both"
        )
    return both


def numbers(both: pd.DataFrame) -> dict:
    """Every statistic the figure draws (and docs/results.md quotes)."""

    def rho(x: str, y: str, rows: pd.Series | None = None) -> dict:
        sub = both if rows is None else both[rows]
        r = spearman_ci(sub[x].to_numpy(), sub[y].to_numpy(), x.rsplit("_", 1)[0])
        return {"rho": r.rho, "lo": r.low, "hi": r.high, "n": r.n}

    canon = DesignGrid(5).index_of(*canonical_design())
    out: dict = {}
    for m in ("M_L", "M_CF"):
        nz = (both[f"{m}_pybullet"] > 0) | (both[f"{m}_mujoco"] > 0)
        out[f"{m} pybullet-mujoco"] = {
            "all": rho(f"{m}_pybullet", f"{m}_mujoco"),
            "nonzero_either": rho(f"{m}_pybullet", f"{m}_mujoco", nz),
        }
    for e in ("pybullet", "mujoco"):
        out[f"M_L theory-{e}"] = {"all": rho("M_L_theory", f"M_L_{e}")}
    best = {e: both.loc[both[f"rank_M_L_{e}"] == 1].iloc[0] for e in ("pybullet", "mujoco", "theory")}
    out["best_design_M_L"] = {
        e: {
            "design": int(r.design),
            "l1": [float(r.l1x), float(r.l1y)],
            "l2": [float(r.l2x), float(r.l2y)],
            "generalists_of_121": int(np.rint(r[f"M_L_{e}"] * CELLS)) if e != "theory" else None,
        }
        for e, r in best.items()
    }
    out["canonical_design"] = int(canon)
    return out


def jitter(n: int, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).uniform(-JITTER, JITTER, n) / CELLS


def marks(ax: Axes, both: pd.DataFrame, x: np.ndarray, y: np.ndarray) -> None:
    """The top designs of each engine by M_L and the canonical design, over the cloud."""
    canon = both.design.to_numpy() == DesignGrid(5).index_of(*canonical_design())
    for e, style in (
        ("pybullet", dict(marker="s", s=70, facecolors="none", edgecolors="tab:orange", linewidths=1.3)),
        ("mujoco", dict(marker="o", s=110, facecolors="none", edgecolors="tab:green", linewidths=1.3)),
    ):
        top = both[f"rank_M_L_{e}"].to_numpy() <= TOP
        ax.scatter(x[top], y[top], label=f"top {TOP} by M_L in {NAME[e]}", zorder=3, **style)
    ax.scatter(
        x[canon],
        y[canon],
        marker="*",
        s=260,
        c="tab:red",
        edgecolors="k",
        linewidths=0.6,
        zorder=4,
        label="canonical design",
    )


def note(ax: Axes, stat: dict, extra: str = "") -> None:
    a = stat["all"]
    text = f"Spearman {a['rho']:.2f} [{a['lo']:.2f}, {a['hi']:.2f}]\n(all {a['n']} designs)"
    if "nonzero_either" in stat:
        b = stat["nonzero_either"]
        text += f"\n{b['rho']:.2f} [{b['lo']:.2f}, {b['hi']:.2f}] ({b['n']} non-zero in either)"
    ax.text(0.03, 0.97, text + extra, transform=ax.transAxes, va="top", fontsize=9.5)


def generalist_axis(ax: Axes, which: str) -> None:
    ticks = np.arange(0, 9, 2) / CELLS
    getattr(ax, f"set_{which}ticks")(ticks, [f"{k}" for k in range(0, 9, 2)])


def figure(both: pd.DataFrame, stats: dict) -> plt.Figure:
    fig, axes = plt.subplots(2, 2, figsize=(11, 9.6))
    n = len(both)
    jp, jm = jitter(n, 1), jitter(n, 2)
    pb, mj, th = both.M_L_pybullet.to_numpy(), both.M_L_mujoco.to_numpy(), both.M_L_theory.to_numpy()
    cloud = dict(s=14, c="0.35", alpha=0.45, linewidths=0, label="a design")

    ax = axes[0, 0]
    ax.scatter(pb + jp, mj + jm, **cloud)
    marks(ax, both, pb + jp, mj + jm)
    lim = (-0.6 / CELLS, 8.6 / CELLS)
    ax.plot(lim, lim, color="0.6", lw=0.8, zorder=0)
    ax.set(xlim=lim, ylim=lim, title="(a) M_L: pybullet against MuJoCo")
    ax.set_xlabel("pybullet: generalists of 121 controllers (M_L x 121)")
    ax.set_ylabel("MuJoCo: generalists of 121 (M_L x 121)")
    generalist_axis(ax, "x")
    generalist_axis(ax, "y")
    zero = int(((pb == 0) & (mj == 0)).sum())
    note(ax, stats["M_L pybullet-mujoco"], f"\n{zero} designs at (0, 0)")
    ax.legend(loc="lower right", fontsize=9, handletextpad=0.3)

    ax = axes[0, 1]
    x, y = both.M_CF_pybullet.to_numpy(), both.M_CF_mujoco.to_numpy()
    ax.scatter(x, y, **cloud)
    marks(ax, both, x, y)
    hi = max(x.max(), y.max()) * 1.05
    ax.plot((0, hi), (0, hi), color="0.6", lw=0.8, zorder=0)
    ax.set(xlim=(-0.02, hi), ylim=(-0.02, hi), title="(b) M_CF: pybullet against MuJoCo")
    ax.set_xlabel("pybullet M_CF")
    ax.set_ylabel("MuJoCo M_CF")
    zero = int(((x == 0) & (y == 0)).sum())
    note(ax, stats["M_CF pybullet-mujoco"], f"\n{zero} designs at (0, 0)")

    for ax, e, y, j, tag in (
        (axes[1, 0], "pybullet", pb, jp, "(c)"),
        (axes[1, 1], "mujoco", mj, jm, "(d)"),
    ):
        ax.scatter(th, y + j, **cloud)
        marks(ax, both, th, y + j)
        ax.set(ylim=lim, title=f"{tag} M_L: theory (41 x 41) against {NAME[e]}")
        ax.set_xlabel("theory M_L")
        ax.set_ylabel(f"{NAME[e]}: generalists of 121")
        generalist_axis(ax, "y")
        note(ax, stats[f"M_L theory-{e}"])
    return fig


CAPTION = """**The two physics engines, design by design.** All 625 designs of the 5-point grid. (a) M_L
(generalists among the 11 x 11 controllers) in pybullet against MuJoCo; (b) M_CF likewise; (c), (d)
each engine's M_L against the theory model's (41 x 41 controllers). Engine M_L values are integers of
121, drawn with a seeded jitter of at most +-{jitter} generalist; the diagonal is equality. Squares:
pybullet's top {top} designs by M_L; circles: MuJoCo's (ties at the 10th value broken as
`metrics.rank_designs`); star: the canonical design. Spearman's rho with its percentile bootstrap 95 %
interval over designs (2000 resamples, seed 0), all designs and (a, b) the designs non-zero in
either engine; the numbers are in `engines.json`. Made by `tools/mujoco_figure.py`.
"""


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=OUT, help="folder for engines.{png,pdf,caption.md,json}")
    args = ap.parse_args(argv)
    use_style(ROOT / "notebooks/style.mplstyle")
    both = tables()
    stats = numbers(both)
    fig = figure(both, stats)
    out: Path = args.out
    save(
        fig,
        CAPTION.format(jitter=JITTER, top=TOP),
        out / "engines.png",
        out / "engines.pdf",
        out / "engines.caption.md",
    )
    plt.close(fig)
    (out / "engines.json").write_text(json.dumps(stats, indent=1) + "\n")
    print(json.dumps(stats, indent=1))


if __name__ == "__main__":
    main()
