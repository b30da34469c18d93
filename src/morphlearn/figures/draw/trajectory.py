"""Theory trajectories in the four environments, the light at the origin."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from matplotlib import patches
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from morphlearn.figures import data
from morphlearn.figures.draw.panel import panel_letter
from morphlearn.figures.draw.sketch import LIGHT_COLOR, robot
from morphlearn.grid import ENV_ANGLES_DEG
from morphlearn.theory.reference import ReferenceTrajectory

ENV_COLORS = ("#1f77b4", "#2ca02c", "#d62728", "#9467bd")
#: Dots every this many time units along each path up to its first success: controllers whose
#: paths look alike in space (Fig. 5) differ in how fast they run them.
TIME_DOTS = 50.0


def time_dots(tr: ReferenceTrajectory, every: float = TIME_DOTS) -> np.ndarray:
    """Positions (k, 2) at t = every, 2 every, ... up to the first success (to the horizon if
    none): how fast a path is run."""
    end = tr.first_time if math.isfinite(tr.first_time) else float(tr.t[-1])
    ts = np.arange(every, end, every)
    return np.column_stack([np.interp(ts, tr.t, tr.path[:, 0]), np.interp(ts, tr.t, tr.path[:, 1])])


def first_times(trs: Sequence[ReferenceTrajectory]) -> str:
    """The first-success times of the four environments, as a range ("t = 150-161"; "none")."""
    ts = [t.first_time for t in trs if math.isfinite(t.first_time)]
    if not ts:
        return "no success"
    lo, hi = min(ts), max(ts)
    return f"t = {lo:.0f}" if round(lo) == round(hi) else f"t = {lo:.0f}-{hi:.0f}"


def design_title(fig: Figure, model: str, which: str, design: data.Design) -> None:
    """The figure's heading: the model and the design every panel draws."""
    fig.suptitle(f"{model}, {which}: {data.design_label(*design)}", fontsize=12)


def trajectory_panel(
    ax: Axes,
    trs: Sequence[ReferenceTrajectory],
    design: tuple,
    r: float,
    radius: float,
    title: str,
    near: float | None = None,
) -> None:
    """The four environments' paths with the light at the origin; starts drawn as small robots."""
    lim = r + 1.6
    for k, (tr, ang) in enumerate(zip(trs, ENV_ANGLES_DEG, strict=True)):
        col = ENV_COLORS[k]
        ax.plot(tr.path[:, 0], tr.path[:, 1], color=col, lw=1.1, label=f"light at {ang}°", zorder=2)
        dots = time_dots(tr)
        ax.plot(dots[:, 0], dots[:, 1], ls="", marker="o", ms=2.6, color=col, zorder=3)
        robot(
            ax,
            design[0],
            design[1],
            xy=(tr.path[0, 0], tr.path[0, 1]),
            heading=0.0,
            scale=0.55,
            sensor_labels=False,
            lw=0.8,
            zorder=4,
        )
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
    ax.set_title(title)
    ax.grid(True, lw=0.3, alpha=0.5)


def trajectory_legend(fig: Figure, near: float | None) -> None:
    h = [
        Line2D([], [], color=c, lw=1.5, label=f"light at {a}°") for c, a in zip(ENV_COLORS, ENV_ANGLES_DEG, strict=True)
    ]
    h += [
        Line2D([], [], ls="", marker="o", ms=2.6, color="0.2", label=f"every {TIME_DOTS:g} time units"),
        Line2D([], [], ls="", marker="o", mfc="white", mec="0.2", label="first success"),
        Line2D([], [], ls="", marker="x", color="0.2", label="position at T"),
        patches.Patch(facecolor=LIGHT_COLOR, edgecolor="#b38f00", label="light (success radius)"),
    ]
    if near is not None:
        h.append(Line2D([], [], ls=":", color="0.5", label=f"'near' radius {near:g}"))
    # "outside": constrained layout keeps room for it below the panels.
    # two rows under three panels; three under two (a narrower figure must not clip the legend)
    fig.legend(handles=h, loc="outside lower center", ncol=5 if fig.get_figwidth() >= 11 else 3, frameon=False)


def controller_panels(
    axes: Sequence[Axes],
    design: data.Design,
    chosen: Sequence[data.Controller],
    settings: data.TheorySettings,
    near: float,
    letters: str = "ABC",
) -> list[str]:
    """One trajectory panel per chosen controller (Figs. 4, 5); returns one caption line per panel."""
    lines = []
    for ax, c, letter in zip(axes, chosen, letters, strict=False):
        trs = data.trajectories(design, (c.w1, c.w2), settings)
        ok = data.stays_near(trs, near)
        far = [data.max_distance_after_success(t) for t in trs]
        solved = sum(math.isfinite(t.first_time) for t in trs)
        status = "generalist" if c.generalist else f"solves {c.overlap} of 4"
        target = "" if c.target is None else f"paper: ({c.target[0]:g}, {c.target[1]:g}); "
        trajectory_panel(
            ax,
            trs,
            design,
            settings.r,
            settings.radius,
            f"$(w_1, w_2) = ({c.w1:.3g}, {c.w2:.3g})$, {status}\n"
            f"{target}{'stays near' if ok else 'does not stay near'}\nfirst success at {first_times(trs)}",
            near=near,
        )
        panel_letter(ax, letter)
        far_s = ", ".join("none" if not math.isfinite(x) else f"{x:.2f}" for x in far)
        first_s = ", ".join("none" if not math.isfinite(t.first_time) else f"{t.first_time:.0f}" for t in trs)
        lines.append(
            f"- **{letter}:** {c.describe()}; on this grid it solves {c.overlap} of 4 environments "
            f"(reference integration: {solved} of 4); first success, per environment 45/135/225/315°, at "
            f"t = {first_s}; largest distance from the light after the first "
            f"success, per environment: {far_s}; "
            f"{'stays' if ok else 'does not stay'} near the source."
        )
    return lines
