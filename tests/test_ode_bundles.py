"""The committed ODE survey against the committed exhaustive ODE runs (issue 40).

``results/ode-survey`` simulates each design with the adaptive weight grid (every 6th weight, then
the cells near a success or near miss; the rest counted as failures); ``results/ode-paper``
simulates every cell of its designs. On every design both bundles hold, the survey must have found
every success the exhaustive grid found, and the cells it did simulate must be the exhaustive
run's bytes: that is what lets the survey rank the 5-point grid as an exhaustive run would.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from morphlearn import configure, metrics, models, store
from morphlearn.figures import data as fd
from morphlearn.results import STATUS_INFERRED

ROOT = Path(__file__).resolve().parents[1]
SURVEY, EXHAUSTIVE = ROOT / "results/ode-survey", ROOT / "results/ode-paper"
Shared = tuple[fd.ModelResults, fd.ModelResults, list[tuple[int, int, int, int]]]


@pytest.fixture(scope="module")
def shared() -> Shared:
    """Both bundles (read and checked as the figures read them) and, for every design of the
    exhaustive one whose outcomes the survey stores (matched by sensor coordinates: the two lie on
    different grids), (exhaustive design, its position there, survey design, its position there)."""
    exh, sur = fd.load_results(EXHAUSTIVE, "ode"), fd.load_results(SURVEY, "ode")
    assert exh is not None and sur is not None
    out = []
    for r in exh.table.itertuples():
        l1, l2 = (r.l1x, r.l1y), (r.l2x, r.l2y)
        j = sur.find(l1, l2)  # None: not on the survey's grid (the paper's best design, y = 0.125)
        if j is not None:
            out.append((int(r.design), exh.position(l1, l2), int(sur.row(l1, l2).design), j))
    return exh, sur, out


def test_the_survey_misses_no_success_of_the_exhaustive_runs(shared: Shared) -> None:
    th = models.get("ode").thresholds(configure.load(ROOT / "config.yaml", [ROOT / "config/ode_paper.yaml"]))
    exh, sur, pairs = shared
    # the ten refined designs: eight lie on the 5-point grid and are among the survey's stored designs
    assert [d for d, *_ in pairs] == [234, 240, 396, 398, 560, 720, 722, 6552]
    for d, i, _, j in pairs:
        a, b = store.read_design(exh.ds, i), store.read_design(sur.ds, j)
        assert not (a["status"] == STATUS_INFERRED).any(), f"design {d}: the exhaustive run inferred cells"
        sa, sb = (
            metrics.success(a["first_time"], a["min_dist"], th),
            metrics.success(b["first_time"], b["min_dist"], th),
        )
        assert np.array_equal(sa, sb), f"design {d}: {int((sa & ~sb).sum())} successes the survey missed"
        simulated = b["status"] != STATUS_INFERRED
        assert 0.05 < simulated.mean() < 0.25  # the survey's saving: it simulated 10-17 % of the cells
        for k in store.VARS:
            assert a[k][simulated].tobytes() == b[k][simulated].tobytes(), f"design {d}: {k} differs"


def test_the_survey_metrics_are_the_exhaustive_metrics(shared: Shared) -> None:
    exh, sur, pairs = shared
    e, s = exh.table.set_index("design"), sur.table.set_index("design")
    cols = ["n_45", "n_135", "n_225", "n_315", "generalists", "at_least_one", "M_L", "M_CF"]
    for d, _, ds, _ in pairs:
        assert e.loc[d, cols].tolist() == s.loc[ds, cols].tolist(), d
