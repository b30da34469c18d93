"""Success matrices and the paper's metrics, one implementation for both models.

Success is derived from the stored arrays: ``first_time <= horizon`` (first entry into the
simulated success radius), so any horizon up to the simulated one is free. A larger radius than
simulated is allowed at the simulated horizon (``min_dist <= radius``); a smaller radius or a
larger horizon needs a new simulation and is refused.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pandas as pd
import xarray as xr

from morphlearn.grid import ENV_ANGLES_DEG
from morphlearn.results import STATUS_FLAGGED

#: How metrics tables store floats (10 significant digits): a value read back equals the metric
#: formatted this way, exactly.
CSV_FLOAT_FORMAT = "%.10g"


@dataclass(frozen=True)
class Thresholds:
    horizon: float
    radius: float
    sim_horizon: float
    sim_radius: float

    def __post_init__(self) -> None:
        if not 0 < self.horizon <= self.sim_horizon:
            raise ValueError(f"horizon = {self.horizon} must be in (0, {self.sim_horizon}] (the simulated horizon)")
        if self.radius < self.sim_radius:
            raise ValueError(
                f"success radius = {self.radius} is below the simulated {self.sim_radius}: "
                "re-simulate with the smaller radius"
            )
        if self.radius > self.sim_radius and self.horizon != self.sim_horizon:
            raise ValueError(
                "a success radius larger than simulated is only known at the simulated horizon "
                f"({self.sim_horizon}); got horizon = {self.horizon}"
            )


def success(first_time: np.ndarray, min_dist: np.ndarray, th: Thresholds) -> np.ndarray:
    """Boolean success array of the same shape."""
    if th.radius > th.sim_radius:
        return np.asarray(min_dist) <= th.radius
    with np.errstate(invalid="ignore"):
        return np.asarray(first_time) <= th.horizon  # NaN compares False


def overlap(succ: np.ndarray) -> np.ndarray:
    """O = sum over environments; ``succ`` has shape (..., 4, m, m)."""
    return succ.sum(axis=-3, dtype=np.int16)


@dataclass(frozen=True)
class Counts:
    """What a design's metrics are computed from: its overlap matrix, counted."""

    cells: int  # controllers (m * m)
    generalists: int  # O == 4
    at_least_one: int  # O >= 1


@dataclass(frozen=True)
class Metric:
    """A per-design metric: its column in the metrics tables, how it is computed from the counts,
    how it is printed, and which way is better."""

    name: str
    of: Callable[[Counts], float]
    fmt: str = ".4f"
    higher_is_better: bool = True
    text: str = ""


#: The metrics, in column order. Every table, summary, ranking, comparison and caption loops over
#: this: adding a metric is one line here (its notebook figure, if any, is a figure's business).
METRICS: dict[str, Metric] = {
    "M_L": Metric("M_L", lambda c: c.generalists / c.cells, text="learnability: generalists / controllers"),
    "M_CF": Metric(
        "M_CF",
        lambda c: c.generalists / c.at_least_one if c.at_least_one else 0.0,
        text="forgetting resistance: generalists / controllers that succeed at least once",
    ),
}


@dataclass(frozen=True)
class DesignMetrics:
    per_env: list[int]
    generalists: int
    at_least_one: int
    values: dict[str, float]  # metric name -> value, for every metric of METRICS
    flagged: int

    def __getattr__(self, name: str) -> float:  # dm.M_L, dm.M_CF, ...: the registered metrics
        values = self.__dict__.get("values", {})
        if name in values:
            return values[name]
        raise AttributeError(name)

    def as_dict(self) -> dict:
        return {
            "per_env": self.per_env,
            "generalists": self.generalists,
            "at_least_one": self.at_least_one,
            **self.values,
            "flagged": self.flagged,
        }


def design_metrics(succ: np.ndarray, status: np.ndarray | None = None) -> DesignMetrics:
    """Metrics of one design from its (4, m, m) success array."""
    o = overlap(succ)
    c = Counts(cells=o.size, generalists=int((o == 4).sum()), at_least_one=int((o >= 1).sum()))
    return DesignMetrics(
        per_env=[int(x) for x in succ.sum(axis=(-2, -1))],
        generalists=c.generalists,
        at_least_one=c.at_least_one,
        values={name: m.of(c) for name, m in METRICS.items()},
        flagged=int(np.isin(status, STATUS_FLAGGED).sum()) if status is not None else 0,
    )


def metrics_table(ds: xr.Dataset, th: Thresholds, block: int = 64) -> pd.DataFrame:
    """One row per design of a merged dataset (opened with ``store.open_merged``), streamed in
    blocks of designs, each chunk verified against its digest. A subset store is refused: the
    metrics (and ranks) are of the whole sweep."""
    from morphlearn import store

    if "subset_of" in ds.attrs:
        raise store.IntegrityError(
            f"{ds.encoding.get('morphlearn_path', 'merged store')}: a subset of "
            f"{ds.attrs.get('subset_source_designs')} designs (subset_of {ds.attrs['subset_of'][:12]}...); "
            "metrics need the whole merged store"
        )
    rows = []
    model = ds.attrs.get("model", "")
    designs = ds["design"].values
    coords = {c: ds[c].values for c in ("l1x", "l1y", "l2x", "l2y")}
    for sl, arrays in store.read_blocks(ds, block):
        succ = success(arrays["first_time"], arrays["min_dist"], th)
        stt = arrays["status"]
        for i in range(succ.shape[0]):
            dm = design_metrics(succ[i], stt[i])
            j = sl.start + i
            row = {
                "model": model,
                "design": int(designs[j]),
                **{c: float(coords[c][j]) for c in ("l1x", "l1y", "l2x", "l2y")},
            }
            row.update({f"n_{ang}": c for ang, c in zip(ENV_ANGLES_DEG, dm.per_env, strict=True)})
            row.update(generalists=dm.generalists, at_least_one=dm.at_least_one, **dm.values, flagged=dm.flagged)
            rows.append(row)
    return pd.DataFrame(rows)


def rank_designs(table: pd.DataFrame, by: str) -> pd.DataFrame:
    """Sorted best first by ``by``; ties broken by the other metrics (in METRICS order), then by
    design index."""
    keys = [by, *(m for m in METRICS if m != by)]
    up = [not METRICS[k].higher_is_better for k in keys]
    return table.sort_values([*keys, "design"], ascending=[*up, True], kind="stable")


def best_designs(table: pd.DataFrame, by: str, n: int) -> list[int]:
    """The ``n`` best designs by ``by`` among those with a positive value (a design with M_L = 0 has
    no generalist: tied at 0 with most others at a coarse weight grid, it is not "best"); fewer
    than ``n`` where fewer are positive. Ties as :func:`rank_designs`."""
    ranked = rank_designs(table, by)
    return [int(d) for d in ranked.design[ranked[by] > 0].head(n)]


def find_row(table: pd.DataFrame, design: tuple[tuple[float, float], tuple[float, float]]) -> pd.Series | None:
    """The row of a design given by its sensor coordinates, or None if the table has none."""
    (a, b), (c, d) = design
    hit = table[(table.l1x == a) & (table.l1y == b) & (table.l2x == c) & (table.l2y == d)]
    return hit.iloc[0] if len(hit) else None


def rank_of(table: pd.DataFrame, row: pd.Series, by: str) -> int:
    """1 + the number of designs strictly better by ``by`` (ties share a rank)."""
    better = table[by] > row[by] if METRICS[by].higher_is_better else table[by] < row[by]
    return int(better.sum()) + 1
