"""morphlearn.figures' public functions on small synthetic data (no workflow run: seconds)."""

from __future__ import annotations

import json
import tempfile
from pathlib import Path
from types import SimpleNamespace

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest
import yaml

from morphlearn import configure, grid, models, store
from morphlearn.figures import caption, data, options, output, registry
from morphlearn.figures.draw import distribution, matrix, panel, sketch
from morphlearn.results import DesignResult

ROOT = Path(__file__).parents[1]
W = np.array([-1.0, 0.0, 1.0])
DESIGNS = [((0.5, 0.5), (0.5, -0.5)), ((-0.5, -0.25), (0.5, 0.25))]


def synthetic(designs=DESIGNS, generalists=(2, 0)) -> data.ModelResults:
    """Two designs on a 3 x 3 weight grid; design k solves all four environments with its first
    ``generalists[k]`` controllers (grid order) and environment 0 only with the rest. Stored the
    way the workflow stores results (a shard merged into a Zarr store with its digests), since the
    figures read only verified data."""
    n = len(designs)
    ft = np.full((n, 4, 3, 3), np.inf, dtype=np.float32)
    ft[:, 0] = 1.0
    for k, g in enumerate(generalists):
        flat = ft[k].reshape(4, 9)
        flat[:, :g] = 1.0
    g5 = grid.DesignGrid(5)
    idx = np.array([g5.index_of(*d) for d in designs], dtype=np.int64)
    order = np.argsort(idx)
    results = [DesignResult(ft[k], np.zeros((4, 3, 3)), np.zeros((4, 3, 3))) for k in order]
    tmp = Path(tempfile.mkdtemp(prefix="synthetic-"))
    sci = {"model": "theory", "grid": {"positions_per_axis": 5, "weights": 3}}
    store.write_shard(
        tmp / "s.nc",
        model="theory",
        grid=g5,
        weights=W,
        designs=idx[order],
        results=results,
        science=sci,
        provenance={},
    )
    store.merge_shards(
        [tmp / "s.nc"],
        tmp / "merged.zarr",
        model="theory",
        grid=g5,
        weights=W,
        shard_designs=[idx[order]],
        science=sci,
        mirror=False,
        provenance={},
    )
    c = np.array([[*a, *b] for a, b in designs])
    table = pd.DataFrame(
        {
            "design": idx,
            "l1x": c[:, 0],
            "l1y": c[:, 1],
            "l2x": c[:, 2],
            "l2y": c[:, 3],
            "generalists": list(generalists),
            "M_L": [g / 9 for g in generalists],
            "M_CF": [g / 9 for g in generalists],
        }
    )
    return data.ModelResults(
        "theory",
        table,
        store.open_merged(tmp / "merged.zarr"),
        None,
        {"metrics": "m.csv", "merged": str(tmp / "merged.zarr")},
    )


# ---------------------------------------------------------------------------------------------- data


def test_overlap_and_best_of_synthetic_results() -> None:
    res = synthetic()
    o = res.overlap(res.position(*DESIGNS[0]))
    assert (o == 4).sum() == 2 and (o == 1).sum() == 7
    assert data.row_design(res.best("M_L")) == DESIGNS[0]


def test_a_design_missing_from_the_dataset_is_an_error_naming_it() -> None:
    res = synthetic()
    res = data.ModelResults(
        res.model, res.table, res.ds.sel(design=[int(res.table.design[1])]), None, res.paths
    )  # a dataset holding only the second design
    assert res.find(*DESIGNS[0]) is None
    missing = r"l1 = \(0.5, 0.5\), l2 = \(0.5, -0.5\) is not in \S*merged.zarr \(1 designs\); Fig. 9"
    with pytest.raises(ValueError, match=missing):
        res.position(*DESIGNS[0], "Fig. 9")
    assert res.position(*DESIGNS[1]) == 0


def test_results_loading_required_and_optional(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match="no theory results"):
        data.require_results(tmp_path, "theory")
    assert data.optional_results(tmp_path, "empirical", enabled=False) is None
    with pytest.raises(FileNotFoundError, match="no empirical results"):
        data.optional_results(tmp_path, "empirical", enabled=True)


def test_pick_controllers_prefers_generalists_then_nearest() -> None:
    o = np.array([[4, 1, 1], [1, 4, 1], [1, 1, 3]])
    picks = data.pick_controllers(o, W, [(1.0, 1.0), (0.9, 0.9), (1.0, 1.0)])
    assert [(c.w1, c.w2, c.overlap) for c in picks] == [(0.0, 0.0, 4), (-1.0, -1.0, 4), (1.0, 1.0, 3)]
    assert picks[2].exact and not picks[0].exact


# ---------------------------------------------------------------------------------------------- caption


def test_caption_and_metric_line() -> None:
    row = synthetic().best("M_L")
    assert caption.metric_line(row, 9) == "M_L = 0.2222 (2 of 9 controllers), M_CF = 0.2222"
    assert caption.design_text(row) == "l1 = (0.5, 0.5), l2 = (0.5, -0.5)"
    text = caption.caption("Figure 9. Test.", ["body", ""], "**Data and config.** none")
    assert text == "**Figure 9. Test.**\n\nbody\n\n**Data and config.** none\n"


def test_resolution_note_names_the_subset() -> None:
    res = synthetic()
    res.ds.attrs["science_json"] = json.dumps({"grid": {"positions_per_axis": 3}})
    assert caption.resolution_note(res) == (
        "reduced resolution (3 positions per axis, 3 weights, 2 of 81 designs; the paper used 9 and 121, all designs)"
    )
    # the paper's grids on a few designs (refined candidates): the resolution is the paper's
    few = SimpleNamespace(positions_per_axis=9, weights=np.zeros(121), n_designs=41)
    assert caption.resolution_note(few) == "paper resolution on 41 of 6561 designs (the paper: all)"
    assert caption.resolution_note(SimpleNamespace(**{**vars(few), "n_designs": 6561})) == "paper resolution"


def physics_results(model: str, rows: dict[int, tuple[float, float]], m: int = 121, n: int = 5) -> data.ModelResults:
    """A physics model's results holding ``rows`` (design -> (M_L, M_CF)) on an ``n``-position grid
    and ``m`` weights: only what captions read (its table, its weights, its record)."""
    import xarray as xr

    c = np.array([grid.DesignGrid(n).coords(d) for d in rows]).reshape(len(rows), 4)
    table = pd.DataFrame({"design": list(rows), "l1x": c[:, 0], "l1y": c[:, 1], "l2x": c[:, 2], "l2y": c[:, 3]})
    table["M_L"], table["M_CF"] = ([v[k] for v in rows.values()] for k in (0, 1))
    ds = xr.Dataset(coords={"w1": np.linspace(-1, 1, m)}, attrs={"science_json": json.dumps({"positions_per_axis": n})})
    return data.ModelResults(model, table, ds, None)


def test_subset_best_says_which_designs_another_engine_ranks_best_and_whether_they_are_held() -> None:
    g = grid.DesignGrid(5)
    canon, a, b = g.index_of(*grid.canonical_design()), 100, 200
    pb = physics_results("empirical", {canon: (0.002, 0.02), a: (0.07, 0.35)})
    text, cited = caption.subset_best(pb, [None])
    assert text == (
        "The pybullet, 121 x 121 weights results hold 2 of the grid's 625 designs; "
        "their best are the best of those, not of all designs."
    )
    assert cited == []
    # MuJoCo holds more designs on the same weights: its best by both is a, which pybullet holds
    mj = physics_results("mujoco", {canon: (0.002, 0.02), a: (0.07, 0.35), b: (0.03, 0.2), 300: (0.0, 0.0)})
    text, cited = caption.subset_best(pb, [mj])
    assert cited == [mj]
    la = data.design_label(*g.coords(a).reshape(2, 2))
    assert text.endswith(
        f" MuJoCo, 121 x 121 weights, over the 4 designs its results hold, ranks {la} best by both M_L and M_CF; "
        "pybullet holds it."
    )
    # best by M_CF another design (b), held by pybullet only as its mirror image; by M_L a design it lacks
    mj = physics_results("mujoco", {canon: (0.0, 0.0), 400: (0.09, 0.1), b: (0.03, 0.5)})
    pb = physics_results("empirical", {canon: (0.0, 0.0), int(g.mirror(b)): (0.03, 0.5)})
    text, _ = caption.subset_best(pb, [mj])
    assert "best by M_L and" in text and text.endswith("; pybullet holds 1 of the two (or their mirror images).")
    lacking = physics_results("mujoco", {400: (0.09, 0.1), 401: (0.0, 0.5), 402: (0.0, 0.0)})
    assert caption.subset_best(pb, [lacking])[0].endswith("; pybullet holds 0 of the two (or their mirror images).")
    one = physics_results("mujoco", {400: (0.09, 0.5), 401: (0.0, 0.0), 402: (0.0, 0.0)})
    assert caption.subset_best(pb, [one])[0].endswith(" best by both M_L and M_CF; pybullet does not hold it.")
    # not cited: fewer designs, another weight grid (counts are not comparable), another design grid
    assert caption.subset_best(pb, [physics_results("mujoco", {1: (0.1, 0.1), 2: (0, 0), 3: (0, 0)}, n=9)])[1] == []
    assert caption.subset_best(pb, [physics_results("mujoco", {1: (0.1, 0.1)})])[1] == []
    assert caption.subset_best(pb, [physics_results("mujoco", {1: (0.1, 0.1), 2: (0, 0), 3: (0, 0)}, m=11)])[1] == []
    # every design of the grid: nothing to say
    assert caption.subset_best(physics_results("mujoco", {d: (0.0, 0.0) for d in range(g.size)}), [mj]) == ("", [])
    # a survey of every design of a coarser grid whose positions are this one's (the ODE survey of
    # the 5-point grid beside the 9-point refined designs): its best found on this grid by position
    nine = grid.DesignGrid(9)
    best = g.index_of((-0.5, 0.5), (0.5, -0.5))  # 120 on the 5-point grid, 720 on the 9-point one
    survey = physics_results("ode", {d: (0.07 if d == best else 0.0, 0.3 if d == best else 0.0) for d in range(g.size)})
    refined = physics_results("ode", {720: (0.07, 0.3), 6560: (0.0, 0.0)}, n=9)
    assert nine.index_of((-0.5, 0.5), (0.5, -0.5)) == 720 and best == 120
    text, cited = caption.subset_best(refined, [survey])
    assert cited == [survey] and text.endswith(
        " ODE, 121 x 121 weights, over the 625 designs of the 5-point grid its results hold, ranks "
        "l1 = (-0.5, 0.5), l2 = (0.5, -0.5) best by both M_L and M_CF; ODE holds it."
    )
    # held only under the coarse grid's index (120), not at its position: not held
    wrong = physics_results("ode", {120: (0.07, 0.3), 6560: (0.0, 0.0)}, n=9)
    assert caption.subset_best(wrong, [survey])[0].endswith("; ODE does not hold it.")
    # a grid whose positions are not all this one's: not cited
    assert caption.subset_best(refined, [physics_results("ode", {d: (0.0, 0.0) for d in range(256)}, n=4)])[1] == []


# ---------------------------------------------------------------------------------------------- drawing


def test_success_pair_counts_each_category() -> None:
    fig, ax = plt.subplots()
    a = np.array([[1, 1, 0], [0, 0, 0], [1, 0, 0]], bool)
    b = np.array([[1, 0, 0], [1, 0, 0], [0, 0, 0]], bool)
    handles = matrix.success_pair(ax, a, b, W, ("45°", "135°"), "t")
    assert [h.get_label() for h in handles] == ["neither (5)", "45° only (2)", "135° only (1)", "both: 45° ∩ 135° (1)"]
    plt.close(fig)


def test_overlap_image_puts_w1_on_x() -> None:
    fig, ax = plt.subplots()
    o = np.zeros((3, 3), int)
    o[2, 0] = 4  # w1 = 1, w2 = -1: bottom right
    im = matrix.overlap_image(ax, o, W, "t")
    assert im.get_array()[0, 2] == 4 and im.get_extent() == [-1.5, 1.5, -1.5, 1.5]
    plt.close(fig)


def test_distribution_marks_and_missing_panel() -> None:
    fig, (a, b) = plt.subplots(1, 2)
    distribution.distribution(a, np.array([0.0, 0.0, 0.1, 0.3]), "M_L", "t", [("best", 0.3, "-")], "subset")
    assert sum(p.get_height() for p in a.patches) == 4  # every design counted once
    fig.canvas.draw()  # and the bars are drawn on the log axis (seaborn's log_scale lost them)
    shown = [p.get_window_extent().height for p in a.patches if p.get_height() > 0]
    assert len(shown) == 3 and all(np.isfinite(h) and h > 1 for h in shown)
    assert [t.get_text() for t in a.get_legend().get_texts()] == ["best: 0.3"]
    panel.missing(b, title="empirical")
    assert panel.MISSING_TEXT in [t.get_text() for t in b.texts]
    plt.close(fig)


def test_robot_sketch_draws_sensors_where_asked() -> None:
    fig, ax = plt.subplots()
    sketch.robot(ax, (0.5, 0.25), (-0.5, -0.25))
    red = [p.center for p in ax.patches if hasattr(p, "center") and p.get_facecolor()[0] > 0.8]
    assert sorted(map(tuple, red)) == [(-0.5, -0.25), (0.5, 0.25)]
    plt.close(fig)


# ---------------------------------------------------------------------------------------------- output


def test_readability_check_and_save(tmp_path: Path) -> None:
    output.use_style(ROOT / registry.STYLE)
    fig, ax = plt.subplots(figsize=(6, 3))
    ax.set_title("readable")
    out = {k: tmp_path / f"f.{k}" for k in ("png", "pdf", "md")}
    output.save(fig, "cap\n", out["png"], out["pdf"], out["md"])
    assert plt.imread(out["png"]).shape[:2] == (3 * output.DPI, 6 * output.DPI)
    assert out["pdf"].read_bytes().startswith(b"%PDF") and out["md"].read_text() == "cap\n"
    ax.text(0, 0, "tiny", fontsize=6)
    fig.set_size_inches(15, 3)
    problems = output.readability_problems(fig)
    assert problems == ["figure is 15 in wide, more than 12", "text 'tiny' is smaller than 9 pt"]
    with pytest.raises(ValueError, match="not readable"):
        output.save(fig, "cap\n", *out.values())
    plt.close(fig)


# ---------------------------------------------------------------------------------------------- registry


def _write(p: Path, text: str) -> None:
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text(text)


def test_notebook_modules_follow_imports_transitively(tmp_path: Path) -> None:
    src = tmp_path / "src"
    pkg = src / "morphlearn"
    _write(pkg / "__init__.py", "")
    _write(pkg / "figures/__init__.py", "")
    _write(pkg / "figures/draw/__init__.py", "")
    _write(pkg / "figures/draw/a.py", "from morphlearn.figures.draw.b import thing\n")
    _write(pkg / "figures/draw/b.py", "def thing():\n    from . import c  # lazy, still a dependency\n")
    _write(pkg / "figures/draw/c.py", "import numpy\n")
    _write(pkg / "figures/draw/unused.py", "")
    _write(pkg / "grid.py", "")
    nb = {
        "cells": [
            {"cell_type": "markdown", "source": ["import morphlearn.figures.draw.unused"]},
            {
                "cell_type": "code",
                "source": [
                    "%matplotlib inline\n",
                    "from morphlearn.figures.draw import a\n",
                    "from morphlearn import grid\n",
                    "import pandas",
                ],
            },
        ]
    }
    _write(tmp_path / "fig9.ipynb", json.dumps(nb))
    got = registry.notebook_modules(tmp_path / "fig9.ipynb", src)
    rel = sorted(str(Path(p).relative_to(src)) for p in got)
    assert rel == [
        "morphlearn/__init__.py",
        "morphlearn/figures/__init__.py",
        "morphlearn/figures/draw/__init__.py",
        "morphlearn/figures/draw/a.py",
        "morphlearn/figures/draw/b.py",
        "morphlearn/figures/draw/c.py",
        "morphlearn/grid.py",
    ]


def _parameters(nb: Path) -> set[str]:
    cells = json.loads(nb.read_text())["cells"]
    cell = next(c for c in cells if "parameters" in c["metadata"].get("tags", []))
    return {ln.split("=")[0].strip() for ln in "".join(cell["source"]).splitlines() if "=" in ln and ln[0] != "#"}


@pytest.mark.parametrize("empirical", [True, False])
def test_every_registered_figure_has_a_notebook_taking_its_options(empirical: bool) -> None:
    """The rule passes the output paths, the style and the registry's options: the notebook's
    parameters cell must name each (papermill would only warn)."""
    base = yaml.safe_load((ROOT / "config.yaml").read_text())
    s = configure.parse({**base, "empirical": {**base.get("empirical", {}), "enabled": empirical}})
    # every notebook is a registered figure, except the scenario report (its own rule, scenarios.smk)
    # and the interactive explorer (no rule: docs/explorer.md)
    assert set(registry.FIGURES) == {p.stem for p in (ROOT / "notebooks").glob("*.ipynb")} - {"scenarios", "explore"}
    for fig in registry.FIGURES:
        names = _parameters(ROOT / registry.notebook_path(fig))
        passed = {"results_dir", "png", "pdf", "caption", "style", *options.figure_options(s, fig)}
        assert passed <= names, (fig, passed - names)
    # the physics figures get every enabled physics model, and only those (registry order)
    assert ("empirical" in options.figure_options(s, "fig6")["physics"]) == empirical
    assert options.figure_options(s, "fig6")["physics_registered"] == models.physics()
    assert options.figure_options(s, "fig2")["fig2_envs"] == s.source["figures"]["fig2_envs"]


def test_grid_helpers_used_by_the_notebooks_exist() -> None:
    assert grid.canonical_design() == DESIGNS[0]
