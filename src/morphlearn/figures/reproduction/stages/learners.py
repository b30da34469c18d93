"""Rows of the learner stage (beyond the paper, issue 15): do M_L and M_CF predict learning?"""

from __future__ import annotations

import pandas as pd

from morphlearn.figures.reproduction.claims import BEYOND
from morphlearn.figures.reproduction.inputs import TableInputs

LEARNER_LABELS = {"random": "random search", "one_plus_one": "(1+1)-ES", "cmaes": "CMA-ES"}


def _ci(r: pd.Series, key: str) -> str:
    if key not in r or pd.isna(r[key]):
        return "n/a"
    return f"{r[key]:+.3f} [{r[key + '_lo']:+.3f}, {r[key + '_hi']:+.3f}]"


def learner_rows(corr: pd.DataFrame, config_name: str) -> list[dict[str, str]]:
    """Rows beyond the paper: per learner and protocol, Spearman rho (95 % bootstrap interval)
    of M_L with the probability of reaching a generalist, of M_CF with 1 - forgetting rate
    (sequential), and the advantage over random search."""
    rows = []
    for _, r in corr.iterrows():
        name = f"{LEARNER_LABELS.get(r.learner, r.learner)}, {r.protocol} training"
        k = f"learners_{r.learner}_{r.protocol}"
        items = [(f"{k}_rho_M_L", f"{name}: Spearman rho(M_L, P(generalist))", _ci(r, "rho_ML_success"))]
        if r.protocol == "sequential":
            items.append(
                (f"{k}_rho_M_CF", f"{name}: Spearman rho(M_CF, 1 - forgetting rate)", _ci(r, "rho_MCF_retention"))
            )
        if r.learner != "random":
            items.append(
                (f"{k}_advantage", f"{name}: P(generalist) minus random search's", _ci(r, "advantage_vs_random"))
            )
        for key, quantity, value in items:
            note = f"{int(r.designs)} designs; learners/correlations.csv"
            rows.append(
                {"key": key, "quantity": quantity, "paper": BEYOND, "ours": value, "config": config_name, "note": note}
            )
    return rows


def rows(t: TableInputs) -> list[dict[str, str]]:
    return [] if t.learners is None else learner_rows(t.learners, t.config_name)
