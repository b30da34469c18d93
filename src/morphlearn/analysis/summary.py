"""The run's summary: each model's canonical design (with its rank) and its best designs by each
registered metric (``summary.json``, ``summary.md``)."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pandas as pd

from morphlearn import models, provenance, store
from morphlearn.bundles.summaries import summarise, summary_markdown
from morphlearn.settings import Settings

__all__ = ["run_summary", "summarise", "summary_markdown"]


def run_summary(
    s: Settings, tables: dict[str, str], out_json: str | Path, out_md: str | Path, out_prov: str | Path | None = None
) -> None:
    """The summary of the models' tables (each checked against its record first); with
    ``out_prov`` its own sealed record: the tables' digests and the summary's."""
    summary = {"weights": s.grid.weights, "positions_per_axis": s.grid.positions_per_axis}
    for model, path in tables.items():
        provenance.check_derived(path)  # custody: the table its metrics rule wrote
        t = pd.read_csv(path)
        one = summarise(t, s.analysis.top)
        one["controllers"] = len(models.get(model).weights(s)) ** 2
        summary[model] = one
    with store.atomic_path(out_json) as tmp:
        tmp.write_text(json.dumps(summary, indent=1, sort_keys=True) + "\n")
    with store.atomic_path(out_md) as tmp:
        tmp.write_text(summary_markdown(summary))
    if out_prov is not None:
        libs = [lib for name in tables for lib in models.get(name).libraries]
        rec = provenance.record({"top": s.analysis.top, "models": sorted(tables)}, [], libs)
        # the tables by their path relative to the summary's folder (the results folder)
        rec["inputs"] = {os.path.relpath(p, Path(out_json).parent): provenance.sha256_file(p) for p in tables.values()}
        provenance.write_sealed(out_prov, rec, [out_json, out_md])
