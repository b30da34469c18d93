"""Every scenario against the base: the canonical and the paper's best design, the best designs,
top-N overlap and Kendall's tau; and how far a result is from the paper's text values of M_L."""

from __future__ import annotations

import math
from typing import Any

import pandas as pd

from morphlearn import grid as gridmod
from morphlearn import metrics
from morphlearn.scenarios.definition import BASE

PAPER_BEST_DESIGN = gridmod.PAPER_BEST_DESIGN
#: The paper's text values of M_L (canonical, best design); its captions give 57 and 2255 / 14641.
TEXT_CANONICAL_M_L = 0.049
TEXT_BEST_M_L = 0.286


def label_of(r: pd.Series) -> str:
    return f"({r.l1x:g},{r.l1y:g}),({r.l2x:g},{r.l2y:g})"


def compare(tables: dict[str, pd.DataFrame], top: int = 10, base: str = BASE) -> pd.DataFrame:
    """One row per scenario, against the base scenario: the canonical design's and the paper's
    best design's M_L / M_CF and rank, the best design by each metric, the overlap of the top
    ``top`` designs with the base's (ranked as the summary ranks), and Kendall's tau-b of the
    designs' M_L (and M_CF) with the base's. Tables are per-design metrics (metrics.csv)."""
    from scipy.stats import kendalltau

    ref = tables[base].set_index("design").sort_index()
    rows = []
    for name, t in tables.items():
        t = t.set_index("design").sort_index()
        if not t.index.equals(ref.index):
            raise ValueError(f"scenario {name!r}: its designs differ from {base!r}'s; allowed: the same grid")
        tr = t.reset_index()
        row: dict[str, Any] = {"scenario": name}
        for label, design in (("canonical", gridmod.canonical_design()), ("paper_best", PAPER_BEST_DESIGN)):
            d = metrics.find_row(tr, design)
            for m in ("M_L", "M_CF"):
                row[f"{label}_{m}"] = float(d[m]) if d is not None else math.nan
                row[f"{label}_rank_{m}"] = metrics.rank_of(tr, d, m) if d is not None else None
        for m in ("M_L", "M_CF"):
            ranked = metrics.rank_designs(tr, m)
            best = ranked.iloc[0]
            row[f"best_{m}_design"] = label_of(best)
            row[f"best_{m}"] = float(best[m])
            mine = set(ranked.design.head(top))
            theirs = set(metrics.rank_designs(ref.reset_index(), m).design.head(top))
            row[f"top{top}_overlap_{m}"] = len(mine & theirs)
            row[f"paper_best_in_top{top}_{m}"] = bool(metrics.find_row(ranked.head(top), PAPER_BEST_DESIGN) is not None)
            tau = kendalltau(t[m].to_numpy(), ref[m].to_numpy()).statistic
            row[f"tau_{m}"] = float(tau)
        row["text_distance"] = text_distance(row["canonical_M_L"], row["best_M_L"])
        rows.append(row)
    return pd.DataFrame(rows)


def text_distance(canonical_ml: float, best_ml: float) -> float:
    """How far (canonical M_L, best M_L) is from the paper's text values (0.049, 0.286): the
    Euclidean norm of the two relative errors (0 = both met exactly)."""
    return math.hypot(canonical_ml / TEXT_CANONICAL_M_L - 1, best_ml / TEXT_BEST_M_L - 1)
