"""Panel letters and the empty, annotated panel for results a run does not have."""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes

MISSING_TEXT = "empirical results not in this run"


def missing(ax: Axes, text: str = MISSING_TEXT, title: str | None = None) -> None:
    """An empty, annotated panel for results this run does not have."""
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_facecolor("#f4f4f4")
    for s in ax.spines.values():
        s.set_linestyle("--")
        s.set_edgecolor("0.6")
    ax.text(0.5, 0.5, text, transform=ax.transAxes, ha="center", va="center", style="italic", color="0.35", wrap=True)
    if title:
        ax.set_title(title)


def panel_letter(ax: Axes, letter: str, level_with_title: bool = True) -> None:
    """The panel's letter left of the axes, its top level with the top of the axes' title (its
    first line: a centred multi-line title wider than the axes runs into a letter level with its
    last line, Fig. 6 D); above the axes when there is no title. Placed at draw time: the title may
    be set after the letter. ``level_with_title=False``: the earlier place, just above the axes'
    corner, which a figure of one-line titles keeps (the scenario set's comparison, whose committed
    bundle has no re-render path yet)."""
    if not level_with_title:
        ax.text(-0.08, 1.02, letter, transform=ax.transAxes, ha="right", va="bottom", fontsize=14, fontweight="bold")
        return
    ax.annotate(
        letter,
        xy=(-0.08, 1.0),
        xycoords=("axes fraction", ax.title),  # x on the axes, y on the title's box
        ha="right",
        va="top",
        fontsize=14,
        fontweight="bold",
        annotation_clip=False,
    )


def fit_to_data(ax: Axes, x: np.ndarray, y: np.ndarray, low: float = 0.04, high: float = 0.06) -> None:
    """Axes of non-negative values fitted to them: from ``-low`` to ``1 + high`` times each
    maximum (a maximum of 0: a small range round 0), no headroom for a legend (place it outside)."""
    for lim, v in ((ax.set_xlim, x), (ax.set_ylim, y)):
        top = float(np.nanmax(np.asarray(v, dtype=np.float64))) or 1e-3
        lim(-low * top, (1 + high) * top)
