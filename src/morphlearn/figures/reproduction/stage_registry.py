"""The stages whose rows follow the paper's claims in the reproduction table, in table order.

As ``figures.registry`` lists the figures, this lists the row builders: a stage is its module
``stages/<name>.py`` (with ``rows(inputs) -> list[dict]``) and one line below. Modules are found
by name, so this module imports none of them (light: the Snakefile imports it at parse time);
``figures.registry.reproduction_code`` gives the reproduction rule every module a stage imports,
so editing one re-renders the table.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

PACKAGE = "morphlearn.figures.reproduction.stages"


@dataclass(frozen=True)
class Stage:
    """What a stage's rows say (its module holds how)."""

    what: str


STAGES: dict[str, Stage] = {
    "survey": Stage("a physics survey of every design: the claims that need all designs; theory vs physics"),
    "screen": Stage("a fast model's map of every design and the paper's engine at its best: which design is best"),
    "refined": Stage("the reference engine's designs at 121 x 121: how the theory's best designs do"),
    "engines": Stage("each further physics engine: its survey or refined rows, and its agreement"),
    "learners": Stage("the learner stage: do M_L and M_CF predict learning (issue 15)"),
    "coopt": Stage("the coopt stage: co-optimising the body (issue 27)"),
    "text_sweep": Stage("a second theory sweep (11 x 11 weights, horizon 1000): the paper's text values"),
}


def rows_of(name: str) -> Callable[[Any], list[dict[str, str]]]:
    """A stage's row builder (its module imported on first use)."""
    return importlib.import_module(f"{PACKAGE}.{name}").rows
