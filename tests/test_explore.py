"""The explorer's logic (morphlearn.explore) on the committed bundles, its widgets driven by calls
(Agg backend), and the notebook executed headless with parameters (papermill)."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import matplotlib
import numpy as np
import pandas as pd
import pytest

from morphlearn import bundle, explore, metrics
from morphlearn import grid as gridmod

matplotlib.use("Agg")

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "results"
PAPER_BEST = gridmod.PAPER_BEST_DESIGN


@pytest.fixture(scope="module")
def paper() -> explore.Explorer:
    return explore.Explorer(explore.open_source(explore.Source(RESULTS / "paper", "theory")))


@pytest.fixture(scope="module")
def survey() -> explore.Explorer:
    return explore.Explorer(explore.open_source(explore.Source(RESULTS / "survey", "theory")))


def test_sources_list_every_model_of_every_bundle() -> None:
    labels = [s.label for s in explore.sources(RESULTS)]
    for want in ("theory (paper)", "empirical (paper)", "theory (survey)", "empirical (survey)"):
        assert want in labels
    assert explore.default_results_dir(ROOT / "notebooks") == ROOT / "results"
    assert labels[0] == "theory (paper)"  # the default, whatever other bundles sort before it


def test_a_damaged_bundle_is_refused(tmp_path: Path) -> None:
    copy = tmp_path / "survey"
    shutil.copytree(RESULTS / "survey", copy)
    table = copy / "theory" / "metrics.csv"
    table.write_text(table.read_text().replace(",0.8", ",0.9", 1))
    with pytest.raises(bundle.BundleError, match="checksum differs"):
        explore.open_source(explore.Source(copy, "theory"))
    with pytest.raises(explore.ExploreError, match="allowed: theory, empirical"):
        explore.open_source(explore.Source(copy, "physics"))


def test_map_layout_places_each_design_at_its_two_sensor_positions(paper: explore.Explorer) -> None:
    n = paper.n
    img = paper.map_image("M_L")
    assert img.shape == (n * n, n * n) and np.isfinite(img).all()  # all 6561 designs
    t = paper.res.table
    for d in (0, 1, 160, 6552, 6560, int(t.design.sample(1, random_state=3).iloc[0])):
        col, row = paper.map_cell(d)
        assert paper.design_at(col, row) == d
        assert paper.design_at(col + 0.4, row - 0.4) == d  # anywhere in the cell
        assert img[row, col] == float(t.loc[t.design == d, "M_L"].iloc[0])
        (x1, y1), (x2, y2) = paper.coords(d)
        # block = sensor 1's position (x to the right, y up), cell in it = sensor 2's
        assert paper.axis[col // n] == x1 and paper.axis[row // n] == y1
        assert paper.axis[col % n] == x2 and paper.axis[row % n] == y2
    assert paper.design_at(-0.6, 0) is None and paper.design_at(0, n * n - 0.4) is None
    with pytest.raises(explore.ExploreError, match="allowed: M_L, M_CF"):
        paper.map_image("M_X")


def test_empirical_map_leaves_unsimulated_designs_blank() -> None:
    ex = explore.Explorer(explore.open_source(explore.Source(RESULTS / "paper", "empirical")))
    img = ex.map_image("M_CF")
    # the designs the bundle's table holds (read apart from the explorer), a few of the 6561
    held_designs = len(pd.read_csv(RESULTS / "paper/empirical/metrics.csv"))
    assert int(np.isfinite(img).sum()) == len(ex.res.table) == held_designs < ex.grid.size
    held = int(ex.res.table.design.iloc[0])
    assert ex.landscape(held).source == "bundle"
    missing = next(d for d in range(ex.grid.size) if not ex.held(d))
    with pytest.raises(explore.ExploreError, match="only the theory model is computed live"):
        ex.landscape(missing)
    with pytest.raises(explore.ExploreError, match="theory model only"):
        ex.settings()


def test_rank_and_mirror(paper: explore.Explorer) -> None:
    best = paper.design_of(*PAPER_BEST)
    mirror = paper.mirror(best)
    assert paper.coords(mirror) == ((0.5, -0.25), (-0.5, 0.25))  # (l1, l2) -> ((x2, -y2), (x1, -y1))
    assert paper.mirror(mirror) == best
    row, mrow = paper.row(best), paper.row(mirror)
    assert (row.M_L, row.M_CF) == (mrow.M_L, mrow.M_CF)  # the model's mirror symmetry
    assert paper.rank(best, "M_L") == paper.rank(mirror, "M_L")
    top = metrics.rank_designs(paper.res.table, "M_L").design.iloc[0]
    assert paper.rank(int(top), "M_L") == 1 and paper.best("M_L") == int(top)
    canonical = paper.design_of(*gridmod.canonical_design())
    assert paper.mirror(canonical) == canonical
    with pytest.raises(explore.ExploreError, match="allowed: 0 to 6560"):
        paper.coords(6561)
    with pytest.raises(explore.ExploreError, match=r"l1\.x=0\.3 is not on the 9-point grid"):
        paper.design_of((0.3, 0.5), (0.5, 0.5))


def test_a_held_design_comes_from_the_bundle_and_agrees_with_its_table(paper: explore.Explorer) -> None:
    d = paper.design_of(*PAPER_BEST)
    land = paper.landscape(d, 41)  # held: the live grid does not apply
    assert land.source == "bundle" and land.seconds is None and len(land.weights) == 121
    assert paper.matches_table(land) is True
    info = explore.describe(paper, land)
    assert info["table"]["generalists"] == info["matrix"]["generalists"] == int(paper.row(d).generalists)


def test_live_landscape_reproduces_the_bundle_on_its_own_grid(survey: explore.Explorer) -> None:
    """The survey's theory run is 41 x 41: a design it does not hold, computed live with the
    bundle's parameters, must give its metrics row exactly (counts per environment too)."""
    d = next(d for d in range(survey.grid.size) if not survey.held(d) and survey.row(d).generalists > 0)
    land = survey.landscape(d, 41)
    assert land.source == "live" and land.seconds > 0
    assert survey.matches_table(land) is True
    row = survey.row(d)
    assert [int(x) for x in land.success.sum(axis=(1, 2))] == [int(row[f"n_{a}"]) for a in gridmod.ENV_ANGLES_DEG]
    assert survey.landscape(d, 41) is land  # cached
    with pytest.raises(explore.ExploreError, match="allowed: 41, 121"):
        survey.landscape(d, 60)


def test_live_landscape_on_another_grid_is_not_compared(paper: explore.Explorer) -> None:
    d = next(d for d in range(paper.grid.size) if not paper.held(d))
    land = paper.landscape(d, 41)
    assert land.source == "live" and land.overlap.shape == (41, 41)
    assert paper.matches_table(land) is None


def test_trajectories_match_the_stored_first_success(paper: explore.Explorer) -> None:
    """The reference integration (the figures') of a held design's controller succeeds in the same
    environments as the stored kernel result, at nearly the same time."""
    d = paper.design_of(*gridmod.canonical_design())
    land = paper.landscape(d)
    w = paper.default_controller(land)
    i, j = land.controller(*w)
    trs = paper.trajectories(d, w)
    ref = np.array(explore.first_success_times(trs))
    kernel = land.first_time[:, i, j]
    assert np.array_equal(np.isnan(ref), np.isnan(kernel))
    ok = ~np.isnan(ref)
    assert ok.any() and np.allclose(ref[ok], kernel[ok], rtol=1e-3)
    assert int(land.overlap[i, j]) == int(ok.sum())


def test_app_selects_by_click_and_by_dropdown(tmp_path: Path) -> None:
    from morphlearn import explore_app

    app = explore_app.App(RESULTS, source="theory (paper)")
    ex = app.ex
    assert app.design == ex.best("M_L") and app.land.source == "bundle"
    # a click on the map, in image coordinates
    target = ex.design_of((0.5, 0.5), (0.5, -0.5))
    col, row = ex.map_cell(target)
    app._on_map_click(type("E", (), {"inaxes": app.fig_maps.axes[0], "xdata": col, "ydata": row})())
    assert app.design == target and app.w_l1.value == (0.5, 0.5) and app.w_l2.value == (0.5, -0.5)
    colorbar = next(a for a in app.fig_maps.axes if a not in app.fig_maps.axes[:2] and a.get_label() == "<colorbar>")
    app._on_map_click(type("E", (), {"inaxes": colorbar, "xdata": 0.5, "ydata": 0.1})())
    assert app.design == target  # a click on a colour bar selects nothing
    # the dropdowns
    app.w_l2.value = (0.5, 0.25)
    assert app.design == ex.design_of((0.5, 0.5), (0.5, 0.25))
    # a click in the overlap matrix picks the nearest controller
    app._on_matrix_click(type("E", (), {"inaxes": app.fig_design.axes[2], "xdata": -0.52, "ydata": 0.61})())
    assert app.w == (-0.5, 0.6) or np.allclose(app.w, (-0.5, 0.6))
    assert "data-stage='done'" in app.w_status.value and len(app.trs) == 4
    app.w_source.value = "empirical (survey)"
    assert app.ex.res.model == "empirical" and app.w_weights.disabled
    rep = explore.write_report(tmp_path / "r.json", app)
    assert rep["source"] == "empirical (survey)" and "first_success" not in rep


def test_notebook_runs_headless_with_parameters(tmp_path: Path) -> None:
    """papermill executes notebooks/explore.ipynb with a design and a controller; the report it
    writes must describe that design with the bundle's metrics and the trajectories' times."""
    report = tmp_path / "report.json"
    params = {"l1": [0.5, 0.5], "l2": [0.5, -0.5], "controller": [0.6, 0.98], "report": str(report)}
    proc = subprocess.run(
        [
            str(Path(sys.executable).with_name("papermill")),
            "notebooks/explore.ipynb",
            str(tmp_path / "out.ipynb"),
            "-y",
            json.dumps(params),
            "--cwd",
            "notebooks",
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    rep = json.loads(report.read_text())
    shown = rep["shown"]
    assert rep["source"] == "theory (paper)" and shown["l1"] == [0.5, 0.5] and shown["l2"] == [0.5, -0.5]
    assert shown["source"] == "bundle" and shown["matches_table"] is True
    assert shown["table"]["M_L"] == pytest.approx(58 / 121**2)  # docs/results.md: canonical, 58 generalists
    assert rep["controller"] == pytest.approx([0.6, 0.9833333333], abs=1e-9)  # the grid's nearest to 0.98
    ref, kernel = rep["first_success"], rep["kernel_first_success"]
    assert [r is None for r in ref] == [k is None for k in kernel]
    assert all(r is None or abs(r - k) < 1e-3 * k for r, k in zip(ref, kernel, strict=True))
