"""The verdict rule: one tolerance per kind of claim, written once, applied to every row.

A claim is *reproduced* when ours is within its kind's tolerance of the paper's value, *differs*
when it is not, and is *not comparable* when ours does not answer the claim as the paper put it
(not in this run; another weight grid or design grid than the paper's 121 x 121 weights and 6561
designs; a claim about the best of all designs answered from a subset; no value in the paper).
One exception, because it cannot mislead: the best of a subset of designs is a lower bound of the
best of all, so a subset's best count or metric already above the paper's tolerance differs.
"""

from __future__ import annotations

from dataclasses import dataclass

from morphlearn.figures.reproduction.claims import COUNT, DESIGN, METRIC, NOT_RUN, SHARE, YES_NO

REPRODUCED, DIFFERS, NOT_COMPARABLE = "reproduced", "differs", "not comparable"
#: Reproduced by a set-up that was itself inferred from the paper's numbers (a weight grid or
#: horizon read off the values being checked): agreement is expected of a right guess, so it is
#: weaker evidence than an independent reproduction, and counted apart.
INFERRED = "reproduced (inferred set-up)"
VERDICTS = (REPRODUCED, INFERRED, DIFFERS, NOT_COMPARABLE)

#: A count of generalists agrees within this many controllers or this share of the paper's count,
#: whichever is larger (a count of a few controllers moves by one with an integrator tolerance).
COUNT_ABS, COUNT_REL = 2, 0.02
#: M_L or M_CF agrees within this share of the paper's value.
METRIC_REL = 0.05
#: A share "k of n" agrees within this many percentage points (the paper's n is small: 6, 35).
SHARE_ABS = 0.10

#: The rule as the table's first note states it.
TOLERANCES: dict[str, str] = {
    COUNT: f"a count of controllers: within {COUNT_ABS} or {COUNT_REL:.0%} of the paper's, whichever is larger",
    METRIC: f"a value of M_L or M_CF: within {METRIC_REL:.0%} of the paper's (relative)",
    SHARE: f"a share k of n: within {SHARE_ABS * 100:.0f} percentage points",
    YES_NO: "a yes/no claim: the same answer",
    DESIGN: "which design is best: the paper's design or its mirror image among ours tied for best",
}


@dataclass(frozen=True)
class Scope:
    """Whether ours answers a claim as the paper asked it (``why``: what is missing when not)."""

    comparable: bool = True
    why: str = ""
    #: ours is the best of a subset of designs, a lower bound of the best of all
    lower_bound: bool = False


FULL = Scope()


def inferred(said: str) -> str:
    """The verdict of a row whose set-up was inferred from the paper's numbers: a reproduction
    becomes :data:`INFERRED`; differs and not comparable stay as they are."""
    return INFERRED if said == REPRODUCED else said


def agrees(kind: str, paper: float | bool, ours: float | bool) -> bool:
    """Ours within the tolerance of ``kind`` of the paper's value."""
    if kind == COUNT:
        return abs(float(ours) - float(paper)) <= max(COUNT_ABS, COUNT_REL * float(paper))
    if kind == METRIC:
        return abs(float(ours) - float(paper)) <= METRIC_REL * abs(float(paper))
    if kind == SHARE:
        return abs(float(ours) - float(paper)) <= SHARE_ABS
    if kind in (YES_NO, DESIGN):  # ours of a design claim: whether the paper's design is among the best
        return bool(ours) == bool(paper)
    raise ValueError(f"claim kind {kind!r}; allowed: {sorted(TOLERANCES)}")


def verdict(kind: str, paper: object, ours: float | bool | None, scope: Scope = FULL) -> tuple[str, str]:
    """(verdict, why not comparable) of one claim."""
    if paper is None:
        return NOT_COMPARABLE, "the paper states no value"
    if ours is None:
        return NOT_COMPARABLE, scope.why or NOT_RUN
    if kind == DESIGN:
        paper = True  # the design itself is checked by the caller: ours says whether it is among the best
    if not scope.comparable:
        exceeds = kind in (COUNT, METRIC) and float(ours) > float(paper)  # type: ignore[arg-type]
        if scope.lower_bound and exceeds and not agrees(kind, paper, ours):  # type: ignore[arg-type]
            return DIFFERS, ""
        return NOT_COMPARABLE, scope.why
    return (REPRODUCED if agrees(kind, paper, ours) else DIFFERS), ""  # type: ignore[arg-type]
