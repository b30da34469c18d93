"""What the figures show, computed from the workflow's results (no plotting here).

A model's results are its metrics table (``<results>/<model>/metrics.csv``, one row per design)
and its merged dataset (``<results>/<model>/merged.zarr``, outcomes over (design, env, w1, w2)).
Both models share this schema; the empirical sweep may hold only a subset of the designs and
its own weight grid, so everything here looks designs up by coordinates and reads the weights
from the dataset.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from morphlearn import grid as gridmod
from morphlearn import metrics, provenance, store
from morphlearn.theory.reference import ReferenceTrajectory, reference_trajectory

Point = tuple[float, float]
Design = tuple[Point, Point]

#: "Stays near the source": after its first success the centre never again moves farther than
#: this from the light, up to the horizon (one body length; the start is r = 4 away).
NEAR_DISTANCE = 1.0
#: At most this many generalists per design are integrated for the persistence count (evenly
#: spread over the generalists in weight-grid order); the paper counted 35 for its best design.
MAX_PERSISTENCE_CONTROLLERS = 35

#: Controllers the paper shows (Figs. 4 and 5).
PAPER_CANONICAL_CONTROLLERS: tuple[Point, ...] = ((0.6, 0.98), (0.77, 0.77))
PAPER_BEST_CONTROLLERS: tuple[Point, ...] = ((-0.85, 0.82), (-0.8, 0.6), (-0.28, 0.37))
#: The paper's best theory design (by M_L).
PAPER_BEST_DESIGN: Design = gridmod.PAPER_BEST_DESIGN


def design_label(l1: Sequence[float], l2: Sequence[float]) -> str:
    return f"l1 = ({l1[0]:g}, {l1[1]:g}), l2 = ({l2[0]:g}, {l2[1]:g})"


def engine_label(model: str) -> str:
    """A physics model's engine as prose names it (``MuJoCo``, ``pybullet``); else the model's name."""
    from morphlearn import models

    m = models.get(model)
    return getattr(m, "engine_label", "") or getattr(m, "engine", model)


def dataset_label(res: ModelResults, short: bool = False) -> str:
    """How a figure names a model's results: a physics engine with its weight grid
    (``pybullet, 121 x 121 weights``; ``short``, for panel titles: ``pybullet (121 x 121)``), the
    theory by its name."""
    from morphlearn import models

    if not hasattr(models.get(res.model), "engine"):
        return res.model
    m = len(res.weights)
    return f"{engine_label(res.model)} ({m} x {m})" if short else f"{engine_label(res.model)}, {m} x {m} weights"


def row_design(row: pd.Series) -> Design:
    return (float(row.l1x), float(row.l1y)), (float(row.l2x), float(row.l2y))


def thresholds_from(d: dict[str, float] | None) -> metrics.Thresholds | None:
    return None if d is None else metrics.Thresholds(**d)


@dataclass
class ModelResults:
    """One model's metrics table and merged dataset, with the thresholds of its metrics."""

    model: str
    table: pd.DataFrame
    ds: xr.Dataset
    thresholds: metrics.Thresholds | None
    paths: dict[str, str] = field(default_factory=dict)
    #: its folder under the results folder: the model's name, or ``survey/<model>`` for a survey
    #: read from another bundle (``survey_from``)
    folder: str = ""

    def __post_init__(self) -> None:
        self.folder = self.folder or self.model

    @property
    def science(self) -> dict[str, Any]:
        """The config subset the dataset was made with (its ``science_json`` attribute)."""
        return json.loads(self.ds.attrs.get("science_json", "{}"))

    @property
    def positions_per_axis(self) -> int | None:
        """Grid positions per axis, from the record as its model reads it (None: no record)."""
        from morphlearn import models

        sci = self.science
        return models.get(self.model).positions_of(sci) if sci else None

    @property
    def weights(self) -> np.ndarray:
        return np.asarray(self.ds["w1"].values, dtype=np.float64)

    @property
    def n_controllers(self) -> int:
        return len(self.weights) ** 2

    @property
    def n_designs(self) -> int:
        return len(self.table)

    def find(self, l1: Sequence[float], l2: Sequence[float]) -> int | None:
        """Position of design ``(l1, l2)`` in the dataset, or None if it was not simulated."""
        c = np.stack([self.ds[k].values for k in ("l1x", "l1y", "l2x", "l2y")], axis=-1)
        hit = np.flatnonzero(np.all(np.isclose(c, [*l1, *l2], atol=1e-9), axis=-1))
        return int(hit[0]) if hit.size else None

    def position(self, l1: Sequence[float], l2: Sequence[float], why: str = "this figure") -> int:
        """Like :meth:`find`, but a design ``why`` needs and the dataset lacks is an error (a merged
        dataset may hold only some designs): never an empty panel."""
        pos = self.find(l1, l2)
        if pos is None:
            raise ValueError(
                f"{self.model}: design {design_label(l1, l2)} is not in {self.paths.get('merged', 'the dataset')} "
                f"({self.ds.sizes['design']} designs); {why} needs its outcomes"
            )
        return pos

    def row(self, l1: Sequence[float], l2: Sequence[float]) -> pd.Series | None:
        t = self.table
        sel = np.isclose(t.l1x, l1[0]) & np.isclose(t.l1y, l1[1]) & np.isclose(t.l2x, l2[0]) & np.isclose(t.l2y, l2[1])
        return t[sel].iloc[0] if sel.any() else None

    def success(self, pos: int) -> np.ndarray:
        """(4, m, m) success of the design at dataset position ``pos`` ([env, i_w1, i_w2])."""
        d = store.read_design(self.ds, pos)  # verified against the store's digests
        ft = d["first_time"]
        if self.thresholds is None:
            return np.isfinite(ft)
        return metrics.success(ft, d["min_dist"], self.thresholds)

    def overlap(self, pos: int) -> np.ndarray:
        """(m, m) overlap O = number of environments solved, [i_w1, i_w2]."""
        o = metrics.overlap(self.success(pos))
        row = self.table[self.table.design == int(self.ds["design"].values[pos])]
        if len(row) and int((o == 4).sum()) != int(row.iloc[0].generalists):
            raise ValueError(
                f"{self.model}: overlap of design {int(self.ds['design'].values[pos])} has "
                f"{int((o == 4).sum())} generalists, metrics.csv {int(row.iloc[0].generalists)}: "
                "the figure's thresholds differ from the metrics'"
            )
        return o

    def best(self, by: str) -> pd.Series:
        """The best design by ``by`` (ties: the other metric, then the smaller index)."""
        return metrics.rank_designs(self.table, by).iloc[0]

    def tied_with(self, row: pd.Series, by: str) -> pd.DataFrame:
        """Designs with the same value of ``by`` as ``row`` (e.g. its mirror image)."""
        return self.table[np.isclose(self.table[by], row[by])]


def load_results(
    results_dir: str | Path, model: str, thresholds: dict[str, float] | None = None, folder: str | None = None
) -> ModelResults | None:
    """A model's results, or None when this run has none (model disabled or not run). ``folder``:
    where under ``results_dir`` they are, if not in the model's own folder (a survey's)."""
    base = Path(results_dir) / (folder or model)
    table_path, merged_path = base / "metrics.csv", base / "merged.zarr"
    if not table_path.is_file() or not merged_path.exists():
        return None
    ds = store.open_merged(merged_path)  # verifies the coordinates; read_design the chunks
    # custody: the table is the one its record names, computed from this store
    provenance.check_derived(table_path, ds)
    table = pd.read_csv(table_path)
    paths = {"metrics": str(table_path), "merged": str(merged_path)}
    return ModelResults(model, table, ds, thresholds_from(thresholds), paths, folder or model)


def load_survey(results_dir: str | Path, survey: dict[str, Any] | None) -> ModelResults | None:
    """The physics survey a config reads from a bundle (``survey_from``; the notebook parameter
    ``survey``: its model and thresholds), or None when it sets none; missing files are an error."""
    if survey is None:
        return None
    folder = f"{store.SURVEY_DIR}/{survey['model']}"
    res = load_results(results_dir, survey["model"], survey["thresholds"], folder)
    if res is None:
        raise FileNotFoundError(f"no survey under {results_dir}/{folder} (metrics.csv and merged.zarr)")
    return res


def require_results(results_dir: str | Path, model: str, thresholds: dict[str, float] | None = None) -> ModelResults:
    """A model's results that a figure cannot do without (FileNotFoundError naming the files)."""
    res = load_results(results_dir, model, thresholds)
    if res is None:
        raise FileNotFoundError(f"no {model} results under {results_dir} ({model}/metrics.csv and {model}/merged.zarr)")
    return res


def optional_results(
    results_dir: str | Path, model: str, enabled: bool, thresholds: dict[str, float] | None = None
) -> ModelResults | None:
    """A model's results when the config enables it (then they must exist), else None: the
    figure draws that model's panels as "not in this run"."""
    return require_results(results_dir, model, thresholds) if enabled else None


def physics_results(results_dir: str | Path, physics: dict[str, dict[str, float]]) -> list[ModelResults]:
    """The results of every enabled physics model a figure reads (``physics``: name -> thresholds,
    in registry order, from :func:`morphlearn.figures.options.figure_options`)."""
    return [require_results(results_dir, name, th) for name, th in physics.items()]


# ---------------------------------------------------------------------------------------------
# Controllers


@dataclass(frozen=True)
class Controller:
    """A controller of the weight grid chosen to stand in for a requested one."""

    target: Point | None  # the requested (paper's) weights, None if chosen freely
    w1: float
    w2: float
    overlap: int  # environments it solves
    exact: bool  # equal to the target

    @property
    def generalist(self) -> bool:
        return self.overlap == 4

    def describe(self) -> str:
        w = f"({self.w1:.3g}, {self.w2:.3g})"
        if self.target is None:
            return w
        t = f"({self.target[0]:g}, {self.target[1]:g})"
        return f"{w} = the paper's {t}" if self.exact else f"{w}, nearest to the paper's {t}"


def pick_controllers(overlap: np.ndarray, weights: np.ndarray, targets: Sequence[Point]) -> list[Controller]:
    """For each target, the nearest unused controller of the grid with the highest overlap left.

    Generalists (O = 4) come first; when there are fewer generalists than targets (or none), the
    remaining targets get the nearest controllers of the next highest overlap. Each controller is
    used once.
    """
    w = np.asarray(weights, dtype=np.float64)
    o = np.asarray(overlap)
    used = np.zeros(o.shape, dtype=bool)
    out = []
    for t in targets:
        free = ~used
        best = int(o[free].max())
        i1, i2 = np.nonzero(free & (o == best))
        d = np.hypot(w[i1] - t[0], w[i2] - t[1])
        k = int(np.argmin(d))
        used[i1[k], i2[k]] = True
        out.append(Controller((float(t[0]), float(t[1])), float(w[i1[k]]), float(w[i2[k]]), best, bool(d[k] < 1e-9)))
    return out


def generalists(overlap: np.ndarray, weights: np.ndarray) -> list[Point]:
    """Weights of all controllers that solve the four environments, in grid order."""
    w = np.asarray(weights, dtype=np.float64)
    i1, i2 = np.nonzero(overlap == 4)
    return [(float(w[a]), float(w[b])) for a, b in zip(i1, i2, strict=True)]


def spread(items: Sequence[Any], k: int) -> list[Any]:
    """At most ``k`` items, evenly spread over the sequence (all of them if it is short)."""
    if len(items) <= k:
        return list(items)
    idx = np.unique(np.linspace(0, len(items) - 1, k).round().astype(int))
    return [items[i] for i in idx]


# ---------------------------------------------------------------------------------------------
# Trajectories (theory, scipy reference) and persistence


@dataclass(frozen=True)
class TheorySettings:
    """What a theory trajectory needs from the config."""

    r: float
    horizon: float
    radius: float
    tol: float = 1e-8


def trajectories(design: Design, w: Point, s: TheorySettings) -> list[ReferenceTrajectory]:
    """The four environments' trajectories (light at the origin), run to the full horizon."""
    l1, l2 = design
    return [
        reference_trajectory(
            tuple(start), l1, l2, w[0], w[1], radius=s.radius, horizon=s.horizon, tol=s.tol, stop_at_success=False
        )
        for start in gridmod.env_starts(s.r)
    ]


def max_distance_after_success(tr: ReferenceTrajectory) -> float:
    """Largest centre-to-light distance from the first success to the horizon (NaN: no success)."""
    if not math.isfinite(tr.first_time):
        return math.nan
    d = np.hypot(tr.path[:, 0], tr.path[:, 1])
    after = d[tr.t >= tr.first_time]
    return float(after.max()) if after.size else 0.0


def stays_near(trs: Sequence[ReferenceTrajectory], near: float = NEAR_DISTANCE) -> bool:
    """Succeeds in every environment and afterwards never moves farther than ``near`` from it."""
    d = [max_distance_after_success(t) for t in trs]
    return all(math.isfinite(x) and x <= near for x in d)


def persistence_table(
    designs: dict[str, Design],
    res: ModelResults,
    s: TheorySettings,
    near: float = NEAR_DISTANCE,
    limit: int = MAX_PERSISTENCE_CONTROLLERS,
) -> pd.DataFrame:
    """Per generalist controller (at most ``limit`` per design): does it stay near the source?

    One row per (design, controller) with the four environments' reference first-success times
    and largest distance after success, and ``stays_near``.
    """
    rows = []
    for label, design in designs.items():
        pos = res.find(*design)
        if pos is None:
            continue
        gen = generalists(res.overlap(pos), res.weights)
        for w in spread(gen, limit):
            trs = trajectories(design, w, s)
            row: dict[str, Any] = {
                "design": label,
                "l1x": design[0][0],
                "l1y": design[0][1],
                "l2x": design[1][0],
                "l2y": design[1][1],
                "generalists": len(gen),
                "w1": w[0],
                "w2": w[1],
            }
            for ang, t in zip(gridmod.ENV_ANGLES_DEG, trs, strict=True):
                row[f"first_time_{ang}"] = t.first_time
                row[f"max_dist_after_{ang}"] = max_distance_after_success(t)
            row["stays_near"] = stays_near(trs, near)
            rows.append(row)
    cols = [
        "design",
        "l1x",
        "l1y",
        "l2x",
        "l2y",
        "generalists",
        "w1",
        "w2",
        *(f"first_time_{a}" for a in gridmod.ENV_ANGLES_DEG),
        *(f"max_dist_after_{a}" for a in gridmod.ENV_ANGLES_DEG),
        "stays_near",
    ]
    return pd.DataFrame(rows, columns=cols)


def persistence_designs(res: ModelResults) -> dict[str, Design]:
    """The designs whose persistence the paper reports: canonical and the best by M_L."""
    out: dict[str, Design] = {"canonical": gridmod.canonical_design()}
    out["best_M_L"] = row_design(res.best("M_L"))
    if res.find(*PAPER_BEST_DESIGN) is not None and out["best_M_L"] != PAPER_BEST_DESIGN:
        out["paper_best"] = PAPER_BEST_DESIGN
    return out
