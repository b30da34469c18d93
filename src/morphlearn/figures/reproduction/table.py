"""The table: one row per paper claim (``claims.CLAIMS``, in that order; a physics claim once per
physics results that can answer it as the paper put it: the authors' robot in the paper's engine),
each with its verdict; then, beyond the paper, the physics claims as results of another robot or
engine answer them (no verdict: they ask another question, ``Model.not_the_paper`` says which) and
each registered stage's rows (``stage_registry.STAGES``, in that order)."""

from __future__ import annotations

import pandas as pd

from morphlearn.figures import data as fd
from morphlearn.figures.reproduction import stage_registry
from morphlearn.figures.reproduction.claim_values import Ours, physics_values, theory_values
from morphlearn.figures.reproduction.claims import CLAIMS, COLUMNS, NOT_RUN, NOTE_SEP, REASONS, Claim
from morphlearn.figures.reproduction.inputs import TableInputs
from morphlearn.figures.reproduction.selection import model_label, not_the_paper, physics_models
from morphlearn.figures.reproduction.text import config_note
from morphlearn.figures.reproduction.verdict import DIFFERS, verdict

#: The section of the rows that answer the paper's claims (with verdicts), of the paper's physics
#: claims as another robot or engine answers them (no verdict), and of the rows beyond the paper.
PAPER, OTHER_ROBOT, BEYOND_SECTION = "paper", "another robot", "beyond"


def claim_engines(
    empirical: fd.ModelResults | None, engines: dict[str, fd.ModelResults]
) -> list[tuple[str, fd.ModelResults]]:
    """The physics results a run holds: the paper's engine (ODE) first, then the reference engine
    (pybullet), then the others in registry order (``models.physics``)."""
    from morphlearn import models

    held = dict(engines)
    if empirical is not None:
        held[physics_models()[0]] = empirical
    return [(n, held[n]) for n in models.physics() if n in held]


def reason_of(claim: Claim, model: str) -> tuple[str, str]:
    """Why ours differs: (sentence, docs/results.md anchor), by claim, else a physics claim's by
    the engine that answers it (its plug-in's ``differs_reason``: a new engine brings its own)."""
    from morphlearn import models

    if claim.key in REASONS:
        return REASONS[claim.key]
    if claim.model == "physics":
        return models.get(model if model in models.MODELS else models.paper_engine()).differs_reason()  # type: ignore[attr-defined]
    raise KeyError(f"no reason in claims.REASONS for {claim.key!r} ({model}), which differs")


def claim_key(claim: Claim, model: str) -> str:
    """A row's key: the claim's, with a physics engine's name for engines other than the reference
    (and "physics_" for the rows of a claim no results of this run answer, which may stand beside
    the reference engine's answers of another robot: keys are unique)."""
    physics = claim.model == "physics" and model != physics_models()[0]
    return claim.key.replace("empirical_", f"{model}_", 1) if physics else claim.key


def claim_row(claim: Claim, model: str, ours: Ours | None, config: str) -> dict[str, str]:
    ours = ours or Ours(NOT_RUN)
    said, why = verdict(claim.kind, claim.value, ours.value, ours.scope)
    reason, anchor = reason_of(claim, model) if said == DIFFERS else (why, "")
    return {
        "key": claim_key(claim, model),
        "section": PAPER,
        "model": model_label(model),
        "quantity": claim.quantity,
        "paper": claim.paper,
        "source": claim.source,
        "ours": ours.text,
        "verdict": said,
        "reason": reason,
        "anchor": anchor,
        "config": config,
        "note": ours.note,
    }


def other_robot_row(claim: Claim, res: fd.ModelResults, ours: Ours | None, config: str) -> dict[str, str]:
    """A paper's physics claim as results of another robot or engine answer it: beyond the paper,
    beside the paper's value, with no verdict (its note says why: the plug-in's reason)."""
    ours = ours or Ours(NOT_RUN)
    label = model_label(res.model, res)
    return {
        "key": claim_key(claim, res.model),
        "section": OTHER_ROBOT,
        "model": label,
        "quantity": claim.quantity,
        "paper": claim.paper,
        "source": claim.source,
        "ours": ours.text,
        "config": config,
        "note": NOTE_SEP.join(x for x in (not_the_paper(res), ours.note) if x),
    }


def reproduction_table(
    theory: fd.ModelResults | None,
    empirical: fd.ModelResults | None,
    persistence: pd.DataFrame | None,
    config_name: str,
    near: float,
    learners: pd.DataFrame | None = None,
    engines: dict[str, fd.ModelResults] | None = None,
    coopt: tuple[pd.DataFrame, pd.DataFrame, float] | None = None,
    survey: fd.ModelResults | None = None,
    screen: tuple[fd.ModelResults, fd.ModelResults] | None = None,
    text_sweep: str | None = None,
) -> pd.DataFrame:
    """The table: the theory's claims, then the physics claims for each engine held (ODE first;
    ``empirical`` is the reference engine's results, ``engines`` the others'), then the rows
    beyond the paper of every registered stage: the physics survey read from a bundle
    (``survey``, config ``survey_from``), each further engine's survey and agreement rows, the
    learner rows when ``learners`` (learners/correlations.csv) is given, the coopt stage's when
    ``coopt`` (its summary, landscape table and step) is given, the screen's when ``screen`` (a
    fast model's map of every design and the paper's engine at its best, config ``screen_from``), the
    second theory sweep's when ``text_sweep`` (its bundle, config ``text_sweep_from``) is given."""
    engines = engines or {}
    rows = []
    said = {} if theory is None else theory_values(theory, persistence, near)
    for claim in (c for c in CLAIMS if c.model == "theory"):
        rows.append(claim_row(claim, "theory", said.get(claim.key), config_note(theory, config_name)))
    physics = claim_engines(empirical, engines)
    judges = {n for n, r in physics if not not_the_paper(r)}
    other_rows = []
    for name, res in physics:
        # the larger sets of designs that check its "best": the survey read from a bundle, the other engines
        others = ([survey] if survey is not None else []) + [r for n, r in physics if n != name]
        said = physics_values(res, others)
        judged = name in judges
        for claim in (c for c in CLAIMS if c.model == "physics"):
            config = config_note(res, config_name)
            if judged:
                rows.append(claim_row(claim, name, said.get(claim.key), config))
            else:
                other_rows.append(other_robot_row(claim, res, said.get(claim.key), config))
    if not judges:  # the paper's physics claims, unanswered in this run
        rows += [claim_row(c, "physics", None, config_name) for c in CLAIMS if c.model == "physics"]
    rows += other_rows
    inputs = TableInputs(
        theory, empirical, persistence, config_name, near, learners, engines, coopt, survey, screen, text_sweep
    )
    for name in stage_registry.STAGES:
        rows += [{"section": BEYOND_SECTION, **r} for r in stage_registry.rows_of(name)(inputs)]
    return pd.DataFrame(rows, columns=COLUMNS).fillna("")
