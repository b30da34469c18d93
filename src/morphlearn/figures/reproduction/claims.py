"""The paper's claims: what it states about the theory and the physics, where it says so, what
kind of number each is (the verdict rule compares by kind: ``verdict.TOLERANCES``), and why ours
differs where it does (a sentence here, the full reason in docs/results.md under its anchor).
Data only: every other module of the table imports it."""

from __future__ import annotations

from dataclasses import dataclass

NOT_RUN = "not in this run"
#: The table's columns: ``section`` "paper" (a claim of the paper, with its verdict) or "beyond";
#: ``anchor``: the section of docs/results.md that says why a "differs" differs.
COLUMNS = [
    "key",
    "section",
    "model",
    "quantity",
    "paper",
    "source",
    "ours",
    "verdict",
    "reason",
    "anchor",
    "config",
    "note",
]
#: Separates a row's notes in its ``note`` column (each note may hold "; " itself).
NOTE_SEP = " || "

#: Claim kinds, each compared by its own tolerance (verdict.TOLERANCES).
COUNT, METRIC, SHARE, YES_NO, DESIGN = "count", "metric", "share", "yes/no", "design"

#: The paper's best physics design: its text gives no coordinates; the authors' code names it
#: (docs/ode.md), and the ode model reproduces its 57 generalists.
PAPER_PHYSICS_BEST_DESIGN = ((-0.5, 0.125), (0.5, -0.375))


@dataclass(frozen=True)
class Claim:
    """One claim of the paper. ``value`` is the paper's number (or answer) the verdict compares
    ours with; None where the paper states none (the row is then not comparable)."""

    key: str
    #: "theory" or "physics" (a physics claim gets one row per physics engine a run holds)
    model: str
    quantity: str
    paper: str
    #: where the paper says it: text (its section), caption or figure
    source: str
    kind: str
    value: float | bool | tuple[float, float] | None


#: The theory's claims (the paper's Results, "Theoretical results", and Figs. 4-6).
THEORY: tuple[Claim, ...] = (
    Claim(
        "theory_canonical_generalists",
        "theory",
        "canonical design: generalist controllers (O = 4)",
        "57 of 14641 (0.4 %)",
        "Fig. 4 caption",
        COUNT,
        57,
    ),
    Claim(
        "theory_canonical_M_L", "theory", "canonical design: M_L", "0.049", "text, Theoretical results", METRIC, 0.049
    ),
    Claim(
        "theory_canonical_M_CF", "theory", "canonical design: M_CF", "0.24", "text, Theoretical results", METRIC, 0.24
    ),
    Claim(
        "theory_canonical_beaten",
        "theory",
        "asymmetric designs score higher than the canonical design on both metrics",
        "yes (many)",
        "text, Theoretical results; Fig. 6",
        YES_NO,
        True,
    ),
    Claim(
        "theory_paper_best_generalists",
        "theory",
        "design (-0.5,-0.25),(0.5,0.25): generalists",
        "2255 of 14641 (15.4 %)",
        "Fig. 5 caption",
        COUNT,
        2255,
    ),
    Claim(
        "theory_paper_best_M_L",
        "theory",
        "design (-0.5,-0.25),(0.5,0.25): M_L",
        "0.286",
        "text, Theoretical results",
        METRIC,
        0.286,
    ),
    Claim(
        "theory_paper_best_M_CF",
        "theory",
        "design (-0.5,-0.25),(0.5,0.25): M_CF",
        "0.636",
        "text, Theoretical results",
        METRIC,
        0.636,
    ),
    Claim(
        "theory_best_design",
        "theory",
        "design with the highest M_L",
        "(-0.5,-0.25),(0.5,0.25) and its mirror image",
        "text, Theoretical results; Figs. 3A, 5",
        DESIGN,
        ((-0.5, -0.25), (0.5, 0.25)),  # type: ignore[arg-type]
    ),
    Claim(
        "theory_best_M_L_with_M_CF_1",
        "theory",
        "highest M_L among designs with M_CF = 1 (several designs)",
        "0.206",
        "text, Theoretical results",
        METRIC,
        0.206,
    ),
    Claim(
        "theory_example_canonical",
        "theory",
        "canonical design: example generalists solve all 4 environments",
        "(0.6, 0.98), (0.77, 0.77)",
        "Fig. 4 caption",
        YES_NO,
        True,
    ),
    Claim(
        "theory_example_best",
        "theory",
        "best design: example generalists solve all 4 environments",
        "(-0.85, 0.82), (-0.8, 0.6), (-0.28, 0.37)",
        "Fig. 5 caption",
        YES_NO,
        True,
    ),
    Claim(
        "theory_persistence_best",
        "theory",
        "best design: generalists that stay near the source",
        "35 of 35",
        "text, Theoretical results",
        SHARE,
        35 / 35,
    ),
    Claim(
        "theory_persistence_canonical",
        "theory",
        "canonical design: generalists that stay near the source",
        "2 of 6",
        "text, Theoretical results",
        SHARE,
        2 / 6,
    ),
)

#: The physics claims (the paper's Results, "Empirical results", and Figs. 3C, 6D-F), made in the
#: Open Dynamics Engine (ODE) with the authors' robot; each physics engine a run holds answers them.
PHYSICS: tuple[Claim, ...] = (
    Claim(
        "empirical_canonical_w11",
        "physics",
        "canonical design: w = (1, 1) solves all 4 environments",
        "yes (the authors' fitness target and only generalist)",
        "text, Methods and Empirical results",
        YES_NO,
        True,
    ),
    Claim(
        "empirical_canonical_generalists",
        "physics",
        "canonical design: generalist controllers",
        "1 of 14641 (0.0068 %)",
        "text, Empirical results",
        COUNT,
        1,
    ),
    Claim(
        "empirical_canonical_M_L",
        "physics",
        "canonical design: M_L",
        "0.000068",
        "text, Empirical results",
        METRIC,
        0.000068,
    ),
    Claim(
        "empirical_canonical_M_CF",
        "physics",
        "canonical design: M_CF",
        "0.00052",
        "text, Empirical results",
        METRIC,
        0.00052,
    ),
    Claim(
        "empirical_paper_best_generalists",
        "physics",
        "the paper's best design (-0.5,0.125),(0.5,-0.375): generalists",
        "57 of 14641 (0.389 %)",
        "text, Empirical results (the design: the authors' code)",
        COUNT,
        57,
    ),
    Claim(
        "empirical_best_design",
        "physics",
        "design with the highest M_L",
        "(-0.5,0.125),(0.5,-0.375) (drawn, no coordinates in the text)",
        "Fig. 3C",
        DESIGN,
        PAPER_PHYSICS_BEST_DESIGN,  # type: ignore[arg-type]
    ),
    # values of the best design: judged at the paper's best design (claim_values.physics_values)
    Claim(
        "empirical_best_M_L",
        "physics",
        "the paper's best design: M_L",
        "0.0039",
        "text, Empirical results",
        METRIC,
        0.0039,
    ),
    Claim(
        "empirical_best_M_CF",
        "physics",
        "the paper's best design: M_CF",
        "0.038",
        "text, Empirical results",
        METRIC,
        0.038,
    ),
    Claim(
        "empirical_best_on_both",
        "physics",
        "one design is best by both M_L and M_CF",
        "yes",
        "text, Empirical results; Fig. 3 and Fig. 6 captions",
        YES_NO,
        True,
    ),
)

CLAIMS: tuple[Claim, ...] = THEORY + PHYSICS

#: (key, quantity, paper's value), every claim in table order. Keys are stable identifiers for
#: tests and downstream tools.
QUANTITIES: tuple[tuple[str, str, str], ...] = tuple((c.key, c.quantity, c.paper) for c in CLAIMS)

#: Why ours differs, where the verdict rule says it does: (one sentence, anchor of its section in
#: docs/results.md). Looked up by claim key, then (physics) by "physics": only the theory and the
#: paper's robot in the paper's engine are judged (results of another robot or engine are rows
#: beyond the paper, their reason said by their plug-in: ``Model.not_the_paper``); a differing
#: claim without a reason here is a test failure, not a silent blank.
REASONS: dict[str, tuple[str, str]] = {
    "theory_canonical_M_L": (
        "The paper's text value disagrees with its own Fig. 4 caption (57 of 14641 = 0.0039), which ours matches.",
        "differs-theory-text-m-l",
    ),
    "theory_paper_best_M_L": (
        "The paper's text value disagrees with its own Fig. 5 caption (2255 of 14641 = 0.154), which ours matches.",
        "differs-theory-text-m-l",
    ),
    "theory_canonical_M_CF": (
        "No horizon, light distance or success radius we ran gives the paper's M_CF values; Eq. 2 is implemented "
        "as written.",
        "differs-theory-m-cf",
    ),
    "theory_paper_best_M_CF": (
        "No horizon, light distance or success radius we ran gives the paper's M_CF values; Eq. 2 is implemented "
        "as written.",
        "differs-theory-m-cf",
    ),
    "theory_best_M_L_with_M_CF_1": (
        "No design reaches M_CF = 1 here: every design with a generalist also has controllers that solve only "
        "some environments.",
        "differs-theory-m-cf",
    ),
    "theory_best_design": (
        "The top 21 designs lie within 11 generalists (0.5 %) of each other; the paper's design is 21st here.",
        "differs-theory-best-design",
    ),
    "theory_persistence_canonical": (
        "None of an even spread of the canonical design's generalists stays near the light; the paper does not "
        "say which 6 it integrated or its rule for staying near.",
        "differs-theory-persistence",
    ),
}

#: The paper's column for rows beyond the paper (the learner stage, issue 15).
BEYOND = "beyond the paper (no learning algorithm tested)"
#: The paper's column for the theory-vs-physics rank agreement (issue 12).
BEYOND_MODELS = "beyond the paper (the two models were not compared design by design)"
#: The paper's column for the comparison of two physics engines (issue 25).
BEYOND_ENGINES = "beyond the paper (one physics engine, ODE)"
#: The paper's column for the coopt stage (issue 27): the question the paper closes on.
BEYOND_COOPT = "beyond the paper (its closing question, not tested there)"
