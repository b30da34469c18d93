"""Matplotlib panels. Conventions: body frame +x forward (drawn to the right), +y left (up);
weight-grid images have w1 on the x axis and w2 on the y axis."""

from __future__ import annotations

import math
from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib import colors, patches
from matplotlib.axes import Axes
from matplotlib.colorbar import Colorbar
from matplotlib.figure import Figure
from matplotlib.image import AxesImage

from morphlearn.grid import ENV_ANGLES_DEG
from morphlearn.theory.reference import ReferenceTrajectory

#: Overlap O = 0..4 (environments solved); 4 (generalists) is cyan as in the paper.
OVERLAP_COLORS = ("#1b2a6b", "#7b3294", "#d6604d", "#fdb863", "#00e5ff")
OVERLAP_LABELS = ("0: none", "1", "2", "3", "4: all (generalist)")
ENV_COLORS = ("#1f77b4", "#2ca02c", "#d62728", "#9467bd")
SENSOR_COLOR = "#d62728"
LIGHT_COLOR = "#ffcc00"
MISSING_TEXT = "empirical results not in this run"


def overlap_cmap() -> tuple[colors.ListedColormap, colors.BoundaryNorm]:
    cmap = colors.ListedColormap(OVERLAP_COLORS, name="overlap")
    return cmap, colors.BoundaryNorm(np.arange(-0.5, 5.0, 1.0), cmap.N)


def _extent(weights: np.ndarray) -> list[float]:
    w = np.asarray(weights, dtype=np.float64)
    h = 0.5 * (w[1] - w[0]) if len(w) > 1 else 0.5
    return [w[0] - h, w[-1] + h, w[0] - h, w[-1] + h]


def _weight_axes(ax: Axes) -> None:
    ax.set_xlabel("$w_1$ (sensor 1 → right wheel)")
    ax.set_ylabel("$w_2$ (sensor 2 → left wheel)")
    ax.set_aspect("equal")


def overlap_image(ax: Axes, overlap: np.ndarray, weights: np.ndarray, title: str) -> AxesImage:
    """The overlap matrix O (m, m) indexed [i_w1, i_w2]."""
    cmap, norm = overlap_cmap()
    im = ax.imshow(np.asarray(overlap).T, origin="lower", extent=_extent(weights), cmap=cmap,
                   norm=norm, interpolation="nearest")  # fmt: skip
    _weight_axes(ax)
    ax.set_title(title, fontsize=10)
    return im


def overlap_colorbar(fig: Figure, im: AxesImage, axes: Sequence[Axes] | Axes) -> Colorbar:
    cb = fig.colorbar(im, ax=axes, ticks=range(5), fraction=0.025, pad=0.02)
    cb.ax.set_yticklabels(OVERLAP_LABELS)
    cb.set_label("environments solved, O")
    return cb


def success_pair(ax: Axes, s_a: np.ndarray, s_b: np.ndarray, weights: np.ndarray, names: tuple[str, str],
                 title: str) -> None:  # fmt: skip
    """Two environments' binary success matrices overlapped: neither, A only, B only, both."""
    cat = np.asarray(s_a, int) + 2 * np.asarray(s_b, int)
    cols = ("#f2f2f2", "#4c72b0", "#e8a33d", "#00b3a4")
    labels = ("neither", f"{names[0]} only", f"{names[1]} only", f"both: {names[0]} ∩ {names[1]}")
    cmap = colors.ListedColormap(cols)
    ax.imshow(cat.T, origin="lower", extent=_extent(weights), cmap=cmap,
              norm=colors.BoundaryNorm(np.arange(-0.5, 4.0, 1.0), 4), interpolation="nearest")  # fmt: skip
    _weight_axes(ax)
    handles = [patches.Patch(facecolor=c, edgecolor="0.4", label=f"{lab} ({int((cat == k).sum())})")
               for k, (c, lab) in enumerate(zip(cols, labels, strict=True))]  # fmt: skip
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=9, frameon=False,
              title="controllers (count)")  # fmt: skip
    ax.set_title(title, fontsize=10)


def missing(ax: Axes, text: str = MISSING_TEXT, title: str | None = None) -> None:
    """An empty, annotated panel for results this run does not have."""
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_facecolor("#f4f4f4")
    for s in ax.spines.values():
        s.set_linestyle("--")
        s.set_edgecolor("0.6")
    ax.text(0.5, 0.5, text, transform=ax.transAxes, ha="center", va="center", fontsize=10,
            style="italic", color="0.35", wrap=True)  # fmt: skip
    if title:
        ax.set_title(title, fontsize=10)


def panel_letter(ax: Axes, letter: str) -> None:
    ax.text(-0.02, 1.02, letter, transform=ax.transAxes, ha="right", va="bottom", fontsize=14,
            fontweight="bold")  # fmt: skip


# ---------------------------------------------------------------------------------------------
# Robot sketches


def robot(ax: Axes, l1: Sequence[float], l2: Sequence[float], *, xy: tuple[float, float] = (0.0, 0.0),
          heading: float = 0.0, scale: float = 1.0, wiring: bool = False, castor: bool = False,
          sensor_labels: bool = True, lw: float = 1.5, zorder: int = 3) -> None:  # fmt: skip
    """Top view of the robot: 1 x 1 body, wheels at its sides, sensors (red) at ``l1``, ``l2``.

    ``wiring`` draws the contralateral synapses (sensor 1 -> right wheel, sensor 2 -> left).
    """
    c, s = math.cos(heading), math.sin(heading)

    def tf(p: Sequence[float]) -> tuple[float, float]:
        return xy[0] + scale * (c * p[0] - s * p[1]), xy[1] + scale * (s * p[0] + c * p[1])

    body = [tf(p) for p in ((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5))]
    ax.add_patch(patches.Polygon(body, closed=True, facecolor="#e9e9e9", edgecolor="0.15", lw=lw,
                                 zorder=zorder))  # fmt: skip
    for side in (1, -1):  # wheels: left (+y) and right (-y), set back slightly
        w = [tf(p) for p in ((-0.25, side * 0.52), (0.2, side * 0.52), (0.2, side * 0.64),
                             (-0.25, side * 0.64))]  # fmt: skip
        ax.add_patch(patches.Polygon(w, closed=True, facecolor="0.1", edgecolor="0.1", zorder=zorder))
    if castor:
        ax.add_patch(patches.Circle(tf((0.42, 0.0)), 0.06 * scale, facecolor="0.6", edgecolor="0.3",
                                    zorder=zorder + 1))  # fmt: skip
    tip, base = tf((0.35, 0.0)), tf((-0.15, 0.0))
    ax.annotate("", xy=tip, xytext=base, zorder=zorder + 1,
                arrowprops={"arrowstyle": "-|>", "color": "0.45", "lw": lw})  # fmt: skip
    if wiring:
        for p, wheel, name in ((l1, (0.0, -0.55), "$w_1$"), (l2, (0.0, 0.55), "$w_2$")):
            a, b = tf(p), tf(wheel)
            ax.plot([a[0], b[0]], [a[1], b[1]], color="#555555", lw=lw * 0.8, ls="--", zorder=zorder + 1)
            mid = tf((0.2 * p[0] + 0.8 * wheel[0] - 0.13, 0.2 * p[1] + 0.8 * wheel[1]))
            ax.text(*mid, name, fontsize=10, ha="center", va="center", zorder=zorder + 2)
    for k, p in enumerate((l1, l2), start=1):
        q = tf(p)
        ax.add_patch(patches.Circle(q, 0.07 * scale, facecolor=SENSOR_COLOR, edgecolor="0.1",
                                    zorder=zorder + 3))  # fmt: skip
        if sensor_labels:
            off = tf((p[0] + 0.16, p[1] + (0.14 if p[1] >= 0 else -0.14)))
            ax.text(*off, str(k), fontsize=10, ha="center", va="center", color=SENSOR_COLOR,
                    fontweight="bold", zorder=zorder + 3)  # fmt: skip


def body_axes(ax: Axes, lim: float = 0.95) -> None:
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_aspect("equal")
    ax.set_xlabel("x (forward)")
    ax.set_ylabel("y (left)")


def theory_robot(ax: Axes, l1: Sequence[float], l2: Sequence[float]) -> None:
    """Fig. 1B: the theoretical model, sensor position vectors l1, l2 from the body centre."""
    robot(ax, l1, l2, wiring=True, sensor_labels=False)
    for k, p in enumerate((l1, l2), start=1):
        ax.annotate("", xy=p, xytext=(0, 0), zorder=8,
                    arrowprops={"arrowstyle": "-|>", "color": "#1f4e9a", "lw": 1.8})  # fmt: skip
        ax.text(0.55 * p[0] - 0.05, 0.55 * p[1] + (0.1 if p[1] >= 0 else -0.1), f"$\\ell_{k}$",
                color="#1f4e9a", fontsize=13, ha="center", va="center", zorder=9)  # fmt: skip
    ax.plot([0], [0], "k+", ms=8, zorder=9)
    body_axes(ax, 0.9)
    ax.set_xticks([-0.5, 0, 0.5])
    ax.set_yticks([-0.5, 0, 0.5])
    ax.text(0.62, 0.0, "heading\n(α = 0)", fontsize=8, va="center", color="0.35")


def braitenberg_wiring(ax: Axes) -> None:
    """Fig. 1A: lateral vs contralateral excitatory connections and where they steer."""
    for x0, kind in ((0.0, "lateral"), (3.3, "contralateral")):
        ax.add_patch(patches.Rectangle((x0 - 0.5, -0.5), 1.0, 1.0, facecolor="#e9e9e9", edgecolor="0.15",
                                       lw=1.5, zorder=3))  # fmt: skip
        for side in (1, -1):
            ax.add_patch(patches.Rectangle((x0 - 0.3, side * 0.52 - (0.12 if side < 0 else 0)), 0.45, 0.12,
                                           facecolor="0.1", zorder=3))  # fmt: skip
        sens = {1: (x0 + 0.5, 0.35), -1: (x0 + 0.5, -0.35)}  # left (+y), right (-y)
        wheels = {1: (x0 - 0.08, 0.46), -1: (x0 - 0.08, -0.46)}
        for side in (1, -1):
            target = wheels[side] if kind == "lateral" else wheels[-side]
            ax.annotate("", xy=target, xytext=sens[side], zorder=4,
                        arrowprops={"arrowstyle": "-|>", "color": "#555555", "lw": 1.3,
                                    "shrinkA": 4, "shrinkB": 2})  # fmt: skip
            ax.add_patch(patches.Circle(sens[side], 0.07, facecolor=SENSOR_COLOR, edgecolor="0.1", zorder=5))
        light = (x0 + 1.5, 1.5)
        ax.add_patch(patches.Circle(light, 0.2, facecolor=LIGHT_COLOR, edgecolor="#b38f00", zorder=5))
        ax.text(light[0] + 0.3, light[1], "light", ha="left", va="center", fontsize=9)
        # lateral: the nearer (left) sensor speeds the left wheel -> turns right, away from the light;
        # contralateral: it speeds the right wheel -> turns left, towards the light.
        turn = -1 if kind == "lateral" else 1
        end = (x0 + 1.5, turn * 1.1) if kind == "lateral" else (light[0] - 0.15, light[1] - 0.25)
        ax.add_patch(patches.FancyArrowPatch((x0 + 0.6, 0.0), end, connectionstyle=f"arc3,rad={0.35 * turn}",
                                             arrowstyle="-|>", mutation_scale=12, color="#8c8c8c", lw=1.5,
                                             ls="--", zorder=2))  # fmt: skip
        label = "lateral\n(turns away)" if kind == "lateral" else "contralateral\n(turns towards)"
        ax.text(x0, -0.75, label, ha="center", va="top", fontsize=9)
    ax.set_xlim(-0.7, 5.6)
    ax.set_ylim(-1.6, 2.0)
    ax.set_aspect("equal")
    ax.axis("off")


# ---------------------------------------------------------------------------------------------
# Trajectories and distributions


def trajectory_panel(ax: Axes, trs: Sequence[ReferenceTrajectory], design: tuple, r: float, radius: float,
                     title: str, near: float | None = None) -> None:  # fmt: skip
    """The four environments' paths with the light at the origin; starts drawn as small robots."""
    lim = r + 1.6
    for k, (tr, ang) in enumerate(zip(trs, ENV_ANGLES_DEG, strict=True)):
        col = ENV_COLORS[k]
        ax.plot(tr.path[:, 0], tr.path[:, 1], color=col, lw=1.1, label=f"light at {ang}°", zorder=2)
        robot(ax, design[0], design[1], xy=(tr.path[0, 0], tr.path[0, 1]), heading=0.0, scale=0.55,
              sensor_labels=False, lw=0.8, zorder=4)  # fmt: skip
        if math.isfinite(tr.first_time):
            i = int(np.searchsorted(tr.t, tr.first_time))
            i = min(i, len(tr.t) - 1)
            ax.plot(tr.path[i, 0], tr.path[i, 1], marker="o", ms=4, mfc="white", mec=col, zorder=6)
        end = tr.path[-1]
        if abs(end[0]) < lim and abs(end[1]) < lim:
            ax.plot(end[0], end[1], marker="x", ms=5, color=col, zorder=6)
    ax.add_patch(patches.Circle((0, 0), radius, facecolor=LIGHT_COLOR, edgecolor="#b38f00", zorder=5))
    if near is not None:
        ax.add_patch(patches.Circle((0, 0), near, facecolor="none", edgecolor="0.5", ls=":", lw=1.0, zorder=1))
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_aspect("equal")
    ax.set_xlabel("x (light at the origin)")
    ax.set_ylabel("y")
    ax.set_title(title, fontsize=10)
    ax.grid(True, lw=0.3, alpha=0.5)


def trajectory_legend(fig: Figure, near: float | None) -> None:
    from matplotlib.lines import Line2D

    h = [Line2D([], [], color=c, lw=1.5, label=f"light at {a}°") for c, a in zip(ENV_COLORS, ENV_ANGLES_DEG,
                                                                                   strict=True)]  # fmt: skip
    h += [Line2D([], [], ls="", marker="o", mfc="white", mec="0.2", label="first success"),
          Line2D([], [], ls="", marker="x", color="0.2", label="position at T"),
          patches.Patch(facecolor=LIGHT_COLOR, edgecolor="#b38f00", label="light (success radius)")]  # fmt: skip
    if near is not None:
        h.append(Line2D([], [], ls=":", color="0.5", label=f"'near' radius {near:g}"))
    fig.legend(handles=h, loc="lower center", ncol=len(h), fontsize=9, frameon=False)


def distribution(ax: Axes, values: np.ndarray, metric: str, title: str,
                 marks: Sequence[tuple[str, float, str]] = (), note: str | None = None) -> None:  # fmt: skip
    """Histogram of a metric over designs (log count axis), with marked designs."""
    v = np.asarray(values, dtype=np.float64)
    hi = max(float(v.max()) if v.size else 0.0, 1e-9)
    bins = np.linspace(0.0, hi * 1.02, 31)
    ax.hist(v, bins=bins, color="#5b7fb0", edgecolor="white", lw=0.5)
    ax.set_yscale("log")
    ax.set_ylim(0.7, None)
    ax.set_xlabel(metric)
    ax.set_ylabel("designs (log scale)")
    for (label, x, ls), col in zip(marks, ("#d62728", "#ff7f0e", "#2ca02c", "#9467bd"), strict=False):
        ax.axvline(x, color=col, ls=ls, lw=1.5, label=f"{label}: {x:.4g}")
    if marks:
        ax.legend(fontsize=8, loc="upper right")
    ax.set_title(title, fontsize=10)
    if note:
        ax.text(0.98, 0.55, note, transform=ax.transAxes, ha="right", va="center", fontsize=8,
                color="0.3", bbox={"facecolor": "white", "edgecolor": "0.7", "boxstyle": "round"})  # fmt: skip


def new_figure(size: tuple[float, float]) -> Figure:
    return plt.figure(figsize=size, dpi=150)
