"""The stage's outputs from its runs: the (a)-(e) table, the ES-vs-random comparison, where the
co-optimised sensors end up, the markdown summary and the figure."""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from morphlearn.coopt.setups import paper_setups
from morphlearn.grid import positions
from morphlearn.settings import CooptSettings

if TYPE_CHECKING:
    from matplotlib.figure import Figure

LEARNER_LABEL = {
    "random": "random",
    "one_plus_one": "(1+1)-ES",
    "cmaes": "CMA-ES",
    "one_plus_one_restart": "(1+1)-ES restart",
    "cmaes_restart": "CMA-ES restart",
}


def learner_label(learner: str, sigma: float) -> str:
    return LEARNER_LABEL[learner] if pd.isna(sigma) else f"{LEARNER_LABEL[learner]} s={sigma:g}"


def bodies(runs: pd.DataFrame) -> pd.DataFrame:
    """Final sensor positions of the co-optimised runs (setups c, d; the joint runs at the
    largest budget and the sequential runs at every budget), with whether the run reached a
    generalist."""
    co = runs[runs.setup.isin(["c", "d"])].copy()
    # positions come first; (0, 4) when no co-optimised setup ran (a config of fixed bodies only)
    x = np.array([[float(v) for v in str(s).split()[:4]] for s in co.x]).reshape(len(co), 4)
    for i, c in enumerate(("l1x", "l1y", "l2x", "l2y")):
        co[c] = 0.5 * x[:, i]
    return co.drop(columns=["x"])


def position_map(metrics_csv: str | Path) -> pd.DataFrame:
    """M_L over the position of one sensor, maximised over the other sensor's grid positions, from
    a theory metrics table: one row per sensor (1, 2) and grid position (x, y). The figure's
    background; a table so that the figure renders from the stage's outputs alone."""
    m = pd.read_csv(metrics_csv)
    rows = []
    for sensor, (cx, cy) in ((1, ("l1x", "l1y")), (2, ("l2x", "l2y"))):
        g = m.groupby([cx, cy]).M_L.max()
        rows += [{"sensor": sensor, "x": float(x), "y": float(y), "M_L": float(v)} for (x, y), v in g.items()]
    return pd.DataFrame(rows, columns=["sensor", "x", "y", "M_L"])


def map_arrays(table: pd.DataFrame) -> tuple[np.ndarray, np.ndarray]:
    """The (n, n) maps of sensor 1 and sensor 2 of a :func:`position_map` table, indexed
    [x, y] on the grid's positions."""
    n = round((len(table) // 2) ** 0.5)
    idx = {float(v): i for i, v in enumerate(positions(n))}
    out = []
    for sensor in (1, 2):
        a = np.zeros((n, n))
        for r in table[table.sensor == sensor].itertuples():
            a[idx[float(r.x)], idx[float(r.y)]] = r.M_L
        out.append(a)
    return out[0], out[1]


def _ci(p: float, lo: float, hi: float) -> str:
    return "n/a" if pd.isna(p) else f"{p:.2f} [{lo:.2f}, {hi:.2f}]"


def table_markdown(summary: pd.DataFrame, s: CooptSettings, sigma: float) -> str:
    """P(generalist) [95 % Wilson] per setup (columns) and learner, protocol, budget (rows);
    evolution strategies at step ``sigma``."""
    setups = [x for x in paper_setups((0.0,) * 4) if x.name in s.setups]  # type: ignore[arg-type]
    head = "| learner | protocol | budget | " + " | ".join(f"({x.name})" for x in setups) + " |"
    lines = [head, "|" + "---|" * (3 + len(setups))]
    keep = summary[summary.sigma0.isna() | (summary.sigma0 == sigma)]
    for (lr, sg, pr, b), g in keep.groupby(["learner", "sigma0", "protocol", "budget"], dropna=False, sort=False):
        g = g.set_index("setup")
        cells = [_ci(*g.loc[x.name, ["p_generalist", "p_lo", "p_hi"]]) if x.name in g.index else "" for x in setups]
        lines.append(f"| {learner_label(lr, sg)} | {pr} | {b} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def sort_summary(summary: pd.DataFrame) -> pd.DataFrame:
    order = {"random": 0, "one_plus_one": 1, "cmaes": 2, "one_plus_one_restart": 3, "cmaes_restart": 4}
    k = summary.assign(_o=summary.learner.map(order), _s=summary.sigma0.fillna(-1.0))
    return k.sort_values(["_o", "_s", "protocol", "budget", "setup"], kind="stable").drop(columns=["_o", "_s"])


def summary_markdown(
    summary: pd.DataFrame, landscape: pd.DataFrame, s: CooptSettings, extra: dict[str, Any] | None = None
) -> str:
    lines = [
        "# Co-optimising the body against a four-synapse controller (beyond the paper)",
        "",
        f"{s.seeds} seeds per setup, learner, step size, protocol and budget; budgets {list(s.budgets)} joint "
        f"evaluations (the sequential protocol: {s.cycles} cycles x 4 phases, the same trajectories). "
        "Setups: (a) canonical body, 2 weights; (b) canonical body, 4 weights; (c) co-optimised body, "
        "2 weights; (d) co-optimised body, 4 weights; (e) best two-weight design, 2 weights.",
        "",
        "## Four-weight landscape",
        "",
        "| design | coords (l1x, l1y, l2x, l2y) | M_L 4 weights | M_CF 4 weights | M_L 2 weights (same grid) "
        "| M_CF 2 weights (same grid) | M_L / M_CF 2 weights (bundle, 121 x 121) |",
        "|---|---|---|---|---|---|---|",
    ]
    for _, r in landscape.iterrows():
        lines.append(
            f"| {r['name']} | ({r.l1x:g}, {r.l1y:g}, {r.l2x:g}, {r.l2y:g}) | {r.M_L_4w:.4f} | {r.M_CF_4w:.4f} | "
            f"{r.M_L_2w:.4f} | {r.M_CF_2w:.4f} | {r.M_L_bundle:.4f} / {r.M_CF_bundle:.4f} |"
        )
    lines += [
        "",
        f"Grid: {int(landscape.m.iloc[0])} points per weight in [-1, 1] ({int(landscape.m.iloc[0]) ** 4} "
        "four-weight controllers x 4 environments per design); the two-weight columns are the slice u1 = u2 = 0 "
        "of the same trajectories.",
        "",
    ]
    for sg in s.sigmas:
        lines += [
            f"## P(generalist within the budget) [95 % Wilson interval], evolution strategies at step {sg:g}",
            "",
            table_markdown(summary, s, sg),
            "",
        ]
    lines += ["## Evaluations to the first generalist and forgetting", "", _detail(summary), ""]
    if extra:
        lines += [f"- {k}: {v}" for k, v in extra.items()]
    return "\n".join(lines) + "\n"


def _detail(summary: pd.DataFrame) -> str:
    lines = [
        "| setup | learner | protocol | budget | P(gen) [95 %] | restricted mean evals [95 %] | KM median "
        "| forgetting rate [95 %] |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for _, r in sort_summary(summary).iterrows():
        fr = r.get("forgetting_rate", math.nan)
        lines.append(
            f"| {r.setup} | {learner_label(r.learner, r.sigma0)} | {r.protocol} | {r.budget} | "
            f"{_ci(r.p_generalist, r.p_lo, r.p_hi)} | {r.evals_restricted_mean:.1f} [{r.evals_rm_lo:.1f}, "
            f"{r.evals_rm_hi:.1f}] | {'>' + str(r.budget) if pd.isna(r.evals_km_median) else f'{r.evals_km_median:g}'} "
            f"| {'' if pd.isna(fr) else _ci(fr, r.forget_lo, r.forget_hi)} |"
        )
    return "\n".join(lines)


def figure(summary: pd.DataFrame, runs: pd.DataFrame, pmap: pd.DataFrame, sigma: float) -> Figure:
    """Left: P(generalist) against the budget per setup (joint and sequential; evolution
    strategies at step ``sigma``). Right: the learned bodies of the co-optimised runs that reached
    a generalist (joint, largest budget) over M_L by sensor position (the other sensor at its best).
    Drawn by notebooks/coopt.ipynb (the figure rule, or ``morphlearn.coopt.bundle render``)."""
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullLocator

    fig, axes = plt.subplots(2, 4, figsize=(12, 7.6), layout="constrained", width_ratios=(1, 1, 1, 1.25))
    colours = {"a": "C0", "b": "C1", "c": "C2", "d": "C3", "e": "C7"}
    labels = {x.name: x.label for x in paper_setups((0.0,) * 4)}  # type: ignore[arg-type]
    keep = summary[summary.sigma0.isna() | (summary.sigma0 == sigma)]
    budgets = sorted(keep.budget.unique())
    for row, pr in enumerate(("joint", "sequential")):
        for col, lr in enumerate(("random", "one_plus_one", "cmaes")):
            ax = axes[row, col]
            g = keep[(keep.protocol == pr) & (keep.learner == lr)]
            for st, h in g.groupby("setup"):
                h = h.sort_values("budget")
                ax.errorbar(
                    h.budget,
                    h.p_generalist,
                    yerr=[h.p_generalist - h.p_lo, h.p_hi - h.p_generalist],
                    marker="o",
                    capsize=3,
                    color=colours[st],
                    label=labels[st],
                )
            ax.set_xscale("log")
            ax.xaxis.set_minor_locator(NullLocator())
            ax.set_ylim(-0.02, 1.02)
            ax.set_xticks(budgets, [str(b) for b in budgets])
            ax.set_title(f"{learner_label(lr, math.nan if lr == 'random' else sigma)}, {pr}", fontsize=10)
            ax.set_xlabel("budget (evaluations)")
            if col == 0:
                ax.set_ylabel("P(generalist within budget)")
            else:
                ax.tick_params(labelleft=False)
    handles, names = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, names, loc="outside lower center", ncols=3, fontsize=9)
    m1, m2 = map_arrays(pmap)
    co = bodies(runs)
    co = co[(co.protocol == "joint") & co.reached]
    for row, (mp, sx, sy, name) in enumerate(((m1, "l1x", "l1y", "sensor 1"), (m2, "l2x", "l2y", "sensor 2"))):
        ax = axes[row, 3]
        n = mp.shape[0]
        h = 0.5 / (n - 1)
        im = ax.imshow(mp.T, origin="lower", extent=(-0.5 - h, 0.5 + h, -0.5 - h, 0.5 + h), cmap="viridis")
        for st, mk in (("c", "o"), ("d", "^")):
            p = co[co.setup == st]
            ec = "w" if st == "c" else "r"
            ax.scatter(p[sx], p[sy], s=14, marker=mk, facecolor="none", edgecolor=ec, lw=0.8)
            ax.scatter([], [], marker=mk, facecolor="none", edgecolor=ec, label=f"({st}) generalists: {len(p)}")
        ax.set_title(f"{name}: learned positions", fontsize=10)
        ax.set_xlabel(f"{sx} (forward)")
        ax.set_ylabel(f"{sy} (left)")
        # a dark frame: the white and red markers show on it as on the map
        ax.legend(fontsize=9, loc="lower left", frameon=True, facecolor="0.3", framealpha=0.9, labelcolor="w")
        fig.colorbar(im, ax=ax, shrink=0.8, label="max M_L (2 weights)")
    return fig
