# ruff: noqa: E501
"""Draft registry lines for the numbers of a document that tests/quoted_numbers.py does not bind yet.

    .venv/bin/python tools/quote_numbers.py docs/results.md

prints, for each unbound number, a line to paste into that document's list in
tests/quoted_numbers.py: a quote of its context with the number marked, and the candidate
expressions (tests/quoted_sources.py) whose value, rounded as written, is the number. A draft
only: choose the expression the sentence means (the quote's table and column), or write one."""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from quoted_match import check, label, matches, tokens  # noqa: E402
from quoted_numbers import QUOTES  # noqa: E402
from quoted_sources import namespace  # noqa: E402

#: Expressions worth trying for a number (a draft's candidates; the registry may use any other).
CANDIDATES = (
    [
        f"{f}(row({t}, {d}), '{c}')" if False else f"row({t}, {d}).{c}"
        for t, ds in (
            ("theory", ("CANONICAL", "PAPER_BEST_THEORY", "THEORY_BEST_M_L", "PAPER_BEST_ODE")),
            (
                "ode",
                (
                    "CANONICAL",
                    "PAPER_BEST_THEORY",
                    "THEORY_BEST_M_L",
                    "PAPER_BEST_ODE",
                    "BEST_OUR_BODY",
                    396,
                    560,
                    234,
                    722,
                    398,
                ),
            ),
            ("pb", ("CANONICAL", "BEST_OUR_BODY")),
            ("mj", ("CANONICAL", "BEST_OUR_BODY")),
        )
        for d in ds
        for c in ("generalists", "at_least_one", "M_L", "M_CF")
        for f in ("x",)
    ]
    + [
        f"rank({t}, {d}, '{by}')"
        for t, ds in (("theory", ("CANONICAL", "PAPER_BEST_THEORY", "THEORY_BEST_M_L", "PAPER_BEST_ODE")),)
        for d in ds
        for by in ("M_L", "M_CF", "generalists")
    ]
    + [
        "len(theory)",
        "(theory.generalists == 0).sum()",
        "100 * (theory.generalists == 0).mean()",
        "theory.M_L.median()",
        "theory.M_L.max()",
        "theory.M_CF.median()",
        "theory.M_CF.max()",
        "(theory.M_L > row(theory, CANONICAL).M_L).sum()",
        "(asymmetric(theory) & (theory.M_L > row(theory, CANONICAL).M_L) & (theory.M_CF > row(theory, CANONICAL).M_CF)).sum()",
        "theory.flagged.sum()",
        "(theory.flagged > 0).sum()",
        "100 * theory.flagged.sum() / (len(theory) * 121**2 * 4)",
        "len(theory) * 121**2 * 4 / 1e6",
        "spearman(theory, theory, 'M_L')",
        "len(ode)",
        "len(survey)",
        "(survey.generalists > 0).sum()",
        "100 * (survey.generalists > 0).mean()",
        "survey.generalists.max()",
        "spearman(theory, survey, 'M_L')",
        "spearman(theory, survey, 'M_CF')",
        "shared(ode, survey)",
        "positions(survey)",
        "positions(theory)",
        "(m9.generalists > 0).sum()",
        "100 * (m9.generalists > 0).mean()",
        "spearman(theory, m9, 'M_L')",
        "spearman(theory, m9, 'M_CF')",
        "engines['M_L pybullet-mujoco']['all']['rho']",
        "engines['M_CF pybullet-mujoco']['all']['rho']",
        "learn.designs.iloc[0]",
        "runs.seeds.iloc[0]",
        "learn.rho_MCF_retention.min()",
        "learn.rho_MCF_retention.max()",
        "learn.rho_ML_success.min()",
        "learn.rho_ML_success.max()",
        "learn.rho_ML_success_pos.min()",
        "learn.rho_ML_success_pos.max()",
        "row(pb, BEST_OUR_BODY).generalists / 57",
        "row(mj, BEST_OUR_BODY).generalists / 57",
        "len(screened)",
        "screened.generalists.max()",
        "red_paper.generalists.max()",
        *[
            f"{n}.{c}.iloc[{i}]"
            for n in ("ra_paper", "ra_survey", "ra_screened", "ra_random")
            for i in (0,)
            for c in (
                "designs",
                "rho_M_L",
                "rho_M_CF",
                "rho_solved",
                "cells_compared",
                "top10_M_L",
                "top10_M_CF",
                "canonical_rank_M_L",
                "canonical_rank_M_L_ode",
                "best_M_L_rank_in_ode",
            )
        ],
        *[
            f"100 * {n}.{c}.iloc[0]"
            for n in ("ra_paper", "ra_survey", "ra_screened", "ra_random")
            for c in ("cells_same", "with_generalist", "with_generalist_ode", "generalists_within_2")
        ],
        *[
            f"{x}agree[(agree.engine == '{e}') & (agree.robot == '{r}')].{c}.iloc[0]"
            for e in ("mujoco", "pybullet")
            for r in ("authors", "project")
            for x, c in (
                ("100 * ", "cells_same"),
                ("", "cells_compared"),
                ("", "rho_solved"),
                ("100 * ", "with_generalist"),
                ("100 * ", "with_generalist_ode"),
            )
        ],
        *[
            f"paper('{k}')"
            for k in (
                "theory_canonical_generalists",
                "theory_canonical_M_L",
                "theory_canonical_M_CF",
                "theory_paper_best_generalists",
                "theory_paper_best_M_L",
                "theory_paper_best_M_CF",
                "theory_best_M_L_with_M_CF_1",
                "empirical_canonical_generalists",
                "empirical_canonical_M_L",
                "empirical_canonical_M_CF",
                "empirical_paper_best_generalists",
                "empirical_best_M_L",
                "empirical_best_M_CF",
            )
        ],
        "cfg('config/paper.yaml', 'theory.weights')",
        "cfg('config.yaml', 'theory.r')",
        "cfg('config.yaml', 'theory.T')",
    ]
)


def main(rel: str) -> None:
    text = (ROOT / rel).read_text()
    report = check(rel, text, list(QUOTES.get(rel, [])))
    ns = namespace()
    ns["label"] = label
    values = []
    for expr in CANDIDATES:
        try:
            values.append((expr, float(eval(expr, ns))))
        except Exception:  # a candidate this checkout's tables do not give
            pass
    unbound = {(int(u.split(":")[1]), u.rsplit(": ", 1)[1]) for u in report.unbound}
    lines = text.splitlines()
    for t in tokens(text):
        if (t.line, t.text) not in unbound:
            continue
        line = lines[t.line - 1]
        col = t.start - sum(len(x) + 1 for x in lines[: t.line - 1])
        lo, hi = max(0, col - 30), min(len(line), col + len(t.text) + 20)
        quote = line[lo:col] + "{" + t.text + "}" + line[col + len(t.text) : hi]
        cands = [e for e, v in values if matches(t.text, v)]
        print(f"    ({quote.strip()!r}, {cands[0] if len(cands) == 1 else 'TODO'!r}),  # {cands[:6]}")
    for s in report.stale + report.wrong:
        print("#", s)


if __name__ == "__main__":
    main(sys.argv[1])
