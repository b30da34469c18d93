"""Weight-grid matrices: the overlap O (0-4) with its colour map, and two environments' success
sets overlapped. Matrices are indexed [i_w1, i_w2] and drawn with w1 on the x axis."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib import colors, patches
from matplotlib.axes import Axes
from matplotlib.colorbar import Colorbar
from matplotlib.figure import Figure
from matplotlib.image import AxesImage

#: Overlap O = 0..4 (environments solved); 4 (generalists) is cyan as in the paper.
OVERLAP_COLORS = ("#1b2a6b", "#7b3294", "#d6604d", "#fdb863", "#00e5ff")
OVERLAP_LABELS = ("0: none", "1", "2", "3", "4: all (generalist)")


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


#: At most this many generalists in a panel are each ringed by a marker: one cell of a 121 x 121
#: grid is under a point at print size, and "generalists in cyan" must show them (Fig. 6 D: the
#: canonical design's one generalist in physics, at (1, 1) in a corner).
FEW_GENERALISTS = 20


def mark_generalists(ax: Axes, overlap: np.ndarray, weights: np.ndarray) -> int:
    """Ring each generalist (O = 4) when there are at most :data:`FEW_GENERALISTS`; returns how
    many were ringed (0 when there are more: they show as cyan areas)."""
    i1, i2 = np.nonzero(np.asarray(overlap) == 4)
    if not 0 < len(i1) <= FEW_GENERALISTS:
        return 0
    w = np.asarray(weights, dtype=np.float64)
    ax.plot(
        w[i1],
        w[i2],
        ls="",
        marker="o",
        ms=9,
        mfc=OVERLAP_COLORS[4],
        mec="white",
        mew=1.4,
        clip_on=False,  # a generalist in a corner (w = (1, 1)) is drawn whole
        zorder=5,
    )
    return len(i1)


def overlap_image(ax: Axes, overlap: np.ndarray, weights: np.ndarray, title: str) -> AxesImage:
    """The overlap matrix O (m, m) indexed [i_w1, i_w2]; a few generalists each ringed
    (:func:`mark_generalists`)."""
    cmap, norm = overlap_cmap()
    im = ax.imshow(
        np.asarray(overlap).T, origin="lower", extent=_extent(weights), cmap=cmap, norm=norm, interpolation="nearest"
    )
    ringed = mark_generalists(ax, overlap, weights)
    _weight_axes(ax)
    ax.set_title(title, pad=11 if ringed else None)  # clear of a ring on the top edge
    return im


def overlap_colorbar(fig: Figure, im: AxesImage, axes: Sequence[Axes] | Axes) -> Colorbar:
    cb = fig.colorbar(im, ax=axes, ticks=range(5), shrink=0.7, pad=0.02)
    cb.ax.set_yticklabels(OVERLAP_LABELS)
    cb.set_label("environments solved, O")
    return cb


#: Two environments' success overlapped: neither, A only, B only, both.
PAIR_COLORS = ("#f2f2f2", "#4c72b0", "#e8a33d", "#00b3a4")


def success_image(ax: Axes, success: np.ndarray, weights: np.ndarray, title: str, color: str) -> AxesImage:
    """One environment's binary success matrix (m, m) indexed [i_w1, i_w2]: ``color`` where solved."""
    cmap = colors.ListedColormap([PAIR_COLORS[0], color])
    im = ax.imshow(
        np.asarray(success, int).T,
        origin="lower",
        extent=_extent(weights),
        cmap=cmap,
        norm=colors.BoundaryNorm([-0.5, 0.5, 1.5], 2),
        interpolation="nearest",
    )
    _weight_axes(ax)
    ax.set_title(title)
    return im


def success_pair(
    ax: Axes, s_a: np.ndarray, s_b: np.ndarray, weights: np.ndarray, names: tuple[str, str], title: str
) -> list[patches.Patch]:
    """Two environments' binary success matrices overlapped: neither, A only, B only, both.

    Returns the legend handles (with the count of controllers in each category) for the caller
    to place."""
    cat = np.asarray(s_a, int) + 2 * np.asarray(s_b, int)
    labels = ("neither", f"{names[0]} only", f"{names[1]} only", f"both: {names[0]} ∩ {names[1]}")
    ax.imshow(
        cat.T,
        origin="lower",
        extent=_extent(weights),
        cmap=colors.ListedColormap(PAIR_COLORS),
        norm=colors.BoundaryNorm(np.arange(-0.5, 4.0, 1.0), 4),
        interpolation="nearest",
    )
    _weight_axes(ax)
    ax.set_title(title)
    return [
        patches.Patch(facecolor=c, edgecolor="0.4", label=f"{lab} ({int((cat == k).sum())})")
        for k, (c, lab) in enumerate(zip(PAIR_COLORS, labels, strict=True))
    ]
