"""Theory against physics, design by design: does the theory's ranking of designs carry over?

:func:`joined` pairs the rows of two metrics tables (``<model>/metrics.csv``): by design index on
one grid (the empirical model may hold a subset), by sensor coordinates when one is a coarser grid
whose positions are the other's (a survey of the 5-point grid beside a 9-point theory run). Rank
agreement is Spearman's rho with a percentile bootstrap interval over designs
(:func:`spearman_ci`, scipy.stats.bootstrap); the many designs with M = 0 are ties,
which Spearman's rho handles by mid-ranks.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
from scipy import stats

from morphlearn import config, metrics

COORDS = ["l1x", "l1y", "l2x", "l2y"]
#: The default names of the two tables (their columns' suffixes): the comparison's two sides, the
#: theory and a physics model, whichever engine that is (not the registry's first two names, which
#: named an ODE survey's columns "empirical", pybullet's key).
PAIR: tuple[str, str] = ("theory", "physics")


#: Fewest bootstrap resamples of an interval: the config's ``learners.bootstrap`` minimum (one rule).
MIN_RESAMPLES: int = config.schema()["properties"]["learners"]["properties"]["bootstrap"]["minimum"]
#: Fewest designs a rank agreement is computed over: with n designs and no association, a perfect
#: agreement (rho = +-1) comes by chance with probability 2 / n!, under 5 % from n = 5 (4 designs: 8 %;
#: 3: 33 %), so fewer cannot tell agreement from chance, and their bootstrap interval is degenerate.
MIN_DESIGNS = 5


def read_table(path: str | Path) -> pd.DataFrame:
    """A metrics table (``<model>/metrics.csv``) checked for what :func:`joined` and the ranking
    read: the columns, integer design indices once each, finite metrics in [0, 1]. Raises
    ValueError with one line naming the file, the column and what is allowed."""
    cols = ["design", *COORDS, "generalists", *metrics.METRICS]
    what = "allowed: a metrics.csv written by the workflow (e.g. results/survey/theory/metrics.csv)"
    if not Path(path).is_file():
        raise ValueError(f"{path}: no such file; {what}")
    try:
        t = pd.read_csv(path, comment="#")
    except (ValueError, UnicodeDecodeError, pd.errors.ParserError) as e:  # EmptyDataError is a ValueError
        raise ValueError(f"{path}: not a CSV table ({type(e).__name__}); {what}") from None
    missing = [c for c in cols if c not in t.columns]
    if missing:
        raise ValueError(f"{path}: not a metrics table (no column{'s' if len(missing) > 1 else ''} {missing}); {what}")
    for c in cols:
        v = pd.to_numeric(t[c], errors="coerce").to_numpy(dtype=float)
        bad = ~np.isfinite(v)
        if c in metrics.METRICS:
            bad |= (v < 0) | (v > 1)
        elif c == "design" or c == "generalists":
            bad |= (v < 0) | (v != np.round(v))
        if bad.any():
            i = int(np.argmax(bad))
            allowed = "a number in [0, 1]" if c in metrics.METRICS else "a finite number"
            if c in ("design", "generalists"):
                allowed = "an integer >= 0"
            raise ValueError(f"{path}: data row {i + 1}: {c} = {str(t[c].iloc[i])!r}; allowed: {allowed}")
        t[c] = v.astype(np.int64) if c in ("design", "generalists") else v
    dup = t.design.duplicated()
    if dup.any():
        raise ValueError(f"{path}: design {int(t.design[dup].iloc[0])} appears twice; allowed: each design once")
    # beside its merged store (a run's or a bundle's): the same check of its meaning as check-bundle's
    from morphlearn.bundles.check import meaning_problems

    problems = meaning_problems(Path(path), t)
    if problems:
        raise ValueError(f"{path}: {problems[0]}; {what}")
    return t


def joined(a: pd.DataFrame, b: pd.DataFrame, names: tuple[str, str] = PAIR) -> pd.DataFrame:
    """One row per design in both tables: coordinates, ``<metric>_<name>`` of each table (e.g.
    ``M_L_theory``, ``M_L_physics``) and each table's rank by each metric (1 = best; ties broken
    as :func:`metrics.rank_designs`). Rows are paired by design index on one grid, by sensor
    coordinates across two (a survey of the 5-point grid beside a 9-point run pairs with the
    designs it shares; ``design`` is then the first table's index); no design in common is an
    error."""
    ms = list(metrics.METRICS)
    cols = ["design", *COORDS, "generalists", *ms]
    x, y = names
    both = a[cols].merge(b[cols], on="design", suffixes=(f"_{x}", f"_{y}"))
    if not all(np.allclose(both[f"{c}_{x}"], both[f"{c}_{y}"]) for c in COORDS):
        both = _joined_by_coordinates(a[cols], b[cols], (x, y))  # another grid: its shared designs
    else:
        both = both.rename(columns={f"{c}_{x}": c for c in COORDS}).drop(columns=[f"{c}_{y}" for c in COORDS])
    for model in names:
        sub = both[["design", *COORDS, *(f"{m}_{model}" for m in ms)]].rename(columns={f"{m}_{model}": m for m in ms})
        for by in ms:
            order = metrics.rank_designs(sub, by).design.to_numpy()
            rank = pd.Series(np.arange(1, len(order) + 1), index=order)
            both[f"rank_{by}_{model}"] = both.design.map(rank).to_numpy()
    return both.sort_values("design").reset_index(drop=True)


def _joined_by_coordinates(a: pd.DataFrame, b: pd.DataFrame, names: tuple[str, str]) -> pd.DataFrame:
    """Rows of two tables on different grids paired by their exact sensor coordinates (a survey of
    the 5-point grid beside a 9-point run: the positions coincide); ``design`` is the first's."""
    key = [f"_{c}" for c in COORDS]
    ka, kb = (t.assign(**{f"_{c}": t[c].round(9) for c in COORDS}) for t in (a, b))
    if ka.duplicated(key).any() or kb.duplicated(key).any():
        raise ValueError("design indices disagree on the sensor coordinates: the two tables use different grids")
    both = ka.merge(kb.drop(columns=["design", *COORDS]), on=key, suffixes=tuple(f"_{n}" for n in names))
    if both.empty:
        raise ValueError("no design in common: the two tables use different grids")
    return both.drop(columns=key)


@dataclass(frozen=True)
class RankAgreement:
    metric: str
    n: int
    rho: float
    low: float  # bootstrap percentile interval
    high: float
    level: float

    def text(self) -> str:
        if self.n < MIN_DESIGNS:
            some = f"{self.n} design{'s' if self.n != 1 else ''}"
            why = f"a rank correlation needs {MIN_DESIGNS} to tell agreement from chance"
            return f"undefined (only {some} in both; {why})"
        if np.isnan(self.rho):
            return f"undefined (one model gives every one of the {self.n} designs the same value)"
        interval = f"{self.level:.0%} bootstrap interval, {self.n} designs"
        return f"{self.rho:.3f} [{self.low:.3f}, {self.high:.3f}] ({interval})"


def spearman_ci(
    x: np.ndarray, y: np.ndarray, metric: str, n_resamples: int = 2000, level: float = 0.95, seed: int = 0
) -> RankAgreement:
    """Spearman's rho of paired per-design values with a percentile bootstrap interval over designs
    (seeded: the same inputs give the same interval; resamples in which a side is constant, rho
    undefined, are left out of the interval)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    if len(x) < MIN_DESIGNS:  # e.g. a physics run of a few refined designs: no ranks to compare
        return RankAgreement(metric, len(x), np.nan, np.nan, np.nan, level)
    rho = float(stats.spearmanr(x, y).statistic)

    def stat(a: np.ndarray, b: np.ndarray) -> float:
        return stats.spearmanr(a, b).statistic

    # a resample with a constant column gives NaN (scipy warns of a degenerate interval): dropped below
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", stats.DegenerateDataWarning)
        res = stats.bootstrap(
            (x, y),
            stat,
            paired=True,
            vectorized=False,
            n_resamples=n_resamples,
            confidence_level=level,
            method="percentile",
            random_state=np.random.default_rng(seed),
        )
    lo, hi = res.confidence_interval
    dist = res.bootstrap_distribution
    if np.isnan(dist).any():  # scipy's interval is then NaN: take it over the defined resamples
        finite = dist[np.isfinite(dist)]
        a = (1 - level) / 2
        lo, hi = stats.quantile(finite, [a, 1 - a]) if finite.size else (np.nan, np.nan)
    return RankAgreement(metric, len(x), rho, float(lo), float(hi), level)


def agreement(both: pd.DataFrame, n_resamples: int = 2000, names: tuple[str, str] = PAIR) -> dict[str, RankAgreement]:
    """Spearman of the two tables of :func:`joined` for each metric, over their designs."""
    x, y = names
    return {m: spearman_ci(both[f"{m}_{x}"], both[f"{m}_{y}"], m, n_resamples) for m in metrics.METRICS}


def top_shared(both: pd.DataFrame, by: str, top: int, names: tuple[str, str] = PAIR) -> int:
    """How many designs of :func:`joined` are in both tables' top ``top`` by ``by``, each table's
    rank taken over the designs both hold. Counted on the joined rows (one design each, whatever
    grid each table indexes), never on the two tables' own design indices: across two grids those
    number different designs."""
    x, y = names
    return int(((both[f"rank_{by}_{x}"] <= top) & (both[f"rank_{by}_{y}"] <= top)).sum())


def sensor_use(table: pd.DataFrame, top: int, by: str = "M_L") -> pd.DataFrame:
    """How often each sensor position is used by the ``top`` designs by ``by`` (both sensors
    counted): columns x, y, count; positions never used have count 0."""
    best = metrics.rank_designs(table, by).head(top)
    pts = np.concatenate([best[["l1x", "l1y"]].to_numpy(), best[["l2x", "l2y"]].to_numpy()])
    axis = np.unique(table[["l1x", "l1y", "l2x", "l2y"]].to_numpy())
    xs, ys = np.meshgrid(axis, axis, indexing="ij")
    counts = [
        int(np.sum(np.isclose(pts[:, 0], x) & np.isclose(pts[:, 1], y)))
        for x, y in zip(xs.ravel(), ys.ravel(), strict=True)
    ]
    return pd.DataFrame({"x": xs.ravel(), "y": ys.ravel(), "count": counts})
