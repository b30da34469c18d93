"""Ours for the paper's own claims (the rows of ``claims.QUANTITIES``): key -> (ours, note), from
the theory's results and a physics model's."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pandas as pd

from morphlearn import grid as gridmod
from morphlearn.figures import data as fd
from morphlearn.figures.caption import subset_best
from morphlearn.figures.reproduction.claims import NOT_RUN
from morphlearn.figures.reproduction.text import frac


def _nearest(o: np.ndarray, ws: np.ndarray, w: fd.Point) -> tuple[fd.Point, int]:
    """The grid controller nearest to ``w`` and the number of environments it solves (overlap ``o``)."""
    i1, i2 = int(np.argmin(np.abs(ws - w[0]))), int(np.argmin(np.abs(ws - w[1])))
    return (float(ws[i1]), float(ws[i2])), int(o[i1, i2])


def _examples(res: fd.ModelResults, design: fd.Design, targets: Sequence[fd.Point]) -> str:
    o = res.overlap(res.find(*design))
    parts = []
    for t in targets:
        (a, b), k = _nearest(o, res.weights, t)
        same = "" if math.isclose(a, t[0]) and math.isclose(b, t[1]) else f" (grid point ({a:.3g}, {b:.3g}))"
        parts.append(f"({t[0]:g}, {t[1]:g}){same}: {k} of 4")
    return "; ".join(parts)


def _persistence(pers: pd.DataFrame | None, label: str) -> tuple[str, str]:
    if pers is None:
        return NOT_RUN, ""
    sub = pers[pers.design == label]
    if sub.empty:
        return "no generalists on this grid", ""
    n_gen = int(sub.generalists.iloc[0])
    note = "" if len(sub) == n_gen else f"an even spread of {len(sub)} of its {n_gen} generalists integrated"
    return f"{int(sub.stays_near.sum())} of {len(sub)}", note


def theory_rows(res: fd.ModelResults, pers: pd.DataFrame | None, near: float) -> dict[str, tuple[str, str]]:
    """key -> (ours, note) for the theory quantities."""
    m2 = res.n_controllers
    out: dict[str, tuple[str, str]] = {}
    scale = "" if m2 == 121**2 else f"counts are over a {len(res.weights)}^2 grid, not 121^2: compare fractions"
    canon = res.row(*gridmod.canonical_design())
    if canon is not None:
        out["theory_canonical_generalists"] = (frac(int(canon.generalists), m2), scale)
        out["theory_canonical_M_L"] = (f"{canon.M_L:.4g}", "M_L = generalists / controllers, as the caption")
        out["theory_canonical_M_CF"] = (f"{canon.M_CF:.4g}", "generalists / controllers solving at least one")
    best = res.row(*fd.PAPER_BEST_DESIGN)
    if best is not None:
        out["theory_paper_best_generalists"] = (frac(int(best.generalists), m2), scale)
        out["theory_paper_best_M_L"] = (f"{best.M_L:.4g}", "")
        out["theory_paper_best_M_CF"] = (f"{best.M_CF:.4g}", "")
    top = res.best("M_L")
    ties = len(res.tied_with(top, "M_L"))
    out["theory_best_design"] = (
        f"{fd.design_label(*fd.row_design(top))}, M_L = {top.M_L:.4g}",
        f"{ties} design(s) share this M_L",
    )
    full = res.table[np.isclose(res.table.M_CF, 1.0)]
    out["theory_best_M_L_with_M_CF_1"] = (
        (f"{full.M_L.max():.4g}", f"{len(full)} designs have M_CF = 1") if len(full) else ("no design", "")
    )
    if canon is not None:
        out["theory_example_canonical"] = (
            _examples(res, gridmod.canonical_design(), fd.PAPER_CANONICAL_CONTROLLERS),
            scale,
        )
    if best is not None:
        out["theory_example_best"] = (_examples(res, fd.PAPER_BEST_DESIGN, fd.PAPER_BEST_CONTROLLERS), scale)
    rule = f"stays near = after its first success the centre never again moves farther than {near:g} from the light"
    for key, label in (("theory_persistence_best", "best_M_L"), ("theory_persistence_canonical", "canonical")):
        ours, note = _persistence(pers, label)
        out[key] = (ours, "; ".join(x for x in (rule, note) if x))
    return out


def empirical_rows(res: fd.ModelResults, others: Sequence[fd.ModelResults] = ()) -> dict[str, tuple[str, str]]:
    """The paper's empirical rows from a physics model's results; where they hold only some designs,
    the best-design rows say so and which designs ``others`` (more designs, same weights) rank best."""
    m2 = res.n_controllers
    out: dict[str, tuple[str, str]] = {}
    scale = "" if m2 == 121**2 else f"over a {len(res.weights)}^2 grid, not 121^2: compare fractions"
    canon_d = gridmod.canonical_design()
    canon = res.row(*canon_d)
    if canon is not None:
        _, k = _nearest(res.overlap(res.find(*canon_d)), res.weights, (1.0, 1.0))
        out["empirical_canonical_w11"] = (f"{k} of 4", "committed morphology (optimise_morphology)")
        out["empirical_canonical_M_L"] = (f"{canon.M_L:.4g} ({frac(int(canon.generalists), m2)})", scale)
        out["empirical_canonical_M_CF"] = (f"{canon.M_CF:.4g}", "")
    subset, _ = subset_best(res, others)
    top, top_cf = res.best("M_L"), res.best("M_CF")
    out["empirical_best_design"] = (fd.design_label(*fd.row_design(top)), subset)
    out["empirical_best_M_L"] = (f"{top.M_L:.4g} ({frac(int(top.generalists), m2)})", scale)
    out["empirical_best_M_CF"] = (f"{top.M_CF:.4g}", "")
    same = fd.row_design(top) == fd.row_design(top_cf)
    out["empirical_best_on_both"] = (
        "yes" if same else f"no (best by M_CF: {fd.design_label(*fd.row_design(top_cf))})",
        subset,
    )
    return out
