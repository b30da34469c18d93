"""Which designs to refine at the paper's 121 x 121 weights (issue 26): the candidates for "best".

The top designs by each metric of every survey given (surveys on a coarser design grid are
mapped onto the refinement grid by their coordinates), the canonical design, and the theory's
best designs; one design of each mirror pair (the run's ``include_mirrors`` adds the other, and
``mirror_derive`` derives it). Each candidate keeps the reasons it was chosen.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from morphlearn import grid as gridmod
from morphlearn import metrics


def _index(g: gridmod.DesignGrid, row: pd.Series) -> int:
    return g.index_of((float(row.l1x), float(row.l1y)), (float(row.l2x), float(row.l2y)))


def candidates(
    surveys: Mapping[str, pd.DataFrame], theory: pd.DataFrame | None, top: int, g: gridmod.DesignGrid
) -> dict[int, list[str]]:
    """Representative design index on ``g`` -> why it is a candidate, in the order first chosen:
    the canonical design, then per survey (name -> metrics table) its ``top`` designs by each
    metric, then the theory's best design by each metric."""
    out: dict[int, list[str]] = {}

    def add(design: int, why: str) -> None:
        rep = int(min(design, int(g.mirror(design))))
        out.setdefault(rep, []).append(why)

    add(g.index_of(*gridmod.canonical_design()), "canonical")
    for name, table in surveys.items():
        for by in metrics.METRICS:
            for rank, (_, row) in enumerate(metrics.rank_designs(table, by).head(top).iterrows(), 1):
                add(_index(g, row), f"{name} #{rank} by {by}")
    if theory is not None:
        for by in metrics.METRICS:
            add(_index(g, metrics.rank_designs(theory, by).iloc[0]), f"theory best by {by}")
    return out


def as_yaml(found: Mapping[int, list[str]], g: gridmod.DesignGrid) -> str:
    """The candidates as a ``designs:`` list for a physics section (one per line, reasons as comments)."""
    lines = ["designs: # one of each mirror pair; include_mirrors adds the other"]
    for d, why in found.items():
        c = np.asarray(g.coords(d)).reshape(2, 2)
        pair = f"[[{c[0, 0]:g}, {c[0, 1]:g}], [{c[1, 0]:g}, {c[1, 1]:g}]]"
        lines.append(f"  - {pair} # {d} (mirror {int(g.mirror(d))}): {'; '.join(why)}")
    return "\n".join(lines) + "\n"
