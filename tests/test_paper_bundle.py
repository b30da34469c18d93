"""The committed paper-resolution bundle (results/paper/): intact, its designs re-simulate to the
committed rows, and the README's re-render command makes the same figures and table from it alone.

The bundle's own machinery (build, damage detection, subsets) is tested on a smoke run in
tests/test_bundle.py; this file checks the one result reviewers read.
"""

from __future__ import annotations

import json
import shutil
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from conftest import ROOT, copy_workflow, job_stats, snakemake

from morphlearn import bundle, metrics, store
from morphlearn import grid as gridmod
from morphlearn.theory import TheoryParams, evaluate

BUNDLE = ROOT / "results" / "paper"
#: The README's re-render command, after `snakemake`.
RERENDER = ("--cores", "2", "--configfile", "config/paper.yaml", "--config", "render_only=True",
            "results_dir=results/paper", "--forceall")  # fmt: skip


def _science() -> dict:
    return json.loads(store.open_merged(BUNDLE / "theory/merged.zarr").attrs["science_json"])


def test_committed_bundle_is_intact_and_at_paper_resolution() -> None:
    assert bundle.check(BUNDLE) == []
    sci = _science()
    assert (sci["grid"]["positions_per_axis"], sci["grid"]["weights"]) == (9, 121)
    table = pd.read_csv(BUNDLE / "theory/metrics.csv")
    assert sorted(table.design) == list(range(9**2 * 9**2))  # every one of the 6561 designs


@pytest.mark.parametrize("which", ["canonical", "best_M_L", "best_M_CF"])
def test_committed_design_resimulates_to_the_committed_row(which: str) -> None:
    """Re-simulate at full resolution from the recorded science: the same row, the same arrays."""
    table = pd.read_csv(BUNDLE / "theory/metrics.csv")
    sci = _science()
    g = gridmod.DesignGrid(sci["grid"]["positions_per_axis"])
    if which == "canonical":
        d = g.index_of(*gridmod.canonical_design())
    else:
        d = int(metrics.rank_designs(table, which.removeprefix("best_")).design.iloc[0])
    params = TheoryParams.from_config(sci["theory"])
    res = evaluate(g.coords(np.array([d])), gridmod.weights(sci["grid"]["weights"]), params)[0]
    th = metrics.Thresholds(params.horizon, params.success_radius, params.horizon, params.success_radius)
    dm = metrics.design_metrics(metrics.success(res.first_time, res.min_dist, th), res.status)
    row = table[table.design == d].iloc[0]
    assert [int(row[f"n_{a}"]) for a in gridmod.ENV_ANGLES_DEG] == dm.per_env
    assert (int(row.generalists), int(row.at_least_one), int(row.flagged)) == (
        dm.generalists, dm.at_least_one, dm.flagged)  # fmt: skip
    assert (row.M_L, row.M_CF) == pytest.approx((dm.M_L, dm.M_CF), rel=1e-12)
    stored = store.open_merged(BUNDLE / "theory/merged.zarr").sel(design=d)
    for v in store.VARS:
        np.testing.assert_array_equal(stored[v].values, getattr(res, v), err_msg=v)


def test_rerender_from_the_committed_bundle(tmp_path: Path) -> None:
    """A clone holding only the bundle: the README's command re-renders all seven figures and the
    reproduction table, simulating nothing, to the committed bytes."""
    wd = copy_workflow(tmp_path / "clone")
    out = wd / "results" / "paper"
    shutil.copytree(BUNDLE, out)
    t0 = time.perf_counter()
    proc = snakemake(wd, *RERENDER, timeout=600)
    print(f"re-rendered the paper bundle in {time.perf_counter() - t0:.0f} s")
    jobs = job_stats(proc.stdout + proc.stderr)
    assert set(jobs) == {*(f"figure_fig{i}" for i in range(1, 8)), "reproduction", "all"}, jobs
    assert bundle.check(out) == []  # figures, captions and table byte-identical to the committed
