"""The table: one row per paper claim (``claims.QUANTITIES``, in that order), then each registered
stage's rows (``stage_registry.STAGES``, in that order)."""

from __future__ import annotations

import pandas as pd

from morphlearn.figures import data as fd
from morphlearn.figures.reproduction import stage_registry
from morphlearn.figures.reproduction.claim_values import empirical_rows, theory_rows
from morphlearn.figures.reproduction.claims import COLUMNS, NOT_RUN, QUANTITIES
from morphlearn.figures.reproduction.inputs import TableInputs
from morphlearn.figures.reproduction.text import config_note


def reproduction_table(
    theory: fd.ModelResults | None,
    empirical: fd.ModelResults | None,
    persistence: pd.DataFrame | None,
    config_name: str,
    near: float,
    learners: pd.DataFrame | None = None,
    engines: dict[str, fd.ModelResults] | None = None,
    coopt: tuple[pd.DataFrame, pd.DataFrame, float] | None = None,
    survey: fd.ModelResults | None = None,
) -> pd.DataFrame:
    """The table, one row per entry of ``QUANTITIES`` in that order, then the survey rows of the
    physics survey read from a bundle (``survey``, config ``survey_from``), for each further
    physics engine in ``engines`` (model name -> results) its survey and engine-agreement rows,
    the learner rows (beyond the paper) when ``learners`` (learners/correlations.csv) is given,
    then the coopt stage's rows when ``coopt`` (its summary, landscape table and step) is given."""
    ours: dict[str, tuple[str, str]] = {}
    if theory is not None:
        ours |= theory_rows(theory, persistence, near)
    if empirical is not None:
        ours |= empirical_rows(empirical, list((engines or {}).values()))
    rows = []
    for key, quantity, paper in QUANTITIES:
        res = {"theory": theory, "empirical": empirical}[key.split("_", 1)[0]]  # a key names its model
        value, note = ours.get(key, (NOT_RUN, ""))
        rows.append(
            {
                "key": key,
                "quantity": quantity,
                "paper": paper,
                "ours": value,
                "config": config_note(res, config_name),
                "note": note,
            }
        )
    inputs = TableInputs(theory, empirical, persistence, config_name, near, learners, engines or {}, coopt, survey)
    for name in stage_registry.STAGES:
        rows += stage_registry.rows_of(name)(inputs)
    return pd.DataFrame(rows, columns=COLUMNS)
