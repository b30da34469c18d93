"""Rows of physics results that are not a survey (designs refined at the paper's 121 x 121), beyond
the paper: how the theory's best designs do in physics. (Each engine's answers to the paper's own
physics claims are rows of the claims table: ``table.reproduction_table``.)"""

from __future__ import annotations

from morphlearn import grid as gridmod
from morphlearn.figures import data as fd
from morphlearn.figures.reproduction.claims import BEYOND_MODELS
from morphlearn.figures.reproduction.inputs import TableInputs
from morphlearn.figures.reproduction.selection import at_paper_weights, is_survey, physics_models
from morphlearn.figures.reproduction.text import config_note, frac


def refined_rows(
    theory: fd.ModelResults | None, res: fd.ModelResults, name: str, config_name: str
) -> list[dict[str, str]]:
    """Rows of a physics engine's results that are not a survey (the designs refined at the
    paper's 121 x 121, issue 26): how the theory's best designs (by M_L and by M_CF) do in it,
    beside the designs it holds."""
    from morphlearn import metrics

    label = fd.engine_label(name)
    rows: list[dict[str, str]] = []
    n_pos = theory.positions_per_axis if theory is not None else None
    if theory is None or n_pos != res.positions_per_axis:
        return rows
    n, m2 = res.n_designs, res.n_controllers
    for by in metrics.METRICS:
        top = theory.best(by)
        design = fd.row_design(top)
        mirror = theory.table[theory.table.design == gridmod.DesignGrid(n_pos).mirror(int(top.design))]
        held = [r for d in (design, fd.row_design(mirror.iloc[0])) if (r := res.row(*d)) is not None]
        if not held:
            ours = f"{fd.design_label(*design)} and its mirror image: not among the {n} designs these results hold"
        else:
            r = held[0]
            which = "" if fd.row_design(r) == design else " (its mirror image)"
            ours = (
                f"{fd.design_label(*fd.row_design(r))}{which}: {frac(int(r.generalists), m2)} generalists, "
                f"M_L {r.M_L:.4g}, M_CF {r.M_CF:.4g}; rank {metrics.rank_of(res.table, r, 'M_L')} by M_L and "
                f"{metrics.rank_of(res.table, r, 'M_CF')} by M_CF of the {n} designs simulated"
            )
        rows.append(
            {
                "key": f"{name}_theory_best_{by}_in_physics",
                "quantity": f"{label}: the theory's best design by {by}, in physics",
                "paper": BEYOND_MODELS,
                "ours": ours,
                "config": config_note(res, config_name),
                "note": f"theory's best by {by}: {fd.design_label(*design)}, M_L {top.M_L:.4g}, M_CF {top.M_CF:.4g}",
            }
        )
    return rows


def rows(t: TableInputs) -> list[dict[str, str]]:
    """The reference engine's refined designs (its further engines': stages.engines)."""
    if at_paper_weights(t.empirical) and not is_survey(t.theory, t.empirical):
        return refined_rows(t.theory, t.empirical, physics_models()[0], t.config_name)  # type: ignore[arg-type]
    return []
