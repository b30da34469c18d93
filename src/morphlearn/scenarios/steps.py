"""What the workflow's scenario rules do (their scripts only unpack and call)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pandas as pd

from morphlearn import metrics, models
from morphlearn.scenarios.comparison import compare
from morphlearn.scenarios.markdown import comparison_markdown
from morphlearn.scenarios.scan import threshold_scan


def run_metrics(
    th: metrics.Thresholds, merged: str | Path, out_csv: str | Path, record: dict[str, Any], out_json: str | Path
) -> None:
    """A scenario's metrics from its simulation at its thresholds (Plan.thresholds), and its record
    (overrides, simulation, how it is answered)."""
    from morphlearn import store
    from morphlearn.workflow import rules

    rules.run_metrics("theory", th, merged, out_csv)
    with store.atomic_path(Path(out_json)) as tmp:
        tmp.write_text(json.dumps(record, indent=1, sort_keys=True) + "\n")


def run_compare(
    tables: dict[str, str],
    merged: dict[str, str],
    top: int,
    out_csv: str | Path,
    out_md: str | Path,
    out_scan: str | Path,
    plan_md: str,
    out_record: str | Path | None = None,
) -> None:
    """The comparison table (compare), and the threshold scan of every simulation for the
    paper's text values (threshold_scan), closest first; with ``out_record`` their sealed record.
    Every scenario's table is checked against its record before it is read (custody)."""
    from morphlearn import provenance, store

    for p in tables.values():
        provenance.check_derived(p)
    comp = compare({n: pd.read_csv(p) for n, p in tables.items()}, top=top)
    scans = [threshold_scan(path).assign(simulation=sid) for sid, path in merged.items()]
    scan = pd.concat(scans, ignore_index=True).sort_values(["text_distance", "r", "horizon", "radius"])
    with store.atomic_path(Path(out_csv)) as tmp:
        comp.to_csv(tmp, index=False, float_format="%.6g")
    with store.atomic_path(Path(out_scan)) as tmp:
        scan.to_csv(tmp, index=False, float_format="%.6g")
    with store.atomic_path(Path(out_md)) as tmp:
        tmp.write_text(comparison_markdown(comp, scan, top, plan_md))
    if out_record is not None:
        # the scenarios vary the theory, the reference model: its libraries
        libs = models.get(models.REFERENCE).libraries
        rec = provenance.record({"scenarios": sorted(tables), "top": top}, [*tables.values()], libs)
        provenance.write_sealed(out_record, rec, [out_csv, out_md, out_scan])
