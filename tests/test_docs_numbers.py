"""The numbers a reviewer reads (issue 59): every number in docs/results.md and in the README's
"What it found" is checked against the committed tables, and the statements that once drifted from
them (the ratio of our body's counts to the paper's, the family of the theory's top designs, the
theory values the paper gives and we do not match, the engines of Figs. 6 D-F and 7 C-D, the
physics config keys' wording) are checked one by one.

How "every number" is checked: the prose is cut into number tokens (code spans, link targets and
anchors left out; design coordinates in code spans are checked separately), and each token must be
a value computed here from a committed table, rounded as the token is written, or a number the
paper states (:data:`PAPER`), or a fixed parameter of the setup (:data:`SETUP`). A number that is
neither fails the test with its line, so a new or changed number must be added here with the table
it comes from."""

from __future__ import annotations

import json
import re
from functools import cache

import numpy as np
import pandas as pd
import pytest
import yaml
from conftest import ROOT
from scipy import stats

from morphlearn.analysis import compare
from morphlearn.grid import DesignGrid

RESULTS_MD = ROOT / "docs/results.md"
README = ROOT / "README.md"
CANONICAL = 6552  # (0.5,0.5),(0.5,-0.5) on the 9-point grid
PAPER_BEST_THEORY = 240  # (-0.5,-0.25),(0.5,0.25)
PAPER_BEST_ODE = 478  # (-0.5,0.125),(0.5,-0.375)
BEST_OUR_BODY = 720  # (-0.5,0.5),(0.5,-0.5)

#: Numbers the paper states (its captions, text and figure numbers), quoted beside ours.
PAPER = {
    "57", "14641", "2255", "0.049", "0.286", "0.24", "0.636", "0.206", "1", "0.000068", "0.00052",
    "0.0039", "0.038", "35", "2", "6", "0.154",
}  # fmt: skip
#: Fixed parameters of the setup, not results: grid sizes, r, T and the success radius, the number
#: of environments, body edges (x = +-0.5), sensor and figure and equation numbers, top-10 lists,
#: the 5- and 9-point grids.
SETUP = {"121", "6561", "625", "9", "5", "11", "4", "500", "0.2", "0.5", "10", "3", "7", "2"}


def _table(rel: str) -> pd.DataFrame:
    return pd.read_csv(ROOT / rel, comment="#")


def _row(t: pd.DataFrame, design: int) -> pd.Series:
    return t[t.design == design].iloc[0]


def _rank(t: pd.DataFrame, design: int, by: str) -> int:
    """1 + the designs strictly better (ties share a rank), as the documents rank."""
    return int(1 + (t[by] > _row(t, design)[by]).sum())


def _top(t: pd.DataFrame, n: int) -> pd.DataFrame:
    return t.sort_values(["generalists", "design"], ascending=[False, True]).head(n)


def _opposite_sides(t: pd.DataFrame) -> np.ndarray:
    """One sensor at the back and one at the front, on opposite sides of the body (y of opposite sign)."""
    return ((t.l1x * t.l2x) < 0).to_numpy() & ((t.l1y * t.l2y) < 0).to_numpy()


@cache
def facts() -> list[float]:
    """Every value the documents may quote, computed from the committed tables."""
    th = _table("results/paper/theory/metrics.csv")
    od = _table("results/ode-paper/ode/metrics.csv")
    sv = _table("results/ode-survey/ode/metrics.csv")
    m9 = _table("results/survey9-mujoco/mujoco/metrics.csv")
    pb = _table("results/refine-pybullet/empirical/metrics.csv")
    mj = _table("results/refine-mujoco/mujoco/metrics.csv")
    ag = _table("results/agreement/agreement.csv")
    lc = _table("results/learners/learners/correlations.csv")
    runs = _table("results/learners/learners/runs.csv")
    pers = _table("results/paper/persistence.csv")
    eng = json.loads((ROOT / "results/mujoco/engines.json").read_text())
    out: list[float] = []
    # the theory: named designs, their ranks, the distributions
    for d in (CANONICAL, PAPER_BEST_THEORY, 160, PAPER_BEST_ODE):
        r = _row(th, d)
        out += [d, r.generalists, r.M_L, r.M_CF, _rank(th, d, "M_L"), _rank(th, d, "M_CF")]
    out += [(th.M_L > _row(th, CANONICAL).M_L).sum()]
    none = int((th.generalists == 0).sum())
    out += [none, 100 * none / len(th), th.M_L.median(), th.M_L.max(), th.M_CF.median(), th.M_CF.max()]
    out += [stats.spearmanr(th.M_L, th.M_CF).statistic]
    trajectories = len(th) * 121**2 * 4
    out += [th.flagged.sum(), (th.flagged > 0).sum(), 100 * th.flagged.sum() / trajectories, trajectories / 1e6]
    top = _top(th, 22)
    out += [len(top), top.generalists.max() - top.generalists.min()]
    out += [100 * (top.generalists.max() - top.generalists.min()) / top.generalists.max()]
    out += [_opposite_sides(top).sum(), (~_opposite_sides(top)).sum(), *top.design[~_opposite_sides(top)]]
    out += [_rank(th, PAPER_BEST_THEORY, "generalists")]
    # the paper's text M_L against its own captions
    out += [0.049 / (57 / 121**2), 0.286 / (2255 / 121**2)]
    # persistence
    for name in ("canonical", "paper_best", "best_M_L"):
        p = pers[pers.design == name]
        out += [len(p), p.stays_near.sum(), p.generalists.iloc[0]]
    # ODE: the ten exhaustive designs, the survey
    for r in od.itertuples():
        out += [r.design, r.generalists, r.at_least_one, r.M_L, r.M_CF]
    out += [len(od), (sv.generalists > 0).sum(), 100 * (sv.generalists > 0).mean(), sv.generalists.max()]
    c5 = int(sv[(sv.l1x == 0.5) & (sv.l1y == 0.5) & (sv.l2x == 0.5) & (sv.l2y == -0.5)].design.iloc[0])
    out += [_rank(sv, c5, "M_L"), _rank(sv, c5, "M_CF")]
    both = compare.joined(th, sv, ("theory", "ode"))
    out += [len(both), *(stats.spearmanr(both[f"{m}_theory"], both[f"{m}_ode"]).statistic for m in ("M_L", "M_CF"))]
    out += [compare.top_shared(both, m, 10, ("theory", "ode")) for m in ("M_L", "M_CF")]
    out += _survey_check()
    # the engines against ODE (results/agreement)
    out += [*(100 * ag.cells_same), *ag.cells_compared, *ag.rho_solved, *(100 * ag.with_generalist)]
    out += [*(100 * ag.with_generalist_ode)]
    # the reproduction table's header counts (verdicts given; rows without one stand apart)
    rt = _table("results/paper/reproduction.csv")
    out += [*rt.verdict.value_counts(), rt.verdict.notna().sum(), *rt.section.value_counts()]
    # the reduced model of the authors' robot against ODE (results/reduced-*, docs/reduced.md)
    for rel in (
        "results/reduced-agreement-paper/agreement.csv",
        "results/reduced-agreement-survey/agreement.csv",
        "results/reduced-agreement-screened/agreement.csv",
        "results/reduced-agreement-random/agreement.csv",
    ):
        if (ROOT / rel).is_file():
            ra = _table(rel)
            out += [*(100 * ra.cells_same), *ra.cells_compared, *ra.rho_M_L, *ra.rho_M_CF, *ra.rho_solved]
            out += [*(100 * ra.generalists_within_2), *ra.top10_M_L, *ra.top10_M_CF, *ra.canonical_rank_M_L]
            out += [*(100 * ra.with_generalist), *ra.best_M_L_rank_in_ode, *ra.designs]
    for rel in (
        "results/reduced-ode-paper/reduced/metrics.csv",
        "results/reduced-survey/reduced/metrics.csv",
        "results/reduced-paper/reduced/metrics.csv",
        "results/ode-screened-paper/ode/metrics.csv",
    ):
        if (ROOT / rel).is_file():
            rt = _table(rel)
            out += [*rt.generalists[rt.generalists > 0], rt.generalists.max(), (rt.generalists > 0).sum()]
            out += [100 * (rt.generalists > 0).mean()]
    # the best design as screened (docs/results.md; the table's screen rows, tests/test_screen_rows.py)
    from morphlearn.figures.reproduction.stages.screen import ruled_out

    rp, osp = _table("results/reduced-paper/reduced/metrics.csv"), _table("results/ode-screened-paper/ode/metrics.csv")
    for by in ("M_L", "M_CF"):
        r = ruled_out(rp, osp, by)
        out += [r.margin, r.best_outside[by], r.best_outside[by] + r.margin, r.margin * 121**2]
    out += [osp.generalists.max() - rp[~rp.design.isin(osp.design)].generalists.max()]
    out += [(_table("results/reduced-survey/reduced/metrics.csv").generalists - sv.generalists).abs().max()]
    # the project's body: refine bundles, the MuJoCo 6561-design survey, pybullet against MuJoCo
    for t in (pb, mj):
        for d in (CANONICAL, BEST_OUR_BODY):
            out += [_row(t, d).generalists]
    out += [_row(pb, CANONICAL).generalists / 1, _row(pb, BEST_OUR_BODY).generalists / 57]
    out += [
        _row(mj, BEST_OUR_BODY).generalists / 57,
        abs(_row(pb, BEST_OUR_BODY).generalists - _row(mj, 720).generalists),
    ]
    out += [(m9.generalists > 0).sum(), 100 * (m9.generalists > 0).mean()]
    m9_th = compare.joined(th, m9, ("theory", "mujoco"))
    out += [stats.spearmanr(m9_th[f"{m}_theory"], m9_th[f"{m}_mujoco"]).statistic for m in ("M_L", "M_CF")]
    out += [eng["M_L pybullet-mujoco"]["all"]["rho"], eng["M_CF pybullet-mujoco"]["all"]["rho"]]
    gravity = yaml.safe_load((ROOT / "config/empirical_morphology.yaml").read_text())["gravity"]
    out += [gravity]
    # learners
    out += [lc.designs.iloc[0], runs.seeds.iloc[0]]
    for col in ("rho_ML_success", "rho_MCF_retention", "rho_MCF_retention_pos"):
        v = lc[col].dropna()
        out += [v.min(), v.max()]
    out += _text_sweep_facts()
    return [float(x) for x in out]


def _text_sweep_facts() -> list[float]:
    """The second theory sweep (results/theory-text, 11 x 11, T = 1000): its named designs, its
    designs at M_CF = 1, the r scan at the longest horizon (results/theory-text-checks), odeint's
    counts of its best designs (results/theory-text-odeint) and the numbers the table's
    second-sweep rows state (horizons, distances after success)."""
    tt = _table("results/theory-text/theory/metrics.csv")
    out: list[float] = []
    for d in (CANONICAL, PAPER_BEST_THEORY, 684):  # 684: its best by M_L, (-0.5,0.5),(0,-0.5)
        r = _row(tt, d)
        out += [r.generalists, r.at_least_one, r.M_L, r.M_CF, r.flagged]
    cf1 = tt[tt.M_CF == 1]
    out += [len(cf1), cf1.M_L.max(), cf1.M_L.max() * 121]
    rs = _table("results/theory-text-checks/r_scan.csv")
    last = rs[rs.horizon == rs.horizon.max()]
    out += [*last.r, *last.horizon, *(last.designs_run - 2)]  # 2: the canonical and the paper's design
    out += [*last.canonical_generalists, *last.canonical_solvers, *last.canonical_mcf, *last.cf1_best_ml.dropna()]
    rt = _table("results/paper/reproduction.csv")
    for text in rt[rt.key.str.endswith("_text_sweep")][["ours", "note"]].to_numpy().ravel():
        out += [float(x) for x in _NUMBER.findall(str(text).replace(",", ""))]
    od = _table("results/theory-text-odeint/designs/summary.csv")  # the paper's integrator on its best designs
    out += [len(od), *od.to_numpy().ravel()]
    # the readings of the paper's numbers the section gives: 0.636 as 35/55, "10^5 timesteps" of the
    # project's step theory.dt
    out += [55, yaml.safe_load((ROOT / "config.yaml").read_text())["theory"]["dt"]]
    return out


def _survey_check() -> list[float]:
    """The survey against the exhaustive ODE runs: designs both hold, their successes and
    generalists (tests/test_ode_bundles.py checks cell by cell that none was missed)."""
    od = _table("results/ode-paper/ode/metrics.csv")
    sv = _table("results/ode-survey/ode/metrics.csv")
    both = od.merge(sv, on=compare.COORDS, suffixes=("", "_s"))
    per_env = [f"n_{a}" for a in (45, 135, 225, 315)]
    return [len(both), both[per_env].to_numpy().sum(), both.generalists.sum()]


def _decimals(token: str) -> int:
    return len(token.split(".")[1]) if "." in token else 0


def _matches(token: str, values: list[float]) -> bool:
    x = float(token)
    d = _decimals(token)
    return any(abs(round(abs(v), d) - x) < 10 ** -(d + 6) for v in values)


_CODE = re.compile(r"`[^`]*`")
_LINK = re.compile(r"\]\([^)]*\)")
_TAG = re.compile(r"<[^>]+>")
_NUMBER = re.compile(r"\d{1,3}(?:,\d{3})+(?:\.\d+)?|\d+(?:\.\d+)?")


def number_tokens(text: str) -> list[tuple[int, str]]:
    """(line number, number) of every number in the prose: code spans, link targets and HTML
    tags left out, thousands separators removed, ordinal suffixes ignored."""
    out = []
    for i, line in enumerate(text.splitlines(), 1):
        prose = _TAG.sub(" ", _LINK.sub("]", _CODE.sub(" ", line)))
        prose = re.sub(r"\b[A-Za-z_]*\d*[A-Za-z_]+\d+[A-Za-z_\d]*\b", " ", prose)  # names: M_L, fig6, n_45
        out += [(i, m.group().replace(",", "")) for m in _NUMBER.finditer(prose)]
    return out


def _found_section(text: str) -> str:
    return text.split("## What it found", 1)[1].split("\n## ", 1)[0]


def _unchecked(text: str) -> list[str]:
    values = facts()
    return [
        f"line {i}: {tok}"
        for i, tok in number_tokens(text)
        if tok not in PAPER and tok not in SETUP and not _matches(tok, values)
    ]


def test_every_number_in_results_md_comes_from_a_committed_table() -> None:
    bad = _unchecked(RESULTS_MD.read_text())
    assert not bad, f"docs/results.md: numbers no committed table gives: {bad}"


def test_every_number_the_readme_found_comes_from_a_committed_table() -> None:
    bad = _unchecked(_found_section(README.read_text()))
    assert not bad, f"README.md, 'What it found': numbers no committed table gives: {bad}"


def test_design_indices_name_their_coordinates() -> None:
    """'478 `(-0.5,0.125),(0.5,-0.375)`': the index is that design of the 9-point grid."""
    g = DesignGrid(9)
    pairs = re.findall(r"\b(\d+) `\((-?[\d.]+),(-?[\d.]+)\),\((-?[\d.]+),(-?[\d.]+)\)`", RESULTS_MD.read_text())
    assert len(pairs) >= 10
    for d, *xy in pairs:
        c = [float(v) for v in xy]
        assert g.index_of((c[0], c[1]), (c[2], c[3])) == int(d), (d, xy)


def test_our_body_to_the_paper_is_the_ratio_of_the_tables() -> None:
    """'N times the paper's ...': the ratio of our body's count to the paper's, in the README and
    docs/results.md (once '20-30 times', which no table gives: 1,037 / 57 = 18.2, 33 / 1 = 33)."""
    pb = _table("results/refine-pybullet/empirical/metrics.csv")
    mj = _table("results/refine-mujoco/mujoco/metrics.csv")
    ratios = [_row(pb, CANONICAL).generalists / 1, _row(mj, CANONICAL).generalists / 1]
    ratios += [_row(pb, BEST_OUR_BODY).generalists / 57, _row(mj, BEST_OUR_BODY).generalists / 57]
    said = []
    for path in (README, RESULTS_MD):
        for lo, hi in re.findall(r"(\d+(?:\.\d+)?)(?:-(\d+(?:\.\d+)?))? times", path.read_text()):
            said += [(path.name, t) for t in (lo, hi) if t]
    assert said, "the documents no longer compare our body's counts with the paper's"
    for name, t in said:
        assert _matches(t, ratios), f"{name}: '{t} times' is no ratio of the tables ({[round(r, 1) for r in ratios]})"


def test_the_family_of_the_theorys_top_designs() -> None:
    """The theory's top designs by generalists: how many lie within how many generalists, and
    which have both sensors on one side (once 'the top 21 ... all one family': 4 of the top 22
    are not)."""
    th = _table("results/paper/theory/metrics.csv")
    text = " ".join(RESULTS_MD.read_text().split())  # sentences across line breaks
    for n in re.findall(r"top (\d+) (?:theory )?designs?[^.]*?all (?:of )?one family", text):
        assert _opposite_sides(_top(th, int(n))).all(), f"the top {n} theory designs are not all one family"
    m = re.search(r"The top (\d+)\s+designs lie within (\d+) generalists", text)
    assert m, "docs/results.md says how close the theory's top designs are"
    n, spread = int(m[1]), int(m[2])
    top = _top(th, n)
    assert top.generalists.max() - top.generalists.min() == spread
    assert th.generalists[~th.design.isin(top.design)].max() < top.generalists.min()  # the whole tie group
    m = re.search(r"(\d+) put them on opposite sides, and (\d+) \(designs ([\d, and]+)\) put both on one side", text)
    assert m, "docs/results.md says which of the top designs have both sensors on one side"
    same = sorted(int(d) for d in re.findall(r"\d+", m[3]))
    assert (int(m[1]), int(m[2])) == (int(_opposite_sides(top).sum()), len(same))
    assert same == sorted(top.design[~_opposite_sides(top)].tolist())
    assert ((top.l1x * top.l2x) < 0).all()  # "all put one sensor at the back and one at the front"


def test_the_readme_says_which_theory_values_are_not_matched() -> None:
    """README: the paper's M_CF values and its designs at M_CF = 1 are not matched, with ours from
    the table (once 'The theory reproduces at the paper's resolution', with no word of them)."""
    th = _table("results/paper/theory/metrics.csv")
    found = " ".join(_found_section(README.read_text()).split())
    m = re.search(r"M_CF`? values \(canonical 0\.24, best 0\.636; ours ([\d.]+) and ([\d.]+)\)", found)
    assert m, "README.md does not say that the paper's M_CF values are not matched"
    assert _matches(m[1], [_row(th, CANONICAL).M_CF]) and _matches(m[2], [_row(th, PAPER_BEST_THEORY).M_CF])
    assert re.search(r"designs at `?M_CF`? = 1 \(ours:\s+none\)", found) and th.M_CF.max() < 1
    assert "The theory reproduces" not in found


@pytest.mark.parametrize(("figure", "panels", "caption_panel"), [("fig6", "D-F", "D"), ("fig7", "C, D", "C, D")])
def test_figure_descriptions_name_the_engine_their_captions_name(figure: str, panels: str, caption_panel: str) -> None:
    """Figs. 6 D-F and 7 C-D show ODE (their captions say so); the documents once said pybullet
    and the MuJoCo survey."""
    engines = ("pybullet", "MuJoCo", "ODE")
    caption = (ROOT / f"results/paper/figures/{figure}.caption.md").read_text()
    panel = re.search(rf"\*\*{caption_panel}:\*\* ([^\n]*)", caption)
    assert panel, caption_panel
    shown = {e for e in engines if e in panel[1]}
    assert len(shown) == 1, panel[1]
    n = figure[-1]
    alt = {"D-F": r"\(?D-F\b", "C, D": r"\(?C(?:, |-)D\b"}[panels]
    for path in (RESULTS_MD, README):
        for clause in clauses(path.read_text()):
            if (re.search(rf"Figs?\. {n}\b", clause) and re.search(alt, clause)) or f"**Fig. {n}**" in clause:
                named = {e for e in engines if e in clause}
                assert named <= shown, f"{path.name}: {clause[:160]} (the caption: {shown})"


def clauses(text: str) -> list[str]:
    """The text's clauses: each table cell alone; a paragraph's lines joined, then cut at the end
    of each sentence and at each semicolon ('Fig. 6' is not a sentence's end)."""
    blocks: list[str] = []
    para: list[str] = []
    for line in [*text.splitlines(), ""]:
        if line.lstrip().startswith("|"):
            blocks += line.split("|")
        elif line.strip():
            para.append(line.strip())
            continue
        if para:
            blocks.append(" ".join(para))
            para = []
    return [c for b in blocks for c in re.split(r"(?<=[.;])\s+(?=[A-Z*(`\[])|;\s+", b) if c.strip()]


def test_no_design_shared_by_theory_and_ode_top_10s() -> None:
    """'no design is in both top 10s by either metric': counted on the coordinates both tables
    share (morphlearn compare once intersected two grids' design indices and printed 1)."""
    assert "no design is in both top 10s by either metric" in " ".join(RESULTS_MD.read_text().split())
    th = _table("results/paper/theory/metrics.csv")
    sv = _table("results/ode-survey/ode/metrics.csv")
    both = compare.joined(th, sv, ("theory", "ode"))
    assert [compare.top_shared(both, m, 10, ("theory", "ode")) for m in ("M_L", "M_CF")] == [0, 0]


def test_config_readme_physics_keys_say_their_own_model() -> None:
    """config/README.md (generated from the schema): the MuJoCo and ODE keys do not call their run
    'the empirical sweep' nor copy into results_dir/empirical/; ODE's mirror_derive and adaptive
    keys state ODE's measurements, not Bullet's or pybullet's."""
    rows = {
        ln.split("|")[1].strip(" `"): ln.split("|")[5]
        for ln in (ROOT / "config/README.md").read_text().splitlines()
        if ln.startswith("| `")
    }
    for model in ("empirical", "mujoco", "ode"):
        assert "empirical sweep" not in rows[f"{model}.enabled"] + rows[f"{model}.weights"]
        assert "results_dir/empirical/" not in rows[f"{model}.results_from"]
    assert "Bullet" not in rows["ode.mirror_derive"] and "exactly" in rows["ode.mirror_derive"]
    for key in ("ode.adaptive_weights", "ode.adaptive_near"):
        assert "ODE" in rows[key] and "20,328" not in rows[key] and "34 %" not in rows[key], rows[key]
