"""Rows of a physics survey (every design of the theory's grid): the paper's claims that need every
design and, beyond the paper, the theory-vs-physics rank agreement."""

from __future__ import annotations

from morphlearn import grid as gridmod
from morphlearn.figures import data as fd
from morphlearn.figures.reproduction.claim_values import asymmetric, exists_scope, grid_scope
from morphlearn.figures.reproduction.claims import BEYOND_MODELS, PAPER_PHYSICS_BEST_DESIGN, YES_NO
from morphlearn.figures.reproduction.inputs import TableInputs
from morphlearn.figures.reproduction.selection import is_survey, model_label, not_the_paper, physics_models
from morphlearn.figures.reproduction.text import config_note
from morphlearn.figures.reproduction.verdict import DIFFERS, verdict


def survey_rows(
    theory: fd.ModelResults,
    empirical: fd.ModelResults,
    config_name: str,
    model: str | None = None,
    label: str = "empirical survey",
    refined: fd.ModelResults | None = None,
) -> list[dict[str, str]]:
    """Rows of the survey: the paper's empirical claims that need every design (asymmetric
    designs best on both metrics, generalists rare) and, beyond the paper, whether the theory's
    ranking of designs carries over (Spearman rho with a 95 % bootstrap interval) and where the
    paper's best design ranks. ``model`` names the physics model's table (keys of other engines
    than the reference are prefixed with it, quantities with ``label``); ``refined``: the same
    engine's designs simulated on the survey's weight grid, which hold the paper's best design
    when the survey's grid does not (the 5-point grid: it is then ranked among the survey's designs
    by its own metrics)."""
    from morphlearn import metrics, models
    from morphlearn.analysis import compare

    model = model or physics_models()[0]  # default: the reference engine's table
    t = empirical.table
    n = len(t)
    names = (models.REFERENCE, model)
    both = compare.joined(theory.table, t, names=names)
    agree = compare.agreement(both, names=names)
    top_l, top_cf = metrics.rank_designs(t, "M_L"), metrics.rank_designs(t, "M_CF")
    best = top_l.iloc[0]
    canon = metrics.find_row(t, gridmod.canonical_design())
    with_g = int((t.generalists > 0).sum())
    asym = t[asymmetric(t)]
    # the paper's claim: the best asymmetric design is above the canonical design by each metric
    below = None if canon is None else all(float(asym[m].max()) > float(canon[m]) for m in metrics.METRICS)
    higher = 0 if canon is None else int(((asym.M_L > canon.M_L) & (asym.M_CF > canon.M_CF)).sum())
    canon_rank = (
        "canonical not simulated"
        if canon is None
        else f"{metrics.rank_of(t, canon, 'M_L')} by M_L, {metrics.rank_of(t, canon, 'M_CF')} by M_CF "
        f"(of {n}; ties share a rank); {higher} asymmetric designs higher on both"
    )
    same_pair = gridmod.DesignGrid(empirical.positions_per_axis).same_pair(best.design, top_cf.iloc[0].design)
    # the three best and every design tied with the third (once three of four tied designs listed)
    shown = top_l[top_l.M_L >= top_l.head(3).M_L.min()]
    top3 = "; ".join(
        f"{fd.design_label(*fd.row_design(r))} (M_L {r.M_L:.4g}, M_CF {r.M_CF:.4g})" for _, r in shown.iterrows()
    )
    engine = "physics" if label == "empirical survey" else label.split()[0]
    items = [
        (
            "survey_share_with_generalist",
            f"{label}: designs with at least one generalist",
            "(not stated)",
            f"{with_g} of {n} ({with_g / n:.1%})",
        ),
        ("survey_best_designs", f"{label}: the best designs by M_L", "(Fig. 3C, not as coordinates)", top3),
        (
            "survey_canonical_rank",
            f"{label}: the canonical design's rank",
            "below the best asymmetric design on both metrics",
            canon_rank,
        ),
        (
            "survey_best_on_both",
            f"{label}: one design (or mirror pair) best by both M_L and M_CF",
            "yes",
            "yes" if same_pair else f"no (best by M_CF: {fd.design_label(*fd.row_design(top_cf.iloc[0]))})",
        ),
    ]
    rank = _paper_best_rank(empirical, refined)
    if rank is not None:  # a survey of a grid without it and no refined row of it: no row
        items.append(("survey_paper_best_rank", f"{label}: the paper's best design's rank", "1 (Fig. 3C)", rank))
    items += [  # beyond the paper, after its claims
        ("survey_rho_M_L", f"theory vs {engine}: Spearman rho of M_L over designs", BEYOND_MODELS, agree["M_L"].text()),
        (
            "survey_rho_M_CF",
            f"theory vs {engine}: Spearman rho of M_CF over designs",
            BEYOND_MODELS,
            agree["M_CF"].text(),
        ),
    ]
    config = config_note(empirical, config_name)  # the survey's configuration: one note
    prefix = "" if label == "empirical survey" else f"{model}_"
    out = [
        {"key": prefix + k, "quantity": q, "paper": p, "ours": o, "config": config, "note": ""} for k, q, p, o in items
    ]
    # two of these are the paper's claims about all designs: verdicts by the table's rule, when the
    # survey is of the paper's robot in its engine (else beyond the paper, its plug-in says why)
    scope = grid_scope(empirical)
    source = {
        # that some asymmetric design is above the canonical one: a subset's "yes" answers it
        "survey_canonical_rank": ("text, Empirical results", below, exists_scope(scope, bool(below))),
        "survey_best_on_both": ("text, Empirical results; Fig. 3 and Fig. 6 captions", same_pair, scope),
    }
    other = not_the_paper(empirical)
    for row in out:
        if row["key"].removeprefix(prefix) not in source:
            continue
        if other:
            row["note"] = other
            continue
        where, ours, scope = source[row["key"].removeprefix(prefix)]
        said, why = verdict(YES_NO, True, ours, scope)
        # judged: the paper's robot in the paper's engine, which says why it differs
        reason, anchor = models.get(model).differs_reason() if said == DIFFERS else (why, "")  # type: ignore[attr-defined]
        row |= {"section": "paper", "model": f"{model_label(model)}: survey", "source": where}
        row |= {"verdict": said, "reason": reason, "anchor": anchor}
    return out


def _paper_best_rank(survey: fd.ModelResults, refined: fd.ModelResults | None) -> str | None:
    """The rank by each metric of the paper's best design among the survey's designs: its own row,
    or else its row of ``refined`` (same engine, same weight grid) ranked among them; None when
    neither holds it."""
    from morphlearn import metrics

    t = survey.table
    row, where = survey.row(*PAPER_PHYSICS_BEST_DESIGN), ""
    if row is None and refined is not None and len(refined.weights) == len(survey.weights):
        row, where = refined.row(*PAPER_PHYSICS_BEST_DESIGN), " and it: its own metrics, every cell simulated"
    if row is None:
        return None
    ranks = ", ".join(f"{metrics.rank_of(t, row, by)} by {by}" for by in metrics.METRICS)
    return f"{ranks} (among the {len(t)} surveyed designs{where}; ties share a rank)"


def rows(t: TableInputs) -> list[dict[str, str]]:
    """The survey read from a bundle (config ``survey_from``), then the run's own pybullet survey
    unless the bundle's is the reference engine's."""
    out: list[dict[str, str]] = []
    theory, survey, empirical = t.theory, t.survey, t.empirical
    if survey is not None and theory is not None and is_survey(theory, survey):
        reference = survey.model == physics_models()[0]
        # the same engine's refined designs (they may hold the paper's best design, the survey's grid not)
        refined = t.empirical if reference else t.engines.get(survey.model)
        if reference:  # the reference engine's survey: the plain survey rows
            out += survey_rows(theory, survey, t.config_name, refined=refined)
        else:
            label = f"{fd.engine_label(survey.model)} survey"
            out += survey_rows(theory, survey, t.config_name, model=survey.model, label=label, refined=refined)
    if is_survey(theory, empirical) and (survey is None or survey.model != physics_models()[0]):
        out += survey_rows(theory, empirical, t.config_name)  # type: ignore[arg-type]
    return out
