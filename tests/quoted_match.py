"""Binding the numbers of a document to the registry (tests/quoted_numbers.py): which numbers a
document's prose holds, which of them a registered quote covers, and whether each quote's
expression, rounded as the number is written, gives it.

A number is covered by a quote when the quote (its whitespace matching any run of whitespace, so a
quote may cross a line break) occurs in the document with that number at the quote's ``{...}``.
Not numbers to bind: code blocks and spans, link targets, HTML tags, names with digits (M_L, fig6, n_45, (1+1)-ES), the
numbers of figures, equations, notes and rows named as such ("Fig. 3C", "Eq. 2", "note 7",
"rows 19 and 25"), and a design index followed by its coordinates in a code span (checked by
test_design_indices_name_their_coordinates)."""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

from quoted_sources import namespace

_FENCE = re.compile(r"^```.*?^```", re.S | re.M)
_CODE = re.compile(r"`[^`\n]*`")
_LINK = re.compile(r"\]\([^)]*\)")
_TAG = re.compile(r"</?[A-Za-z][^>\n]*>")
_NAME = re.compile(r"\b[A-Za-z_]*\d*[A-Za-z_]+\d+[A-Za-z_\d]*\b")
_LABEL = re.compile(
    r"\b(?:Figs?|Eqs?|[Nn]otes?|[Rr]ows?)\.?\s+\d+[A-Z]?(?:(?:,\s*|\s+and\s+|-|\s+)\d+[A-Z]?\b(?![.,]?\d))*"
)
_ES = re.compile(r"\(1\+1\)-ES")  # the learner's name
_INDEX = re.compile(r"\b\d+(?= `\(-?[\d.]+,-?[\d.]+\),\(-?[\d.]+,-?[\d.]+\)`)")
NUMBER = re.compile(r"(?<![\d.])(?:\d{1,3}(?:,\d{3})+(?:\.\d+)?|\d+(?:\.\d+)?)")
_MARK = re.compile(r"\{([^{}]*)\}")


def _blank(text: str, pattern: re.Pattern[str]) -> str:
    return pattern.sub(lambda m: " " * len(m.group()), text)


@dataclass(frozen=True)
class Token:
    start: int
    line: int
    text: str  # as written, with its thousands separators

    @property
    def value(self) -> str:
        return self.text.replace(",", "")


def tokens(text: str) -> list[Token]:
    """Every number of the prose to bind, with its offset and line."""
    prose = text
    for pattern in (_FENCE, _CODE, _LINK, _TAG, _ES, _NAME, _LABEL):
        prose = _blank(prose, pattern)
    indices = {m.start() for m in _INDEX.finditer(text)}
    out = []
    for m in NUMBER.finditer(prose):
        if m.start() in indices:
            continue
        # a trailing "." or "," of a sentence is not a decimal point
        out.append(Token(m.start(), text.count("\n", 0, m.start()) + 1, m.group()))
    return out


def quote_pattern(quote: str) -> re.Pattern[str]:
    """The quote as a pattern: its marks as groups, any whitespace as any run of whitespace."""
    parts = _MARK.split(quote)
    rx = ""
    for i, part in enumerate(parts):
        if i % 2:
            rx += f"(?<![\\d.,])({re.escape(part)})(?![\\d]|[.,]\\d)"
        else:
            rx += r"\s+".join(re.escape(w) for w in re.split(r"\s+", part)) if part.strip() else part
    return re.compile(rx)


def decimals(token: str) -> int:
    return len(token.split(".")[1]) if "." in token else 0


def matches(token: str, value: float) -> bool:
    """The value, rounded as the token is written (its sign aside), is the token."""
    x, d = float(token.replace(",", "")), decimals(token)
    return abs(round(abs(float(value)), d) - x) < 10 ** -(d + 6)


def label(why: str) -> None:
    """A number that is a name, not a quantity (a version, a section): bound to nothing, with why."""
    assert len(why.split()) >= 2, "label(...) needs a reason"


@dataclass
class Report:
    unbound: list[str]  # numbers no quote covers
    stale: list[str]  # quotes that no longer occur
    wrong: list[str]  # quotes whose expression does not give their number


def check(rel: str, text: str, quotes: list[tuple[str, ...]]) -> Report:
    ns: dict[str, Any] = namespace()
    ns["label"] = label
    toks = tokens(text)
    by_start = {t.start: t for t in toks}
    covered: set[int] = set()
    stale, wrong = [], []
    for entry in quotes:
        quote, exprs = entry[0], entry[1:]
        marks = _MARK.findall(quote)
        if len(marks) != len(exprs):
            wrong.append(f"{quote!r}: {len(marks)} marked numbers, {len(exprs)} expressions")
            continue
        found = False
        for m in quote_pattern(quote).finditer(text):
            starts = [m.start(g) for g in range(1, len(marks) + 1)]
            if not all(s in by_start for s in starts):
                continue
            found = True
            covered.update(starts)
        if not found:
            stale.append(f"{quote!r} no longer occurs in {rel} (or its marks are not whole numbers)")
            continue
        for mark, expr in zip(marks, exprs, strict=True):
            try:
                value = eval(expr, ns)  # expressions of the committed registry only
            except Exception as e:  # the registry's own mistake: say which entry
                wrong.append(f"{quote!r}: {expr}: {type(e).__name__}: {e}")
                continue
            if value is not None and not matches(mark, value):
                wrong.append(f"{quote!r}: {expr} = {value}, not {mark}")
    unbound = [f"{rel}:{t.line}: {t.text}" for t in toks if t.start not in covered]
    return Report(unbound, stale, wrong)
