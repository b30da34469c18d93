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


def r_scan(
    first_time: np.ndarray, g: gridmod.DesignGrid, rs: Iterable[float], horizons: Iterable[float], top: int = 20
):
    """The text quantities at other light distances ``rs``, on the designs that carry them at the
    sweep's own r: the canonical and the paper's design, the ``top`` designs by M_L and the ``top``
    designs at M_CF = 1 with the highest M_L (at the sweep's longest horizon). Designs outside that
    set are not re-run, so a row's best values are those of the set (a lower bound of all designs').
    Each r is a sweep of those designs at the longest horizon, read at every horizon."""
    from morphlearn.theory import TheoryParams, evaluate

    hs = sorted(float(h) for h in horizons)
    gen, solv = counts(first_time, hs[-1])
    cf1 = np.flatnonzero((gen > 0) & (gen == solv))
    keep = {g.index_of(*gridmod.canonical_design()), g.index_of(*gridmod.PAPER_BEST_DESIGN)}
    keep |= set(np.argsort(-gen, kind="stable")[:top].tolist()) | set(
        cf1[np.argsort(-gen[cf1], kind="stable")][:top].tolist()
    )
    designs = np.array(sorted(keep), dtype=np.int64)
    m = first_time.shape[-1]
    w = gridmod.weights(m)
    rows = []
    for r in rs:
        p = TheoryParams(r=float(r), horizon=hs[-1], max_steps=40_000)
        res = evaluate(g.coords(designs), w, p)
        ft = np.full((g.size, *first_time.shape[1:]), np.nan)  # designs not re-run never succeed
        ft[designs] = np.stack([d.first_time for d in res])
        rows += [asdict(text_values(ft, g, h, r)) | {"designs_run": len(designs)} for h in hs]
    return pd.DataFrame(rows)


def main(argv: list[str] | None = None) -> int:
    """``python -m morphlearn.theory.text_sweep BUNDLE OUT.csv --r 3.5 4 4.5``: the horizon scan
    (500 to the sweep's horizon, steps of 50) at the bundle's own r over all designs, then
    :func:`r_scan` at each r given."""
    import argparse

    ap = argparse.ArgumentParser(description="the paper's text quantities over horizons and light distances")
    ap.add_argument("bundle")
    ap.add_argument("out")
    ap.add_argument("--r", type=float, nargs="*", default=[])
    a = ap.parse_args(argv)
    ft, _, g, science = load_first_times(Path(a.bundle) / "theory" / "merged.zarr")
    top_h = float(science["theory"]["horizon"])
    hs = [float(h) for h in range(500, int(top_h) + 1, 50)]
    own = horizon_scan(ft, g, hs, float(science["theory"]["r"])).assign(designs_run=g.size)
    parts = [own] + ([r_scan(ft, g, a.r, hs)] if a.r else [])
    pd.concat(parts).to_csv(a.out, index=False, float_format="%.6g")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
