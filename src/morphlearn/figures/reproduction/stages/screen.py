"""Rows of a screen (config ``screen_from``): the paper's claims about the best of all designs,
answered by a fast model's map of every design and the paper's engine at the map's best designs.

The rule, written once (:func:`ruled_out`): the engine's best of the designs it holds is the best
of all when every other design is ruled out, i.e. its screen value plus the largest difference
between screen and engine at the designs both hold stays below the engine's best. A design the
screen cannot rule out leaves the claim not comparable, and the row names how many and the
nearest one. The margin is measured, not assumed: at the refined designs, which are the screen's
best and so where a screen's error matters most.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pandas as pd

from morphlearn import grid as gridmod
from morphlearn.figures import data as fd
from morphlearn.figures.reproduction.claim_values import grid_scope, is_among, weights_scope
from morphlearn.figures.reproduction.claims import CLAIMS, PAPER_PHYSICS_BEST_DESIGN
from morphlearn.figures.reproduction.inputs import TableInputs
from morphlearn.figures.reproduction.selection import model_label, not_the_paper
from morphlearn.figures.reproduction.text import config_note
from morphlearn.figures.reproduction.verdict import DIFFERS, Scope, verdict

#: The paper's claims a screen answers (claims.CLAIMS keys), and the key of each one's row here.
ANSWERS = {"empirical_best_design": "screen_best_design", "empirical_best_on_both": "screen_best_on_both"}


class Ruled(NamedTuple):
    """One metric's screen check: the engine's best held design, the margin, what stays open."""

    best: pd.Series
    #: the largest |screen - engine| of the metric at the designs both hold
    margin: float
    #: designs outside the refinement the screen cannot rule out (screen rows), best first
    open: pd.DataFrame
    #: the best screen row outside the refinement
    best_outside: pd.Series | None


def ruled_out(screen: pd.DataFrame, refined: pd.DataFrame, by: str) -> Ruled:
    """Whether the screen rules out every design the refinement does not hold, by ``by``: a design
    stays open when its screen value, moved by the margin towards better, reaches the engine's best
    (a tie stays open: it could share the best)."""
    from morphlearn import metrics

    higher = metrics.METRICS[by].higher_is_better
    held = screen.set_index("design")[by].reindex(refined.design)
    if held.isna().any():
        raise ValueError(f"the screen lacks {int(held.isna().sum())} of the refinement's designs")
    margin = float(np.abs(refined[by].to_numpy() - held.to_numpy()).max())
    best = metrics.rank_designs(refined, by).iloc[0]
    outside = metrics.rank_designs(screen[~screen.design.isin(refined.design)], by)
    reach = outside[by] + margin if higher else outside[by] - margin
    still = reach >= best[by] if higher else reach <= best[by]
    return Ruled(best, margin, outside[still], outside.iloc[0] if len(outside) else None)


def _scope(screen: fd.ModelResults, refined: fd.ModelResults, checks: list[Ruled]) -> Scope:
    for part, scope in (("the screen", grid_scope(screen)), ("the refinement", weights_scope(refined))):
        if not scope.comparable:
            return Scope(False, f"{part}: {scope.why}")
    n_open = {int(d) for r in checks for d in r.open.design}
    if n_open:
        return Scope(False, f"the screen cannot rule out {len(n_open)} designs the refinement does not hold")
    return Scope()


def _why(r: Ruled, by: str, refined_label: str) -> str:
    """How the screen rules the other designs out by ``by`` (or which one it cannot)."""
    if r.best_outside is None:
        return f"by {by}: the refinement holds every design"
    near = r.open.iloc[0] if len(r.open) else r.best_outside
    return (
        f"by {by}: the screen's best design outside the refinement, {fd.design_label(*fd.row_design(near))}, "
        f"{near[by]:.4g} + the largest screen-vs-{refined_label} difference at the refined designs {r.margin:.2g} "
        f"{'reaches' if len(r.open) else 'stays below'} {refined_label}'s best {r.best[by]:.4g}"
        + (f" ({len(r.open)} designs open)" if len(r.open) else "")
    )


def screen_rows(screen: fd.ModelResults, refined: fd.ModelResults, config_name: str) -> list[dict[str, str]]:
    """The best-design claims as the screen and its refinement answer them (verdicts when the
    refinement is the paper's robot in its engine, else beside the paper with its reason)."""
    from morphlearn import metrics, models

    m2 = refined.n_controllers
    checks = {by: ruled_out(screen.table, refined.table, by) for by in metrics.METRICS}
    scope = _scope(screen, refined, list(checks.values()))
    top_l, top_cf = checks["M_L"].best, checks["M_CF"].best
    same_pair = gridmod.DesignGrid(refined.positions_per_axis or 0).same_pair(top_l.design, top_cf.design)
    label = fd.engine_label(refined.model)
    how = (
        f"{label} at {refined.n_designs} designs (the screen's best and their mirror images), the screen "
        f"({fd.engine_label(screen.model)}) at all {screen.n_designs}; "
        + "; ".join(_why(r, by, label) for by, r in checks.items())
    )
    ours = {
        "empirical_best_design": (
            f"{fd.design_label(*fd.row_design(top_l))}: {int(top_l.generalists)} of {m2}, M_L {top_l.M_L:.4g}",
            is_among(refined, top_l, PAPER_PHYSICS_BEST_DESIGN, "M_L"),
        ),
        "empirical_best_on_both": (
            "yes" if same_pair else f"no (best by M_CF: {fd.design_label(*fd.row_design(top_cf))})",
            same_pair,
        ),
    }
    other = not_the_paper(refined)
    out = []
    for claim in (c for c in CLAIMS if c.key in ANSWERS):
        text, value = ours[claim.key]
        row = {
            "key": ANSWERS[claim.key],
            "quantity": f"screened: {claim.quantity}",
            "paper": claim.paper,
            "ours": text,
            "config": config_note(refined, config_name),
            "note": how if not other else f"{other} || {how}",
        }
        if not other:
            said, why = verdict(claim.kind, claim.value, value, scope)
            reason, anchor = models.get(refined.model).differs_reason() if said == DIFFERS else (why, "")  # type: ignore[attr-defined]
            row |= {"section": "paper", "model": f"{model_label(refined.model)}: screened", "source": claim.source}
            row |= {"verdict": said, "reason": reason, "anchor": anchor}
        out.append(row)
    return out


def rows(t: TableInputs) -> list[dict[str, str]]:
    """The screen's rows, when the config reads one (``screen_from``)."""
    if t.screen is None:
        return []
    return screen_rows(*t.screen, t.config_name)
