"""The explorer's logic (morphlearn.apps.explore) on the committed bundles, its widgets driven by calls
(Agg backend), and the notebook executed headless with parameters (papermill)."""

from __future__ import annotations

import html
import json
import shutil
import subprocess
import sys
from pathlib import Path

import matplotlib
import numpy as np
import pandas as pd
import pytest

from morphlearn import grid as gridmod
from morphlearn import metrics
from morphlearn.apps import explore
from morphlearn.bundles import make as bundle

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
    for want in ("theory (paper)", "pybullet (paper)", "MuJoCo (paper)", "ODE (paper)", "pybullet (survey)"):
        assert want in labels
    # issue 59: one name per source, the engine's (as the engines table and the figures name it),
    # never the registry's ('empirical (paper)' in one list, 'pybullet' in another)
    assert not [x for x in labels if x.split(" (")[0] in ("empirical", "mujoco", "ode")], labels
    assert len(set(labels)) == len(labels)
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
    from morphlearn.apps import explore_app

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
    app.w_source.value = "pybullet (survey)"
    assert app.ex.res.model == "empirical" and app.w_weights.disabled
    rep = explore.write_report(tmp_path / "r.json", app)
    assert rep["source"] == "pybullet (survey)" and "first_success" not in rep


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


# -- the laptop-usable explorer (issue 41, Build item 5) -----------------------------------------------
def test_top_table_ranks_and_searches(paper: explore.Explorer) -> None:
    top = paper.top("M_L", 10)
    assert len(top) == 10 and top["rank"].iloc[0] == 1 and top.design.iloc[0] == paper.best("M_L")
    for r in top.itertuples():  # the table's rank is the explorer's (ties share one)
        assert r.rank == paper.rank(int(r.design), "M_L")
    assert (top.M_L.diff().dropna() <= 0).all()
    by_cf = paper.top("M_CF", 5)
    assert by_cf.design.iloc[0] == paper.best("M_CF") and (by_cf.M_CF.diff().dropna() <= 0).all()
    # search: a design number, a sensor position (spaces ignored)
    assert list(paper.top("M_L", 5, "design 2531:").design) == [2531]
    hits = paper.top("M_L", 1000, "l1 (0.5, 0.5)")
    assert len(hits) == 81 and ((hits.l1x == 0.5) & (hits.l1y == 0.5)).all()
    assert paper.top("M_L", 5, "no such design").empty
    with pytest.raises(explore.ExploreError, match="allowed: M_L, M_CF"):
        paper.top("generalists")


def test_hover_names_the_design_its_sensors_and_metrics(paper: explore.Explorer) -> None:
    import matplotlib.pyplot as plt

    from morphlearn.apps import explore_app

    d = paper.design_of((0.5, 0.5), (0.5, -0.5))
    row = paper.row(d)
    text = paper.hover(d)
    assert text.startswith(f"design {d}: l1 (0.5, 0.5), l2 (0.5, -0.5): M_L {row.M_L:.4g} (rank ")
    assert f"M_CF {row.M_CF:.4g} (rank {paper.rank(d, 'M_CF')})" in text
    fig = plt.figure()
    explore_app.draw_maps(fig, paper)
    col, row_ = paper.map_cell(d)
    for ax in fig.axes[:2]:  # ipympl's read-out under the mouse: the same text, not "(x, y) = (, )"
        assert ax.format_coord(col, row_) == text
    assert fig.axes[0].format_coord(-5, -5) == ""
    plt.close(fig)
    emp = explore.Explorer(explore.open_source(explore.Source(RESULTS / "paper", "empirical")))
    assert "not simulated in this bundle (3 designs are)" in emp.hover(0)


def test_view_round_trips_through_the_url() -> None:
    v = explore.View("theory (paper)", 2531, "M_CF", (0.6, 0.98333333))
    q = v.query()
    assert "source=theory+%28paper%29" in q and "design=2531" in q and "metric=M_CF" in q
    back = explore.parse_view("?" + q)
    assert (back.source, back.design, back.metric) == ("theory (paper)", 2531, "M_CF")
    assert back.w == pytest.approx((0.6, 0.983333))
    assert explore.parse_view("") == explore.View() and explore.parse_view(None) == explore.View()
    for bad, msg in (("design=x", "design='x'"), ("metric=M_X", "allowed: M_L, M_CF"), ("w=1", "two numbers")):
        with pytest.raises(explore.ExploreError, match=msg):
            explore.parse_view(bad)


def test_export_holds_the_shown_design(paper: explore.Explorer) -> None:
    land = paper.landscape(paper.best("M_L"))
    rows = explore.export_csv(land).splitlines()
    m = len(land.weights)
    assert len(rows) == 1 + m * m and rows[0].split(",")[:4] == ["design", "w1", "w2", "overlap"]
    i, j = 17, 100
    cells = rows[1 + i * m + j].split(",")
    assert int(cells[0]) == land.design and float(cells[1]) == pytest.approx(land.weights[i])
    assert float(cells[2]) == pytest.approx(land.weights[j]) and int(cells[3]) == land.overlap[i, j]
    assert [int(c) for c in cells[4:8]] == [int(s) for s in land.success[:, i, j]]
    data = json.loads(explore.export_json(paper, land, (0.6, 0.5), "theory (paper)"))
    assert data["design"] == land.design and data["results"] == "theory (paper)" and data["engine"] == "theory"
    assert np.array_equal(np.array(data["overlap"]), land.overlap) and data["controller"] == [0.6, 0.5]
    assert data["table"]["generalists"] == int(np.array(data["overlap"]).__eq__(4).sum())
    ft = np.array(data["first_time"], dtype=float)
    assert np.array_equal(np.isnan(ft), np.isnan(land.first_time))


def test_nearest_design_across_grids(paper: explore.Explorer, survey: explore.Explorer) -> None:
    d = paper.design_of((0.5, 0.25), (-0.5, 0.0))
    assert survey.nearest_design(*paper.coords(d)) == (survey.design_of((0.5, 0.25), (-0.5, 0.0)), True)
    near, exact = survey.nearest_design((0.375, 0.5), (0.0, 0.125))
    assert not exact and survey.coords(near)[1] in ((0.0, 0.0), (0.0, 0.25))


def test_layout_fits_the_page_and_nothing_is_clipped_inside_a_figure(paper: explore.Explorer) -> None:
    """The figures' sizes for a page (app) width: none wider than it; drawn at those sizes, every
    axes (maps, colour bars, matrix, trajectories) inside its figure."""
    import matplotlib.pyplot as plt

    from morphlearn.apps import explore_app

    land = paper.landscape(paper.best("M_L"))
    w = paper.default_controller(land)
    trs = paper.trajectories(land.design, w)
    for page in (1000, 1336, 1890):
        sizes = explore_app.layout_sizes(page)
        assert all(s[0] <= page for s in sizes.values()), (page, sizes)
        if page >= 1100:  # the maps and the side bar side by side
            assert sizes["maps"][0] + sizes["side"][0] + 16 <= page
        for name, draw in (
            ("maps", lambda f: explore_app.draw_maps(f, paper)),
            ("design", lambda f: explore_app.draw_design(f, paper, land, land.design, w)),
            ("traj", lambda f: explore_app.draw_trajectories(f, paper, land.design, w, trs, 4)),
        ):
            fig = plt.figure(figsize=explore_app._inches(sizes[name]), layout=None if name == "traj" else "constrained")
            draw(fig)
            fig.canvas.draw()
            r = fig.canvas.get_renderer()
            box = fig.bbox
            for ax in fig.axes:
                tb = ax.get_tightbbox(r)
                assert tb.x0 >= box.x0 - 1 and tb.x1 <= box.x1 + 1, (page, name, ax.get_label(), tb, box)
                assert tb.y0 >= box.y0 - 1 and tb.y1 <= box.y1 + 1, (page, name, ax.get_label(), tb, box)
                for leg in fig.legends:  # the trajectories' legend: inside, clear of the x label
                    lb = leg.get_window_extent(r)
                    assert lb.y0 >= box.y0 and not lb.overlaps(tb), (page, name, lb, tb)
            plt.close(fig)


def test_app_keeps_the_design_across_sources_and_opens_a_shared_view() -> None:
    from morphlearn.apps import explore_app

    app = explore_app.App(RESULTS, url_query="source=theory+%28paper%29&design=720&metric=M_CF&w=0.6,0.95")
    assert app.design == 720 and app.w == pytest.approx((0.6, 0.95)) and app.w_rank_by.value == "M_CF"
    assert app.w_top.options[0][1] == app.ex.best("M_CF")  # the top-N table ranks by the URL's metric
    assert explore.parse_view(app.bridge.query).design == 720
    # the bundle's models side by side: design 720 is in all four (ODE holds it among its ten, pybullet among its three)
    rows = {r["engine"]: r for r in app.engines()}
    assert set(rows) == {"theory", "ODE", "pybullet", "MuJoCo"}
    assert all(r["M_L"] is not None and r["landscape"] is not None for r in rows.values())
    assert len(app.fig_engines.axes) == 5  # four matrices and their colour bar
    assert "rank 1 of 3" in explore_app.engines_html(app.engines(), "paper")
    # another source of the same bundle: the same design
    app.w_source.value = "MuJoCo (paper)"
    assert app.design == 720 and app.land.source == "bundle"
    assert explore.parse_view(app.bridge.query) == explore.View("MuJoCo (paper)", 720, "M_CF", app.w)
    # a bundle with a coarser grid: the nearest design, said so
    app.w_source.value = "theory (paper)"
    app.select(app.ex.design_of((0.375, 0.5), (0.0, 0.125)))
    app.w_source.value = "theory (survey)"
    assert app.ex.n == 5 and "is not on this bundle's 5 x 5 grid" in html.unescape(app.w_info.value)
    # the top-N table picks a design; its search narrows it
    app.w_search.value = "l1 (0.5, 0.5)"
    assert app.w_top.options and all("0.5,0.5" in label.split()[2] for label, _ in app.w_top.options)
    app.w_top.value = app.w_top.options[2][1]
    assert app.design == app.w_top.options[2][1]
    # a link with a typo: said so, the default view opens
    bad = explore_app.App(RESULTS, url_query="design=abc")
    assert "URL design='abc'" in html.unescape(bad.w_info.value) and bad.design == bad.ex.best("M_L")


def test_status_done_only_when_the_page_has_drawn(tmp_path: Path) -> None:
    """With a page, an update says "sent" until the page echoes the token sent after its images;
    an image that went by the page's own request (draw_idle) is sent again first."""
    from morphlearn.apps import explore_app

    app = explore_app.App(RESULTS, source="theory (paper)")
    app._has_page = lambda: True  # as under ipympl
    sent: list[dict] = []
    app.bridge.send = lambda msg: sent.append(msg)  # the page's download
    app.select(app.ex.best("M_CF"))
    assert "data-stage='sent'" in app.w_status.value and app.timings[-1].get("page_s") is None
    token = app.bridge.token
    app.bridge.drawn = token - 1  # an older update's echo: still waiting
    assert "data-stage='sent'" in app.w_status.value
    app._unsettled = True  # an image went by draw_idle: one more round
    app.bridge.drawn = token
    assert "data-stage='sent'" in app.w_status.value and app.bridge.token == token + 1
    app.bridge.drawn = token + 1
    assert "data-stage='done'" in app.w_status.value and app.timings[-1]["page_s"] > 0
    # export: a download of the shown design, by the bridge
    text = app.export("csv")
    assert sent[-1]["download"] == f"morphlearn_theory_paper_design{app.design}.csv" and sent[-1]["text"] == text
    assert json.loads(app.export("json"))["design"] == app.design and sent[-1]["mime"] == "application/json"


def test_explorer_extra_is_pinned_in_the_lock() -> None:
    """pyproject's ``explorer`` extra names the explorer's libraries; tools/setup.sh installs them
    from requirements.lock, so each must be pinned there (and the explorer's conda env too)."""
    import tomllib

    extra = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]["explorer"]
    lock = {
        line.split("==")[0].lower()
        for line in (ROOT / "requirements.lock").read_text().splitlines()
        if "==" in line and not line.startswith("#")
    }
    assert {"ipywidgets", "ipympl", "anywidget", "voila"} <= set(extra)
    assert [p for p in extra if p.lower() not in lock] == []
    env = (ROOT / "envs" / "explorer.yaml").read_text()
    assert all(f"- {p}==" in env for p in ("ipywidgets", "ipympl", "anywidget", "voila"))
