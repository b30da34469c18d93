"""Rows of each further physics engine (beyond the paper, which used one): its survey or refined
rows, and whether it ranks the designs as the reference engine does."""

from __future__ import annotations

from morphlearn.figures import data as fd
from morphlearn.figures.reproduction.claims import BEYOND_ENGINES
from morphlearn.figures.reproduction.inputs import TableInputs
from morphlearn.figures.reproduction.selection import at_paper_weights, is_survey, physics_models
from morphlearn.figures.reproduction.stages.refined import refined_rows
from morphlearn.figures.reproduction.stages.survey import survey_rows
from morphlearn.figures.reproduction.text import config_note


def engine_rows(
    reference: fd.ModelResults, other: fd.ModelResults, names: tuple[str, str], label: str, config_name: str
) -> list[dict[str, str]]:
    """Beyond the paper: does a second physics engine rank the designs as the reference engine
    does? Spearman rho with 95 % bootstrap intervals over the designs both hold, and over those
    non-zero in either; top-10 overlap (ranks as :func:`metrics.rank_designs`)."""
    from morphlearn import metrics
    from morphlearn.analysis import compare

    both = compare.joined(reference.table, other.table, names=names)
    a, b = names
    ref = fd.engine_label(a)
    items = []
    ranked = len(both) >= compare.MIN_DESIGNS
    if not ranked:  # one row says so: no rho, no top-10 overlap ("2 of 2" tells nothing)
        items.append(
            (
                "rho_not_computed",
                f"{ref} vs {label}: Spearman rho and top-10 overlap of M_L and M_CF over designs",
                f"not computed: the two hold {len(both)} designs in common, and a comparison of rankings needs "
                f"at least {compare.MIN_DESIGNS} to tell agreement from chance",
            )
        )
    for m in metrics.METRICS if ranked else ():
        top = int(((both[f"rank_{m}_{a}"] <= 10) & (both[f"rank_{m}_{b}"] <= 10)).sum())
        # of at most the designs both hold (a few refined designs: not "of 10")
        top_row = (f"top10_{m}", f"{ref} vs {label}: designs in both top 10 by {m}", f"{top} of {min(10, len(both))}")
        ag = compare.spearman_ci(both[f"{m}_{a}"], both[f"{m}_{b}"], m)
        nz = both[(both[f"{m}_{a}"] > 0) | (both[f"{m}_{b}"] > 0)]
        ag_nz = compare.spearman_ci(nz[f"{m}_{a}"], nz[f"{m}_{b}"], m)  # too few: "undefined"
        items += [
            (f"rho_{m}", f"{ref} vs {label}: Spearman rho of {m} over designs", ag.text()),
            (
                f"rho_{m}_nonzero",
                f"{ref} vs {label}: Spearman rho of {m}, designs non-zero in either",
                ag_nz.text(),
            ),
            top_row,
        ]
    config = config_note(other, config_name)  # the engine's configuration: one note with its claims'
    return [
        {
            "key": f"engines_{b}_{k}",
            "quantity": q,
            "paper": BEYOND_ENGINES,
            "ours": o,
            "config": config,
            "note": "",
        }
        for k, q, o in items
    ]


def rows(t: TableInputs) -> list[dict[str, str]]:
    out: list[dict[str, str]] = []
    for name, res in t.engines.items():
        label = fd.engine_label(name)
        if is_survey(t.theory, res) and (t.survey is None or t.survey.model != name):
            out += survey_rows(t.theory, res, t.config_name, model=name, label=f"{label} survey")  # type: ignore[arg-type]
        elif at_paper_weights(res):
            out += refined_rows(t.theory, res, name, t.config_name)
        if t.empirical is not None:
            out += engine_rows(t.empirical, res, (physics_models()[0], name), label, t.config_name)
    return out
