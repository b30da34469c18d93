"""Rows of the coopt stage (beyond the paper, issue 27): co-optimising the body against a
four-synapse controller, the question the paper closes on."""

from __future__ import annotations

import pandas as pd

from morphlearn.figures.reproduction.claims import BEYOND_COOPT
from morphlearn.figures.reproduction.inputs import TableInputs
from morphlearn.figures.reproduction.stages.learners import LEARNER_LABELS

#: Setups of the coopt stage (coopt.setups.paper_setups; repeated here: this module stays light).
COOPT_SETUPS = {
    "a": "canonical body, 2 weights",
    "b": "canonical body, 4 weights",
    "c": "co-optimised body, 2 weights",
    "d": "co-optimised body, 4 weights",
    "e": "best two-weight design, 2 weights",
}


def coopt_rows(summary: pd.DataFrame, landscape: pd.DataFrame, sigma: float, config_name: str) -> list[dict[str, str]]:
    """Rows beyond the paper from the coopt stage (coopt/summary.csv, coopt/landscape.csv): per
    setup and protocol, P(generalist within the largest budget) [95 % Wilson] of random search and
    of the evolution strategies at step ``sigma``; the canonical design's four-weight M_L and M_CF
    beside its two-weight values on the same grid."""
    rows = []

    def add(key: str, quantity: str, value: str, note: str) -> None:
        rows.append(
            {
                "key": key,
                "quantity": quantity,
                "paper": BEYOND_COOPT,
                "ours": value,
                "config": config_name,
                "note": note,
            }
        )

    budget = int(summary.budget.max())
    keep = summary[(summary.budget == budget) & (summary.sigma0.isna() | (summary.sigma0 == sigma))]
    for protocol in ("joint", "sequential"):
        for setup, label in COOPT_SETUPS.items():
            g = keep[(keep.protocol == protocol) & (keep.setup == setup)]
            if not len(g):
                continue
            cells, runs = [], set()
            for learner in LEARNER_LABELS:
                for r in g[g.learner == learner].itertuples():
                    name = LEARNER_LABELS[learner] + ("" if pd.isna(r.sigma0) else f" (step {r.sigma0:g})")
                    cells.append(f"{name} {r.p_generalist:.2f} [{r.p_lo:.2f}, {r.p_hi:.2f}]")
                    runs.add(int(r.runs))
            add(
                f"coopt_{setup}_{protocol}_P_generalist",
                f"coopt ({setup}) {label}, {protocol} training: P(generalist within {budget} evaluations)",
                "; ".join(cells),
                f"{'/'.join(str(n) for n in sorted(runs))} runs per learner, 95 % Wilson intervals; coopt/summary.csv",
            )
    canon = landscape[landscape["name"] == "canonical"]
    if len(canon):
        r = canon.iloc[0]
        m = int(r.m)
        for metric in ("M_L", "M_CF"):
            add(
                f"coopt_canonical_{metric}_4w_vs_2w",
                f"coopt, canonical design: {metric} with four weights vs two",
                f"{r[metric + '_4w']:.4g} (4 weights) vs {r[metric + '_2w']:.4g} (2 weights)",
                f"{m} points per weight in [-1, 1] ({m}^4 controllers; two weights: the slice u1 = u2 = 0, "
                f"{m} x {m}); at the bundle's 121 x 121: {r[metric + '_bundle']:.4g}; coopt/landscape.csv",
            )
    return rows


def rows(t: TableInputs) -> list[dict[str, str]]:
    return [] if t.coopt is None else coopt_rows(*t.coopt, t.config_name)
