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
here has every number of its prose bound (tests/test_docs_numbers.py); to bind another document,
add its list."""

from __future__ import annotations

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
        # the second theory sweep (results/theory-text)
        ("A second sweep at {11} x {11} weights and a horizon of {1000} (`results/theory-text`", "text_science('grid.weights')", "text_science('grid.weights')", "text_science('theory.horizon')"),
        ("gives the text's canonical {0.049} and {0.24} (ours {0.0496}, {0.24}) and its best `M_L` at `M_CF` = {1}, {0.206} (ours {0.2066}), but not the best design's {0.286} and {0.636}", "paper('theory_canonical_M_L')", "paper('theory_canonical_M_CF')", "row(theory_text, CANONICAL).M_L", "row(theory_text, CANONICAL).M_CF", "label('the value of M_CF the paper names')", "paper('theory_best_M_L_with_M_CF_1')", "theory_text[theory_text.M_CF == 1].M_L.max()", "paper('theory_paper_best_M_L')", "paper('theory_paper_best_M_CF')"),
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
        ("counts **{16} reproduced, {3} reproduced (inferred set-up), {11} differ, {3} not comparable** of the {33} claims it judges", "(rep.verdict == 'reproduced').sum()", "(rep.verdict == 'reproduced (inferred set-up)').sum()", "(rep.verdict == 'differs').sum()", "(rep.verdict == 'not comparable').sum()", "rep.verdict.notna().sum()"),
        # the second theory sweep (results/theory-text, its checks and the odeint runs)
        ("| theory, second sweep ({11} x {11}, horizon {1000}): the text's canonical M_L, M_CF; best M_L at M_CF = {1} | {0.049}, {0.24}; {0.206} | {0.0496}, {0.24}; {0.2066} | reproduced (inferred set-up)", "text_science('grid.weights')", "text_science('grid.weights')", "text_science('theory.horizon')", "label('the value of M_CF the paper names')", "paper('theory_canonical_M_L')", "paper('theory_canonical_M_CF')", "paper('theory_best_M_L_with_M_CF_1')", "row(theory_text, CANONICAL).M_L", "row(theory_text, CANONICAL).M_CF", "theory_text[theory_text.M_CF == 1].M_L.max()"),
        ("near the light | {0.286}, {0.636}; {2} of {6} | {0.1736}, {0.84}; {0} of {6} by our rule | differs |", "paper('theory_paper_best_M_L')", "paper('theory_paper_best_M_CF')", "paper('theory_persistence_canonical') * 6", "label('the paper integrated 6')", "row(theory_text, PAPER_BEST_THEORY).M_L", "row(theory_text, PAPER_BEST_THEORY).M_CF", "text_persistence()[0]", "text_persistence()[1]"),
        ("theory, second sweep: the paper's design's M_L, M_CF; \"{2} of {6}\" near", "paper('theory_persistence_canonical') * 6", "label('the paper integrated 6')"),
        ("### The second theory sweep: the text's values at {11} x {11} weights and a horizon of {1000}", "text_science('grid.weights')", "text_science('grid.weights')", "text_science('theory.horizon')"),
        # the text's values read as fractions, and the paper's 10^5 steps as a horizon
        ("fractions of an {11} x {11} weight grid ({0.049} = {6}/{121} truncated, {0.24} = {6}/{25}, {0.206} = {25}/{121} truncated), and the {10}^{5} integration steps it names, of {0.01} each, make a horizon of {1000}, not the {500} the captions' counts need", "text_science('grid.weights')", "text_science('grid.weights')", "paper('theory_canonical_M_L')", "round(paper('theory_canonical_M_L') * text_science('grid.weights') ** 2)", "text_science('grid.weights') ** 2", "paper('theory_canonical_M_CF')", "round(paper('theory_canonical_M_L') * text_science('grid.weights') ** 2)", "round(round(paper('theory_canonical_M_L') * text_science('grid.weights') ** 2) / paper('theory_canonical_M_CF'))", "paper('theory_best_M_L_with_M_CF_1')", "round(paper('theory_best_M_L_with_M_CF_1') * text_science('grid.weights') ** 2)", "text_science('grid.weights') ** 2", "label('the paper says 10^5 timesteps (Methods)')", "label('the paper says 10^5 timesteps (Methods)')", "text_science('theory.horizon') / 10**5", "text_science('theory.horizon')", "cfg('config.yaml', 'theory.horizon')"),
        ("config `config/theory_text.yaml`: all {6561} designs, {11} x {11} weights, horizon {1000}, r = {4}, radius {0.2}; every design's first-success times kept, so every shorter horizon is read from it; {5} CPU-minutes)", "len(theory_text)", "cfg('config/theory_text.yaml', 'grid.weights')", "cfg('config/theory_text.yaml', 'grid.weights')", "cfg('config/theory_text.yaml', 'theory.horizon')", "text_science('theory.r')", "text_science('theory.success_radius')", "text_cost.cpu_s.sum() / 60"),
        ("Each row's note gives the horizons of {500}-{1000} at which its verdict holds", "text_horizons()[0]", "text_horizons()[-1]"),
        ("| the text's value | paper | second sweep, horizon {1000} | verdict | horizons that give it |", "text_science('theory.horizon')"),
        ("| canonical design: M_L | {0.049} | {0.0496} ({6} generalists) | reproduced (inferred set-up) | {890}-{1000} |", "paper('theory_canonical_M_L')", "row(theory_text, CANONICAL).M_L", "row(theory_text, CANONICAL).generalists", "text_span('theory_canonical_M_L')[0]", "text_span('theory_canonical_M_L')[1]"),
        ("| canonical design: M_CF | {0.24} | {0.24} ({6} of {25} controllers that solve one environment or more) | reproduced (inferred set-up) | {890}-{1000} |", "paper('theory_canonical_M_CF')", "row(theory_text, CANONICAL).M_CF", "row(theory_text, CANONICAL).generalists", "row(theory_text, CANONICAL).at_least_one", "text_span('theory_canonical_M_CF')[0]", "text_span('theory_canonical_M_CF')[1]"),
        ("| designs at M_CF = {1}: highest M_L | {0.206} | {0.2066} ({25} generalists; {142} designs at M_CF = {1}) | reproduced (inferred set-up) | {560}-{1000} |", "label('the value of M_CF the paper names')", "paper('theory_best_M_L_with_M_CF_1')", "theory_text[theory_text.M_CF == 1].M_L.max()", "theory_text[theory_text.M_CF == 1].generalists.max()", "(theory_text.M_CF == 1).sum()", "label('the value of M_CF the paper names')", "text_span('theory_best_M_L_with_M_CF_1')[0]", "text_span('theory_best_M_L_with_M_CF_1')[1]"),
        ("`(-0.5,-0.25),(0.5,0.25)`: M_L | {0.286} | {0.1736} ({21} generalists of {25}) | differs | none |", "paper('theory_paper_best_M_L')", "row(theory_text, PAPER_BEST_THEORY).M_L", "row(theory_text, PAPER_BEST_THEORY).generalists", "row(theory_text, PAPER_BEST_THEORY).at_least_one"),
        ("| the paper's design: M_CF | {0.636} | {0.84} | differs | {510} only |", "paper('theory_paper_best_M_CF')", "row(theory_text, PAPER_BEST_THEORY).M_CF", "text_span('theory_paper_best_M_CF')[0] if text_span('theory_paper_best_M_CF')[0] == text_span('theory_paper_best_M_CF')[1] else -1"),
        ("`(-0.5,0.5),(0,-0.5)`, M_L {0.281}, M_CF {0.6939} | differs | none |", "row(theory_text, TEXT_BEST_M_L).M_L if rank(theory_text, TEXT_BEST_M_L, 'M_L') == 1 else -1", "row(theory_text, TEXT_BEST_M_L).M_CF"),
        ("| canonical generalists that stay near the light | {2} of {6} | {0} of {6} within {1} of the light; {2} of {6} within any threshold from {2.58} to below {9.94} | differs (by our rule) |", "paper('theory_persistence_canonical') * 6", "label('the paper integrated 6')", "text_persistence()[0]", "text_persistence()[1]", "default('figures.near_distance')", "paper('theory_persistence_canonical') * 6", "text_persistence()[1]", "text_persistence()[2][round(paper('theory_persistence_canonical') * 6) - 1]", "text_persistence()[2][round(paper('theory_persistence_canonical') * 6)]"),
        # other light distances (results/theory-text-checks/r_scan.csv), at horizon 1000
        ("Only r = {4} reproduces the canonical pair: over the canonical design, the paper's design and the {40} designs that carry the text's values at r = {4} (`results/theory-text-checks/r_scan.csv`), r = {3.5} gives the canonical design {12} generalists of {29} at {1000} (M_CF {0.4138}), r = {4.5} gives {3} of {23}, and r = {5} and {4} sqrt({2}) fewer still.", "text_science('theory.r') if [r for r in sorted(r_scan.r.unique()) if (scan(r).canonical_generalists, scan(r).canonical_solvers) == (row(theory_text, CANONICAL).generalists, row(theory_text, CANONICAL).at_least_one)] == [text_science('theory.r')] else -1", "scan(3.5).designs_run - 2", "text_science('theory.r')", "scan(3.5).r", "scan(3.5).canonical_generalists", "scan(3.5).canonical_solvers", "scan(3.5).horizon", "scan(3.5).canonical_mcf", "scan(4.5).r", "scan(4.5).canonical_generalists", "scan(4.5).canonical_solvers", "scan(5).r if max(scan(5).canonical_generalists, scan(r_scan.r.max()).canonical_generalists) < scan(4.5).canonical_generalists else -1", "r_scan.r.max() / np.sqrt(2)", "label('the 2 of sqrt(2)')"),
        ("The highest M_L at M_CF = {1} among those designs is {0.2066} at r = {3.5} too, {0.1983} at r = {4.5} and {0.124} at r = {5}; at {4} sqrt({2}) none of them has M_CF = {1} (horizon {1000}).", "label('the value of M_CF the paper names')", "scan(3.5).cf1_best_ml", "scan(3.5).r", "scan(4.5).cf1_best_ml", "scan(4.5).r", "scan(5).cf1_best_ml", "scan(5).r", "r_scan.r.max() / np.sqrt(2) if scan(r_scan.r.max()).cf1_designs == 0 else -1", "label('the 2 of sqrt(2)')", "label('the value of M_CF the paper names')", "scan(5).horizon"),
        # the best design's values, and the paper's integrator (results/theory-text-odeint)
        ("the paper's design has {21} generalists here ({0.1736}), and the best design by M_L, {34} generalists of {49} ({0.281}, {0.6939})", "row(theory_text, PAPER_BEST_THEORY).generalists", "row(theory_text, PAPER_BEST_THEORY).M_L", "row(theory_text, TEXT_BEST_M_L).generalists if rank(theory_text, TEXT_BEST_M_L, 'M_L') == 1 else -1", "row(theory_text, TEXT_BEST_M_L).at_least_one", "row(theory_text, TEXT_BEST_M_L).M_L", "row(theory_text, TEXT_BEST_M_L).M_CF"),
        ("(its {17} flagged trajectories,", "row(theory_text, TEXT_BEST_M_L).flagged"),
        ("{0.636} = {35}/{55} points to a design with {35} generalists of {55} controllers that solve one environment or more: none has them at horizon {1000} here.", "paper('theory_paper_best_M_CF')", "round(paper('theory_paper_best_M_L') * text_science('grid.weights') ** 2)", "round(round(paper('theory_paper_best_M_L') * text_science('grid.weights') ** 2) / paper('theory_paper_best_M_CF'))", "round(paper('theory_paper_best_M_L') * text_science('grid.weights') ** 2)", "round(round(paper('theory_paper_best_M_L') * text_science('grid.weights') ** 2) / paper('theory_paper_best_M_CF'))", "text_science('theory.horizon') if not ((theory_text.generalists == round(paper('theory_paper_best_M_L') * text_science('grid.weights') ** 2)) & (theory_text.generalists == (theory_text.at_least_one * paper('theory_paper_best_M_CF')).round())).any() else -1"),
        ("success tested on {10}^{5} output samples; `results/theory-text-odeint`) the paper's design has {23} generalists of {25} (M_L {0.1901}, M_CF {0.92}), two more than our kernel's {21}, and the canonical design the same {6} of {25}.", "label('the base of 10^5')", "cost_line('results/theory-text-odeint/README.md', r'with 10\\^(\\d+) output samples')", "row(odeint, PAPER_BEST_THEORY).odeint_generalists if row(odeint, PAPER_BEST_THEORY).odeint_generalists - row(odeint, PAPER_BEST_THEORY).kernel_generalists == 2 else -1", "row(odeint, PAPER_BEST_THEORY).odeint_solvers", "row(odeint, PAPER_BEST_THEORY).odeint_M_L", "row(odeint, PAPER_BEST_THEORY).odeint_M_CF", "row(odeint, PAPER_BEST_THEORY).kernel_generalists", "row(odeint, CANONICAL).odeint_generalists if (row(odeint, CANONICAL).odeint_generalists, row(odeint, CANONICAL).odeint_solvers) == (row(odeint, CANONICAL).kernel_generalists, row(odeint, CANONICAL).kernel_solvers) else -1", "row(odeint, CANONICAL).odeint_solvers"),
        # the canonical design's generalists near the light, integrated to the horizon
        ("The canonical design has {6} generalists at {1000}, as many as the paper's \"{6} found controllers\"", "row(theory_text, CANONICAL).generalists", "text_science('theory.horizon')", "label('the paper integrated 6')"),
        ("Integrated to {1000}, the two that stay nearest never move farther than {2.58} from the light after their first success, the others {9.94} or more: any threshold in between gives the paper's {2} of {6}, our {1} gives none.", "text_science('theory.horizon')", "text_persistence()[2][round(paper('theory_persistence_canonical') * 6) - 1]", "text_persistence()[2][round(paper('theory_persistence_canonical') * 6)]", "paper('theory_persistence_canonical') * 6", "label('the paper integrated 6')", "default('figures.near_distance') if text_persistence()[0] == 0 else -1"),
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
        # the theory at the paper's resolution
        ("all 6561 designs ({9} sensor positions per axis) x 14,641 controllers x {4} environments, r = {4}, T = 500, success radius {0.2}", "positions(theory)", "len(gridmod.ENV_ANGLES_DEG)", "cfg('config.yaml', 'theory.r')", "cfg('config.yaml', 'theory.success_radius')"),
        ("| {57} generalists (caption); M_L 0.049 (text), M_CF 0.24 | {58} generalists; M_L {0.003961}, M_CF {0.01726}; {3428}th of 6561 by M_L, {3472}nd by M_CF |", "paper('theory_canonical_generalists')", "row(theory, CANONICAL).generalists", "row(theory, CANONICAL).M_L", "row(theory, CANONICAL).M_CF", "rank(theory, CANONICAL, 'M_L')", "rank(theory, CANONICAL, 'M_CF')"),
        ("| {2,243}; M_L {0.1532}, M_CF {0.8326}, the best of all by M_CF |", "row(theory, PAPER_BEST_THEORY).generalists", "row(theory, PAPER_BEST_THEORY).M_L", "row(theory, PAPER_BEST_THEORY).M_CF if rank(theory, PAPER_BEST_THEORY, 'M_CF') == 1 else -1"),
        ("and its mirror image, {2,254} (M_L {0.154}) | differs", "row(theory, THEORY_BEST_M_L).generalists", "row(theory, THEORY_BEST_M_L).M_L"),
        ("| designs with M_CF = {1}, and their best M_L |", "label('the value of M_CF the claim names')"),
        ("none: the largest M_CF is {0.8326} |", "theory.M_CF.max()"),
        ("| {35} of {35} | {35} of {35} | reproduced |", "paper('theory_persistence_best') * 35", "label('the paper integrated 35')", "pers[pers.design == best_label()].stays_near.sum()", "(pers.design == best_label()).sum()"),
        ("| {2} of {6} | {0} of {35} | differs |", "paper('theory_persistence_canonical') * 6", "label('the paper integrated 6')", "pers[pers.design == 'canonical'].stays_near.sum()", "(pers.design == 'canonical').sum()"),
        ("{2,920} of the 6561 designs ({44.5} %) have no generalist. M_L has median {0.0070} and maximum {0.154}; M_CF median {0.0557} and maximum {0.8326}. The two metrics rank designs almost alike (Spearman {0.973})", "(theory.generalists == 0).sum()", "100 * (theory.generalists == 0).mean()", "theory.M_L.median()", "theory.M_L.max()", "theory.M_CF.median()", "theory.M_CF.max()", "spearman_within(theory, 'M_L', 'M_CF')"),
        ("{4,990,940} of the {384} million trajectories ({1.3} %, in {4,200} designs)", "theory.flagged.sum()", "len(theory) * cfg('config/paper.yaml', 'grid.weights') ** 2 * 4 / 1e6", "100 * theory.flagged.sum() / (len(theory) * cfg('config/paper.yaml', 'grid.weights') ** 2 * 4)", "(theory.flagged > 0).sum()"),
        ("(canonical {57} of 14,641, Fig. 4; best 2,255, Fig. 5)", "paper('theory_canonical_generalists')"),
        ("the captions give {0.0039} and {0.154}; the text disagrees with them by factors of {12.6} and {1.9}", "paper('theory_canonical_generalists') / cfg('config/paper.yaml', 'grid.weights') ** 2", "paper('theory_paper_best_generalists') / cfg('config/paper.yaml', 'grid.weights') ** 2", "paper('theory_canonical_M_L') / (paper('theory_canonical_generalists') / cfg('config/paper.yaml', 'grid.weights') ** 2)", "paper('theory_paper_best_M_L') / (paper('theory_paper_best_generalists') / cfg('config/paper.yaml', 'grid.weights') ** 2)"),
        ("designs at M_CF = {1})", "label('the value of M_CF the paper names')"),
        ("(ours: {0.01726} and {0.8326})", "row(theory, CANONICAL).M_CF", "row(theory, PAPER_BEST_THEORY).M_CF"),
        ("no design reaches M_CF = {1}:", "1 if theory.M_CF.max() < 1 else -1"),
        ("stays below {1}.", "label('the bound of a ratio')"),
        ("the designs at M_CF = {1} have", "label('the value of M_CF the paper names')"),
        ("and its mirror image ({2,254} generalists); the paper's `(-0.5,-0.25),(0.5,0.25)` has {2,243} here and ranks {21}st", "row(theory, THEORY_BEST_M_L).generalists", "row(theory, PAPER_BEST_THEORY).generalists", "rank(theory, PAPER_BEST_THEORY, 'M_L')"),
        ("The top {22} designs lie within {11} generalists ({0.5} %)", "len(top(theory, 22))", "top(theory, 22).generalists.max() - top(theory, 22).generalists.min()", "100 * (top(theory, 22).generalists.max() - top(theory, 22).generalists.min()) / top(theory, 22).generalists.max()"),
        ("All {22} put one sensor at the back (x = -{0.5}) and one at the front (x = {0.5}); {18} put them on opposite sides, and {4} (designs {153}, {727}, {5913} and {6487})", "len(top(theory, 22))", "-gridmod.positions(2)[0]", "gridmod.positions(2)[-1]", "opposite_sides(top(theory, 22)).sum()", "(~opposite_sides(top(theory, 22))).sum()", "sorted(top(theory, 22).design[~opposite_sides(top(theory, 22))])[0]", "sorted(top(theory, 22).design[~opposite_sides(top(theory, 22))])[1]", "sorted(top(theory, 22).design[~opposite_sides(top(theory, 22))])[2]", "sorted(top(theory, 22).design[~opposite_sides(top(theory, 22))])[3]"),
        ("persistence differs ({2} of {6})", "paper('theory_persistence_canonical') * 6", "label('the paper integrated 6')"),
        ("The paper integrated {6} of the canonical design's generalists and says {2} stay near", "label('the paper integrated 6')", "paper('theory_persistence_canonical') * 6"),
        ("not say which {6},", "label('the paper integrated 6')"),
        ("an even spread of {35} of the {58}", "(pers.design == 'canonical').sum()", "row(theory, CANONICAL).generalists"),
        ("farther than {1} from the light", "default('figures.near_distance')"),
        ("The best design's {35} of {35} is reproduced", "pers[pers.design == best_label()].stays_near.sum()", "(pers.design == best_label()).sum()"),
        # ODE
        ("({10} designs, every cell", "len(ode)"),
        ("(all {625} designs of the {5}-point grid", "len(survey)", "positions(survey)"),
        ("| {1} of 14,641 | {1}, at w = ({1}, {1}) | reproduced |", "paper('empirical_canonical_generalists')", "row(ode, CANONICAL).generalists", "w11('ODE')", "w11('ODE')"),
        ("only generalist is w = ({1}, {1}) |", "label('the controller the paper names')", "label('the controller the paper names')"),
        ("| {0.000068}, {0.00052} | {0.0000683}, {0.000524} | reproduced |", "paper('empirical_canonical_M_L')", "paper('empirical_canonical_M_CF')", "row(ode, CANONICAL).M_L", "row(ode, CANONICAL).M_CF"),
        ("(the authors' code names it) | {57} | {57} | reproduced |", "paper('empirical_paper_best_generalists')", "row(ode, PAPER_BEST_ODE).generalists"),
        ("| its M_L, M_CF | {0.0039}, {0.038} | {0.003893}, {0.03883} | reproduced |", "paper('empirical_best_M_L')", "paper('empirical_best_M_CF')", "row(ode, PAPER_BEST_ODE).M_L", "row(ode, PAPER_BEST_ODE).M_CF"),
        ("best of the {22} best of all 6561 designs in the reduced model, run in ODE, every other design ruled out by the screen; best of the {10} run exhaustively", "len(screened)", "len(ode)"),
        ("not comparable: {10} of 6561 designs exhaustive, {625} surveyed |", "len(ode)", "len(survey)"),
        ("| yes | yes: {57} generalists against {1}; the canonical design is {107}th of {625} by M_L and {119}th by M_CF | agrees |", "row(ode, PAPER_BEST_ODE).generalists", "row(ode, CANONICAL).generalists", "rank(survey, int(at(survey, (0.5, 0.5), (0.5, -0.5)).design), 'M_L')", "len(survey)", "rank(survey, int(at(survey, (0.5, 0.5), (0.5, -0.5)).design), 'M_CF')"),
        ("| histograms | {119} of {625} designs ({19.0} %) have a generalist, at most {56} | agrees in shape |", "(survey.generalists > 0).sum()", "len(survey)", "100 * (survey.generalists > 0).mean()", "survey.generalists.max()"),
        ("| the paper's best design | **{57}** | {1,468} | {0.003893} | {0.03883} |", "row(ode, 478).generalists", "row(ode, 478).at_least_one", "row(ode, 478).M_L", "row(ode, 478).M_CF"),
        ("| the survey's best by both | {56} | {1,474} | {0.003825} | {0.03799} |", "row(ode, 396).generalists", "row(ode, 396).at_least_one", "row(ode, 396).M_L", "row(ode, 396).M_CF"),
        ("| the survey's top {10}; best on our body in pybullet and MuJoCo | {56} | {1,872} | {0.003825} | {0.02991} |", "label('a top-10 list')", "row(ode, 720).generalists", "row(ode, 720).at_least_one", "row(ode, 720).M_L", "row(ode, 720).M_CF"),
        ("`(-0.5,0.25),(0.5,-0.25)` | the survey's top {10} | {46} | {1,464} | {0.003142} | {0.03142} |", "label('a top-10 list')", "row(ode, 560).generalists", "row(ode, 560).at_least_one", "row(ode, 560).M_L", "row(ode, 560).M_CF"),
        ("`(-0.5,-0.25),(0.5,-0.5)` | the survey's top {10} | {46} | {1,468} | {0.003142} | {0.03134} |", "label('a top-10 list')", "row(ode, 234).generalists", "row(ode, 234).at_least_one", "row(ode, 234).M_L", "row(ode, 234).M_CF"),
        ("| the survey's top {10} by M_L | {42} | {1,710} | {0.002869} | {0.02456} |", "label('a top-10 list')", "row(ode, 722).generalists", "row(ode, 722).at_least_one", "row(ode, 722).M_L", "row(ode, 722).M_CF"),
        ("| the survey's top {10} by M_CF | {39} | {1,393} | {0.002664} | {0.02800} |", "label('a top-10 list')", "row(ode, 398).generalists", "row(ode, 398).at_least_one", "row(ode, 398).M_L", "row(ode, 398).M_CF"),
        ("| the canonical design | {1} | {1,910} | {0.0000683} | {0.000524} |", "row(ode, CANONICAL).generalists", "row(ode, CANONICAL).at_least_one", "row(ode, CANONICAL).M_L", "row(ode, CANONICAL).M_CF"),
        ("| the theory's best by M_L | {0} | {845} | {0} | {0} |", "row(ode, THEORY_BEST_M_L).generalists", "row(ode, THEORY_BEST_M_L).at_least_one", "row(ode, THEORY_BEST_M_L).M_L", "row(ode, THEORY_BEST_M_L).M_CF"),
        ("| the theory's best by M_CF | {0} | {957} | {0} | {0} |", "row(ode, PAPER_BEST_THEORY).generalists", "row(ode, PAPER_BEST_THEORY).at_least_one", "row(ode, PAPER_BEST_THEORY).M_L", "row(ode, PAPER_BEST_THEORY).M_CF"),
        ("on the {8} designs both hold, its adaptive grid missed {0} of {17,183} successes and {0} of {286} generalists", "survey_check()['designs']", "0", "survey_check()['successes']", "0", "survey_check()['generalists']"),
        ("`(-0.5,0),(0.5,-0.5)` with {56} generalists, is one of", "at(survey, (-0.5, 0), (0.5, -0.5)).generalists"),
        ("nearest neighbours on the {5}-point grid", "positions(survey)"),
        ("ODE holds {10} designs exhaustively and surveys {625}", "len(ode)", "len(survey)"),
        ("its best design by both metrics is the paper's, with {56} generalists (ODE: {57}). ODE then ran the map's {20} best designs by each metric and their mirror images, {22} designs", "at(red_paper, (-0.5, 0.125), (0.5, -0.375)).generalists", "row(ode, PAPER_BEST_ODE).generalists", "cfg('config/ode_screened_paper.yaml', 'ode.designs.top_of.n')", "len(screened)"),
        ("the paper's design with {57} generalists, M_L {0.003893}, M_CF {0.03883}, its exhaustive run's numbers", "at(screened, (-0.5, 0.125), (0.5, -0.375)).generalists", "at(screened, (-0.5, 0.125), (0.5, -0.375)).M_L", "at(screened, (-0.5, 0.125), (0.5, -0.375)).M_CF"),
        ("{99.957} % of {1,288,408} cells and ranks them at Spearman {0.98}", "100 * ra_screened.cells_same.iloc[0]", "ra_screened.cells_compared.iloc[0]", "ra_screened.rho_M_L.iloc[0]"),
        ("difference at the {22} refined designs", "len(screened)"),
        ("the map's best design outside the {22}, `(-0.5,0.375),(0.5,-0.375)`, has {0.002937}, + {0.00014} ({2} generalists) = {0.003074} < {0.003893}", "len(screened)", "screen_rule('M_L').best_outside.M_L", "screen_rule('M_L').margin", "screen_rule('M_L').margin * cfg('config/paper.yaml', 'grid.weights') ** 2", "screen_rule('M_L').best_outside.M_L + screen_rule('M_L').margin", "screen_rule('M_L').best.M_L"),
        ("has {0.02915}, + {0.0014} = {0.0305} < {0.03883}:", "screen_rule('M_CF').best_outside.M_CF", "screen_rule('M_CF').margin", "screen_rule('M_CF').best_outside.M_CF + screen_rule('M_CF').margin", "screen_rule('M_CF').best.M_CF"),
        ("no design outside the {22} is off", "len(screened)"),
        ("the largest error at the {22} (the margin it needs: {14} generalists by M_L, where the largest error seen is {2}, there and over the {625} designs of the survey", "len(screened)", "(screen_rule('M_L').best.M_L - screen_rule('M_L').best_outside.M_L) * cfg('config/paper.yaml', 'grid.weights') ** 2", "screen_rule('M_L').margin * cfg('config/paper.yaml', 'grid.weights') ** 2", "len(survey)"),
        ("at the {40} designs of the random check", "ra_random.designs.iloc[0]"),
        ("without the map's {56}-generalist designs", "red_paper.generalists.max()"),
        # beyond the paper
        ("have **{0}** generalists in ODE ({845} and {957} controllers", "max(row(ode, THEORY_BEST_M_L).generalists, row(ode, PAPER_BEST_THEORY).generalists)", "row(ode, THEORY_BEST_M_L).at_least_one", "row(ode, PAPER_BEST_THEORY).at_least_one"),
        ("ranks {729}th of 6561 by M_L in the theory", "rank(theory, PAPER_BEST_ODE, 'M_L')"),
        ("Over the {625} designs both hold, theory and ODE rank designs only loosely alike: Spearman {0.543} for M_L and {0.488} for M_CF, and no design is in both top {10}s", "shared(theory, survey)", "spearman(theory, survey, 'M_L')", "spearman(theory, survey, 'M_CF')", "label('a top-10 list')"),
        ("have sensor {1} (which drives the right wheel)", "label('the sensor named')"),
        ("outcome in **{99.956} %** of the {585,640} cells", "100 * ra_paper.cells_same.iloc[0]", "ra_paper.cells_compared.iloc[0]"),
        ("Over the {625}-design survey at", "ra_survey.designs.iloc[0]"),
        ("Spearman of M_L **{0.986}**, of M_CF {0.986}, the {10} best by each metric are ODE's {10}, every design's generalists are within {2} of ODE's, and the canonical design ranks {105}th (ODE: {107}th)", "ra_survey.rho_M_L.iloc[0]", "ra_survey.rho_M_CF.iloc[0]", "label('a top-10 list')", "ra_survey.top10_M_L.iloc[0]", "2 if ra_survey.generalists_within_2.iloc[0] == 1 else -1", "ra_survey.canonical_rank_M_L.iloc[0]", "ra_survey.canonical_rank_M_L_ode.iloc[0]"),
        ("over the {625} designs at {11} x {11})", "len(survey)", "cfg('config.yaml', 'empirical.weights')", "cfg('config.yaml', 'empirical.weights')"),
        ("with every mass x {1}e-{6}", "label('a factor of the ablation (reduced.md)')", "label('a factor of the ablation (reduced.md)')"),
        ("its ranking of the {625} designs", "len(survey)"),
        ("Spearman of the cells each of the {625} designs solves at {11} x {11}", "len(survey)", "cfg('config.yaml', 'empirical.weights')", "cfg('config.yaml', 'empirical.weights')"),
        ("`results/agreement`, {625} designs at {11} x {11})", "agree.designs.iloc[0]", "agree_weights()", "agree_weights()"),
        ("| {99.68} % of {302,500} | {99.93} % of {302,500} |", "100 * engine_row('mujoco', 'authors').cells_same", "engine_row('mujoco', 'authors').cells_compared", "100 * engine_row('pybullet', 'authors').cells_same", "engine_row('pybullet', 'authors').cells_compared"),
        ("| {99.97} % of {302,500} |", "100 * engine_row('reduced', 'authors').cells_same", "engine_row('reduced', 'authors').cells_compared"),
        ("| {0.96} | {0.99} | {0.83} | {0.71} | {0.996} |", "engine_row('mujoco', 'authors').rho_solved", "engine_row('pybullet', 'authors').rho_solved", "engine_row('mujoco', 'project').rho_solved", "engine_row('pybullet', 'project').rho_solved", "engine_row('reduced', 'authors').rho_solved"),
        ("(ODE: {1.1} %) | {1.4} % | {1.8} % | {24.2} % | {25.4} % | {0.96} % |", "100 * agree.with_generalist_ode.iloc[0]", "100 * engine_row('mujoco', 'authors').with_generalist", "100 * engine_row('pybullet', 'authors').with_generalist", "100 * engine_row('mujoco', 'project').with_generalist", "100 * engine_row('pybullet', 'project').with_generalist", "100 * engine_row('reduced', 'authors').with_generalist"),
        ("gravity -{9.81}", "cfg('config/empirical_morphology.yaml', 'gravity')"),
        ("the canonical design has {33} generalists in both engines (the paper: {1}, {33} times as many)", "row(pb, CANONICAL).generalists if row(pb, CANONICAL).generalists == row(mj, CANONICAL).generalists else -1", "paper('empirical_canonical_generalists')", "row(pb, CANONICAL).generalists / paper('empirical_canonical_generalists')"),
        ("has {1,037} in pybullet and {1,040} in MuJoCo (the paper's best: {57}, {18.2} times as many)", "row(pb, BEST_OUR_BODY).generalists", "row(mj, BEST_OUR_BODY).generalists", "paper('empirical_paper_best_generalists')", "row(pb, BEST_OUR_BODY).generalists / paper('empirical_paper_best_generalists')"),
        ("Over the {625} designs of the {5}-point grid at {11} x {11}, pybullet and MuJoCo rank designs alike (Spearman {0.857} for M_L, {0.847}", "engines['M_L pybullet-mujoco']['all']['n']", "positions(survey)", "cfg('config.yaml', 'empirical.weights')", "cfg('config.yaml', 'empirical.weights')", "engines['M_L pybullet-mujoco']['all']['rho']", "engines['M_CF pybullet-mujoco']['all']['rho']"),
        ("the MuJoCo survey of all 6561 designs at {11} x {11} (`results/survey9-mujoco`) finds a generalist in {1,245} ({19.0} %) and ranks designs like the theory with Spearman {0.510} for M_L and {0.389} for M_CF", "cfg('config/survey9_mujoco.yaml', 'mujoco.weights')", "cfg('config/survey9_mujoco.yaml', 'mujoco.weights')", "(m9.generalists > 0).sum()", "100 * (m9.generalists > 0).mean()", "spearman(theory, m9, 'M_L')", "spearman(theory, m9, 'M_CF')"),
        ("trained on {325} designs, jointly and sequentially, {20} seeds each", "learn.designs.iloc[0]", "runs.seeds.iloc[0]"),
        # the figures
        ("the ODE survey, {625} designs of the {5}-point grid", "len(survey)", "positions(survey)"),
        ("over the {625} surveyed designs", "len(survey)"),
        # numbers once stale (issue 69): each bound to the column its sentence names
        ("| yes | yes: {3,422} asymmetric designs score higher on both metrics ({3,427} designs of any kind have a higher M_L) |", "(asymmetric(theory) & (theory.M_L > row(theory, CANONICAL).M_L) & (theory.M_CF > row(theory, CANONICAL).M_CF)).sum()", "(theory.M_L > row(theory, CANONICAL).M_L).sum()"),
        ("| {91.0} % of the {8,228} both simulated | {90.4} % of the {7,260} both simulated |", "100 * engine_row('mujoco', 'project').cells_same", "engine_row('mujoco', 'project').cells_compared", "100 * engine_row('pybullet', 'project').cells_same", "engine_row('pybullet', 'project').cells_compared"),
        ("at the best design ({1,037} and {1,040}) and the canonical one ({33} and {33}), less at the third design both hold, `(-0.5,0.375),(0.5,-0.5)` ({936} in pybullet, {985} in MuJoCo)", "row(pb, BEST_OUR_BODY).generalists", "row(mj, BEST_OUR_BODY).generalists", "row(pb, CANONICAL).generalists", "row(mj, CANONICAL).generalists", "at(pb, (-0.5, 0.375), (0.5, -0.5)).generalists", "at(mj, (-0.5, 0.375), (0.5, -0.5)).generalists"),
        ("retain (Spearman {0.88}-{0.93} over all designs) and M_L which designs are learned ({0.86}-{0.97})", "learn.rho_MCF_retention.min()", "learn.rho_MCF_retention.max()", "learn.rho_ML_success.min()", "learn.rho_ML_success.max()"),
        ("the two ES learners only weakly ({0.12}-{0.33}, and {3} of their {4} bootstrap intervals include {0}); random search, at {0.76}-{0.83}", "learn[learn.learner != 'random'].rho_ML_success_pos.min()", "learn[learn.learner != 'random'].rho_ML_success_pos.max()", "(learn[learn.learner != 'random'].rho_ML_success_pos_lo < 0).sum()", "(learn.learner != 'random').sum()", "0", "learn[learn.learner == 'random'].rho_ML_success_pos.min()", "learn[learn.learner == 'random'].rho_ML_success_pos.max()"),
    ],
}
# fmt: on
