"""Which physics results a run holds: the registered engines, a survey of every design, the
paper's 121 x 121 weights. The table and its stages decide their rows by these."""

from __future__ import annotations

from morphlearn import grid as gridmod
from morphlearn.figures import data as fd
from morphlearn.figures.caption import PAPER_WEIGHTS
from morphlearn.figures.reproduction.claims import PAPER_ENGINE


def is_survey(theory: fd.ModelResults | None, empirical: fd.ModelResults | None) -> bool:
    """The empirical results cover every design of the theory's grid (config/survey.yaml), or of a
    grid whose positions are the theory's (a survey of the 5-point grid beside the paper's 9-point
    theory: config ``survey_from``)."""
    if theory is None or empirical is None:
        return False
    p, n = empirical.positions_per_axis or 0, theory.positions_per_axis or 0
    return gridmod.is_subgrid(p, n) and empirical.n_designs == gridmod.DesignGrid(p).size


def physics_models() -> list[str]:
    """The registered physics engines' model names, the reference engine (pybullet) first."""
    from morphlearn import models

    return sorted(models.physics(), key=lambda n: not getattr(models.get(n), "figure_body", False))


def at_paper_weights(res: fd.ModelResults | None) -> bool:
    """Physics results on the paper's 121 x 121 weight grid (the designs refined, issue 26)."""
    return res is not None and len(res.weights) == PAPER_WEIGHTS


def model_label(name: str) -> str:
    """The model column: the theory, or a physics engine and whether it is the paper's."""
    if name == "theory":
        return "theory"
    if name == "physics":
        return "physics"
    label = fd.engine_label(name)
    return f"{label} (the paper's engine)" if name == PAPER_ENGINE else f"{label} (another engine)"
