"""Caption text: what a figure shows (written in its notebook) plus where its data came from.

Captions use only Markdown that is also valid reStructuredText (paragraphs, ``**bold**``, ``- ``
lists), because the Snakemake report renders them as RST. The reproduction table uses the same
summaries.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import pandas as pd

from morphlearn.figures.data import ModelResults, design_label, row_design
from morphlearn.provenance import sha256_file

PAPER_POSITIONS, PAPER_WEIGHTS = 9, 121


def _short(h: str | None) -> str:
    return (h or "?")[:12]


def _provenance_record(res: ModelResults) -> dict[str, Any]:
    p = Path(res.paths["metrics"]).with_suffix(".provenance.json")
    return json.loads(p.read_text()) if p.is_file() else {}


def science_summary(res: ModelResults) -> str:
    """The config subset the dataset was made with (from the dataset itself)."""
    sci = res.science
    m = len(res.weights)
    if res.model == "theory":
        g, th = sci.get("grid", {}), sci.get("theory", {})
        tol = (f"rtol = atol = {th.get('rtol')}" if th.get("integrator") == "dp5" else f"dt = {th.get('dt')}")
        return (f"grid {g.get('positions_per_axis')} positions per axis per sensor, {g.get('weights')} "
                f"weights per synapse; r = {th.get('r')}, T = {th.get('horizon')}, success radius "
                f"{th.get('success_radius')}, integrator {th.get('integrator')} ({tol}), step cap "
                f"{th.get('max_steps')}, mirror symmetry {sci.get('mirror_symmetry')}")  # fmt: skip
    pr = sci.get("params", {})
    how = ("one of each mirror pair simulated, the other derived" if sci.get("mirror_derive")
           else "simulated")  # fmt: skip
    if ad := sci.get("adaptive_weights"):
        how += (f", weight grid refined adaptively around successes and near misses (within "
                f"{ad.get('near')} contact distances; cells not simulated count as failures; "
                "measured miss rate in docs/empirical_levers.md)")  # fmt: skip
    return (f"{res.n_designs} designs {how} on the {sci.get('positions_per_axis')}-point grid, "
            f"{m} weights per synapse; light distance {pr.get('light_distance', float('nan')):.4g}, "
            f"{pr.get('steps')} steps of dt = {pr.get('dt')}, success = touching the light; body "
            f"from the committed morphology (wheel radius {pr.get('wheel_radius', float('nan')):.4g})")  # fmt: skip


def resolution_note(res: ModelResults) -> str:
    """"paper resolution", or how this run's grid and design set differ from the paper's."""
    n = res.positions_per_axis
    m = len(res.weights)
    full_designs = res.n_designs == (n or 0) ** 4
    if n == PAPER_POSITIONS and m == PAPER_WEIGHTS and full_designs:
        return "paper resolution"
    subset = "" if full_designs else f", {res.n_designs} of {(n or 0) ** 4} designs"
    return (f"reduced resolution ({n} positions per axis, {m} weights{subset}; the paper used "
            f"{PAPER_POSITIONS} and {PAPER_WEIGHTS}, all designs)")  # fmt: skip


def provenance_md(results: Sequence[ModelResults | None], extra: str = "") -> str:
    """The caption's data-and-config paragraph: files, checksums, git commit, config, resolution."""
    parts = []
    for res in results:
        if res is None:
            continue
        rec = _provenance_record(res)
        merged_sha = next(iter(rec.get("inputs", {}).values()), None)
        # Paths relative to the results folder: a bundle re-rendered anywhere gives the same caption.
        metrics_rel, merged_rel = (f"{res.model}/{Path(res.paths[k]).name}" for k in ("metrics", "merged"))
        parts.append(
            f"- {res.model}: {metrics_rel} (sha256 {_short(sha256_file(res.paths['metrics']))}) "
            f"and {merged_rel} (sha256 {_short(merged_sha)}), git commit "
            f"{rec.get('git_commit', '?')}; {science_summary(res)}; {resolution_note(res)}."
        )
    text = "**Data and config.**" + (" " + extra if extra else "")
    return text + ("\n\n" + "\n".join(parts) if parts else "")


def caption(title: str, body: Sequence[str], provenance: str) -> str:
    """Bold title, the body paragraphs (empty ones dropped), then the provenance paragraph."""
    paras = [f"**{title}**"] + [b for b in body if b] + [provenance]
    return "\n\n".join(paras) + "\n"


def design_text(row: pd.Series) -> str:
    """``l1 = (x, y), l2 = (x, y)`` of a metrics-table row."""
    return design_label(*row_design(row))


def metric_line(row: pd.Series, n_controllers: int, sep: str = ", ") -> str:
    """``M_L = ... (k of n controllers), M_CF = ...`` of a metrics-table row."""
    return (f"M_L = {row.M_L:.4g} ({int(row.generalists)} of {n_controllers} controllers){sep}"
            f"M_CF = {row.M_CF:.4g}")  # fmt: skip
