"""Caption text: what a figure shows (written in its notebook) plus where its data came from.

Captions use only Markdown that is also valid reStructuredText (paragraphs, ``**bold**``, ``- ``
lists), because the Snakemake report renders them as RST. The reproduction table uses the same
summaries.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import pandas as pd

from morphlearn import grid as gridmod
from morphlearn import provenance
from morphlearn.figures.data import ModelResults, dataset_label, design_label, engine_label, row_design
from morphlearn.provenance import sha256_file

PAPER_POSITIONS, PAPER_WEIGHTS = 9, 121


def _short(h: str | None) -> str:
    return (h or "?")[:12]


def _provenance_record(res: ModelResults) -> dict[str, Any]:
    # quoted in the caption as fact: its seal (or the bundle's manifest) is checked here first
    provenance.check_derived(res.paths["metrics"])
    return provenance.read_record(provenance.sidecar_of(res.paths["metrics"]))


def science_summary(res: ModelResults) -> str:
    """The config subset the dataset was made with (from the dataset itself), in its model's words."""
    from morphlearn import models

    return models.get(res.model).describe(res.science, res.n_designs, len(res.weights))


def grid_words(res: ModelResults, run: ModelResults) -> str:
    """The design grid of a survey in words beside the run's: "the grid", or a coarser grid whose
    positions are the run's ("the 5-point grid, every 2nd position of this run's 9")."""
    p, n = res.positions_per_axis, run.positions_per_axis
    if p == n or not p or not n:
        return "the grid"
    step = (n - 1) // (p - 1)
    return f"the {p}-point grid, every {step}{_ordinal(step)} position of this run's {n}"


def _ordinal(k: int) -> str:
    return "th" if 10 <= k % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(k % 10, "th")


def resolution_note(res: ModelResults) -> str:
    """ "paper resolution", or how this run's grid and design set differ from the paper's."""
    n = res.positions_per_axis
    m = len(res.weights)
    full_designs = res.n_designs == (n or 0) ** 4
    if n == PAPER_POSITIONS and m == PAPER_WEIGHTS:
        # the grids are the paper's; only the design set may be smaller (refined candidates)
        return "paper resolution" + ("" if full_designs else f" on {res.n_designs} of {n**4} designs (the paper: all)")
    subset = "" if full_designs else f", {res.n_designs} of {(n or 0) ** 4} designs"
    return (
        f"reduced resolution ({n} positions per axis, {m} weights{subset}; the paper used "
        f"{PAPER_POSITIONS} and {PAPER_WEIGHTS}, all designs)"
    )


def provenance_md(results: Sequence[ModelResults | None], extra: str = "") -> str:
    """The caption's data-and-config paragraph: files, checksums, git commit, config, resolution."""
    parts = []
    for res in results:
        if res is None:
            continue
        rec = _provenance_record(res)
        merged_sha = next(iter(rec.get("inputs", {}).values()), None)
        # Paths relative to the results folder: a bundle re-rendered anywhere gives the same caption.
        metrics_rel, merged_rel = (f"{res.folder}/{Path(res.paths[k]).name}" for k in ("metrics", "merged"))
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


def title_head(short: str, what: str, width: int) -> str:
    """A panel title's first line, ``short, what``, or two lines where it is wider than ``width``
    characters (a long engine label, "reduced model (121 x 121)", would run past its panel)."""
    one = f"{short}, {what}"
    return one if len(one) <= width else f"{short},\n{what}"


def design_text(row: pd.Series) -> str:
    """``l1 = (x, y), l2 = (x, y)`` of a metrics-table row."""
    return design_label(*row_design(row))


def paper_design_note(res: ModelResults, design: Any, paper: Any) -> str:
    """A sentence for a figure that draws ``design`` where the paper drew ``paper``: "" when they are
    the same design, else the paper's and where ``res`` ranks it by M_L (one sentence, not a second
    parenthesis beside the design's own coordinates)."""
    if tuple(design) == tuple(paper):
        return ""
    from morphlearn import metrics

    row = res.row(*paper)
    k = None if row is None else metrics.rank_of(res.table, row, "M_L")
    rank = "" if k is None else f"; this run ranks it {k}{_ordinal(k)} by M_L"
    return f" The paper's design is {design_label(*paper)}{rank}."


def metric_line(row: pd.Series, n_controllers: int, sep: str = ", ") -> str:
    """``M_L = ... (k of n controllers), M_CF = ...`` of a metrics-table row."""
    return f"M_L = {row.M_L:.4g} ({int(row.generalists)} of {n_controllers} controllers){sep}M_CF = {row.M_CF:.4g}"


def subset_best(
    res: ModelResults, others: Sequence[ModelResults | None] = (), name_ties: bool = False
) -> tuple[str, list[ModelResults]]:
    """Caption text for a physics model's "best" design when its results hold only some of the
    grid's designs (e.g. the few refined at 121 x 121 weights in pybullet, issue 26): the best of
    those, not of all; and, for each results in ``others`` on the same weight grid that hold more
    designs (MuJoCo's refined candidates, or a survey of every design of a coarser grid whose
    positions are this one's: the ODE survey of the 5-point grid), which designs they rank best and
    whether ``res`` holds them (or their mirror images), so the choice of designs is checked, not
    assumed. ``name_ties``: say how many designs share the best M_L (the reproduction table's note;
    the figures' captions keep their words). Returns the text ("" when ``res`` holds every design)
    and the results of ``others`` it cites (for the caption's data paragraph)."""
    n = res.positions_per_axis or 0
    g = gridmod.DesignGrid(n)
    if res.n_designs == g.size:
        return "", []
    used = []
    held = set(int(d) for d in res.table.design)
    text = (
        f"The {dataset_label(res)} results hold {res.n_designs} of the grid's {g.size} designs; "
        "their best are the best of those, not of all designs."
    )
    for o in others:
        if o is None or o.n_designs <= res.n_designs or not gridmod.is_subgrid(o.positions_per_axis or 0, n):
            continue
        if len(o.weights) != len(res.weights):  # counts over another weight grid do not compare
            continue
        used.append(o)
        best_l, best_cf = o.best("M_L"), o.best("M_CF")
        # on this grid by their coordinates (a coarser grid's indices are not this grid's)
        picks = sorted({g.index_of(*row_design(r)) for r in (best_l, best_cf)})
        found = ["itself" if d in held else "mirror" if int(g.mirror(d)) in held else "" for d in picks]
        if len(picks) == 1:
            ranks = f"ranks {design_text(best_l)} best by both M_L and M_CF"
            has = {"itself": "holds it", "mirror": "holds its mirror image", "": "does not hold it"}[found[0]]
        else:  # a design's mirror image counts as the design here (MuJoCo flips none; pybullet few)
            ranks = f"ranks {design_text(best_l)} best by M_L and {design_text(best_cf)} best by M_CF"
            has = f"holds {sum(map(bool, found))} of the two (or their mirror images)"
        tied = len(o.tied_with(best_l, "M_L"))
        if name_ties and tied > 1:  # a mirror pair counts 2, as the table's note on the theory's best
            ranks += f" ({tied} designs share its M_L {best_l.M_L:.4g}, a mirror pair counting 2)"
        p = o.positions_per_axis
        of = "" if p == n else f" of the {p}-point grid"
        text += (
            f" {dataset_label(o)}, over the {o.n_designs} designs{of} its results hold, {ranks}; "
            f"{engine_label(res.model)} {has}."
        )
    return text, used
