"""The interactive explorer's logic (notebooks/explore.ipynb; widgets in morphlearn.apps.explore_app).

Reads a committed results bundle (checked against its manifest first, as
``morphlearn.bundles.check.extract_model`` does), lays every design's M_L and M_CF out as one map over
sensor placements, and gives one design's overlap matrix: from the bundle when it holds the
design's outcome arrays, otherwise computed live by the theory kernel with the bundle's own theory
parameters and thresholds (timed). No plotting here, so all of it is tested headless.

The map: a design is two sensor positions on an ``n x n`` grid of the body, so the ``n**4`` designs
fill an ``n*n x n*n`` image of ``n x n`` blocks. The block at (column, row) = (i1x, i1y) is sensor
1's position, the cell inside it at (i2x, i2y) sensor 2's: x (forward) grows to the right, y (left)
upwards, in the blocks as inside them.
"""

from __future__ import annotations

import csv
import io
import json
import math
import time
import urllib.parse
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from morphlearn import bounded, metrics, store
from morphlearn import grid as gridmod
from morphlearn.bundles import check as bundle_check
from morphlearn.bundles import make as bundlemod
from morphlearn.figures import data
from morphlearn.models import MODELS, REFERENCE
from morphlearn.theory import TheoryParams, evaluate
from morphlearn.theory.reference import ReferenceTrajectory

#: Weight grids a live theory evaluation offers: the default run's 41 (about a second on 2 cores)
#: and the paper's 121 (a few seconds).
LIVE_WEIGHTS = (41, 121)
#: The controller shown first: the paper's canonical controller of Fig. 4B (nearest controller
#: with the highest overlap of the design's matrix).
DEFAULT_CONTROLLER: data.Point = data.PAPER_CANONICAL_CONTROLLERS[1]


#: What the maps and the top-N table rank by.
METRIC_NAMES = ("M_L", "M_CF")


class ExploreError(ValueError):
    """Bad input to the explorer; the message names the value and what is allowed."""


@dataclass(frozen=True)
class Source:
    """One model's results in one bundle."""

    bundle: Path
    model: str

    @property
    def label(self) -> str:
        """The one name the explorer gives these results everywhere (results list, engines table,
        URL, export): the engine (``pybullet``, ``MuJoCo``, ``ODE``) or ``theory``, and the bundle."""
        return f"{self.engine} ({self.bundle.name})"

    @property
    def engine(self) -> str:
        """The model as prose names it: its physics engine (pybullet, MuJoCo, ODE) or the theory."""
        return engine_label(self.model)


def engine_label(model: str) -> str:
    """``theory`` stays; a physics model is named by its engine (``empirical`` is pybullet's)."""
    m = MODELS.get(model)
    return (getattr(m, "engine_label", "") or getattr(m, "engine", "") or model) if model != REFERENCE else model


def default_results_dir(start: str | Path | None = None) -> Path:
    """The project's ``results`` folder: the nearest one holding a bundle from ``start`` (default:
    the working directory, which is ``notebooks/`` under Voila and Jupyter) upwards."""
    here = Path.cwd() if start is None else Path(start)
    for d in (here, *here.resolve().parents):
        if any((d / "results").glob(f"*/{bundlemod.MANIFEST}")):
            return d / "results"
    raise ExploreError(f"no results/<bundle>/{bundlemod.MANIFEST} in {here} or above it: run from the project")


#: The bundle listed first (the app's default): the paper-resolution one reviewers open first.
FIRST_BUNDLE = "paper"


def sources(results_dir: str | Path = "results") -> list[Source]:
    """Every model of every bundle (a folder with ``bundle.json``) under ``results_dir``:
    ``FIRST_BUNDLE`` first, the others by name."""
    out = []
    # a hidden folder is no source: a render's working copy (.rerender-<name>-*) holds a bundle.json
    bundles = (p.parent for p in Path(results_dir).glob(f"*/{bundlemod.MANIFEST}") if not p.parent.name.startswith("."))
    for b in sorted(bundles, key=lambda b: (b.name != FIRST_BUNDLE, b.name)):
        out += [Source(b, m) for m in MODELS if (b / m / "metrics.csv").is_file()]
    return out


#: Bundles checked in this process: a bundle holds several models and the explorer opens each (the
#: check reads every file of the bundle, ~1 s for the paper bundle), so one check per bundle.
_VERIFIED: set[Path] = set()


def open_source(src: Source, *, verify: bool = True) -> data.ModelResults:
    """A model's results from a bundle, after checking every file of the bundle against its
    SHA-256 in ``bundle.json`` (a damaged or edited bundle is refused, naming the first problem);
    the thresholds are the ones its metrics were computed with (``metrics.provenance.json``)."""
    if src.model not in MODELS:
        raise ExploreError(f"model {src.model!r}: allowed: {', '.join(MODELS)}")
    if verify and src.bundle.resolve() not in _VERIFIED:
        problems = bundle_check.check(src.bundle)
        if problems:
            raise bundlemod.BundleError(f"{src.bundle}: {len(problems)} problem(s), first: {problems[0]}")
        _VERIFIED.add(src.bundle.resolve())
    prov = bounded.json_file(src.bundle / src.model / "metrics.provenance.json")
    res = data.load_results(src.bundle, src.model, prov["config"]["thresholds"])
    if res is None:
        raise FileNotFoundError(f"{src.bundle}: no {src.model}/metrics.csv and {src.model}/merged.zarr")
    return res


@dataclass
class Landscape:
    """One design's outcomes over the weight grid."""

    design: int
    coords: data.Design
    weights: np.ndarray
    success: np.ndarray  # (4, m, m) [env, i_w1, i_w2]
    first_time: np.ndarray  # (4, m, m), NaN: never succeeded
    source: str  # "bundle" or "live"
    seconds: float | None  # the live computation's wall time (None: read from the bundle)

    @property
    def overlap(self) -> np.ndarray:
        return metrics.overlap(self.success)

    @property
    def metrics(self) -> metrics.DesignMetrics:
        return metrics.design_metrics(self.success)

    def controller(self, w1: float, w2: float) -> tuple[int, int]:
        """Grid indices of the controller nearest to ``(w1, w2)``."""
        return int(np.argmin(np.abs(self.weights - w1))), int(np.argmin(np.abs(self.weights - w2)))


class Explorer:
    """One model's results: maps, ranks, mirror images, landscapes and trajectories."""

    def __init__(self, res: data.ModelResults) -> None:
        self.res = res
        n = res.positions_per_axis
        if n is None:
            raise ExploreError(f"{res.paths.get('merged')}: its science record has no positions_per_axis")
        self.grid = gridmod.DesignGrid(int(n))
        self.table = res.table.set_index("design", drop=False)
        self._held = {int(d): i for i, d in enumerate(res.ds["design"].values)}
        self._cache: dict[tuple[int, int], Landscape] = {}
        self._text: pd.Series | None = None
        sci = res.science
        # The theory model's parameters (live evaluation, trajectories); the empirical model has none.
        self.theory_params: dict[str, Any] | None = sci.get("theory") if res.model == REFERENCE else None

    # -- designs ---------------------------------------------------------------------------------
    @property
    def n(self) -> int:
        return self.grid.n

    @property
    def axis(self) -> np.ndarray:
        return self.grid.axis

    def check_design(self, design: int) -> int:
        d = int(design)
        if not 0 <= d < self.grid.size:
            raise ExploreError(f"design {design}: allowed: 0 to {self.grid.size - 1} ({self.n} positions per axis)")
        return d

    def design_of(self, l1: data.Point, l2: data.Point) -> int:
        """Design index of two sensor positions of this grid (ExploreError names the bad one)."""
        try:
            return self.grid.index_of(tuple(l1), tuple(l2))
        except ValueError as e:
            raise ExploreError(f"design l1 = {tuple(l1)}, l2 = {tuple(l2)}: {e}") from None

    def coords(self, design: int) -> data.Design:
        c = self.grid.coords(self.check_design(design))
        return (float(c[0]), float(c[1])), (float(c[2]), float(c[3]))

    def nearest_design(self, l1: data.Point, l2: data.Point) -> tuple[int, bool]:
        """The design of this grid whose sensors are nearest to ``l1`` and ``l2`` (each coordinate
        to the nearest grid value), and whether it is exactly that placement: what a design of one
        bundle becomes in another with a coarser or finer grid."""
        ax = self.axis
        snap = [float(ax[int(np.argmin(np.abs(ax - v)))]) for v in (*l1, *l2)]
        d = self.grid.index_of((snap[0], snap[1]), (snap[2], snap[3]))
        return int(d), bool(np.allclose(snap, [*l1, *l2]))

    def mirror(self, design: int) -> int:
        return int(self.grid.mirror(self.check_design(design)))

    def held(self, design: int) -> bool:
        """Whether the bundle holds the design's outcome arrays."""
        return int(design) in self._held

    def row(self, design: int) -> pd.Series | None:
        d = self.check_design(design)
        return self.table.loc[d] if d in self.table.index else None

    def rank(self, design: int, by: str) -> int | None:
        """Rank by ``by`` among the table's designs (1 = best; ties share a rank); None: not in it."""
        if by not in ("M_L", "M_CF"):
            raise ExploreError(f"rank by {by!r}: allowed: M_L, M_CF")
        row = self.row(design)
        return None if row is None else metrics.rank_of(self.res.table, row, by)

    def best(self, by: str) -> int:
        return int(self.res.best(by).design)

    def top(self, by: str, n: int = 25, query: str = "") -> pd.DataFrame:
        """The table's designs ranked by ``by`` (best first; ``rank``: 1 + the designs strictly
        better, so ties share a rank, as :meth:`rank`), those whose :func:`design_text` contains
        ``query`` (spaces ignored: ``"2531"``, ``"(0.5,-0.25)"``, ``"l2 (0,0)"``), the first ``n``."""
        if by not in METRIC_NAMES:
            raise ExploreError(f"rank by {by!r}: allowed: {', '.join(METRIC_NAMES)}")
        t = metrics.rank_designs(self.res.table, by).copy()
        higher = metrics.METRICS[by].higher_is_better
        t["rank"] = t[by].rank(method="min", ascending=not higher).astype(int)
        q = "".join(query.split())
        if q:
            t = t[self._texts().loc[t.design].str.contains(q, regex=False).to_numpy()]
        return t.head(n)[["rank", "design", "l1x", "l1y", "l2x", "l2y", "M_L", "M_CF"]].reset_index(drop=True)

    def _texts(self) -> pd.Series:
        """:func:`design_text` of every design in the table, without spaces (searched), cached."""
        if self._text is None:
            d = self.res.table.design.to_numpy()
            self._text = pd.Series(["".join(design_text(self, int(x)).split()) for x in d], index=d)
        return self._text

    def hover(self, design: int) -> str:
        """One line for the design under the mouse: its sensors, M_L and M_CF with ranks."""
        row = self.row(design)
        text = design_text(self, design)
        if row is None:
            return f"{text}: not simulated in this bundle ({len(self.res.table)} designs are)"
        ranks = ", ".join(f"{by} {float(row[by]):.4g} (rank {self.rank(design, by)})" for by in METRIC_NAMES)
        return f"{text}: {ranks} of {len(self.res.table)}"

    # -- the map ---------------------------------------------------------------------------------
    def map_image(self, metric: str) -> np.ndarray:
        """(n*n, n*n) image of ``metric`` over designs, [row, column] as in the module docstring;
        NaN where the table has no design (the empirical sweep may hold only some)."""
        if metric not in ("M_L", "M_CF"):
            raise ExploreError(f"map metric {metric!r}: allowed: M_L, M_CF")
        n = self.n
        img = np.full((n * n, n * n), np.nan)
        t = self.res.table
        i = self.grid.indices(t.design.to_numpy())
        img[i[:, 1] * n + i[:, 3], i[:, 0] * n + i[:, 2]] = t[metric].to_numpy(dtype=float)
        return img

    def map_cell(self, design: int) -> tuple[int, int]:
        """(column, row) of a design in :meth:`map_image`."""
        i = self.grid.indices(self.check_design(design))
        return int(i[0] * self.n + i[2]), int(i[1] * self.n + i[3])

    def design_at(self, x: float, y: float) -> int | None:
        """The design under map image coordinates ``(x, y)`` (pixel centres at integers, as
        ``imshow`` draws them); None outside the map."""
        n = self.n
        col, row = math.floor(x + 0.5), math.floor(y + 0.5)
        if not (0 <= col < n * n and 0 <= row < n * n):
            return None
        return int(self.grid.flat(np.array([col // n, row // n, col % n, row % n])))

    # -- landscapes --------------------------------------------------------------------------------
    def landscape(self, design: int, live_weights: int = LIVE_WEIGHTS[0]) -> Landscape:
        """The design's outcomes: the bundle's arrays when it holds them, else (theory only) a live
        evaluation on ``live_weights`` x ``live_weights`` controllers, timed and cached."""
        d = self.check_design(design)
        if d in self._held:
            return self._from_bundle(d)
        if self.theory_params is None:
            raise ExploreError(
                f"{self.res.model}: design {d} ({data.design_label(*self.coords(d))}) is not held in "
                f"{self.res.paths.get('merged')} ({len(self._held)} designs are), and only the theory "
                "model is computed live"
            )
        if live_weights not in LIVE_WEIGHTS:
            raise ExploreError(f"live weights {live_weights!r}: allowed: {', '.join(map(str, LIVE_WEIGHTS))}")
        key = (d, live_weights)
        if key not in self._cache:
            self._cache[key] = self._live(d, live_weights)
        return self._cache[key]

    def _from_bundle(self, d: int) -> Landscape:
        arrays = store.read_design(self.res.ds, self._held[d])  # verified against the store's digests
        succ = self.res.success(self._held[d])
        return Landscape(d, self.coords(d), self.res.weights, succ, arrays["first_time"], "bundle", None)

    def _live(self, d: int, m: int) -> Landscape:
        params = TheoryParams.from_config({**self.theory_params, "backend": "cpu"})
        w = gridmod.weights(m)
        t0 = time.perf_counter()
        (res,) = evaluate(self.grid.coords(np.array([d])), w, params)
        seconds = time.perf_counter() - t0
        th = self.res.thresholds
        succ = np.isfinite(res.first_time) if th is None else metrics.success(res.first_time, res.min_dist, th)
        return Landscape(d, self.coords(d), w, succ, res.first_time, "live", seconds)

    def matches_table(self, land: Landscape) -> bool | None:
        """Whether the landscape's generalist and at-least-one counts equal the metrics table's
        (None when its weight grid differs from the bundle's, so the counts cannot agree)."""
        row = self.row(land.design)
        if row is None or len(land.weights) != len(self.res.weights):
            return None
        dm = land.metrics
        return (dm.generalists, dm.at_least_one) == (int(row.generalists), int(row.at_least_one))

    def default_controller(self, land: Landscape) -> tuple[float, float]:
        (c,) = data.pick_controllers(land.overlap, land.weights, [DEFAULT_CONTROLLER])
        return c.w1, c.w2

    # -- trajectories ------------------------------------------------------------------------------
    def settings(self) -> data.TheorySettings:
        """What a theory trajectory needs: the bundle's light distance and tolerance, and the
        horizon and success radius its metrics used."""
        if self.theory_params is None:
            raise ExploreError(f"{self.res.model}: trajectories are drawn for the theory model only")
        th = self.res.thresholds
        p = self.theory_params
        return data.TheorySettings(
            float(p["r"]),
            th.horizon if th else float(p["horizon"]),
            th.radius if th else float(p["success_radius"]),
            float(p["rtol"]),
        )

    def trajectories(self, design: int, w: tuple[float, float]) -> list[ReferenceTrajectory]:
        """The four environments' reference trajectories (scipy, the figures' integrator) to the
        horizon. A trajectory stopped at the evaluation cap (no path) is kept as its start point,
        so each environment still draws."""
        s = self.settings()
        trs = data.trajectories(self.coords(design), w, s)
        starts = gridmod.env_starts(s.r)
        return [
            tr
            if len(tr.t)
            else ReferenceTrajectory(tr.first_time, tr.min_dist, tr.status, np.zeros(1), np.array([[*starts[k], 0.0]]))
            for k, tr in enumerate(trs)
        ]


def design_text(ex: Explorer, design: int) -> str:
    """``design 2531: l1 (-0.125, 0), l2 (-0.25, -0.25)``: what the hover, the top-N table and its
    search show."""
    (x1, y1), (x2, y2) = ex.coords(design)
    return f"design {design}: l1 ({x1:g}, {y1:g}), l2 ({x2:g}, {y2:g})"


# -- the view in the URL ---------------------------------------------------------------------------
@dataclass(frozen=True)
class View:
    """What the URL holds (``?source=theory+(paper)&design=2531&metric=M_L&w=0.6,0.983``): the
    results source, the design (an index of that source's grid), what the top-N table ranks by and
    the controller; None: the default."""

    source: str | None = None
    design: int | None = None
    metric: str = METRIC_NAMES[0]
    w: tuple[float, float] | None = None

    def query(self) -> str:
        q: dict[str, str] = {}
        if self.source is not None:
            q["source"] = self.source
        if self.design is not None:
            q["design"] = str(self.design)
        q["metric"] = self.metric
        if self.w is not None:
            q["w"] = f"{self.w[0]:.6g},{self.w[1]:.6g}"
        return urllib.parse.urlencode(q)


#: The longest design index a URL may give (any grid's designs are far fewer than 10^9; a 5,000-digit
#: one once raised Python's own ValueError out of the app).
MAX_DESIGN_DIGITS = 9


def _shown(value: str) -> str:
    """A URL value as a message quotes it: whole up to 40 characters, else its start and length."""
    return repr(value) if len(value) <= 40 else f"'{value[:20]}... ({len(value)} characters)'"


def parse_view(query: str | None) -> View:
    """A :class:`View` from a URL's query string (with or without the ``?``); ExploreError names
    the bad value (a shared link with a typo should say so, not open something else)."""
    q = urllib.parse.parse_qs((query or "").lstrip("?"), keep_blank_values=False)

    def one(k: str) -> str | None:
        v = q.get(k)
        return None if not v else v[-1]

    design = one("design")
    metric = one("metric") or METRIC_NAMES[0]
    w = one("w")
    if design is not None and not (design.isascii() and design.isdigit() and len(design) <= MAX_DESIGN_DIGITS):
        raise ExploreError(
            f"URL design={_shown(design)}: allowed: a design index (0, 1, ...; at most {MAX_DESIGN_DIGITS} digits)"
        )
    if metric not in METRIC_NAMES:
        raise ExploreError(f"URL metric={_shown(metric)}: allowed: {', '.join(METRIC_NAMES)}")
    pair = None
    if w is not None:
        try:
            a, b = (float(v) for v in w.split(","))
        except ValueError:
            raise ExploreError(f"URL w={_shown(w)}: allowed: two numbers in [-1, 1], w1,w2") from None
        # nan, inf or 1e308 would open the nearest controller, (-1, -1) or (1, 1), without a word
        if not all(math.isfinite(v) and -1.0 <= v <= 1.0 for v in (a, b)):
            raise ExploreError(f"URL w={_shown(w)}: allowed: two finite numbers in [-1, 1], w1,w2")
        pair = (a, b)
    return View(one("source"), None if design is None else int(design), metric, pair)


# -- export ----------------------------------------------------------------------------------------
def export_json(ex: Explorer, land: Landscape, w: tuple[float, float] | None, source: str = "") -> str:
    """The shown design as JSON: :func:`describe` (metrics, ranks, mirror image), where it came from
    (the source's label, model, engine), the controller and the outcome arrays (weights, overlap,
    success and first-success time per environment, ``null``: never)."""
    out = {
        "results": source,  # describe()'s "source" is where the arrays came from: bundle or live
        "model": ex.res.model,
        "engine": engine_label(ex.res.model),
        **describe(ex, land),
        "controller": None if w is None else list(w),
        "environments_deg": list(gridmod.ENV_ANGLES_DEG),
        "weights": [round(float(v), 12) for v in land.weights],  # 0.65, not 0.6499999999999999
        "overlap": land.overlap.astype(int).tolist(),
        "success": land.success.astype(int).tolist(),
        "first_time": [[[None if math.isnan(v) else float(v) for v in r] for r in env] for env in land.first_time],
    }
    return json.dumps(out, default=float) + "\n"


def export_csv(land: Landscape) -> str:
    """The shown design's outcomes, one row per controller: w1, w2, the overlap (environments
    solved) and per environment success (0/1) and first-success time (empty: never)."""
    buf = io.StringIO()
    out = csv.writer(buf, lineterminator="\n")
    angles = gridmod.ENV_ANGLES_DEG
    out.writerow(
        ["design", "w1", "w2", "overlap", *(f"success_{a}" for a in angles), *(f"first_time_{a}" for a in angles)]
    )
    ov, s, ft, w = land.overlap, land.success, land.first_time, land.weights
    for i in range(len(w)):
        for j in range(len(w)):
            out.writerow(
                [
                    land.design,
                    f"{w[i]:.6g}",
                    f"{w[j]:.6g}",
                    int(ov[i, j]),
                    *(int(s[k, i, j]) for k in range(len(angles))),
                    *("" if math.isnan(ft[k, i, j]) else f"{ft[k, i, j]:.6g}" for k in range(len(angles))),
                ]
            )
    return buf.getvalue()


def warm_up() -> None:
    """One tiny live evaluation: loads the theory kernel's compiled code from numba's cache."""
    evaluate(np.array([[0.5, 0.5, 0.5, -0.5]]), gridmod.weights(2), TheoryParams(horizon=1.0))


def describe(ex: Explorer, land: Landscape) -> dict[str, Any]:
    """What the explorer prints beside a design: its metrics (table and matrix), ranks, mirror."""
    d = land.design
    row, mirror = ex.row(d), ex.mirror(d)
    mrow = ex.row(mirror)
    dm = land.metrics
    out: dict[str, Any] = {
        "design": d,
        "l1": land.coords[0],
        "l2": land.coords[1],
        "source": land.source,
        "seconds": land.seconds,
        "weights": len(land.weights),
        "matrix": {"generalists": dm.generalists, "at_least_one": dm.at_least_one, "M_L": dm.M_L, "M_CF": dm.M_CF},
        "matches_table": ex.matches_table(land),
        "designs": len(ex.res.table),
        "mirror": mirror,
        "mirror_coords": ex.coords(mirror),
    }
    if row is not None:
        out["table"] = {
            k: (float(row[k]) if k.startswith("M_") else int(row[k]))
            for k in ("generalists", "at_least_one", "M_L", "M_CF", "flagged")
        }
        out["rank"] = {by: ex.rank(d, by) for by in ("M_L", "M_CF")}
    if mrow is not None:
        out["mirror_table"] = {k: float(mrow[k]) for k in ("M_L", "M_CF")}
    return out


def first_success_times(trs: list[ReferenceTrajectory]) -> list[float]:
    """Per environment (45, 135, 225, 315 degrees), the first-success time (NaN: none)."""
    return [float(t.first_time) for t in trs]


def write_report(path: str | Path, app: Any) -> dict[str, Any]:
    """Write what an explorer app shows (design, metrics, controller, first-success times, the
    timings of its updates) as JSON: the record a headless run (papermill) leaves."""
    ex, land = app.ex, app.land
    out: dict[str, Any] = {"source": app.w_source.value, "design": app.design, "timings": app.timings}
    if land is not None:
        out["shown"] = describe(ex, land)
        out["controller"] = app.w
        if app.trs is not None:
            out["first_success"] = [None if math.isnan(t) else t for t in first_success_times(app.trs)]
            i, j = land.controller(*app.w)
            out["kernel_first_success"] = [None if math.isnan(t) else float(t) for t in land.first_time[:, i, j]]
    Path(path).write_text(json.dumps(out, indent=1, default=float) + "\n")
    return out
