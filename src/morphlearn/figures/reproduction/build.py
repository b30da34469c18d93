"""The reproduction rule's work: load a run's results, build the table and the persistence counts
(workflow/scripts/reproduction.py calls :func:`run`, then ``writers.write`` and
``record.write_record``)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pandas as pd

from morphlearn import provenance
from morphlearn.figures import data as fd
from morphlearn.figures.reproduction.selection import physics_models
from morphlearn.figures.reproduction.table import reproduction_table


def persistence_counts(theory: fd.ModelResults, settings: fd.TheorySettings, near: float, limit: int) -> pd.DataFrame:
    """Persistence table of the canonical and best designs (see :func:`data.persistence_table`)."""
    return fd.persistence_table(fd.persistence_designs(theory), theory, settings, near, limit)


def _screen(screen: dict[str, Any] | None) -> tuple[fd.ModelResults, fd.ModelResults] | None:
    """(the screen, its refinement), each read from its bundle, its table checked against its record."""
    if screen is None:
        return None
    out = []
    for part in ("screen", "refinement"):
        b = screen[part]
        res = fd.load_results(b["bundle"], b["model"], b["thresholds"])
        if res is None:
            raise FileNotFoundError(f"screen_from: no {b['model']} results in {b['bundle']} (metrics.csv, merged.zarr)")
        out.append(res)
    return out[0], out[1]


def run(
    results_dir: str,
    config_name: str,
    thresholds: dict[str, dict[str, Any]],
    settings: dict[str, float],
    near: float,
    limit: int,
    learners_enabled: bool = False,
    coopt_sigma: float | None = None,
    survey: dict[str, Any] | None = None,
    screen: dict[str, Any] | None = None,
    text_sweep: str | None = None,
    stored_persistence: str | Path | None = None,
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Load the results of the models of ``thresholds`` (model -> its thresholds: the models this
    config runs) and build (reproduction table, persistence table). ``coopt_sigma``: the coopt
    stage ran (its rows use the evolution strategies at that step). ``survey``: the physics survey
    read from a bundle (its model and thresholds; config ``survey_from``). ``screen``: the screen
    and its refinement, each a bundle with its model and thresholds (config ``screen_from``), read
    where they are. ``text_sweep``: a theory bundle of every design at another weight grid and
    horizon (config ``text_sweep_from``), read where it is. ``stored_persistence``:
    a persistence table already made for these results (render_only; checked at start by
    :func:`morphlearn.workflow.rules.check_stored_persistence`), read instead of integrated again."""
    corr = None
    if learners_enabled:
        provenance.check_derived(Path(results_dir) / "learners" / "correlations.csv")  # custody
        corr = pd.read_csv(Path(results_dir) / "learners" / "correlations.csv")
    coopt = None
    if coopt_sigma is not None:
        c = Path(results_dir) / "coopt"
        provenance.check_derived(c / "summary.csv")  # custody: the analysis's sealed record
        coopt = (pd.read_csv(c / "summary.csv"), pd.read_csv(c / "landscape.csv"), coopt_sigma)
    res = {m: fd.load_results(results_dir, m, th) for m, th in thresholds.items()}
    missing = [m for m, r in res.items() if r is None]
    if missing:
        raise FileNotFoundError(f"{missing[0]} is enabled but its results are missing under {results_dir}")
    theory, emp = res.get("theory"), res.get(physics_models()[0])  # the reference engine's
    if theory is None:
        raise FileNotFoundError(f"no theory results under {results_dir}")
    if stored_persistence is not None:
        pers = pd.read_csv(stored_persistence)
    else:
        pers = persistence_counts(theory, fd.TheorySettings(**settings), near, limit)
    engines = {m: r for m, r in res.items() if m in physics_models()[1:] and r is not None}
    table = reproduction_table(
        theory,
        emp,
        pers,
        config_name,
        near,
        corr,
        engines,
        coopt,
        fd.load_survey(results_dir, survey),
        _screen(screen),
        text_sweep,
    )
    return table, pers
