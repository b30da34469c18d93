"""Learner runs of the paper's comparison (setups a-e) and their statistics.

Per setup, learner (and step size for the evolution strategies), protocol, budget and seed one
run. Joint runs are made once at the largest budget: a joint run's asks do not depend on its
budget (the last generation of CMA-ES is cut short, never reordered), so its first generalist
within a smaller budget ``B`` is the full run's when that comes at ``<= B`` evaluations, exactly.
Sequential runs are made per budget (``cycles`` x 4 phases of ``B / cycles`` evaluations: the
same learner trajectories as a joint run of ``B`` evaluations).

Evaluations to the first generalist are in joint-evaluation units (4 trajectories; a sequential
evaluation is one trajectory, so its count is divided by 4) and censored at the budget: runs that
reach none count as censored at ``B``, never dropped. With one censoring time for all runs the
Kaplan-Meier estimate is the empirical one, and its restricted mean is ``mean(min(T, B))``.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from morphlearn import provenance
from morphlearn.coopt.setups import Setup, SetupEvaluator, paper_setups
from morphlearn.learners import algorithms, protocols
from morphlearn.settings import CooptSettings
from morphlearn.theory import TheoryParams

#: Columns of the per-run table.
RUN_COLUMNS = (
    "setup",
    "learner",
    "sigma0",
    "protocol",
    "budget",
    "seed",
    "reached",
    "evals_to_generalist",
    "final_generalist",
    "forget_events",
    "forget_opportunities",
    "x",
)


def best_design(metrics_csv: str | Path) -> dict[str, Any]:
    """The best two-weight designs of a theory metrics table: top by M_L and top by M_CF (ties:
    the lowest design index, so one of each mirror pair). The table is checked against its record
    first (custody: the one its metrics rule wrote, or a bundle's as its manifest lists it)."""
    provenance.check_derived(metrics_csv)
    m = pd.read_csv(metrics_csv)
    cols = ["l1x", "l1y", "l2x", "l2y"]
    out = {}
    for key in ("M_L", "M_CF"):
        r = m.sort_values([key, "design"], ascending=[False, True], kind="stable").iloc[0]
        out[key] = {
            "design": int(r.design),
            "coords": tuple(float(r[c]) for c in cols),
            "M_L": float(r.M_L),
            "M_CF": float(r.M_CF),
        }
    return out


def variants(s: CooptSettings) -> list[tuple[str, float]]:
    """(learner, step size): random search once (it has no step), each ES at every step size."""
    return [(lr, sg) for lr in s.learners for sg in (s.sigmas if lr != "random" else (math.nan,))]


def run_rng(s: CooptSettings, setup: int, learner: str, sigma: float, protocol: str, budget: int, k: int):
    """A run's generator: a function of the base seed and the run's identity only."""
    sg = 0 if math.isnan(sigma) else round(sigma * 10_000)
    ident = [s.seed, 27, setup, algorithms.NAMES.index(learner), sg, protocols.PROTOCOLS.index(protocol), budget, k]
    return np.random.default_rng(ident)


def plan(s: CooptSettings) -> list[tuple[str, int]]:
    """(protocol, budget) of the runs: joint once at the largest budget, sequential at each."""
    top = max(s.budgets)
    return [(pr, b) for pr in s.protocols for b in ((top,) if pr == "joint" else s.budgets)]


def run_setup(
    s: CooptSettings,
    setup: Setup,
    index: int,
    params: TheoryParams,
    only: list[tuple[str, float]] | None = None,
    runs_of: list[tuple[str, int]] | None = None,
) -> pd.DataFrame:
    """Every run of one setup (or of the variants ``only`` and the (protocol, budget) pairs
    ``runs_of``: a run does not depend on what is batched beside it, so any split of the work
    gives the same rows), batched in one driver; one row per run (RUN_COLUMNS)."""
    keys, runs = [], []
    for lr, sg in only if only is not None else variants(s):
        sigma = 0.5 if math.isnan(sg) else sg
        for pr, b in runs_of if runs_of is not None else plan(s):
            for k in range(s.seeds):
                rng = run_rng(s, index, lr, sg, pr, b, k)
                learner = algorithms.make(lr, rng, sigma, setup.dim)
                if pr == "joint":
                    g = protocols.joint(learner, b)
                else:
                    g = protocols.sequential(learner, b // s.cycles, s.cycles)
                keys.append((lr, sg, pr, b, k))
                runs.append((0, g))
    results = protocols.drive(SetupEvaluator(setup, params), runs)  # type: ignore[arg-type]
    rows = []
    for (lr, sg, pr, b, k), r in zip(keys, results, strict=True):
        ev = r.evals_to_generalist if pr == "joint" else r.evals_to_generalist / protocols.N_ENV
        x = " ".join(f"{v:.6f}" for v in r.incumbent)
        rows.append((setup.name, lr, sg, pr, b, k, r.reached, ev, r.final_generalist, *_forget(r), x))
    return pd.DataFrame(rows, columns=list(RUN_COLUMNS))


def _forget(r: protocols.RunResult) -> tuple[int, int]:
    return r.forget_events, r.forget_opportunities


def run_all(s: CooptSettings, params: TheoryParams, best: tuple[float, float, float, float]) -> pd.DataFrame:
    setups = {x.name: (i, x) for i, x in enumerate(paper_setups(best))}
    return pd.concat([run_setup(s, setups[n][1], setups[n][0], params) for n in s.setups], ignore_index=True)


def wilson(k: int, n: int, z: float = 1.959964) -> tuple[float, float]:
    """Wilson score 95 % interval of a binomial proportion."""
    if n == 0:
        return math.nan, math.nan
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return max(0.0, c - h), min(1.0, c + h)


def _boot(x: np.ndarray, f, n_boot: int, rng: np.random.Generator) -> tuple[float, float]:
    if len(x) == 0:
        return math.nan, math.nan
    b = np.array([f(x[rng.integers(0, len(x), len(x))]) for _ in range(n_boot)])
    b = b[np.isfinite(b)]
    return (float(np.quantile(b, 0.025)), float(np.quantile(b, 0.975))) if b.size else (math.nan, math.nan)


def _pooled_rate(a: np.ndarray) -> float:
    """Forgetting events / opportunities over the seeds of ``a`` (rows: events, opportunities)."""
    return a[:, 0].sum() / a[:, 1].sum() if a[:, 1].sum() else math.nan


def summarise(runs: pd.DataFrame, s: CooptSettings) -> pd.DataFrame:
    """Per setup, learner, step, protocol and budget: P(generalist within the budget) with its
    Wilson interval; evaluations to the first generalist censored at the budget (restricted mean
    with a bootstrap interval; Kaplan-Meier median, NaN when fewer than half reach one); in the
    sequential protocol the pooled forgetting rate with a bootstrap interval over seeds."""
    rng = np.random.default_rng([s.seed, 27, 1])
    rows = []
    key = ["setup", "learner", "sigma0", "protocol"]
    for (st, lr, sg, pr), g in runs.groupby(key, sort=True, dropna=False):
        for b in s.budgets:
            gb = g[g.budget == (max(s.budgets) if pr == "joint" else b)]
            t = gb.evals_to_generalist.to_numpy(dtype=np.float64)
            hit = np.isfinite(t) & (t <= b)
            n, k = len(t), int(hit.sum())
            if n == 0:  # not run (a partial run of the stage's jobs)
                continue
            tc = np.where(hit, t, b)
            lo, hi = wilson(k, n)
            rm_lo, rm_hi = _boot(tc, np.mean, s.bootstrap, rng)
            row = {
                "setup": st,
                "learner": lr,
                "sigma0": sg,
                "protocol": pr,
                "budget": b,
                "runs": n,
                "p_generalist": k / n if n else math.nan,
                "p_lo": lo,
                "p_hi": hi,
                "evals_restricted_mean": float(tc.mean()) if n else math.nan,
                "evals_rm_lo": rm_lo,
                "evals_rm_hi": rm_hi,
                "evals_km_median": float(np.quantile(np.where(hit, t, np.inf), 0.5, method="inverted_cdf"))
                if 2 * k >= n and n
                else math.nan,
            }
            if pr == "sequential":
                ev, op = gb.forget_events.to_numpy(), gb.forget_opportunities.to_numpy()
                pair = np.stack([ev, op], axis=1).astype(np.float64)
                rate = float(ev.sum() / op.sum()) if op.sum() else math.nan
                f_lo, f_hi = _boot(pair, _pooled_rate, s.bootstrap, rng)
                row |= {
                    "forgetting_rate": rate,
                    "forget_lo": f_lo,
                    "forget_hi": f_hi,
                    "p_final_generalist": float(gb.final_generalist.mean()),
                }
            rows.append(row)
    return pd.DataFrame(rows)
