"""The free search over the thresholds a stored simulation can answer: M_L of the canonical, the
best and the paper's best design at every (horizon, radius) derivable without re-simulating."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from morphlearn import grid as gridmod
from morphlearn import metrics
from morphlearn.scenarios.comparison import PAPER_BEST_DESIGN, label_of, text_distance
from morphlearn.scenarios.plan import answers

#: The free threshold scan over every stored simulation: horizons in steps of this, up to the
#: simulated one, and these radii (each where the simulation answers it).
SCAN_HORIZON_STEP = 50.0
SCAN_RADII = (0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0)


def derivable(
    sim_horizon: float, sim_radius: float, horizons: Iterable[float], radii: Iterable[float]
) -> list[tuple[float, float]]:
    """The (horizon, radius) pairs of the given lists (plus the simulation's own) that a stored
    simulation answers without re-simulating."""
    pairs = {(float(t), float(r)) for t in [*horizons, sim_horizon] for r in [*radii, sim_radius]}
    return sorted(p for p in pairs if answers((sim_horizon, sim_radius), p))


def generalist_fraction(first_time: np.ndarray, min_dist: np.ndarray, th: metrics.Thresholds) -> np.ndarray:
    """M_L per design from arrays of shape (designs, 4, m, m) (metrics.success, metrics.overlap)."""
    o = metrics.overlap(metrics.success(first_time, min_dist, th))
    return (o == 4).mean(axis=(-2, -1))


def threshold_scan(merged: str | Path, pairs: Sequence[tuple[float, float]] | None = None) -> pd.DataFrame:
    """Canonical M_L, best M_L and the paper's best design's M_L at every (horizon, radius) of
    ``pairs`` that the merged store answers (its simulated horizon and radius from its attrs);
    by default every pair of the free scan (SCAN_HORIZON_STEP, SCAN_RADII) it answers."""
    from morphlearn import store

    ds = store.open_merged(merged)
    sci = store.science_of(ds)["theory"]
    ts, rs = float(sci["horizon"]), float(sci["success_radius"])
    if pairs is None:
        horizons = np.arange(SCAN_HORIZON_STEP, ts + SCAN_HORIZON_STEP / 2, SCAN_HORIZON_STEP)
        pairs = derivable(ts, rs, horizons, SCAN_RADII)
    ft, md = [], []
    for _, arrays in store.read_blocks(ds):
        ft.append(arrays["first_time"])
        md.append(arrays["min_dist"])
    first_time, min_dist = np.concatenate(ft), np.concatenate(md)
    coords = pd.DataFrame({c: ds[c].values for c in ("l1x", "l1y", "l2x", "l2y")})
    canon = metrics.find_row(coords, gridmod.canonical_design()).name
    best = metrics.find_row(coords, PAPER_BEST_DESIGN)
    rows = []
    for t, r in pairs:
        if not answers((ts, rs), (t, r)):
            allowed = derivable(ts, rs, [t], [r]) or "none"
            raise ValueError(
                f"(horizon {t}, radius {r}) is not answered by the simulation at "
                f"(horizon {ts}, radius {rs}); allowed: {allowed}"
            )
        ml = generalist_fraction(first_time, min_dist, metrics.Thresholds(t, r, ts, rs))
        rows.append(
            {
                "r": float(sci["r"]),
                "horizon": t,
                "radius": r,
                "canonical_M_L": float(ml[canon]),
                "best_M_L": float(ml.max()),
                "best_design": label_of(coords.iloc[int(ml.argmax())]),
                "paper_best_M_L": float(ml[best.name]) if best is not None else math.nan,
                "text_distance": text_distance(float(ml[canon]), float(ml.max())),
            }
        )
    return pd.DataFrame(rows)
