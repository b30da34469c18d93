"""What a run's summary says of its metrics tables: each model's canonical design (with its rank)
and its best designs by each registered metric, as JSON and Markdown. The summary rule writes it
(:mod:`morphlearn.analysis.summary`); check-bundle recomputes it from a bundle's tables."""

from __future__ import annotations

import math
from typing import Any

import pandas as pd

from morphlearn import grid as gridmod
from morphlearn import metrics, models


def _row(r: pd.Series) -> dict[str, Any]:
    return {
        "l1": [r.l1x, r.l1y],
        "l2": [r.l2x, r.l2y],
        "generalists": int(r.generalists),
        "at_least_one": int(r.at_least_one),
        **{m: float(r[m]) for m in metrics.METRICS},
        "flagged": int(r.flagged),
    }


def summarise(table: pd.DataFrame, top: int) -> dict[str, Any]:
    """Canonical design (with its rank by each metric), best designs by each metric."""
    c = metrics.find_row(table, gridmod.canonical_design())
    out: dict[str, Any] = {"designs": len(table), "controllers": None}
    if c is not None:
        out["canonical"] = _row(c) | {f"rank_{m}": metrics.rank_of(table, c, m) for m in metrics.METRICS}
    for m in metrics.METRICS:
        out[f"top_{m}"] = [_row(r) for _, r in metrics.rank_designs(table, m).head(top).iterrows()]
    out["M_CF_eq_1"] = int((table.M_CF == 1.0).sum())  # the paper's "best M_L among M_CF = 1"
    best_cf1 = table[table.M_CF == 1.0]
    out["best_M_L_among_M_CF_eq_1"] = float(best_cf1.M_L.max()) if len(best_cf1) else None
    return out


def _fmt(d: dict[str, Any]) -> str:
    vals = " | ".join(f"{d[m]:{spec.fmt}}" for m, spec in metrics.METRICS.items())
    return (
        f"| ({d['l1'][0]:g}, {d['l1'][1]:g}) | ({d['l2'][0]:g}, {d['l2'][1]:g}) | "
        f"{d['generalists']} | {d['at_least_one']} | {vals} | {d['flagged']} |"
    )


def grid_line(summary: dict[str, Any]) -> str:
    """The grid the models ran on: ``grid.weights`` is the theory's; a physics model at another
    weight grid (the reduced model at 121 x 121 beside a 41 x 41 theory) is named with its own
    (read from its controller count, so a summary recomputed from a bundle says the same)."""
    n, w = summary["positions_per_axis"], summary["weights"]
    weights = {
        m: math.isqrt(summary[m]["controllers"])
        for m in models.MODELS
        if isinstance(summary.get(m), dict) and summary[m].get("controllers")
    }
    if all(m == w for m in weights.values()):
        return f"Grid: {n} positions per axis per sensor, {w} weights per synapse."
    each = ", ".join(f"{model} {m}" for model, m in weights.items())
    return f"Grid: {n} positions per axis per sensor; weights per synapse: {each}."


def summary_markdown(summary: dict[str, Any]) -> str:
    names = list(metrics.METRICS)
    head = (
        f"| l1 | l2 | generalists | at least one | {' | '.join(names)} | flagged |\n"
        f"|---|---|---|---|{'---|' * len(names)}---|"
    )
    lines = ["# Summary", "", grid_line(summary)]
    for model in models.MODELS:
        one = summary.get(model)
        if not one:
            continue
        lines += ["", f"## {model} ({one['designs']} designs, {one['controllers']} controllers each)", ""]
        if "canonical" in one:
            c = one["canonical"]
            ranks = ", ".join(f"{c[f'rank_{m}']} by {m}" for m in names)
            lines += [f"Canonical design: rank {ranks}.", "", head, _fmt(c), ""]
        for m in names:
            lines += [f"Top designs by {m}:", "", head, *map(_fmt, one[f"top_{m}"]), ""]
        lines += [f"Designs with M_CF = 1: {one['M_CF_eq_1']}; best M_L among them: {one['best_M_L_among_M_CF_eq_1']}"]
    return "\n".join(lines) + "\n"
