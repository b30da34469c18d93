"""The run's summary: each model's canonical design (with its rank) and its best designs by each
registered metric (``summary.json``, ``summary.md``)."""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import pandas as pd

from morphlearn import grid as gridmod
from morphlearn import metrics, models, provenance, store
from morphlearn.settings import Settings


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


def run_summary(
    s: Settings, tables: dict[str, str], out_json: str | Path, out_md: str | Path, out_prov: str | Path | None = None
) -> None:
    """The summary of the models' tables (each checked against its record first); with
    ``out_prov`` its own sealed record: the tables' digests and the summary's."""
    summary = {"weights": s.grid.weights, "positions_per_axis": s.grid.positions_per_axis}
    weights: dict[str, int] = {}  # each model's own weights per synapse (a physics model's may differ)
    for model, path in tables.items():
        provenance.check_derived(path)  # custody: the table its metrics rule wrote
        t = pd.read_csv(path)
        one = summarise(t, s.analysis.top)
        weights[model] = len(models.get(model).weights(s))
        one["controllers"] = weights[model] ** 2
        summary[model] = one
    with store.atomic_path(out_json) as tmp:
        tmp.write_text(json.dumps(summary, indent=1, sort_keys=True) + "\n")
    with store.atomic_path(out_md) as tmp:
        tmp.write_text(summary_markdown(summary, weights))
    if out_prov is not None:
        libs = [lib for name in tables for lib in models.get(name).libraries]
        rec = provenance.record({"top": s.analysis.top, "models": sorted(tables)}, [], libs)
        # the tables by their path relative to the summary's folder (the results folder)
        rec["inputs"] = {os.path.relpath(p, Path(out_json).parent): provenance.sha256_file(p) for p in tables.values()}
        provenance.write_sealed(out_prov, rec, [out_json, out_md])


def _fmt(d: dict[str, Any]) -> str:
    vals = " | ".join(f"{d[m]:{spec.fmt}}" for m, spec in metrics.METRICS.items())
    return (
        f"| ({d['l1'][0]:g}, {d['l1'][1]:g}) | ({d['l2'][0]:g}, {d['l2'][1]:g}) | "
        f"{d['generalists']} | {d['at_least_one']} | {vals} | {d['flagged']} |"
    )


def grid_line(summary: dict[str, Any], weights: dict[str, int] | None = None) -> str:
    """The grid the models ran on: ``grid.weights`` is the theory's; a physics model at another
    weight grid (the reduced model at 121 x 121 beside a 41 x 41 theory) is named with its own."""
    n, w = summary["positions_per_axis"], summary["weights"]
    if not weights or all(m == w for m in weights.values()):
        return f"Grid: {n} positions per axis per sensor, {w} weights per synapse."
    each = ", ".join(f"{model} {m}" for model, m in weights.items())
    return f"Grid: {n} positions per axis per sensor; weights per synapse: {each}."


def summary_markdown(summary: dict[str, Any], weights: dict[str, int] | None = None) -> str:
    """``weights``: each model's weights per synapse, where they may differ from ``grid.weights``."""
    names = list(metrics.METRICS)
    head = (
        f"| l1 | l2 | generalists | at least one | {' | '.join(names)} | flagged |\n"
        f"|---|---|---|---|{'---|' * len(names)}---|"
    )
    lines = [
        "# Summary",
        "",
        grid_line(summary, weights),
    ]
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
