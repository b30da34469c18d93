"""What the table is built from: the results a run holds, handed to every stage's rows."""

from __future__ import annotations

from dataclasses import dataclass, field

import pandas as pd

from morphlearn.figures import data as fd


@dataclass(frozen=True)
class TableInputs:
    """The results one reproduction table reads (None: not in this run)."""

    theory: fd.ModelResults | None
    empirical: fd.ModelResults | None
    persistence: pd.DataFrame | None
    config_name: str
    near: float
    #: learners/correlations.csv (the learner stage)
    learners: pd.DataFrame | None = None
    #: further physics engines: model name -> results
    engines: dict[str, fd.ModelResults] = field(default_factory=dict)
    #: the coopt stage's summary, landscape table and step
    coopt: tuple[pd.DataFrame, pd.DataFrame, float] | None = None
    #: the physics survey read from a bundle (config survey_from)
    survey: fd.ModelResults | None = None
    #: the screen (every design, a fast model's) and its refinement (the paper's engine at its best)
    screen: tuple[fd.ModelResults, fd.ModelResults] | None = None
    #: the second theory sweep's bundle (config text_sweep_from)
    text_sweep: str | None = None
