"""The paper's claims: what it states about the theory and the physics, and the paper's column of
the rows beyond it. Data only: every other module of the table imports it."""

from __future__ import annotations

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
#: The paper's column for the coopt stage (issue 27): the question the paper closes on.
BEYOND_COOPT = "beyond the paper (its closing question, not tested there)"
