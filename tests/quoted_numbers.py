# ruff: noqa: E501  (one quote per line, by design: a new number is a one-line change)
"""The registry of quoted numbers: each number a document states, bound to where it is read.

One entry per quote: ``(quote, expression, ...)``. The quote is the document's text around the
number (whitespace may differ, so it may cross a line break) with each bound number in braces;
each marked number gets one expression, evaluated in tests/quoted_sources.py's names (the
committed tables by short name, ``row``, ``rank``, ``spearman``, ``paper(claim key)``,
``cfg(config, key)``, ``csv(path)``) and compared rounded as the number is written.
``label("why")`` binds a number that names something (a version, a count of figures) to nothing.

To quote a new number: add one line to its document's list, e.g.
``("has {58} generalists", "row(theory, CANONICAL).generalists"),``; ``python
tools/quote_numbers.py DOC`` drafts the lines of a document's unbound numbers. A document listed
here has every number of its prose bound (tests/test_docs_numbers.py)."""

from __future__ import annotations

#: The sections of a document whose every number must be bound here (None: the whole document);
#: docs/results.md's other sections are, until bound, checked the old way (each number a value of
#: some committed table: tests/test_docs_numbers.py facts(); no number allowed for free).
STRICT: dict[str, list[str] | None] = {"README.md": None, "docs/results.md": ["The answer", "In one minute"]}

# fmt: off
QUOTES: dict[str, list[tuple[str, ...]]] = {
    "README.md": [
        # set-up and the default run
        ("(Python {3.11}, pip", "label('the Python version tools/setup.sh needs')"),
        ("reduced workflow ({625} designs, {41} x {41} controllers", "cfg('config.yaml', 'grid.positions_per_axis') ** 4", "cfg('config.yaml', 'grid.weights')", "cfg('config.yaml', 'grid.weights')"),
        ("about {4} minutes on {2} cores", "label('measured: the default run, docs/performance.md')", "label('the machine the cost was measured on')"),
        # the theory
        ("do not** ({6561} designs x {14,641} controllers)", "len(theory)", "cfg('config/paper.yaml', 'grid.weights') ** 2"),
        ("the canonical design has {58} generalists (paper: {57})", "row(theory, CANONICAL).generalists", "paper('theory_canonical_generalists')"),
        ("best design has {2,243} (paper: {2,255})", "row(theory, PAPER_BEST_THEORY).generalists", "paper('theory_paper_best_generalists')"),
        ("(canonical {0.24}, best {0.636}; ours {0.0173} and {0.8326})", "paper('theory_canonical_M_CF')", "paper('theory_paper_best_M_CF')", "row(theory, CANONICAL).M_CF", "row(theory, PAPER_BEST_THEORY).M_CF"),
        ("at `M_CF` = {1} (ours:", "label('the value of M_CF the paper names')"),
        ("`M_L` values ({0.049}, {0.286})", "paper('theory_canonical_M_L')", "paper('theory_paper_best_M_L')"),
        # the physics in ODE
        ("(paper: {1} of {14,641})", "paper('empirical_canonical_generalists')", "cfg('config/paper.yaml', 'grid.weights') ** 2"),
        ("best design has {57} (paper: {57}), `M_L` {0.00389} and `M_CF` {0.0388} (paper: {0.0039}, {0.038})", "row(ode, PAPER_BEST_ODE).generalists", "paper('empirical_paper_best_generalists')", "row(ode, PAPER_BEST_ODE).M_L", "row(ode, PAPER_BEST_ODE).M_CF", "paper('empirical_best_M_L')", "paper('empirical_best_M_CF')"),
        ("Surveyed over the {625} designs", "len(survey)"),
        ("{121} x {121}", "cfg('config/paper.yaml', 'grid.weights')", "cfg('config/paper.yaml', 'grid.weights')"),
        ("{5}-point grid", "positions(survey)"),
        ("{19} % of designs have a generalist, the best {56}, and the canonical design ranks {107}th", "100 * (survey.generalists > 0).mean()", "survey.generalists.max()", "rank(survey, int(at(survey, (0.5, 0.5), (0.5, -0.5)).design), 'M_L')"),
        ("over all {6561} designs it is the best as screened (ODE at the {22} best", "len(theory)", "len(screened)"),
        ("ODE run of all {6561}", "len(theory)"),
        # the reduced model
        ("{99.956} % of the {585,640} cells", "100 * ra_paper.cells_same.iloc[0]", "ra_paper.cells_compared.iloc[0]"),
        ("over the {625}-design survey", "ra_survey.designs.iloc[0]"),
        ("(Spearman of `M_L` {0.986}; the theory: {0.54}; the {10} best by each metric are ODE's {10}; every design's generalists within {2} of ODE's)", "ra_survey.rho_M_L.iloc[0]", "spearman(theory, survey, 'M_L')", "label('the top 10 the column counts')", "ra_survey.top10_M_L.iloc[0]", "2 if ra_survey.generalists_within_2.iloc[0] == 1 else -1"),
        # the body, not the engine
        ("best designs have {0} generalists in the authors' robot", "max(row(ode, THEORY_BEST_M_L).generalists, row(ode, PAPER_BEST_THEORY).generalists)"),
        ("MuJoCo has {33} times the paper's count for the canonical design ({33}) and {18} times for the best ({1,037})", "row(pb, CANONICAL).generalists / paper('empirical_canonical_generalists')", "row(pb, CANONICAL).generalists", "row(pb, BEST_OUR_BODY).generalists / paper('empirical_paper_best_generalists')", "row(pb, BEST_OUR_BODY).generalists"),
        ("outcome in {99.7} % and {99.9} % of {302,500} cells over {625} designs", "100 * agree[(agree.engine == 'mujoco') & (agree.robot == 'authors')].cells_same.iloc[0]", "100 * agree[(agree.engine == 'pybullet') & (agree.robot == 'authors')].cells_same.iloc[0]", "agree[agree.robot == 'authors'].cells_compared.iloc[0]", "agree[agree.robot == 'authors'].designs.iloc[0]"),
        ("solves {0.96} and {0.99}; with our body {0.71}-{0.83})", "agree[(agree.engine == 'mujoco') & (agree.robot == 'authors')].rho_solved.iloc[0]", "agree[(agree.engine == 'pybullet') & (agree.robot == 'authors')].rho_solved.iloc[0]", "agree[agree.robot == 'project'].rho_solved.min()", "agree[agree.robot == 'project'].rho_solved.max()"),
        # the learners
        ("over {325} designs", "learn.designs.iloc[0]"),
        ("(Spearman {0.88}-{0.93} over all designs)", "learn.rho_MCF_retention.min()", "learn.rho_MCF_retention.max()"),
        ("learned at all ({0.86}-{0.97})", "learn.rho_ML_success.min()", "learn.rho_ML_success.max()"),
        ("only weakly ({0.12}-{0.33}; {3} of their {4} bootstrap intervals include {0})", "learn[learn.learner != 'random'].rho_ML_success_pos.min()", "learn[learn.learner != 'random'].rho_ML_success_pos.max()", "(learn[learn.learner != 'random'].rho_ML_success_pos_lo < 0).sum()", "(learn.learner != 'random').sum()", "0"),
        # your own designs
        ("each in [-{0.5}, {0.5}]", "-gridmod.positions(2)[0]", "gridmod.positions(2)[-1]"),
        ("`status`: {4} environments", "len(gridmod.ENV_ANGLES_DEG)"),
        # measured at dc5762f: git clone, tools/setup.sh, then the recipe under /usr/bin/time -v, niced
        ("took {2} min {1} s of wall time and {37} CPU-s from a fresh clone (niced, {2} cores shared", "label('measured: the recipe from a fresh clone, wall')", "label('measured: wall')", "label('measured: user + system CPU')", "label('the machine it was measured on')"),
        ("`--model ode` takes about {1,800} CPU-s a design", "cost_line('docs/ode.md', r'about \\*\\*([\\d,]+) CPU-s at 121 x 121')"),
        ("the smallest that does: {21} for these three", "recipe_grid()"),
        # the render
        # measured (/usr/bin/time -v, niced, 2 loaded cores): 101 and 119 CPU-s at 0a70f09, 64 CPU-s and 50 s on i69
        ("Measured: {64}-{119} CPU-s, {50} s to {1} min {10} s of wall time on {2} cores", "label('measured render cost, least')", "label('measured render cost, most')", "label('measured render time, least')", "label('measured render time, most')", "label('measured render time, most')", "label('the machine it was measured on')"),
    ],
    "docs/results.md": [
        # The answer
        ("its resolution, {6561} designs x {14,641} controllers", "len(theory)", "cfg('config/paper.yaml', 'grid.weights') ** 2"),
        ("environments: {2,920} designs ({44.5} %) have no such generalist, the best has {2,254}", "(theory.generalists == 0).sum()", "100 * (theory.generalists == 0).mean()", "theory.generalists.max()"),
        ("(canonical design {58}, paper {57}; its best design {2,243}, paper {2,255})", "row(theory, CANONICAL).generalists", "paper('theory_canonical_generalists')", "row(theory, PAPER_BEST_THEORY).generalists", "paper('theory_paper_best_generalists')"),
        ("({3,422} of them on both metrics)", "(asymmetric(theory) & (theory.M_L > row(theory, CANONICAL).M_L) & (theory.M_CF > row(theory, CANONICAL).M_CF)).sum()"),
        ("its best design is {21}st by `M_L`", "rank(theory, PAPER_BEST_THEORY, 'M_L')"),
        ("the canonical design has {1} generalist and the paper's best design {57}, exactly", "row(ode, CANONICAL).generalists", "row(ode, PAPER_BEST_ODE).generalists"),
        ("only {19.0} % of the {625} surveyed designs", "100 * (survey.generalists > 0).mean()", "len(survey)"),
        ("the best of all {6561} rests on a screen (a validated reduced model over all {6561}, ODE at its {22}", "len(theory)", "len(red_paper)", "len(screened)"),
        ("best designs have {0} generalists in ODE, and over the {625} designs both hold", "max(row(ode, THEORY_BEST_M_L).generalists, row(ode, PAPER_BEST_THEORY).generalists)", "shared(theory, survey)"),
        ("(Spearman of `M_L` {0.543})", "spearman(theory, survey, 'M_L')"),
        ("ranks designs as ODE does (Spearman {0.986})", "ra_survey.rho_M_L.iloc[0]"),
        ("over {325} designs `M_CF` predicts how much real learners forget (Spearman {0.88}-{0.93}) and `M_L` which designs they learn ({0.86}-{0.97})", "learn.designs.iloc[0]", "learn.rho_MCF_retention.min()", "learn.rho_MCF_retention.max()", "learn.rho_ML_success.min()", "learn.rho_ML_success.max()"),
        ("the ES learners only weakly ({0.12}-{0.33})", "learn[learn.learner != 'random'].rho_ML_success_pos.min()", "learn[learn.learner != 'random'].rho_ML_success_pos.max()"),
        # the verdict rule (morphlearn.figures.reproduction.verdict.TOLERANCES)
        ("(a count within {2} controllers or {2} %, M_L or M_CF within {5} %, a share within {10} points", "tol('COUNT_ABS')", "100 * tol('COUNT_REL')", "100 * tol('METRIC_REL')", "100 * tol('SHARE_ABS')"),
        ("both at the paper's {121} x {121} controllers", "cfg('config/paper.yaml', 'grid.weights')", "cfg('config/paper.yaml', 'grid.weights')"),
        # In one minute
        ("| {57} of {14,641} | {58} | reproduced |", "paper('theory_canonical_generalists')", "cfg('config/paper.yaml', 'grid.weights') ** 2", "row(theory, CANONICAL).generalists"),
        ("| {2,255} | {2,243} | reproduced |", "paper('theory_paper_best_generalists')", "row(theory, PAPER_BEST_THEORY).generalists"),
        ("| {0.049}, {0.286} | {0.003961}, {0.1532} |", "paper('theory_canonical_M_L')", "paper('theory_paper_best_M_L')", "row(theory, CANONICAL).M_L", "row(theory, PAPER_BEST_THEORY).M_L"),
        ("(canonical, best; designs at M_CF = {1}) | {0.24}, {0.636}; several at {1} | {0.01726}, {0.8326}; none at {1} |", "label('the value of M_CF the claim names')", "paper('theory_canonical_M_CF')", "paper('theory_paper_best_M_CF')", "label('the value of M_CF the claim names')", "row(theory, CANONICAL).M_CF", "row(theory, PAPER_BEST_THEORY).M_CF", "1 if theory.M_CF.max() < 1 else -1"),
        ("the paper's is {21}st | differs", "rank(theory, PAPER_BEST_THEORY, 'M_L')"),
        ("| yes | yes: {3,422} asymmetric designs above it on both metrics |", "(asymmetric(theory) & (theory.M_L > row(theory, CANONICAL).M_L) & (theory.M_CF > row(theory, CANONICAL).M_CF)).sum()"),
        ("| {1}, at w = ({1}, {1}) | {1}, at w = ({1}, {1}) | reproduced |", "paper('empirical_canonical_generalists')", "label('the controller the paper names')", "label('the controller the paper names')", "row(ode, CANONICAL).generalists", "w11('ODE')", "w11('ODE')"),
        ("| {57}; M_L {0.0039}, M_CF {0.038} | {57}; M_L {0.003893}, M_CF {0.03883} | reproduced |", "paper('empirical_paper_best_generalists')", "paper('empirical_best_M_L')", "paper('empirical_best_M_CF')", "row(ode, PAPER_BEST_ODE).generalists", "row(ode, PAPER_BEST_ODE).M_L", "row(ode, PAPER_BEST_ODE).M_CF"),
        ("| best of {6561} | best of ODE's runs of the {22} best designs of all {6561} in the reduced model's map", "len(theory)", "len(screened)", "len(red_paper)"),
        ("best of the {10} designs run with every cell; above every design of the {625}-design survey", "len(ode)", "len(survey)"),
        ("(ODE did not run all {6561})", "len(theory)"),
        ("counts **{16} reproduced, {7} differ, {3} not comparable** of the {26} claims it judges", "(rep.verdict == 'reproduced').sum()", "(rep.verdict == 'differs').sum()", "(rep.verdict == 'not comparable').sum()", "rep.verdict.notna().sum()"),
        ("the {18} rows from pybullet and MuJoCo", "(rep.section == 'another robot').sum()"),
        # numbers with one meaning wherever they stand in this document
        ("{6561}", "len(theory)"),
        ("{121} x {121}", "cfg('config/paper.yaml', 'grid.weights')", "cfg('config/paper.yaml', 'grid.weights')"),
        ("{14,641}", "cfg('config/paper.yaml', 'grid.weights') ** 2"),
        ("{0.049}", "paper('theory_canonical_M_L')"),
        ("{0.286}", "paper('theory_paper_best_M_L')"),
        ("{0.24}", "paper('theory_canonical_M_CF')"),
        ("{0.636}", "paper('theory_paper_best_M_CF')"),
        ("{0.206}", "paper('theory_best_M_L_with_M_CF_1')"),
        ("{2,255}", "paper('theory_paper_best_generalists')"),
        ("T = {500}", "cfg('config.yaml', 'theory.horizon')"),
        # numbers once stale (issue 69): each bound to the column its sentence names
        ("| yes | yes: {3,422} asymmetric designs score higher on both metrics ({3,427} designs of any kind have a higher M_L) |", "(asymmetric(theory) & (theory.M_L > row(theory, CANONICAL).M_L) & (theory.M_CF > row(theory, CANONICAL).M_CF)).sum()", "(theory.M_L > row(theory, CANONICAL).M_L).sum()"),
        ("| {91.0} % of the {8,228} both simulated | {90.4} % of the {7,260} both simulated |", "100 * engine_row('mujoco', 'project').cells_same", "engine_row('mujoco', 'project').cells_compared", "100 * engine_row('pybullet', 'project').cells_same", "engine_row('pybullet', 'project').cells_compared"),
        ("at the best design ({1,037} and {1,040}) and the canonical one ({33} and {33}), less at the third design both hold, `(-0.5,0.375),(0.5,-0.5)` ({936} in pybullet, {985} in MuJoCo)", "row(pb, BEST_OUR_BODY).generalists", "row(mj, BEST_OUR_BODY).generalists", "row(pb, CANONICAL).generalists", "row(mj, CANONICAL).generalists", "at(pb, (-0.5, 0.375), (0.5, -0.5)).generalists", "at(mj, (-0.5, 0.375), (0.5, -0.5)).generalists"),
        ("retain (Spearman {0.88}-{0.93} over all designs) and M_L which designs are learned ({0.86}-{0.97})", "learn.rho_MCF_retention.min()", "learn.rho_MCF_retention.max()", "learn.rho_ML_success.min()", "learn.rho_ML_success.max()"),
        ("the two ES learners only weakly ({0.12}-{0.33}, and {3} of their {4} bootstrap intervals include {0}); random search, at {0.76}-{0.83}", "learn[learn.learner != 'random'].rho_ML_success_pos.min()", "learn[learn.learner != 'random'].rho_ML_success_pos.max()", "(learn[learn.learner != 'random'].rho_ML_success_pos_lo < 0).sum()", "(learn.learner != 'random').sum()", "0", "learn[learn.learner == 'random'].rho_ML_success_pos.min()", "learn[learn.learner == 'random'].rho_ML_success_pos.max()"),
    ],
}
# fmt: on
