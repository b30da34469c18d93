"""Panel letters and the empty, annotated panel for results a run does not have."""

from __future__ import annotations

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


def panel_letter(ax: Axes, letter: str) -> None:
    # left of the axes, clear of a centred multi-line title as wide as the axes (Fig. 6)
    ax.text(-0.08, 1.02, letter, transform=ax.transAxes, ha="right", va="bottom", fontsize=14, fontweight="bold")
