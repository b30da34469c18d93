"""Robot sketches (top view): the theoretical 1 x 1 body, its sensors, wiring and heading."""

from __future__ import annotations

import math
from collections.abc import Sequence

from matplotlib import patches
from matplotlib.axes import Axes

SENSOR_COLOR = "#d62728"
LIGHT_COLOR = "#ffcc00"


def robot(
    ax: Axes,
    l1: Sequence[float],
    l2: Sequence[float],
    *,
    xy: tuple[float, float] = (0.0, 0.0),
    heading: float = 0.0,
    scale: float = 1.0,
    wiring: bool = False,
    castor: bool = False,
    sensor_labels: bool = True,
    lw: float = 1.5,
    zorder: int = 3,
) -> None:
    """Top view of the robot: 1 x 1 body, wheels at its sides, sensors (red) at ``l1``, ``l2``.

    ``wiring`` draws the contralateral synapses (sensor 1 -> right wheel, sensor 2 -> left).
    """
    c, s = math.cos(heading), math.sin(heading)

    def tf(p: Sequence[float]) -> tuple[float, float]:
        return xy[0] + scale * (c * p[0] - s * p[1]), xy[1] + scale * (s * p[0] + c * p[1])

    body = [tf(p) for p in ((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5))]
    ax.add_patch(patches.Polygon(body, closed=True, facecolor="#e9e9e9", edgecolor="0.15", lw=lw, zorder=zorder))
    for side in (1, -1):  # wheels: left (+y) and right (-y), set back slightly
        w = [tf(p) for p in ((-0.25, side * 0.52), (0.2, side * 0.52), (0.2, side * 0.64), (-0.25, side * 0.64))]
        ax.add_patch(patches.Polygon(w, closed=True, facecolor="0.1", edgecolor="0.1", zorder=zorder))
    if castor:
        ax.add_patch(patches.Circle(tf((0.42, 0.0)), 0.06 * scale, facecolor="0.6", edgecolor="0.3", zorder=zorder + 1))
    tip, base = tf((0.35, 0.0)), tf((-0.15, 0.0))
    ax.annotate("", xy=tip, xytext=base, zorder=zorder + 1, arrowprops={"arrowstyle": "-|>", "color": "0.45", "lw": lw})
    if wiring:
        for p, wheel, name in ((l1, (0.0, -0.55), "$w_1$"), (l2, (0.0, 0.55), "$w_2$")):
            a, b = tf(p), tf(wheel)
            ax.plot([a[0], b[0]], [a[1], b[1]], color="#555555", lw=lw * 0.8, ls="--", zorder=zorder + 1)
            mid = tf((0.2 * p[0] + 0.8 * wheel[0] - 0.13, 0.2 * p[1] + 0.8 * wheel[1]))
            ax.text(*mid, name, ha="center", va="center", zorder=zorder + 2)
    for k, p in enumerate((l1, l2), start=1):
        q = tf(p)
        ax.add_patch(patches.Circle(q, 0.07 * scale, facecolor=SENSOR_COLOR, edgecolor="0.1", zorder=zorder + 3))
        if sensor_labels:
            off = tf((p[0] + 0.16, p[1] + (0.14 if p[1] >= 0 else -0.14)))
            ax.text(*off, str(k), ha="center", va="center", color=SENSOR_COLOR, fontweight="bold", zorder=zorder + 3)


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
        ax.annotate("", xy=p, xytext=(0, 0), zorder=8, arrowprops={"arrowstyle": "-|>", "color": "#1f4e9a", "lw": 1.8})
        ax.text(
            0.55 * p[0] - 0.05,
            0.55 * p[1] + (0.1 if p[1] >= 0 else -0.1),
            f"$\\ell_{k}$",
            color="#1f4e9a",
            fontsize=13,
            ha="center",
            va="center",
            zorder=9,
        )
    ax.plot([0], [0], "k+", ms=8, zorder=9)
    body_axes(ax, 0.9)
    ax.set_xticks([-0.5, 0, 0.5])
    ax.set_yticks([-0.5, 0, 0.5])
    ax.set_xlim(-0.9, 1.4)  # room on the right for the heading label
    ax.text(0.62, 0.0, "heading\n(α = 0)", va="center", color="0.35")


def braitenberg_wiring(ax: Axes) -> None:
    """Fig. 1A: lateral vs contralateral excitatory connections and where they steer."""
    for x0, kind in ((0.0, "lateral"), (3.3, "contralateral")):
        ax.add_patch(
            patches.Rectangle((x0 - 0.5, -0.5), 1.0, 1.0, facecolor="#e9e9e9", edgecolor="0.15", lw=1.5, zorder=3)
        )
        for side in (1, -1):
            ax.add_patch(
                patches.Rectangle(
                    (x0 - 0.3, side * 0.52 - (0.12 if side < 0 else 0)), 0.45, 0.12, facecolor="0.1", zorder=3
                )
            )
        sens = {1: (x0 + 0.5, 0.35), -1: (x0 + 0.5, -0.35)}  # left (+y), right (-y)
        wheels = {1: (x0 - 0.08, 0.46), -1: (x0 - 0.08, -0.46)}
        for side in (1, -1):
            target = wheels[side] if kind == "lateral" else wheels[-side]
            ax.annotate(
                "",
                xy=target,
                xytext=sens[side],
                zorder=4,
                arrowprops={"arrowstyle": "-|>", "color": "#555555", "lw": 1.3, "shrinkA": 4, "shrinkB": 2},
            )
            ax.add_patch(patches.Circle(sens[side], 0.07, facecolor=SENSOR_COLOR, edgecolor="0.1", zorder=5))
        light = (x0 + 1.5, 1.5)
        ax.add_patch(patches.Circle(light, 0.2, facecolor=LIGHT_COLOR, edgecolor="#b38f00", zorder=5))
        ax.text(light[0] + 0.3, light[1], "light", ha="left", va="center")
        # lateral: the nearer (left) sensor speeds the left wheel -> turns right, away from the light;
        # contralateral: it speeds the right wheel -> turns left, towards the light.
        turn = -1 if kind == "lateral" else 1
        end = (x0 + 1.5, turn * 1.1) if kind == "lateral" else (light[0] - 0.15, light[1] - 0.25)
        ax.add_patch(
            patches.FancyArrowPatch(
                (x0 + 0.6, 0.0),
                end,
                connectionstyle=f"arc3,rad={0.35 * turn}",
                arrowstyle="-|>",
                mutation_scale=12,
                color="#8c8c8c",
                lw=1.5,
                ls="--",
                zorder=2,
            )
        )
        label = "lateral\n(turns away)" if kind == "lateral" else "contralateral\n(turns towards)"
        ax.text(x0, -0.75, label, ha="center", va="top")
    ax.set_xlim(-0.7, 5.6)
    ax.set_ylim(-1.6, 2.0)
    ax.set_aspect("equal")
    ax.axis("off")
