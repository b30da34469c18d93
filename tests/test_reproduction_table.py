"""The reproduction table a reviewer reads (issue 41): one verdict rule per kind of claim, applied
to every row; a reason linked in docs/results.md for every "differs"; configuration and method
notes once, numbered; the paper's engine (ODE) first; rows beyond the paper in their own table."""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import pandas as pd
import pytest
from conftest import ROOT

from morphlearn.figures import data as fd
from morphlearn.figures.reproduction import claims, verdict, writers
from morphlearn.figures.reproduction.table import OTHER_ROBOT, PAPER, reproduction_table
from morphlearn.figures.reproduction.verdict import DIFFERS, NOT_COMPARABLE, REPRODUCED, Scope

DOCS = (ROOT / "docs/results.md").read_text()
CONFIG = "config.yaml + paper.yaml"


def test_the_verdict_rule_per_kind_of_claim() -> None:
    """Each tolerance at its edge, by hand: a count within max(2, 2 %), a metric within 5 %, a
    share within 10 points, yes/no equal."""
    v = verdict.verdict
    assert v(claims.COUNT, 57, 58) == (REPRODUCED, "")  # the theory's canonical count
    assert v(claims.COUNT, 57, 59)[0] == REPRODUCED and v(claims.COUNT, 57, 60)[0] == DIFFERS
    assert v(claims.COUNT, 2255, 2243)[0] == REPRODUCED  # 12 <= 2 % of 2255 = 45.1
    assert v(claims.COUNT, 2255, 2209)[0] == DIFFERS  # 46 > 45.1
    assert v(claims.COUNT, 1, 33)[0] == DIFFERS
    assert v(claims.METRIC, 0.0039, 0.003961)[0] == REPRODUCED  # 1.6 %
    assert v(claims.METRIC, 0.049, 0.003961)[0] == DIFFERS
    assert v(claims.METRIC, 0.24, 0.2519)[0] == REPRODUCED and v(claims.METRIC, 0.24, 0.2521)[0] == DIFFERS
    assert v(claims.SHARE, 2 / 6, 0 / 35)[0] == DIFFERS and v(claims.SHARE, 1.0, 35 / 35)[0] == REPRODUCED
    assert v(claims.SHARE, 2 / 6, 3 / 7)[0] == REPRODUCED  # 0.095 apart
    assert v(claims.YES_NO, True, False)[0] == DIFFERS and v(claims.YES_NO, True, True)[0] == REPRODUCED
    # not comparable: nothing to compare, or ours answers another question
    assert v(claims.METRIC, None, 0.5) == (NOT_COMPARABLE, "the paper states no value")
    assert v(claims.METRIC, 0.5, None) == (NOT_COMPARABLE, claims.NOT_RUN)
    reduced = Scope(False, "41 x 41 weights (the paper: 121 x 121)")
    assert v(claims.COUNT, 57, 57, reduced) == (NOT_COMPARABLE, reduced.why)
    # the best of a subset is a lower bound of the best of all: above the tolerance it differs,
    # within or below it nothing follows
    subset = Scope(False, "2 of the paper's 6561 designs held", lower_bound=True)
    assert v(claims.METRIC, 0.0039, 0.0708, subset) == (DIFFERS, "")
    assert v(claims.METRIC, 0.0039, 0.0039, subset)[0] == NOT_COMPARABLE
    assert v(claims.METRIC, 0.0039, 0.001, subset)[0] == NOT_COMPARABLE
    assert v(claims.YES_NO, True, True, subset)[0] == NOT_COMPARABLE
    with pytest.raises(ValueError, match="claim kind 'ratio'"):
        verdict.agrees("ratio", 1, 1)


def test_every_claim_kind_has_a_stated_tolerance_and_the_rule_is_note_one() -> None:
    assert {c.kind for c in claims.CLAIMS} <= set(verdict.TOLERANCES)
    for text in verdict.TOLERANCES.values():
        assert text in writers.RULE
    assert "(pybullet)" not in " ".join(c.paper for c in claims.CLAIMS)  # the paper's physics is ODE's


@pytest.fixture(scope="module")
def paper_table() -> pd.DataFrame:
    """The table of the committed paper bundle (theory at paper resolution; ODE on 10 designs,
    pybullet on 3, MuJoCo on 41, all at 121 x 121; the ODE survey) as the reproduction rule builds it."""
    b = ROOT / "results/paper"
    theory = fd.load_results(b, "theory", None)
    emp = fd.load_results(b, "empirical", None)
    engines = {m: fd.load_results(b, m, None) for m in ("mujoco", "ode")}
    survey = fd.load_survey(b, {"model": "ode", "thresholds": None})
    pers = pd.read_csv(b / "persistence.csv")
    return reproduction_table(theory, emp, pers, CONFIG, 1.0, engines=engines, survey=survey)


def test_a_claim_whose_value_differs_carries_its_reason_linked_in_the_docs(paper_table: pd.DataFrame) -> None:
    t = paper_table.set_index("key")
    # canonical M_CF: the paper's 0.24 against ours, recomputed here from the committed metrics
    theory = pd.read_csv(ROOT / "results/paper/theory/metrics.csv")
    canon = theory[(theory.l1x == 0.5) & (theory.l1y == 0.5) & (theory.l2x == 0.5) & (theory.l2y == -0.5)].iloc[0]
    assert abs(canon.M_CF - 0.24) > 0.05 * 0.24
    row = t.loc["theory_canonical_M_CF"]
    assert row.verdict == DIFFERS and row.ours == f"{canon.M_CF:.4g}" and row.anchor == "differs-theory-m-cf"
    # the caption's count (57) is within the rule of ours
    assert abs(canon.generalists - 57) <= 2 and t.loc["theory_canonical_generalists", "verdict"] == REPRODUCED
    # pybullet's canonical design: 33 generalists, not the paper's 1; another engine and our body
    # answer another question: beside the paper's claim, no verdict (issue 59)
    emp = pd.read_csv(ROOT / "results/paper/empirical/metrics.csv")
    g = int(emp[(emp.l1x == 0.5) & (emp.l1y == 0.5) & (emp.l2x == 0.5) & (emp.l2y == -0.5)].generalists.iloc[0])
    row = t.loc["empirical_canonical_generalists"]
    assert g > 3 and row.section == OTHER_ROBOT and row.verdict == "" and row.ours.startswith(f"{g} of ")
    assert "another engine and another robot than the paper's" in row.note
    # every "differs" has a one-sentence reason and an anchor that docs/results.md defines
    claims_rows = paper_table[paper_table.section == PAPER]
    for r in claims_rows[claims_rows.verdict == DIFFERS].itertuples():
        assert r.reason.endswith(".") and not re.search(r"\.\s+[A-Z]", r.reason), r.reason  # one sentence
        assert f'<a id="{r.anchor}"></a>' in DOCS, r.anchor
    # a "not comparable" says why
    nc = claims_rows[claims_rows.verdict == NOT_COMPARABLE]
    assert len(nc) and (nc.reason != "").all() and (nc.anchor == "").all()
    assert set(claims_rows.verdict) == {REPRODUCED, DIFFERS, NOT_COMPARABLE}
    # the best design of ODE's 10 designs is no verdict on the best of all 6561
    assert t.loc["ode_best_design", "verdict"] == NOT_COMPARABLE


def test_notes_once_and_numbered_and_the_beyond_rows_apart(paper_table: pd.DataFrame) -> None:
    md = writers.to_markdown(paper_table, CONFIG)
    notes = re.findall(r"^(\d+)\. (.*)$", md, flags=re.M)
    texts = [t for _, t in notes]
    assert [int(n) for n, _ in notes] == list(range(1, len(notes) + 1)) and texts[0].startswith("Verdict rule")
    assert len(texts) == len(set(texts))
    # each configuration once, in a note, never in a row; no bare config-name note
    for config in set(paper_table.config) - {CONFIG}:
        said = config.removeprefix(f"{CONFIG}: ")
        assert md.count(said) == 1 and said in texts, said[:80]
    assert CONFIG not in texts and "undefined (only" not in md
    # every note a row cites exists
    cited = {int(n) for n in re.findall(r" \[(\d+)\]", md.split("## Notes")[0])}
    assert cited and cited <= set(range(1, len(notes) + 1))
    # the claims table, then the beyond table, each row in one of them
    claims_part, beyond_part = md.split("## Beyond the paper")
    n_claims = (paper_table.section == PAPER).sum()
    assert len(re.findall(r"^\| \d+ \|", claims_part, flags=re.M)) == n_claims
    assert "beyond the paper" not in claims_part.split("## The paper's claims")[1] and "beyond the paper" in beyond_part
    # the other engines' answers: a table of their own between the two, no verdicts
    other = claims_part.split(f"## {writers.OTHER_HEADING}")[1]
    assert len(re.findall(r"^\| [a-z]", other, flags=re.M)) == (paper_table.section == OTHER_ROBOT).sum() + 1
    # linked from the repository's root: the same bytes wherever the results folder is
    assert "](/docs/results.md#differs-theory-m-cf)" in claims_part
    # the verdict counts in the header are the table's
    c = writers.counts(paper_table)["all"]
    assert f"**{c[REPRODUCED]} reproduced, {c[DIFFERS]} differ, {c[NOT_COMPARABLE]} not comparable**" in md
    assert sum(c.values()) == n_claims
    # the HTML is a styled page with the same rows and notes, not a bare to_html
    page = writers.to_html(paper_table, CONFIG)
    assert page.startswith("<!DOCTYPE html>") and "<style>" in page and 'class="v v-differs"' in page
    assert page.count('<li id="note-') == len(notes) and page.count('<td class="num">') == n_claims
    assert 'href="/docs/results.md#differs-theory-m-cf"' in page


def test_the_paper_engine_comes_first_and_the_paper_column_names_no_other_engine(paper_table: pd.DataFrame) -> None:
    """With the authors' robot in ODE (the committed results/ode-paper), its rows answer the
    physics claims; pybullet's (another engine, the project's body) stand apart without a verdict;
    the paper's column is the paper's, whatever engine answers it."""
    ode = fd.load_results(ROOT / "results/ode-paper", "ode", None)
    emp = fd.load_results(ROOT / "results/paper", "empirical", None)
    t = reproduction_table(None, emp, None, CONFIG, 1.0, engines={"ode": ode})
    physics = t[(t.section == PAPER) & ~t.model.eq("theory")]
    models_in_order = list(dict.fromkeys(physics.model))
    assert models_in_order == ["ODE (the paper's engine)"]
    assert set(t[t.section == OTHER_ROBOT].model) == {"pybullet (another engine, the project's own body)"}
    rows = t.set_index("key")
    table = pd.read_csv(ROOT / "results/ode-paper/ode/metrics.csv").set_index("design")
    assert int(table.loc[6552, "generalists"]) == 1 and int(table.loc[478, "generalists"]) == 57  # the paper's
    assert rows.loc["ode_canonical_generalists", "verdict"] == REPRODUCED
    assert rows.loc["ode_paper_best_generalists", "verdict"] == REPRODUCED
    assert rows.loc["ode_canonical_M_L", "verdict"] == REPRODUCED  # 1/14641 against 0.000068
    # the M_L of the paper's best design, judged at it; which design is best of all 6561: no
    # verdict from the few held
    assert rows.loc["ode_best_M_L", "verdict"] == REPRODUCED
    assert rows.loc["ode_best_design", "verdict"] == NOT_COMPARABLE
    assert f"{len(table)} of the paper's 6561 designs held" in rows.loc["ode_best_design", "reason"]
    for frame in (t, paper_table):
        assert not frame[frame.section == PAPER].paper.str.contains("pybullet|MuJoCo").any()
    # the same claim for each engine: the paper's value once per row, the engine in its own column
    assert set(t[t.key.str.endswith("canonical_M_L") & ~t.key.str.startswith("theory")].paper) == {"0.000068"}


def test_the_paper_best_design_is_ranked_among_a_survey_that_lacks_it() -> None:
    """The paper's best design is not on the 5-point grid an ODE survey covers: its row of the same
    engine's refined results (same weights) is ranked among the survey's designs by each metric;
    a survey that holds it ranks its own row; without it, or on another weight grid, no rank (and
    no row: the pybullet and MuJoCo surveys of the 5-point grid have none)."""
    from morphlearn.figures.reproduction.claims import PAPER_PHYSICS_BEST_DESIGN
    from morphlearn.figures.reproduction.stages.survey import _paper_best_rank, survey_rows

    ode = fd.load_results(ROOT / "results/ode-paper", "ode", None)
    table = pd.read_csv(ROOT / "results/ode-paper/ode/metrics.csv")
    best = table[table.design == 478].iloc[0]  # (-0.5, 0.125), (0.5, -0.375): 57 generalists
    assert ode.row(*PAPER_PHYSICS_BEST_DESIGN).design == 478
    # a "survey" without the design; two of its rows made better than it by M_L, one tied
    others = table[table.design != 478].reset_index(drop=True)
    others.loc[0, "M_L"], others.loc[1, "M_L"], others.loc[2, "M_L"] = 0.5, 0.4, best.M_L
    others.loc[:, "M_CF"] = 0.0
    survey = dataclasses.replace(ode, table=others)
    said = _paper_best_rank(survey, ode)
    assert said.startswith(f"3 by M_L, 1 by M_CF (among the {len(others)} surveyed designs and it:"), said
    assert _paper_best_rank(ode, None).startswith("1 by M_L, ")  # the design's own row
    assert _paper_best_rank(survey, None) is None  # no row
    coarse = dataclasses.replace(ode, ds=ode.ds.isel(w1=slice(0, 11)))  # another weight grid
    assert _paper_best_rank(survey, coarse) is None
    # the committed pybullet survey (5-point grid) beside its theory: no such row
    theory5 = fd.load_results(ROOT / "results/survey", "theory", None)
    pybullet5 = fd.load_results(ROOT / "results/survey", "empirical", None)
    assert not [r for r in survey_rows(theory5, pybullet5, "cfg") if r["key"].endswith("paper_best_rank")]


def test_engine_agreement_on_a_few_shared_designs_is_one_row_not_four_undefined() -> None:
    from morphlearn.analysis.compare import MIN_DESIGNS
    from morphlearn.figures.reproduction.stages.engines import engine_rows

    emp = fd.load_results(ROOT / "results/paper", "empirical", None)
    mj = dataclasses.replace(emp, model="mujoco")  # the same 3 designs
    assert emp.n_designs == 3 < MIN_DESIGNS
    rows = engine_rows(emp, mj, ("empirical", "mujoco"), "MuJoCo", "cfg")
    said = [r["ours"] for r in rows if "Spearman" in r["quantity"]]
    assert len(said) == 1 and said[0].startswith(f"not computed: the two hold {emp.n_designs} designs in common")
    assert said[0].endswith(f"at least {MIN_DESIGNS} to tell agreement from chance")
    assert len(rows) == 1  # nor a top-10 overlap of 3 designs ("3 of 3": no result)
    assert not any("undefined" in r["ours"] for r in rows)


def test_a_rerender_reseals_the_table_with_its_record() -> None:
    """The reproduction rule writes the table and its sealed record together: a re-render that
    changes the table re-seals both (the record was refused as "not made by the render"), and
    still nothing the render does not make."""
    from morphlearn.bundles import render as bundle_rerender

    for rel in ("reproduction.md", "reproduction.html", "reproduction.provenance.json", "figures/fig3.png"):
        assert bundle_rerender.is_rendered(rel), rel
    for rel in ("summary.provenance.json", "theory/metrics.provenance.json", "theory/metrics.csv", "README.md"):
        assert not bundle_rerender.is_rendered(rel), rel


def test_a_rerender_moves_a_changed_record_once(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A bundle that lists the record (results/paper does): a render that changes the table and
    its record re-seals both, each moved into the bundle once (the record is also one of the files
    a render may leave beside a bundle; moving it twice failed with FileNotFoundError)."""
    import json

    from morphlearn import provenance
    from morphlearn.bundles import check as bundle_check
    from morphlearn.bundles import make as bundle
    from morphlearn.bundles import render as bundle_rerender

    b = tmp_path / "b"
    b.mkdir()
    files = {"reproduction.csv": "a\n", "reproduction.md": "# t\n", "reproduction.provenance.json": "{}\n"}
    files["data.csv"] = "x\n"
    for rel, text in files.items():
        (b / rel).write_text(text)
    listed = {rel: provenance.sha256_file(b / rel) for rel in files}
    (b / bundle.MANIFEST).write_text(json.dumps({"files": listed, "made_by": {"configs": []}}))
    monkeypatch.setattr(bundle_check, "check", lambda _: [])  # the moves are tested here, not the checks

    def render(_cmd: list[str], root: Path, target: Path) -> None:
        for rel in ("reproduction.md", "reproduction.provenance.json"):
            (root / target / rel).write_text((root / target / rel).read_text() + "new\n")

    monkeypatch.setattr(bundle_rerender, "_render", render)
    assert bundle_rerender.rerender("b", tmp_path) == ["reproduction.md", "reproduction.provenance.json"]
    assert (b / "reproduction.provenance.json").read_text() == "{}\nnew\n" and (b / "data.csv").read_text() == "x\n"
    manifest = json.loads((b / bundle.MANIFEST).read_text())
    assert manifest["files"]["reproduction.md"] == provenance.sha256_file(b / "reproduction.md")
    assert not list(tmp_path.glob(".rerender-*"))


def test_a_run_without_physics_says_so_once() -> None:
    """Without physics results the physics claims are one set of "not in this run" rows, and the
    header says no physics ran (not that other engines answer the claims)."""
    t = reproduction_table(None, None, None, "cfg.yaml", 1.0)
    claims_rows = t[t.section == PAPER]
    assert len(claims_rows) == len(claims.CLAIMS) and set(claims_rows.verdict) == {NOT_COMPARABLE}
    assert set(claims_rows.reason) == {claims.NOT_RUN}
    md = writers.to_markdown(t, "cfg.yaml")
    assert "No physics results are in this run." in md and "other engines answer" not in md
