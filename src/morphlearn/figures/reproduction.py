"""The reproduction table: every number the paper states about the two models, beside ours.

One row per quantity (``QUANTITIES`` lists them; a test checks they are all present), with the
paper's value, ours, the config/resolution that produced ours and a note. Counts of controllers
scale with the weight grid (the paper used 121 x 121), so at a reduced resolution compare the
fractions (M_L) rather than the counts. A quantity this run cannot give (model disabled, design
not simulated) is reported as "not in this run", never dropped.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from morphlearn import grid as gridmod
from morphlearn import provenance, store
from morphlearn.figures import data as fd
from morphlearn.figures.caption import PAPER_WEIGHTS, resolution_note, science_summary, subset_best

NOT_RUN = "not in this run"

#: (key, quantity, paper's value). Keys are stable identifiers for tests and downstream tools.
QUANTITIES: tuple[tuple[str, str, str], ...] = (
    (
        "theory_canonical_generalists",
        "theory, canonical design: generalist controllers (O = 4)",
        "57 of 14641 (0.39 %)",
    ),
    ("theory_canonical_M_L", "theory, canonical design: M_L", "0.049 (text); 57/14641 = 0.0039 (caption)"),
    ("theory_canonical_M_CF", "theory, canonical design: M_CF", "0.24"),
    ("theory_paper_best_generalists", "theory, design (-0.5,-0.25),(0.5,0.25): generalists", "2255 of 14641 (15.4 %)"),
    (
        "theory_paper_best_M_L",
        "theory, design (-0.5,-0.25),(0.5,0.25): M_L",
        "0.286 (text); 2255/14641 = 0.154 (caption)",
    ),
    ("theory_paper_best_M_CF", "theory, design (-0.5,-0.25),(0.5,0.25): M_CF", "0.636"),
    ("theory_best_design", "theory, design with the highest M_L", "(-0.5,-0.25),(0.5,0.25) and its mirror image"),
    ("theory_best_M_L_with_M_CF_1", "theory, highest M_L among designs with M_CF = 1", "0.206"),
    (
        "theory_example_canonical",
        "theory, canonical design: example generalists (Fig. 4)",
        "(0.6, 0.98), (0.77, 0.77) solve all 4",
    ),
    (
        "theory_example_best",
        "theory, best design: example generalists (Fig. 5)",
        "(-0.85, 0.82), (-0.8, 0.6), (-0.28, 0.37) solve all 4",
    ),
    ("theory_persistence_best", "theory, best design: generalists that stay near the source", "35 of 35"),
    ("theory_persistence_canonical", "theory, canonical design: generalists that stay near the source", "2 of 6"),
    (
        "empirical_canonical_w11",
        "empirical, canonical design: environments solved by w = (1, 1)",
        "4 of 4 (the authors' fitness target and only generalist)",
    ),
    ("empirical_canonical_M_L", "empirical, canonical design: M_L", "0.000068 (1 of 14641)"),
    ("empirical_canonical_M_CF", "empirical, canonical design: M_CF", "0.00052"),
    ("empirical_best_design", "empirical, design with the highest M_L", "(not stated as coordinates)"),
    ("empirical_best_M_L", "empirical, best design: M_L", "0.0039 (57 of 14641)"),
    ("empirical_best_M_CF", "empirical, best design: M_CF", "0.038"),
    ("empirical_best_on_both", "empirical, one design best by both M_L and M_CF", "yes"),
)
COLUMNS = ["key", "quantity", "paper", "ours", "config", "note"]
#: The paper's column for rows beyond the paper (the learner stage, issue 15).
BEYOND = "beyond the paper (no learning algorithm tested)"
#: The paper's column for the theory-vs-physics rank agreement (issue 12).
BEYOND_MODELS = "beyond the paper (the two models were not compared design by design)"
#: The paper's column for the comparison of two physics engines (issue 25).
BEYOND_ENGINES = "beyond the paper (one physics engine, pybullet)"
LEARNER_LABELS = {"random": "random search", "one_plus_one": "(1+1)-ES", "cmaes": "CMA-ES"}
#: The paper's column for the coopt stage (issue 27): the question the paper closes on.
BEYOND_COOPT = "beyond the paper (its closing question, not tested there)"
#: Setups of the coopt stage (coopt.setups.paper_setups; repeated here: this module stays light).
COOPT_SETUPS = {
    "a": "canonical body, 2 weights",
    "b": "canonical body, 4 weights",
    "c": "co-optimised body, 2 weights",
    "d": "co-optimised body, 4 weights",
    "e": "best two-weight design, 2 weights",
}


def _ci(r: pd.Series, key: str) -> str:
    if key not in r or pd.isna(r[key]):
        return "n/a"
    return f"{r[key]:+.3f} [{r[key + '_lo']:+.3f}, {r[key + '_hi']:+.3f}]"


def learner_rows(corr: pd.DataFrame, config_name: str) -> list[dict[str, str]]:
    """Rows beyond the paper: per learner and protocol, Spearman rho (95 % bootstrap interval)
    of M_L with the probability of reaching a generalist, of M_CF with 1 - forgetting rate
    (sequential), and the advantage over random search."""
    rows = []
    for _, r in corr.iterrows():
        name = f"{LEARNER_LABELS.get(r.learner, r.learner)}, {r.protocol} training"
        k = f"learners_{r.learner}_{r.protocol}"
        items = [(f"{k}_rho_M_L", f"{name}: Spearman rho(M_L, P(generalist))", _ci(r, "rho_ML_success"))]
        if r.protocol == "sequential":
            items.append(
                (f"{k}_rho_M_CF", f"{name}: Spearman rho(M_CF, 1 - forgetting rate)", _ci(r, "rho_MCF_retention"))
            )
        if r.learner != "random":
            items.append(
                (f"{k}_advantage", f"{name}: P(generalist) minus random search's", _ci(r, "advantage_vs_random"))
            )
        for key, quantity, value in items:
            note = f"{int(r.designs)} designs; learners/correlations.csv"
            rows.append(
                {"key": key, "quantity": quantity, "paper": BEYOND, "ours": value, "config": config_name, "note": note}
            )
    return rows


def coopt_rows(summary: pd.DataFrame, landscape: pd.DataFrame, sigma: float, config_name: str) -> list[dict[str, str]]:
    """Rows beyond the paper from the coopt stage (coopt/summary.csv, coopt/landscape.csv): per
    setup and protocol, P(generalist within the largest budget) [95 % Wilson] of random search and
    of the evolution strategies at step ``sigma``; the canonical design's four-weight M_L and M_CF
    beside its two-weight values on the same grid."""
    rows = []

    def add(key: str, quantity: str, value: str, note: str) -> None:
        rows.append(
            {
                "key": key,
                "quantity": quantity,
                "paper": BEYOND_COOPT,
                "ours": value,
                "config": config_name,
                "note": note,
            }
        )

    budget = int(summary.budget.max())
    keep = summary[(summary.budget == budget) & (summary.sigma0.isna() | (summary.sigma0 == sigma))]
    for protocol in ("joint", "sequential"):
        for setup, label in COOPT_SETUPS.items():
            g = keep[(keep.protocol == protocol) & (keep.setup == setup)]
            if not len(g):
                continue
            cells, runs = [], set()
            for learner in LEARNER_LABELS:
                for r in g[g.learner == learner].itertuples():
                    name = LEARNER_LABELS[learner] + ("" if pd.isna(r.sigma0) else f" (step {r.sigma0:g})")
                    cells.append(f"{name} {r.p_generalist:.2f} [{r.p_lo:.2f}, {r.p_hi:.2f}]")
                    runs.add(int(r.runs))
            add(
                f"coopt_{setup}_{protocol}_P_generalist",
                f"coopt ({setup}) {label}, {protocol} training: P(generalist within {budget} evaluations)",
                "; ".join(cells),
                f"{'/'.join(str(n) for n in sorted(runs))} runs per learner, 95 % Wilson intervals; coopt/summary.csv",
            )
    canon = landscape[landscape["name"] == "canonical"]
    if len(canon):
        r = canon.iloc[0]
        m = int(r.m)
        for metric in ("M_L", "M_CF"):
            add(
                f"coopt_canonical_{metric}_4w_vs_2w",
                f"coopt, canonical design: {metric} with four weights vs two",
                f"{r[metric + '_4w']:.4g} (4 weights) vs {r[metric + '_2w']:.4g} (2 weights)",
                f"{m} points per weight in [-1, 1] ({m}^4 controllers; two weights: the slice u1 = u2 = 0, "
                f"{m} x {m}); at the bundle's 121 x 121: {r[metric + '_bundle']:.4g}; coopt/landscape.csv",
            )
    return rows


def is_survey(theory: fd.ModelResults | None, empirical: fd.ModelResults | None) -> bool:
    """The empirical results cover every design of the theory's grid (config/survey.yaml)."""
    if theory is None or empirical is None or empirical.positions_per_axis != theory.positions_per_axis:
        return False
    return empirical.n_designs == gridmod.DesignGrid(theory.positions_per_axis or 0).size


def survey_rows(
    theory: fd.ModelResults,
    empirical: fd.ModelResults,
    config_name: str,
    model: str = "empirical",
    label: str = "empirical survey",
) -> list[dict[str, str]]:
    """Rows of the survey: the paper's empirical claims that need every design (asymmetric
    designs best on both metrics, generalists rare) and, beyond the paper, whether the theory's
    ranking of designs carries over (Spearman rho with a 95 % bootstrap interval). ``model``
    names the physics model's table (keys of other engines than the reference are prefixed with
    it, quantities with ``label``)."""
    from morphlearn import compare, metrics, models

    t = empirical.table
    n = len(t)
    names = (models.REFERENCE, model)
    both = compare.joined(theory.table, t, names=names)
    agree = compare.agreement(both, names=names)
    top_l, top_cf = metrics.rank_designs(t, "M_L"), metrics.rank_designs(t, "M_CF")
    best = top_l.iloc[0]
    canon = metrics.find_row(t, gridmod.canonical_design())
    with_g = int((t.generalists > 0).sum())
    canon_rank = (
        "canonical not simulated"
        if canon is None
        else f"{metrics.rank_of(t, canon, 'M_L')} by M_L, {metrics.rank_of(t, canon, 'M_CF')} by M_CF "
        f"(of {n}; ties share a rank)"
    )
    same = int(best.design) == int(top_cf.iloc[0].design)
    mirror_l, mirror_cf = (
        gridmod.DesignGrid(empirical.positions_per_axis).mirror(int(r.design)) for r in (best, top_cf.iloc[0])
    )
    same_pair = same or int(mirror_l) == int(top_cf.iloc[0].design) or int(mirror_cf) == int(best.design)
    top3 = "; ".join(
        f"{fd.design_label(*fd.row_design(r))} (M_L {r.M_L:.4g}, M_CF {r.M_CF:.4g})"
        for _, r in top_l.head(3).iterrows()
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
        ("survey_rho_M_L", f"theory vs {engine}: Spearman rho of M_L over designs", BEYOND_MODELS, agree["M_L"].text()),
        (
            "survey_rho_M_CF",
            f"theory vs {engine}: Spearman rho of M_CF over designs",
            BEYOND_MODELS,
            agree["M_CF"].text(),
        ),
    ]
    note = f"{model}: {science_summary(empirical)}"
    prefix = "" if label == "empirical survey" else f"{model}_"
    return [
        {"key": prefix + k, "quantity": q, "paper": p, "ours": o, "config": config_name, "note": note}
        for k, q, p, o in items
    ]


def physics_models() -> list[str]:
    """The registered physics engines' model names, the reference engine (pybullet) first."""
    from morphlearn import models
    from morphlearn.physics.model import Physics

    return sorted(
        (n for n, m in models.MODELS.items() if isinstance(m, Physics)), key=lambda n: not models.get(n).figure_body
    )  # type: ignore[attr-defined]


def engine_rows(
    reference: fd.ModelResults, other: fd.ModelResults, names: tuple[str, str], label: str, config_name: str
) -> list[dict[str, str]]:
    """Beyond the paper: does a second physics engine rank the designs as the reference engine
    does? Spearman rho with 95 % bootstrap intervals over the designs both hold, and over those
    non-zero in either; top-10 overlap (ranks as :func:`metrics.rank_designs`)."""
    from morphlearn import compare, metrics

    both = compare.joined(reference.table, other.table, names=names)
    a, b = names
    ref = fd.engine_label(a)
    items = []
    for m in metrics.METRICS:
        ag = compare.spearman_ci(both[f"{m}_{a}"], both[f"{m}_{b}"], m)
        nz = both[(both[f"{m}_{a}"] > 0) | (both[f"{m}_{b}"] > 0)]
        ag_nz = compare.spearman_ci(nz[f"{m}_{a}"], nz[f"{m}_{b}"], m)  # fewer than 3: "undefined"
        top = int(((both[f"rank_{m}_{a}"] <= 10) & (both[f"rank_{m}_{b}"] <= 10)).sum())
        items += [
            (f"rho_{m}", f"{ref} vs {label}: Spearman rho of {m} over designs", ag.text()),
            (
                f"rho_{m}_nonzero",
                f"{ref} vs {label}: Spearman rho of {m}, designs non-zero in either",
                ag_nz.text(),
            ),
            # of at most the designs both hold (a few refined designs: not "of 10")
            (f"top10_{m}", f"{ref} vs {label}: designs in both top 10 by {m}", f"{top} of {min(10, len(both))}"),
        ]
    note = f"{b}: {science_summary(other)}"
    return [
        {
            "key": f"engines_{b}_{k}",
            "quantity": q,
            "paper": BEYOND_ENGINES,
            "ours": o,
            "config": config_name,
            "note": note,
        }
        for k, q, o in items
    ]


def _frac(n: int, m: int) -> str:
    return f"{n} of {m} ({100 * n / m:.2f} %)"


def _config(res: fd.ModelResults | None, config_name: str) -> str:
    if res is None:
        return config_name
    return f"{config_name}: {resolution_note(res)}; {science_summary(res)}"


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
        out["theory_canonical_generalists"] = (_frac(int(canon.generalists), m2), scale)
        out["theory_canonical_M_L"] = (f"{canon.M_L:.4g}", "M_L = generalists / controllers, as the caption")
        out["theory_canonical_M_CF"] = (f"{canon.M_CF:.4g}", "generalists / controllers solving at least one")
    best = res.row(*fd.PAPER_BEST_DESIGN)
    if best is not None:
        out["theory_paper_best_generalists"] = (_frac(int(best.generalists), m2), scale)
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
        out["empirical_canonical_M_L"] = (f"{canon.M_L:.4g} ({_frac(int(canon.generalists), m2)})", scale)
        out["empirical_canonical_M_CF"] = (f"{canon.M_CF:.4g}", "")
    subset, _ = subset_best(res, others)
    top, top_cf = res.best("M_L"), res.best("M_CF")
    out["empirical_best_design"] = (fd.design_label(*fd.row_design(top)), subset)
    out["empirical_best_M_L"] = (f"{top.M_L:.4g} ({_frac(int(top.generalists), m2)})", scale)
    out["empirical_best_M_CF"] = (f"{top.M_CF:.4g}", "")
    same = fd.row_design(top) == fd.row_design(top_cf)
    out["empirical_best_on_both"] = (
        "yes" if same else f"no (best by M_CF: {fd.design_label(*fd.row_design(top_cf))})",
        subset,
    )
    return out


def at_paper_weights(res: fd.ModelResults | None) -> bool:
    """Physics results on the paper's 121 x 121 weight grid (the designs refined, issue 26)."""
    return res is not None and len(res.weights) == PAPER_WEIGHTS


def refined_rows(
    theory: fd.ModelResults | None, res: fd.ModelResults, name: str, config_name: str
) -> list[dict[str, str]]:
    """Rows of a physics engine's results that are not a survey (the designs refined at the
    paper's 121 x 121, issue 26): for an engine other than the reference, its canonical and best
    designs as the reference engine's rows ask (``<name>_...`` keys); for every engine, how the
    theory's best designs (by M_L and by M_CF) do in it, beside the designs it holds."""
    from morphlearn import metrics

    label = fd.engine_label(name)
    rows = []
    if name != physics_models()[0]:
        said = empirical_rows(res)
        for key, quantity, paper in QUANTITIES:
            if key in said:
                ours, note = said[key]
                rows.append(
                    {
                        "key": key.replace("empirical_", f"{name}_", 1),
                        "quantity": quantity.replace("empirical", label, 1),
                        "paper": f"{paper} (pybullet)",
                        "ours": ours,
                        "config": _config(res, config_name),
                        "note": note,
                    }
                )
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
                f"{fd.design_label(*fd.row_design(r))}{which}: {_frac(int(r.generalists), m2)} generalists, "
                f"M_L {r.M_L:.4g}, M_CF {r.M_CF:.4g}; rank {metrics.rank_of(res.table, r, 'M_L')} by M_L and "
                f"{metrics.rank_of(res.table, r, 'M_CF')} by M_CF of the {n} designs simulated"
            )
        rows.append(
            {
                "key": f"{name}_theory_best_{by}_in_physics",
                "quantity": f"{label}: the theory's best design by {by}, in physics",
                "paper": BEYOND_MODELS,
                "ours": ours,
                "config": _config(res, config_name),
                "note": f"theory's best by {by}: {fd.design_label(*design)}, M_L {top.M_L:.4g}, M_CF {top.M_CF:.4g}",
            }
        )
    return rows


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
) -> pd.DataFrame:
    """The table, one row per entry of ``QUANTITIES`` in that order, then the survey rows of the
    physics survey read from a bundle (``survey``, config ``survey_from``), for each further
    physics engine in ``engines`` (model name -> results) its survey and engine-agreement rows,
    the learner rows (beyond the paper) when ``learners`` (learners/correlations.csv) is given,
    then the coopt stage's rows when ``coopt`` (its summary, landscape table and step) is given."""
    ours: dict[str, tuple[str, str]] = {}
    if theory is not None:
        ours |= theory_rows(theory, persistence, near)
    if empirical is not None:
        ours |= empirical_rows(empirical, list((engines or {}).values()))
    rows = []
    for key, quantity, paper in QUANTITIES:
        res = {"theory": theory, "empirical": empirical}[key.split("_", 1)[0]]  # a key names its model
        value, note = ours.get(key, (NOT_RUN, ""))
        rows.append(
            {
                "key": key,
                "quantity": quantity,
                "paper": paper,
                "ours": value,
                "config": _config(res, config_name),
                "note": note,
            }
        )
    if survey is not None and theory is not None and is_survey(theory, survey):
        if survey.model == physics_models()[0]:  # the reference engine's survey: the plain survey rows
            rows += survey_rows(theory, survey, config_name)
        else:
            rows += survey_rows(
                theory, survey, config_name, model=survey.model, label=f"{fd.engine_label(survey.model)} survey"
            )
    if is_survey(theory, empirical) and (survey is None or survey.model != physics_models()[0]):
        rows += survey_rows(theory, empirical, config_name)
    if at_paper_weights(empirical) and not is_survey(theory, empirical):
        rows += refined_rows(theory, empirical, physics_models()[0], config_name)
    for name, res in (engines or {}).items():
        label = fd.engine_label(name)
        if is_survey(theory, res) and (survey is None or survey.model != name):
            rows += survey_rows(theory, res, config_name, model=name, label=f"{label} survey")
        elif at_paper_weights(res):
            rows += refined_rows(theory, res, name, config_name)
        if empirical is not None:
            rows += engine_rows(empirical, res, (physics_models()[0], name), label, config_name)
    if learners is not None:
        rows += learner_rows(learners, config_name)
    if coopt is not None:
        rows += coopt_rows(*coopt, config_name)
    return pd.DataFrame(rows, columns=COLUMNS)


def to_markdown(table: pd.DataFrame) -> str:
    """A GitHub Markdown table (no extra dependency), config column once below the table."""
    esc = lambda s: str(s).replace("|", "\\|")  # noqa: E731
    lines = ["| quantity | paper | ours | note |", "|---|---|---|---|"]
    lines += [f"| {esc(r.quantity)} | {esc(r.paper)} | {esc(r.ours)} | {esc(r.note)} |" for r in table.itertuples()]
    configs = dict.fromkeys(table.config)
    return "\n".join(["# Reproduction table", "", *lines, "", "Configs:", "", *(f"- {c}" for c in configs), ""])


def write(table: pd.DataFrame, csv: str | Path, md: str | Path, html: str | Path) -> None:
    table.to_csv(csv, index=False)
    Path(md).write_text(to_markdown(table))
    Path(html).write_text(table.drop(columns=["key"]).to_html(index=False, border=0) + "\n")


#: The table's sealed record of its inputs and outputs.
RECORD = "reproduction.provenance.json"


def write_record(
    results_dir: str | Path, models: list[str], outputs: list[str | Path], extra: list[str | Path]
) -> None:
    """The table's sealed provenance record (``reproduction.provenance.json``): the digests of the
    metrics tables it read, of the merged stores (their recorded overall digest: hashing a
    3.5 GB store costs minutes) and of its own files."""
    r = Path(results_dir)
    # paths relative to the results folder and no commit: a bundle re-rendered anywhere, at any
    # commit, gives the same bytes (as its captions do)
    rec = {
        "inputs": {
            str(Path(p).relative_to(r)): provenance.sha256_file(p)
            for p in [*(r / m / "metrics.csv" for m in models), *extra]
        },
        # the full dataset's digest: the same for a run's store and for its bundle's subset
        "merged_stores": {
            f"{m}/merged.zarr": provenance.merged_source(store.open_merged(r / m / "merged.zarr")) for m in models
        },
    }
    provenance.write_sealed(Path(outputs[0]).with_name(RECORD), rec, outputs)


def persistence_counts(theory: fd.ModelResults, settings: fd.TheorySettings, near: float, limit: int) -> pd.DataFrame:
    """Persistence table of the canonical and best designs (see :func:`data.persistence_table`)."""
    return fd.persistence_table(fd.persistence_designs(theory), theory, settings, near, limit)


def run(
    results_dir: str,
    config_name: str,
    thresholds: dict[str, dict[str, Any]],
    settings: dict[str, float],
    near: float,
    limit: int,
    learners_enabled: bool = False,
    coopt_sigma: float | None = None,
    survey: dict[str, Any] | None = None,
    stored_persistence: str | Path | None = None,
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Load the results of the models of ``thresholds`` (model -> its thresholds: the models this
    config runs) and build (reproduction table, persistence table). ``coopt_sigma``: the coopt
    stage ran (its rows use the evolution strategies at that step). ``survey``: the physics survey
    read from a bundle (its model and thresholds; config ``survey_from``). ``stored_persistence``:
    a persistence table already made for these results (render_only; checked at start by
    :func:`morphlearn.rules.check_stored_persistence`), read instead of integrated again."""
    corr = None
    if learners_enabled:
        provenance.check_derived(Path(results_dir) / "learners" / "correlations.csv")  # custody
        corr = pd.read_csv(Path(results_dir) / "learners" / "correlations.csv")
    coopt = None
    if coopt_sigma is not None:
        c = Path(results_dir) / "coopt"
        provenance.check_derived(c / "summary.csv")  # custody: the analysis's sealed record
        coopt = (pd.read_csv(c / "summary.csv"), pd.read_csv(c / "landscape.csv"), coopt_sigma)
    res = {m: fd.load_results(results_dir, m, th) for m, th in thresholds.items()}
    missing = [m for m, r in res.items() if r is None]
    if missing:
        raise FileNotFoundError(f"{missing[0]} is enabled but its results are missing under {results_dir}")
    theory, emp = res.get("theory"), res.get("empirical")
    if theory is None:
        raise FileNotFoundError(f"no theory results under {results_dir}")
    if stored_persistence is not None:
        pers = pd.read_csv(stored_persistence)
    else:
        pers = persistence_counts(theory, fd.TheorySettings(**settings), near, limit)
    engines = {m: r for m, r in res.items() if m in physics_models()[1:] and r is not None}
    table = reproduction_table(
        theory, emp, pers, config_name, near, corr, engines, coopt, fd.load_survey(results_dir, survey)
    )
    return table, pers
