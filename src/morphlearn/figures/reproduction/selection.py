"""Which physics results a run holds: the registered engines, a survey of every design, the
paper's 121 x 121 weights. The table and its stages decide their rows by these."""

from __future__ import annotations

from morphlearn import grid as gridmod
from morphlearn.figures import data as fd
from morphlearn.figures.caption import PAPER_WEIGHTS


def is_survey(theory: fd.ModelResults | None, empirical: fd.ModelResults | None) -> bool:
    """The empirical results cover every design of the theory's grid (config/survey.yaml), or of a
    grid whose positions are the theory's (a survey of the 5-point grid beside the paper's 9-point
    theory: config ``survey_from``)."""
    if theory is None or empirical is None:
        return False
    p, n = empirical.positions_per_axis or 0, theory.positions_per_axis or 0
    return gridmod.is_subgrid(p, n) and empirical.n_designs == gridmod.DesignGrid(p).size


def physics_models() -> list[str]:
    """The registered physics engines' model names in registry order: the reference engine (the
    workflow's ``empirical`` results, pybullet) first."""
    from morphlearn import models

    physics = set(models.physics())
    return [n for n in models.MODELS if n in physics]


def at_paper_weights(res: fd.ModelResults | None) -> bool:
    """Physics results on the paper's 121 x 121 weight grid (the designs refined, issue 26)."""
    return res is not None and len(res.weights) == PAPER_WEIGHTS


def not_the_paper(res: fd.ModelResults) -> str:
    """Why ``res`` cannot answer the paper's claims as it put them (its plug-in says: another robot
    or engine), or "" when it can (the theory; the authors' robot in the paper's engine)."""
    from morphlearn import models

    return models.get(res.model).not_the_paper(res.science)


def model_label(name: str, res: fd.ModelResults | None = None) -> str:
    """The model column: the theory, or a physics engine and whether it is the paper's (and, for
    results of another robot or engine, ``res``: whose body)."""
    from morphlearn import models

    if name in ("theory", "physics"):
        return name
    model = models.get(name)
    label = fd.engine_label(name)
    if res is not None and not_the_paper(res):
        engine = "the paper's engine" if getattr(model, "paper_engine", False) else "another engine"
        return f"{label} ({engine}, {model.robot_label(res.science)})"  # type: ignore[attr-defined]
    return f"{label} (the paper's engine)" if getattr(model, "paper_engine", False) else f"{label} (another engine)"
