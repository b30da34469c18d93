"""A metric's distribution over designs (seaborn), with marked designs."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import seaborn as sns
from matplotlib.axes import Axes

#: Colours of the marked designs, in order (e.g. canonical, best).
MARK_COLORS = ("#d62728", "#2ca02c", "#ff7f0e", "#9467bd")


def distribution(
    ax: Axes,
    values: np.ndarray,
    metric: str,
    title: str,
    marks: Sequence[tuple[str, float, str]] = (),
    note: str | None = None,
    bins: int = 30,
) -> None:
    """Histogram of ``values`` (one per design) on a log count axis; ``marks`` are
    ``(label, value, linestyle)`` vertical lines, ``note`` a boxed remark (e.g. "subset")."""
    v = np.asarray(values, dtype=np.float64)
    hi = max(float(v.max()) if v.size else 0.0, 1e-9)
    # Log counts: most designs sit near 0 and the few good ones would be invisible on a linear axis.
    sns.histplot(
        x=v, bins=np.linspace(0.0, hi * 1.02, bins + 1), ax=ax, color="#5b7fb0", edgecolor="white", linewidth=0.5
    )
    ax.set_yscale("log", nonpositive="clip")  # seaborn's log_scale drops bars that start at 0
    ax.set_ylim(0.7, None)
    ax.set_xlabel(metric)
    ax.set_ylabel("designs (log scale)")
    for (label, x, ls), col in zip(marks, MARK_COLORS, strict=False):
        ax.axvline(x, color=col, ls=ls, lw=1.8, label=f"{label}: {x:.3g}")
    if marks:
        ax.legend(loc="upper right")
    ax.set_title(title)
    if note:
        ax.text(
            0.97,
            0.5,
            note,
            transform=ax.transAxes,
            ha="right",
            va="center",
            color="0.3",
            bbox={"facecolor": "white", "edgecolor": "0.7", "boxstyle": "round"},
        )
