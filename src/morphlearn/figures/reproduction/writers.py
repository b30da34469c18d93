"""The table's files: CSV (every column), Markdown and a styled HTML page for a reader.

Both documents carry the same content: the paper's claims with their verdicts, the rows beyond the
paper in a second table, and the configuration and method notes once each, as numbered notes (a
row cites its notes by number). The first note is the verdict rule; a "differs" links its reason
in docs/results.md by a path from the repository's root (:data:`DOCS`): a path relative to the
table would change with the results folder, and a bundle re-rendered in another folder must give
the same bytes."""

from __future__ import annotations

import html
import re
from collections.abc import Callable
from pathlib import Path

import pandas as pd

from morphlearn.figures.reproduction.claims import NOTE_SEP
from morphlearn.figures.reproduction.table import BEYOND_SECTION, OTHER_ROBOT, PAPER
from morphlearn.figures.reproduction.verdict import (
    DIFFERS,
    INFERRED,
    NOT_COMPARABLE,
    REPRODUCED,
    TOLERANCES,
    VERDICTS,
)

TITLE = "Reproduction table"
#: Where the reasons of the "differs" verdicts are, from the repository's root (GitHub resolves it).
DOCS = "/docs/results.md"
#: The verdict rule, stated once (note 1 of every table).
RULE = (
    "Verdict rule: **reproduced** when ours is within its kind's tolerance of the paper's value ("
    + "; ".join(TOLERANCES.values())
    + "); **differs** when not, with its reason; **not comparable** when ours does not answer the claim as the "
    "paper put it (not in this run; another weight grid or design grid than the paper's 121 x 121 weights and "
    "6561 designs; the best of all designs asked, a subset held; no value in the paper). The best of a subset of "
    "designs is a lower bound of the best of all: a subset's best count or metric already above the tolerance "
    "differs, and a design that a claim says exists, found among a subset, exists among all. A value the paper "
    "states of its best design is judged at that design (as the authors' code names it); that the design is the "
    "best of all is a claim of its own. Only the theory and the paper's robot in the paper's engine (the authors' "
    "robot in ODE, the Open Dynamics Engine) are judged: results of another robot or engine (pybullet and MuJoCo "
    "with the project's own body) answer another question, and are given beside the paper's claims without a "
    "verdict, counted apart."
)
#: What the verdict of a set-up inferred from the paper's numbers means (a note of its own, second,
#: in a table that has such rows: the other tables read as before).
INFERRED_RULE = (
    f"**{INFERRED}**: reproduced by the verdict rule, by a sweep whose set-up (weight grid, horizon) was inferred "
    "from the paper's numbers themselves; a right guess is expected to agree, so it is weaker evidence than an "
    "independent reproduction, and counted apart."
)
#: The heading of the paper's physics claims as another robot or engine answers them.
OTHER_HEADING = "The paper's physics claims in another engine or body (no verdict)"


def notes_of(table: pd.DataFrame, config_name: str) -> tuple[list[str], list[list[int]]]:
    """The numbered notes (the rule first, then every distinct configuration and note text in
    order of first use) and, per row, the numbers it cites. A row's config is cited without the
    config files' names (said once, in the header); a config that is only those names is none."""
    notes = [RULE, *([INFERRED_RULE] if (table.verdict == INFERRED).any() else [])]
    cites: list[list[int]] = []
    for r in table.itertuples():
        mine = []
        config = str(r.config)
        config = config.removeprefix(f"{config_name}: ") if config != config_name else ""
        for text in (config, *(s.strip() for s in str(r.note).split(NOTE_SEP))):
            if not text:
                continue
            if text not in notes:
                notes.append(text)
            mine.append(notes.index(text) + 1)
        cites.append(sorted(set(mine)))
    return notes, cites


def counts(table: pd.DataFrame) -> dict[str, dict[str, int]]:
    """Verdicts per model of the paper's claims, and in all ("all")."""
    claims = table[table.section == PAPER]
    # the inferred set-up's verdict only where a table has it: the other tables count as before
    held = [v for v in VERDICTS if v != INFERRED or (claims.verdict == v).any()]
    out = {m: {v: int((g.verdict == v).sum()) for v in held} for m, g in claims.groupby("model", sort=False)}
    out["all"] = {v: int((claims.verdict == v).sum()) for v in held}
    return out


def engine_sentence(table: pd.DataFrame) -> str:
    """The rows of another robot or engine, counted apart; and say so when no results of the paper's
    robot in its engine answer the physics claims."""
    models = set(table[table.section == PAPER].model)
    other = table[table.section == OTHER_ROBOT]
    said = ""
    if len(other):
        names = list(dict.fromkeys(m.split(" (")[0] for m in other.model))
        said = (
            f" Another {len(other)} rows give the paper's physics claims as {' and '.join(names)} "
            f"{'answers' if len(names) == 1 else 'answer'} them, "
            "another engine or body than the paper's: no verdict, in a table of their own."
        )
    if "physics" in models and not len(other):  # the placeholder rows of a run without physics
        return said + " No physics results are in this run."
    if "physics" in models:
        return said + " No results of the paper's robot in its engine (the authors' robot in ODE) are in this run."
    return said


def _summary(c: dict[str, int]) -> str:
    also = f", {c[INFERRED]} {INFERRED}" if c.get(INFERRED) else ""  # a table without such rows reads as before
    return f"{c[REPRODUCED]} reproduced{also}, {c[DIFFERS]} differ, {c[NOT_COMPARABLE]} not comparable"


def _verdict_md(r: object, docs: str) -> str:
    v, reason, anchor = r.verdict, str(r.reason), str(r.anchor)  # type: ignore[attr-defined]
    link = f" ([why]({docs}#{anchor}))" if anchor else ""
    return f"**{v}**" + (f": {reason}{link}" if reason else "")


def to_markdown(table: pd.DataFrame, config_name: str = "", docs: str = DOCS) -> str:
    """A GitHub Markdown document: the claims table, the beyond table and the numbered notes."""
    esc: Callable[[object], str] = lambda s: str(s).replace("|", "\\|")  # noqa: E731
    notes, cites = notes_of(table, config_name)
    ref = lambda i: "".join(f" [{n}]" for n in cites[i])  # noqa: E731
    c = counts(table)
    per_model = "; ".join(f"{m}: {_summary(v)}" for m, v in c.items() if m != "all")
    lines = [
        f"# {TITLE}",
        "",
        f"The paper's claims beside ours (made by `{config_name}`), each with a verdict by one rule (note 1). "
        f"**{_summary(c['all'])}** of {sum(c['all'].values())} rows ({per_model}).{engine_sentence(table)}",
        "",
        "## The paper's claims",
        "",
        "| # | claim | paper | source | model | ours | verdict |",
        "|---|---|---|---|---|---|---|",
    ]
    n = 0
    for i, r in enumerate(table.itertuples()):
        if r.section != PAPER:
            continue
        n += 1
        lines.append(
            f"| {n} | {esc(r.quantity)} | {esc(r.paper)} | {esc(r.source)} | {esc(r.model)} | "
            f"{esc(r.ours)}{ref(i)} | {esc(_verdict_md(r, docs))} |"
        )
    other = [(i, r) for i, r in enumerate(table.itertuples()) if r.section == OTHER_ROBOT]
    if other:
        lines += ["", f"## {OTHER_HEADING}", "", "| claim | paper | model | ours |", "|---|---|---|---|"]
        lines += [f"| {esc(r.quantity)} | {esc(r.paper)} | {esc(r.model)} | {esc(r.ours)}{ref(i)} |" for i, r in other]
    beyond = [(i, r) for i, r in enumerate(table.itertuples()) if r.section == BEYOND_SECTION]
    if beyond:
        lines += ["", "## Beyond the paper", "", "| question | paper | ours |", "|---|---|---|"]
        lines += [f"| {esc(r.quantity)} | {esc(r.paper)} | {esc(r.ours)}{ref(i)} |" for i, r in beyond]
    lines += ["", "## Notes", "", *(f"{k}. {esc(t)}" for k, t in enumerate(notes, 1)), ""]
    return "\n".join(lines)


CSS = """
body { font: 15px/1.45 system-ui, -apple-system, "Segoe UI", sans-serif; color: #1d232a; margin: 2rem auto;
       max-width: 1200px; padding: 0 1rem; }
h1 { font-size: 1.6rem; margin-bottom: .3rem; } h2 { font-size: 1.2rem; margin-top: 2rem; }
p.lead { color: #44505c; }
table { border-collapse: collapse; width: 100%; font-size: 14px; }
th, td { border-bottom: 1px solid #d8dee4; padding: .45rem .55rem; text-align: left; vertical-align: top; }
th { background: #f3f5f7; position: sticky; top: 0; }
tr:hover td { background: #fafbfc; }
td.num { color: #6a737d; text-align: right; } td.src { color: #44505c; font-size: 13px; }
sup a { text-decoration: none; color: #0969da; margin-left: 1px; }
.v { display: inline-block; border-radius: 10px; padding: 0 .5rem; font-weight: 600; font-size: 13px;
     white-space: nowrap; }
.v-reproduced { background: #dafbe1; color: #116329; } .v-differs { background: #fff1d6; color: #8a4600; }
.v-not-comparable { background: #eaeef2; color: #44505c; }
.v-reproduced-inferred-set-up { background: #eef8e6; color: #3d6b1f; }
.why { display: block; color: #44505c; font-size: 13px; margin-top: .2rem; }
ol.notes { font-size: 13px; color: #44505c; } ol.notes li { margin-bottom: .3rem; }
.badges span { margin-right: .6rem; }
"""


def _md_inline(text: str) -> str:
    """The few Markdown marks the notes use (bold, code) as HTML, after escaping."""

    out = html.escape(text)
    out = re.sub(r"\*\*(.+?)\*\*", r"<strong>\1</strong>", out)
    return re.sub(r"`(.+?)`", r"<code>\1</code>", out)


def to_html(table: pd.DataFrame, config_name: str = "", docs: str = DOCS) -> str:
    """A self-contained, styled HTML page with the same content as :func:`to_markdown`."""
    e = html.escape
    notes, cites = notes_of(table, config_name)
    ref = lambda i: "".join(f'<sup><a href="#note-{n}">[{n}]</a></sup>' for n in cites[i])  # noqa: E731
    badge = lambda v: f'<span class="v v-{re.sub("[^a-z]+", "-", v).strip("-")}">{e(v)}</span>'  # noqa: E731
    c = counts(table)
    summary = " ".join(f"{badge(v)} {n}" for v, n in c["all"].items())
    per_model = "; ".join(f"{e(m)}: {e(_summary(v))}" for m, v in c.items() if m != "all")
    out = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        f"<title>{TITLE}</title><style>{CSS}</style></head><body>",
        f"<h1>{TITLE}</h1>",
        f'<p class="lead">The paper\'s claims beside ours (made by <code>{e(config_name)}</code>), each with a '
        f'verdict by one rule (<a href="#note-1">note 1</a>).</p>',
        f'<p class="badges">{summary} &nbsp;of {sum(c["all"].values())} rows ({per_model}).'
        f"{e(engine_sentence(table))}</p>",
        "<h2>The paper's claims</h2>",
        "<table><thead><tr><th>#</th><th>claim</th><th>paper</th><th>source</th><th>model</th><th>ours</th>"
        "<th>verdict</th></tr></thead><tbody>",
    ]
    n = 0
    for i, r in enumerate(table.itertuples()):
        if r.section != PAPER:
            continue
        n += 1
        why = ""
        if r.reason:
            link = f' <a href="{e(docs)}#{e(r.anchor)}">why</a>' if r.anchor else ""
            why = f'<span class="why">{e(r.reason)}{link}</span>'
        out.append(
            f'<tr><td class="num">{n}</td><td>{e(r.quantity)}</td><td>{e(r.paper)}</td>'
            f'<td class="src">{e(r.source)}</td><td>{e(r.model)}</td><td>{e(r.ours)}{ref(i)}</td>'
            f"<td>{badge(r.verdict)}{why}</td></tr>"
        )
    out.append("</tbody></table>")
    other = [(i, r) for i, r in enumerate(table.itertuples()) if r.section == OTHER_ROBOT]
    if other:
        out += [
            f"<h2>{e(OTHER_HEADING)}</h2>",
            "<table><thead><tr><th>claim</th><th>paper</th><th>model</th><th>ours</th></tr></thead><tbody>",
            *(
                f"<tr><td>{e(r.quantity)}</td><td>{e(r.paper)}</td><td>{e(r.model)}</td><td>{e(r.ours)}{ref(i)}</td></tr>"
                for i, r in other
            ),
            "</tbody></table>",
        ]
    beyond = [(i, r) for i, r in enumerate(table.itertuples()) if r.section == BEYOND_SECTION]
    if beyond:
        out += [
            "<h2>Beyond the paper</h2>",
            "<table><thead><tr><th>question</th><th>paper</th><th>ours</th></tr></thead><tbody>",
            *(f"<tr><td>{e(r.quantity)}</td><td>{e(r.paper)}</td><td>{e(r.ours)}{ref(i)}</td></tr>" for i, r in beyond),
            "</tbody></table>",
        ]
    out += ['<h2>Notes</h2><ol class="notes">']
    out += [f'<li id="note-{k}">{_md_inline(t)}</li>' for k, t in enumerate(notes, 1)]
    out += ["</ol></body></html>", ""]
    return "\n".join(out)


def write(table: pd.DataFrame, csv: str | Path, md: str | Path, html_path: str | Path, config_name: str = "") -> None:
    """The three files (``config_name``: the config files that made the run, said once)."""
    table.to_csv(csv, index=False)
    Path(md).write_text(to_markdown(table, config_name))
    Path(html_path).write_text(to_html(table, config_name))
