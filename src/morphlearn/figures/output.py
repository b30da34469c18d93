"""Style, readability check and the three files of every figure (PNG, PDF, caption)."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
from matplotlib.figure import Figure
from matplotlib.text import Text

#: Pixels per inch of the PNG; the HTML report shows a figure at most about this wide.
DPI = 150
MAX_WIDTH_IN = 12.0
MIN_FONT_PT = 9.0


def use_style(path: str | Path) -> None:
    """Apply the shared style file (notebooks/style.mplstyle) for every figure."""
    plt.style.use(str(path))


def readability_problems(fig: Figure, max_width: float = MAX_WIDTH_IN, min_pt: float = MIN_FONT_PT) -> list[str]:
    """Why ``fig`` would be hard to read when shown at report width: wider than ``max_width``
    inches (it is then scaled down) or any visible text smaller than ``min_pt`` points."""
    out = []
    w = fig.get_size_inches()[0]
    if w > max_width:
        out.append(f"figure is {w:g} in wide, more than {max_width:g}")
    small = {
        t.get_text()[:30]
        for t in fig.findobj(Text)
        if t.get_visible() and t.get_text().strip() and t.get_fontsize() < min_pt
    }
    out += [f"text {s!r} is smaller than {min_pt:g} pt" for s in sorted(small)]
    return out


def save(fig: Figure, caption_text: str, png: str | Path, pdf: str | Path, caption: str | Path) -> None:
    """Write the PNG (``DPI``), the PDF (no timestamp) and the caption; refuse unreadable figures."""
    problems = readability_problems(fig)
    if problems:
        raise ValueError("figure not readable at report size: " + "; ".join(problems))
    for p in (png, pdf, caption):
        Path(p).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(png, dpi=DPI, metadata={"Software": None})
    fig.savefig(pdf, metadata={"CreationDate": None, "ModDate": None, "Producer": None})
    Path(caption).write_text(caption_text)
