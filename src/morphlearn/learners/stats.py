"""Per-design summaries of learner runs; rank correlations with bootstrap intervals."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pandas as pd
from scipy import stats as sps

from morphlearn.learners.protocols import RunResult

#: Columns of a per-design row (one per design x learner x protocol).
COLUMNS = (
    "design",
    "learner",
    "protocol",
    "seeds",
    "p_generalist",
    "evals_to_generalist_mean",
    "evals_to_generalist_median",
    "p_final_generalist",
    "forget_events",
    "forget_opportunities",
    "forgetting_rate",
)


def summarise_runs(design: int, learner: str, protocol: str, runs: Sequence[RunResult]) -> dict:
    """Probability of reaching a generalist within the budget, evaluations to the first one (over
    the runs that reached one; NaN if none did), probability of ending on one, and the pooled
    forgetting rate (events / opportunities over all seeds; NaN without opportunities)."""
    reached = np.array([r.reached for r in runs])
    evals = np.array([r.evals_to_generalist for r in runs if r.reached], dtype=np.float64)
    ev = sum(r.forget_events for r in runs)
    op = sum(r.forget_opportunities for r in runs)
    return {
        "design": int(design),
        "learner": learner,
        "protocol": protocol,
        "seeds": len(runs),
        "p_generalist": float(reached.mean()),
        "evals_to_generalist_mean": float(evals.mean()) if evals.size else math.nan,
        "evals_to_generalist_median": float(np.median(evals)) if evals.size else math.nan,
        "p_final_generalist": float(np.mean([r.final_generalist for r in runs])),
        "forget_events": int(ev),
        "forget_opportunities": int(op),
        "forgetting_rate": ev / op if op else math.nan,
    }


def spearman_ci(
    x: np.ndarray, y: np.ndarray, *, n_boot: int, seed: int, level: float = 0.95
) -> tuple[float, float, float, int]:
    """Spearman's rho of the finite pairs, with a percentile bootstrap interval over designs
    (resampled with replacement; resamples where either side is constant are dropped, as rho is
    undefined there). Returns (rho, low, high, n)."""
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    keep = np.isfinite(x) & np.isfinite(y)
    x, y = x[keep], y[keep]
    n = len(x)
    if n < 3 or np.ptp(x) == 0 or np.ptp(y) == 0:
        return math.nan, math.nan, math.nan, n
    rho = float(sps.spearmanr(x, y).statistic)
    rng = np.random.default_rng(seed)
    idx = rng.integers(0, n, size=(n_boot, n))
    xb, yb = x[idx], y[idx]
    ok = (np.ptp(xb, axis=1) > 0) & (np.ptp(yb, axis=1) > 0)
    rx = sps.rankdata(xb[ok], axis=1)
    ry = sps.rankdata(yb[ok], axis=1)
    rx -= rx.mean(axis=1, keepdims=True)
    ry -= ry.mean(axis=1, keepdims=True)
    boot = (rx * ry).sum(1) / np.sqrt((rx * rx).sum(1) * (ry * ry).sum(1))
    a = (1.0 - level) / 2.0
    return rho, float(np.quantile(boot, a)), float(np.quantile(boot, 1.0 - a)), n


def mean_diff_ci(
    a: np.ndarray, b: np.ndarray, *, n_boot: int, seed: int, level: float = 0.95
) -> tuple[float, float, float]:
    """Mean of the paired differences ``a - b`` over designs, with a percentile bootstrap interval."""
    d = np.asarray(a, dtype=np.float64) - np.asarray(b, dtype=np.float64)
    d = d[np.isfinite(d)]
    if not d.size:
        return math.nan, math.nan, math.nan
    rng = np.random.default_rng(seed)
    boot = d[rng.integers(0, d.size, size=(n_boot, d.size))].mean(axis=1)
    q = (1.0 - level) / 2.0
    return float(d.mean()), float(np.quantile(boot, q)), float(np.quantile(boot, 1.0 - q))


def correlations(runs: pd.DataFrame, metrics: pd.DataFrame, *, n_boot: int, seed: int) -> pd.DataFrame:
    """Per learner and protocol: Spearman (M_L, P(generalist)); in the sequential protocol also
    (M_CF, 1 - forgetting rate); and the advantage over random search in the same protocol
    (mean paired difference of P(generalist) over designs). ``metrics`` is the theory table
    (columns design, M_L, M_CF); designs are those of ``runs``."""
    m = metrics.set_index("design")
    rows = []
    for (learner, protocol), g in runs.groupby(["learner", "protocol"], sort=True):
        g = g.set_index("design").sort_index()
        ml, mcf = m.loc[g.index, "M_L"].to_numpy(), m.loc[g.index, "M_CF"].to_numpy()
        rho, lo, hi, n = spearman_ci(ml, g.p_generalist.to_numpy(), n_boot=n_boot, seed=seed)
        row = {
            "learner": learner,
            "protocol": protocol,
            "designs": len(g),
            "mean_p_generalist": float(g.p_generalist.mean()),
            "rho_ML_success": rho,
            "rho_ML_success_lo": lo,
            "rho_ML_success_hi": hi,
        }
        # The same among designs with M_L > 0 only: designs without a generalist on the grid are
        # one large tie at M_L = 0 (and rarely learnable), which alone can make rho large.
        pos = ml > 0
        rho, lo, hi, n = spearman_ci(ml[pos], g.p_generalist.to_numpy()[pos], n_boot=n_boot, seed=seed)
        row |= {
            "rho_ML_success_pos": rho,
            "rho_ML_success_pos_lo": lo,
            "rho_ML_success_pos_hi": hi,
            "designs_ML_pos": n,
        }
        if protocol == "sequential":
            retention = 1.0 - g.forgetting_rate.to_numpy()
            rho, lo, hi, n = spearman_ci(mcf, retention, n_boot=n_boot, seed=seed)
            row |= {
                "rho_MCF_retention": rho,
                "rho_MCF_retention_lo": lo,
                "rho_MCF_retention_hi": hi,
                "designs_with_forgetting_data": n,
                "mean_forgetting_rate": float(g.forgetting_rate.mean()),
            }
            pos = mcf > 0
            rho, lo, hi, n = spearman_ci(mcf[pos], retention[pos], n_boot=n_boot, seed=seed)
            row |= {
                "rho_MCF_retention_pos": rho,
                "rho_MCF_retention_pos_lo": lo,
                "rho_MCF_retention_pos_hi": hi,
                "designs_MCF_pos": n,
            }
        base = runs[(runs.learner == "random") & (runs.protocol == protocol)].set_index("design")
        if len(base) and learner != "random":
            common = g.index.intersection(base.index)
            d, lo, hi = mean_diff_ci(
                g.loc[common, "p_generalist"], base.loc[common, "p_generalist"], n_boot=n_boot, seed=seed
            )
            row |= {"advantage_vs_random": d, "advantage_vs_random_lo": lo, "advantage_vs_random_hi": hi}
        rows.append(row)
    return pd.DataFrame(rows)
