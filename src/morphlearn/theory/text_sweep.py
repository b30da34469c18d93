"""The paper's text values read from a coarse theory sweep (results/theory-text).

The paper's text gives the canonical design M_L 0.049 and M_CF 0.24, its best design 0.286 and
0.636, and "several" designs at M_CF = 1 whose highest M_L is 0.206. Read as fractions these are
counts on an 11 x 11 weight grid (6/121, 6/25, 25/121, 35/55), not on the 121 x 121 grid its
captions count on. This module computes the same quantities from a sweep's first-success times at
any horizon up to the simulated one, so one sweep at the longest horizon answers every shorter one.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from morphlearn import grid as gridmod
from morphlearn import store

#: The paper's text values (Theoretical results), by the names of :class:`TextValues`' fields.
PAPER_TEXT: dict[str, float] = {
    "canonical_ml": 0.049,
    "canonical_mcf": 0.24,
    "paper_best_ml": 0.286,
    "paper_best_mcf": 0.636,
    "cf1_best_ml": 0.206,
}


@dataclass(frozen=True)
class TextValues:
    """What the paper's text values are measured against, at one horizon and light distance."""

    r: float
    horizon: float
    canonical_generalists: int
    canonical_solvers: int  # controllers solving at least one environment (M_CF's denominator)
    canonical_ml: float
    canonical_mcf: float
    paper_best_generalists: int
    paper_best_solvers: int
    paper_best_ml: float
    paper_best_mcf: float
    best_design: int  # the highest M_L (lowest index among ties)
    best_ml: float
    best_mcf: float
    cf1_designs: int  # designs with M_CF = 1 (every controller that solves one solves all four)
    cf1_best_ml: float  # their highest M_L (NaN: none)
    max_mcf: float


def load_first_times(merged: str | Path) -> tuple[np.ndarray, np.ndarray, gridmod.DesignGrid, dict]:
    """(first-success times (design, env, w1, w2), weights, design grid, science) of a merged
    store holding every design of its grid, each chunk checked against its digest."""
    ds = store.open_merged(merged)
    science = store.science_of(ds)
    n = int(science["grid"]["positions_per_axis"])
    designs = ds["design"].values
    if not np.array_equal(designs, np.arange(n**4)):
        raise ValueError(f"{merged}: holds {len(designs)} of the {n**4} designs of its grid; need every design")
    ft = np.stack([store.read_design(ds, i)["first_time"] for i in range(len(designs))])
    return ft, np.asarray(ds["w1"].values), gridmod.DesignGrid(n), science


def counts(first_time: np.ndarray, horizon: float) -> tuple[np.ndarray, np.ndarray]:
    """(generalists, solvers) per design at ``horizon``: controllers solving all four
    environments, and at least one."""
    with np.errstate(invalid="ignore"):
        o = (first_time <= horizon).sum(axis=1)  # NaN (no success) compares False
    return (o == 4).sum(axis=(1, 2)), (o >= 1).sum(axis=(1, 2))


def text_values(first_time: np.ndarray, g: gridmod.DesignGrid, horizon: float, r: float) -> TextValues:
    """The text's quantities at ``horizon`` (the sweep's light distance ``r`` recorded with them)."""
    gen, solv = counts(first_time, horizon)
    cells = first_time.shape[-1] * first_time.shape[-2]
    m_l = gen / cells
    with np.errstate(invalid="ignore", divide="ignore"):
        m_cf = np.where(solv > 0, gen / np.maximum(solv, 1), 0.0)
    can = g.index_of(*gridmod.canonical_design())
    pb = g.index_of(*gridmod.PAPER_BEST_DESIGN)
    best = int(np.argmax(m_l))
    cf1 = np.flatnonzero((gen > 0) & (gen == solv))
    return TextValues(
        r=float(r),
        horizon=float(horizon),
        canonical_generalists=int(gen[can]),
        canonical_solvers=int(solv[can]),
        canonical_ml=float(m_l[can]),
        canonical_mcf=float(m_cf[can]),
        paper_best_generalists=int(gen[pb]),
        paper_best_solvers=int(solv[pb]),
        paper_best_ml=float(m_l[pb]),
        paper_best_mcf=float(m_cf[pb]),
        best_design=best,
        best_ml=float(m_l[best]),
        best_mcf=float(m_cf[best]),
        cf1_designs=int(cf1.size),
        cf1_best_ml=float(m_l[cf1].max()) if cf1.size else float("nan"),
        max_mcf=float(m_cf.max()),
    )


def horizon_scan(first_time: np.ndarray, g: gridmod.DesignGrid, horizons: Iterable[float], r: float) -> pd.DataFrame:
    """:func:`text_values` at each horizon, one row each."""
    return pd.DataFrame([asdict(text_values(first_time, g, h, r)) for h in horizons])
