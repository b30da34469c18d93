"""Ours for the paper's own claims (``claims.CLAIMS``): key -> :class:`Ours` (the text shown, a
note, the value the verdict rule compares and whether ours answers the claim as the paper put it),
from the theory's results and from each physics model's."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
import pandas as pd

from morphlearn import grid as gridmod
from morphlearn.figures import data as fd
from morphlearn.figures.caption import PAPER_POSITIONS, PAPER_WEIGHTS, subset_best
from morphlearn.figures.reproduction.claims import NOT_RUN, NOTE_SEP, PAPER_PHYSICS_BEST_DESIGN
from morphlearn.figures.reproduction.text import frac
from morphlearn.figures.reproduction.verdict import FULL, Scope


class Ours(NamedTuple):
    text: str
    note: str = ""
    #: what the verdict rule compares with the paper's value (None: nothing to compare)
    value: float | bool | None = None
    scope: Scope = FULL


def weights_scope(res: fd.ModelResults) -> Scope:
    """A claim about given designs needs the paper's weight grid (counts scale with it)."""
    m = len(res.weights)
    if m == PAPER_WEIGHTS:
        return FULL
    return Scope(False, f"{m} x {m} weights (the paper: {PAPER_WEIGHTS} x {PAPER_WEIGHTS})")


def grid_scope(res: fd.ModelResults) -> Scope:
    """A claim about all designs needs the paper's weights and every design of its grid; the best
    of a subset of the paper's grid is a lower bound of the best of all."""
    scope = weights_scope(res)
    if not scope.comparable:
        return scope
    n, size = res.positions_per_axis or 0, PAPER_POSITIONS**4
    if n != PAPER_POSITIONS and not gridmod.is_subgrid(n, PAPER_POSITIONS):
        return Scope(False, f"a {n}-position design grid (the paper: {PAPER_POSITIONS})")
    if res.n_designs < size:  # a coarser grid whose positions are the paper's holds some of its designs
        grid = "" if n == PAPER_POSITIONS else f" (the {n}-position grid's)"
        return Scope(False, f"{res.n_designs} of the paper's {size} designs held{grid}", lower_bound=True)
    return FULL


def exists_scope(scope: Scope, found: bool) -> Scope:
    """A claim that some design exists (one higher than the canonical design on both metrics): a
    design found among a subset of the paper's designs, at its weights, is one of all of them, so a
    subset's "yes" answers the claim; its "no" does not."""
    return FULL if scope.lower_bound and found else scope


def asymmetric(t: pd.DataFrame) -> pd.Series:
    """Designs whose sensors are not mirror images of each other about the body's axis."""
    return ~(np.isclose(t.l1x, t.l2x) & np.isclose(t.l1y, -t.l2y))


def _nearest(o: np.ndarray, ws: np.ndarray, w: fd.Point) -> tuple[fd.Point, int]:
    """The grid controller nearest to ``w`` and the number of environments it solves (overlap ``o``)."""
    i1, i2 = int(np.argmin(np.abs(ws - w[0]))), int(np.argmin(np.abs(ws - w[1])))
    return (float(ws[i1]), float(ws[i2])), int(o[i1, i2])


def _examples(res: fd.ModelResults, design: fd.Design, targets: Sequence[fd.Point]) -> Ours:
    o = res.overlap(res.find(*design))
    parts, solved = [], []
    for t in targets:
        (a, b), k = _nearest(o, res.weights, t)
        same = "" if math.isclose(a, t[0]) and math.isclose(b, t[1]) else f" (grid point ({a:.3g}, {b:.3g}))"
        parts.append(f"({t[0]:g}, {t[1]:g}){same}: {k} of 4")
        solved.append(k == 4)
    return Ours("; ".join(parts), value=all(solved), scope=weights_scope(res))


def _persistence(pers: pd.DataFrame | None, label: str, rule: str, scope: Scope) -> Ours:
    if pers is None:
        return Ours(NOT_RUN)
    sub = pers[pers.design == label]
    if sub.empty:
        return Ours("no generalists on this grid", rule, None, Scope(False, "no generalist to integrate"))
    n_gen, stays = int(sub.generalists.iloc[0]), int(sub.stays_near.sum())
    spread = "" if len(sub) == n_gen else f"an even spread of {len(sub)} of its {n_gen} generalists integrated"
    return Ours(f"{stays} of {len(sub)}", NOTE_SEP.join(x for x in (rule, spread) if x), stays / len(sub), scope)


def best_label(pers: pd.DataFrame | None) -> str:
    """The persistence table's label of the paper's "best design", (-0.5,-0.25),(0.5,0.25): that
    design where it was integrated ("paper_best"; the best by M_L here is another design, with
    another count of generalists), else the best by M_L, which it then is."""
    return "paper_best" if pers is not None and (pers.design == "paper_best").any() else "best_M_L"


def is_among(res: fd.ModelResults, top: pd.Series, design: fd.Design, by: str) -> bool:
    """``design`` or its mirror image is among the designs tied with ``top`` by ``by``."""
    tied = {fd.row_design(r) for _, r in res.tied_with(top, by).iterrows()}
    grid = gridmod.DesignGrid(res.positions_per_axis or 0)
    row = res.row(*design)
    mirror = None if row is None else res.table[res.table.design == grid.mirror(int(row.design))]
    return design in tied or (mirror is not None and len(mirror) and fd.row_design(mirror.iloc[0]) in tied)


def theory_values(res: fd.ModelResults, pers: pd.DataFrame | None, near: float) -> dict[str, Ours]:
    """key -> ours for the theory's claims."""
    from morphlearn import metrics

    m2, t = res.n_controllers, res.table
    out: dict[str, Ours] = {}
    per_design, whole = weights_scope(res), grid_scope(res)
    canon = res.row(*gridmod.canonical_design())
    if canon is not None:
        out["theory_canonical_generalists"] = Ours(
            frac(int(canon.generalists), m2), "", int(canon.generalists), per_design
        )
        out["theory_canonical_M_L"] = Ours(
            f"{canon.M_L:.4g}", "M_L = generalists / controllers (Eq. 1)", float(canon.M_L), per_design
        )
        out["theory_canonical_M_CF"] = Ours(
            f"{canon.M_CF:.4g}",
            "M_CF = generalists / controllers solving at least one (Eq. 2)",
            float(canon.M_CF),
            per_design,
        )
        higher = asymmetric(t) & (t.M_L > canon.M_L) & (t.M_CF > canon.M_CF)
        out["theory_canonical_beaten"] = Ours(
            f"{'yes' if higher.any() else 'no'}: {int(higher.sum())} asymmetric designs higher on both (of {len(t)})",
            value=bool(higher.any()),
            scope=exists_scope(whole, bool(higher.any())),  # one higher design suffices
        )
    best = res.row(*fd.PAPER_BEST_DESIGN)
    if best is not None:
        out["theory_paper_best_generalists"] = Ours(
            frac(int(best.generalists), m2), "", int(best.generalists), per_design
        )
        out["theory_paper_best_M_L"] = Ours(f"{best.M_L:.4g}", "", float(best.M_L), per_design)
        out["theory_paper_best_M_CF"] = Ours(f"{best.M_CF:.4g}", "", float(best.M_CF), per_design)
    top = res.best("M_L")
    ties = len(res.tied_with(top, "M_L"))
    rank = "" if best is None else f"; the paper's design: rank {metrics.rank_of(t, best, 'M_L')} by M_L"
    out["theory_best_design"] = Ours(
        f"{fd.design_label(*fd.row_design(top))}, M_L = {top.M_L:.4g}{rank}",
        f"{ties} design(s) share the highest M_L (a mirror pair counts 2)",
        is_among(res, top, fd.PAPER_BEST_DESIGN, "M_L"),
        whole,
    )
    full = t[np.isclose(t.M_CF, 1.0)]
    out["theory_best_M_L_with_M_CF_1"] = Ours(
        f"{len(full)} designs; the best of them has M_L {full.M_L.max():.4g}"
        if len(full)
        else f"no design (the largest M_CF is {t.M_CF.max():.4g})",
        value=len(full) >= 2,
        scope=whole,
    )
    if canon is not None:
        out["theory_example_canonical"] = _examples(res, gridmod.canonical_design(), fd.PAPER_CANONICAL_CONTROLLERS)
    if best is not None:
        out["theory_example_best"] = _examples(res, fd.PAPER_BEST_DESIGN, fd.PAPER_BEST_CONTROLLERS)
    rule = f"stays near = after its first success the centre never again moves farther than {near:g} from the light"
    for key, label in (("theory_persistence_best", best_label(pers)), ("theory_persistence_canonical", "canonical")):
        out[key] = _persistence(pers, label, rule, per_design)
    return out


def physics_values(res: fd.ModelResults, others: Sequence[fd.ModelResults] = ()) -> dict[str, Ours]:
    """key -> ours for the physics claims (``empirical_...`` keys) from one physics model's results;
    where they hold only some designs, the best-design rows say so and which designs ``others``
    (more designs, same weights) rank best."""
    m2 = res.n_controllers
    out: dict[str, Ours] = {}
    per_design, whole = weights_scope(res), grid_scope(res)
    canon_d = gridmod.canonical_design()
    canon = res.row(*canon_d)
    if canon is not None:
        _, k = _nearest(res.overlap(res.find(*canon_d)), res.weights, (1.0, 1.0))
        out["empirical_canonical_w11"] = Ours(f"{'yes' if k == 4 else 'no'} ({k} of 4)", "", k == 4, per_design)
        g = int(canon.generalists)
        out["empirical_canonical_generalists"] = Ours(frac(g, m2), "", g, per_design)
        out["empirical_canonical_M_L"] = Ours(f"{canon.M_L:.4g}", "", float(canon.M_L), per_design)
        out["empirical_canonical_M_CF"] = Ours(f"{canon.M_CF:.4g}", "", float(canon.M_CF), per_design)
    # One rule for the values the paper states of its best design (its generalists, M_L, M_CF):
    # each is judged at that design (as the authors' code names it), on the paper's weights; that it
    # is the best of all designs is a claim of its own (empirical_best_design), judged over all.
    pb = res.row(*PAPER_PHYSICS_BEST_DESIGN)
    subset, _ = subset_best(res, others, name_ties=True)
    top, top_cf = res.best("M_L"), res.best("M_CF")
    if pb is None:
        why = f"the design is not among the {res.n_designs} designs held"
        out["empirical_paper_best_generalists"] = Ours(why, "", None, Scope(False, why))
        for key, best, by in (("empirical_best_M_L", top, "M_L"), ("empirical_best_M_CF", top_cf, "M_CF")):
            held = f"{why}; their best by {by}: {fd.design_label(*fd.row_design(best))}, {best[by]:.4g}"
            out[key] = Ours(held + f" ({frac(int(best.generalists), m2)})", "", None, Scope(False, why))
    else:
        g = int(pb.generalists)
        out["empirical_paper_best_generalists"] = Ours(
            f"{frac(g, m2)}; M_L {pb.M_L:.4g}, M_CF {pb.M_CF:.4g}", "", g, per_design
        )
        for key, by in (("empirical_best_M_L", "M_L"), ("empirical_best_M_CF", "M_CF")):
            best = top if by == "M_L" else top_cf
            also = (
                f"also the best by {by} of the {res.n_designs} designs held"
                if fd.row_design(best) == fd.row_design(pb) or float(best[by]) == float(pb[by])
                else f"the best by {by} of the {res.n_designs} designs held: {fd.design_label(*fd.row_design(best))}, "
                f"{best[by]:.4g}"
            )
            out[key] = Ours(
                f"{pb[by]:.4g} at the paper's best design ({frac(g, m2)}); {also}", "", float(pb[by]), per_design
            )
    out["empirical_best_design"] = Ours(
        fd.design_label(*fd.row_design(top)), subset, is_among(res, top, PAPER_PHYSICS_BEST_DESIGN, "M_L"), whole
    )
    same = fd.row_design(top) == fd.row_design(top_cf)
    out["empirical_best_on_both"] = Ours(
        "yes" if same else f"no (best by M_CF: {fd.design_label(*fd.row_design(top_cf))})", subset, same, whole
    )
    return out
