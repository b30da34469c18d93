"""The numbers a reviewer reads (issue 59): every number in docs/results.md and in the README's
"What it found" is checked against the committed tables, and the statements that once drifted from
them (the ratio of our body's counts to the paper's, the family of the theory's top designs, the
theory values the paper gives and we do not match, the engines of Figs. 6 D-F and 7 C-D, the
physics config keys' wording) are checked one by one.

How "every number" is checked: each number of the prose of a document tests/quoted_numbers.py
lists (code, link targets, anchors and the numbers of figures, equations, notes and rows left
out) is bound there to the table and column it is read from (a quote of its context and an
expression); a number no quote binds, a quote whose expression does not give its number and a
quote that no longer occurs each fail the test. No number is allowed for free.
"""

from __future__ import annotations

import re

import pandas as pd
import pytest
import quoted_sources as qs
from conftest import ROOT
from quoted_numbers import QUOTES

from morphlearn.analysis import compare
from morphlearn.grid import DesignGrid

RESULTS_MD = ROOT / "docs/results.md"
README = ROOT / "README.md"
CANONICAL = 6552  # (0.5,0.5),(0.5,-0.5) on the 9-point grid
PAPER_BEST_THEORY = 240  # (-0.5,-0.25),(0.5,0.25)
PAPER_BEST_ODE = 478  # (-0.5,0.125),(0.5,-0.375)
BEST_OUR_BODY = 720  # (-0.5,0.5),(0.5,-0.5)


def _table(rel: str) -> pd.DataFrame:
    return pd.read_csv(ROOT / rel, comment="#")


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


def unbound(rel: str) -> list[str]:
    """The numbers of a document the registry does not bind, or binds to a value it does not give,
    and the registry's quotes that no longer occur there."""
    from quoted_match import check
    from quoted_numbers import QUOTES

    report = check(rel, (ROOT / rel).read_text(), QUOTES[rel])
    return report.unbound + report.stale + report.wrong


@pytest.mark.parametrize("rel", sorted(QUOTES))
def test_every_quoted_number_is_bound_to_its_source(rel: str) -> None:
    """Each number read from the table and column its quote in tests/quoted_numbers.py names (once a
    number only had to appear in some table, and 2-11 were always allowed: "3,427 designs above it"
    under "asymmetric designs", where 3,422 are asymmetric, passed)."""
    bad = unbound(rel)
    assert not bad, f"{rel}: numbers not bound to their source (tests/quoted_numbers.py): {bad}"


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
    ratios = [qs.row(pb, CANONICAL).generalists / 1, qs.row(mj, CANONICAL).generalists / 1]
    ratios += [qs.row(pb, BEST_OUR_BODY).generalists / 57, qs.row(mj, BEST_OUR_BODY).generalists / 57]
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
        assert qs.opposite_sides(qs.top(th, int(n))).all(), f"the top {n} theory designs are not all one family"
    m = re.search(r"The top (\d+)\s+designs lie within (\d+) generalists", text)
    assert m, "docs/results.md says how close the theory's top designs are"
    n, spread = int(m[1]), int(m[2])
    top = qs.top(th, n)
    assert top.generalists.max() - top.generalists.min() == spread
    assert th.generalists[~th.design.isin(top.design)].max() < top.generalists.min()  # the whole tie group
    m = re.search(r"(\d+) put them on opposite sides, and (\d+) \(designs ([\d, and]+)\) put both on one side", text)
    assert m, "docs/results.md says which of the top designs have both sensors on one side"
    same = sorted(int(d) for d in re.findall(r"\d+", m[3]))
    assert (int(m[1]), int(m[2])) == (int(qs.opposite_sides(top).sum()), len(same))
    assert same == sorted(top.design[~qs.opposite_sides(top)].tolist())
    assert ((top.l1x * top.l2x) < 0).all()  # "all put one sensor at the back and one at the front"


def test_the_readme_says_which_theory_values_are_not_matched() -> None:
    """README: the paper's M_CF values and its designs at M_CF = 1 are not matched, with ours from
    the table (once 'The theory reproduces at the paper's resolution', with no word of them)."""
    th = _table("results/paper/theory/metrics.csv")
    found = " ".join(_found_section(README.read_text()).split())
    m = re.search(r"M_CF`? values \(canonical 0\.24, best 0\.636; ours ([\d.]+) and ([\d.]+)\)", found)
    assert m, "README.md does not say that the paper's M_CF values are not matched"
    assert _matches(m[1], [qs.row(th, CANONICAL).M_CF]) and _matches(m[2], [qs.row(th, PAPER_BEST_THEORY).M_CF])
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
