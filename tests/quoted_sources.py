"""What a quoted number may be read from (tests/quoted_numbers.py evaluates its expressions here):
the committed bundles' tables by short name, the paper's claims, the configs, and a few helpers
that rank and compare as the documents do.

A table is named once in :data:`TABLES` and loaded on first use; a number from a table no name
covers is ``csv("results/x/y.csv")``. Everything here reads committed files only."""

from __future__ import annotations

import json
import re
from functools import cache
from itertools import pairwise
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import yaml
from scipy import stats

ROOT = Path(__file__).resolve().parents[1]

CANONICAL = 6552  # (0.5,0.5),(0.5,-0.5) on the 9-point grid
PAPER_BEST_THEORY = 240  # (-0.5,-0.25),(0.5,0.25)
THEORY_BEST_M_L = 160  # (-0.5,-0.375),(0.5,0.375)
PAPER_BEST_ODE = 478  # (-0.5,0.125),(0.5,-0.375)
BEST_OUR_BODY = 720  # (-0.5,0.5),(0.5,-0.5)
TEXT_BEST_M_L = 684  # (-0.5,0.5),(0,-0.5): the second theory sweep's best by M_L

#: Short names of the committed tables the documents quote.
TABLES = {
    "theory": "results/paper/theory/metrics.csv",
    "ode": "results/ode-paper/ode/metrics.csv",
    "survey": "results/ode-survey/ode/metrics.csv",
    "m9": "results/survey9-mujoco/mujoco/metrics.csv",
    "pb": "results/refine-pybullet/empirical/metrics.csv",
    "mj": "results/refine-mujoco/mujoco/metrics.csv",
    "agree": "results/agreement/agreement.csv",
    "learn": "results/learners/learners/correlations.csv",
    "runs": "results/learners/learners/runs.csv",
    "pers": "results/paper/persistence.csv",
    "rep": "results/paper/reproduction.csv",
    "red_paper": "results/reduced-paper/reduced/metrics.csv",
    "red_survey": "results/reduced-survey/reduced/metrics.csv",
    "red_odepaper": "results/reduced-ode-paper/reduced/metrics.csv",
    "screened": "results/ode-screened-paper/ode/metrics.csv",
    "ra_paper": "results/reduced-agreement-paper/agreement.csv",
    "ra_survey": "results/reduced-agreement-survey/agreement.csv",
    "ra_screened": "results/reduced-agreement-screened/agreement.csv",
    "ra_random": "results/reduced-agreement-random/agreement.csv",
    "theory_text": "results/theory-text/theory/metrics.csv",
    "r_scan": "results/theory-text-checks/r_scan.csv",
    "odeint": "results/theory-text-odeint/designs/summary.csv",
    "text_cost": "results/theory-text/run_cost.csv",
}

#: The second theory sweep's merged store (every design's first-success times).
TEXT_MERGED = "results/theory-text/theory/merged.zarr"


@cache
def csv(rel: str) -> pd.DataFrame:
    """A committed table (comment lines skipped)."""
    return pd.read_csv(ROOT / rel, comment="#")


@cache
def json_file(rel: str) -> Any:
    return json.loads((ROOT / rel).read_text())


def cfg(rel: str, dotted: str) -> Any:
    """A config value: ``cfg("config/paper.yaml", "theory.weights")``."""
    value: Any = yaml.safe_load((ROOT / rel).read_text())
    for part in dotted.split("."):
        value = value[part]
    return value


def default(dotted: str) -> Any:
    """A config key's default (src/morphlearn/config_schema.yaml): ``default("figures.near_distance")``."""
    node: Any = yaml.safe_load((ROOT / "src/morphlearn/config_schema.yaml").read_text())
    for part in dotted.split("."):
        node = node["properties"][part]
    return node["default"]


def paper(key: str) -> Any:
    """The paper's number of a claim of the reproduction table (morphlearn...claims), by key."""
    from morphlearn.figures.reproduction.claims import PHYSICS, THEORY

    return {c.key: c.value for c in (*THEORY, *PHYSICS)}[key]


def row(t: pd.DataFrame, design: int) -> pd.Series:
    return t[t.design == design].iloc[0]


def at(t: pd.DataFrame, l1: tuple[float, float], l2: tuple[float, float]) -> pd.Series:
    """The row of the design with those sensor positions."""
    m = (t.l1x == l1[0]) & (t.l1y == l1[1]) & (t.l2x == l2[0]) & (t.l2y == l2[1])
    return t[m].iloc[0]


def rank(t: pd.DataFrame, design: int, by: str) -> int:
    """1 + the designs strictly better (ties share a rank), as the documents rank."""
    return int(1 + (t[by] > row(t, design)[by]).sum())


def top(t: pd.DataFrame, n: int) -> pd.DataFrame:
    """The n best designs by generalists (ties by index)."""
    return t.sort_values(["generalists", "design"], ascending=[False, True]).head(n)


def opposite_sides(t: pd.DataFrame) -> np.ndarray:
    """One sensor at the back and one at the front, on opposite sides of the body."""
    return ((t.l1x * t.l2x) < 0).to_numpy() & ((t.l1y * t.l2y) < 0).to_numpy()


def asymmetric(t: pd.DataFrame) -> pd.Series:
    """Designs not mirror-symmetric about the body's axis (the table's row 4 counts these)."""
    return ~((t.l1x == t.l2x) & (t.l1y == -t.l2y))


def spearman(a: pd.DataFrame, b: pd.DataFrame, col: str) -> float:
    """Spearman's rho of ``col`` over the designs (coordinates) both tables hold."""
    from morphlearn.analysis import compare

    both = compare.joined(a, b, ("a", "b"))
    return float(stats.spearmanr(both[f"{col}_a"], both[f"{col}_b"]).statistic)


def shared(a: pd.DataFrame, b: pd.DataFrame) -> int:
    from morphlearn.analysis import compare

    return len(compare.joined(a, b, ("a", "b")))


def positions(t: pd.DataFrame) -> int:
    """Sensor positions per axis of a table's design grid."""
    return int(t.l1y.nunique())


def cost_line(rel: str, pattern: str) -> float:
    """A number a bundle's README states in a line matching ``pattern`` (its first group)."""
    m = re.search(pattern, (ROOT / rel).read_text())
    assert m, (rel, pattern)
    return float(m[1].replace(",", ""))


def tol(name: str) -> float:
    """A tolerance of the verdict rule (morphlearn.figures.reproduction.verdict: COUNT_ABS, ...)."""
    from morphlearn.figures.reproduction import verdict

    return float(getattr(verdict, name))


def engine_row(engine: str, robot: str) -> pd.Series:
    """A row of results/agreement/agreement.csv (an engine and robot against ODE)."""
    t = csv(TABLES["agree"])
    return t[(t.engine == engine) & (t.robot == robot)].iloc[0]


def w11(model: str) -> int:
    """1 when the reproduction table says w = (1, 1) solves all 4 environments of the canonical
    design in ``model`` (its row empirical_canonical_w11), else -1 (no number matches -1)."""
    t = csv(TABLES["rep"])
    r = t[(t.key == "empirical_canonical_w11") & t.model.str.startswith(model)]
    return 1 if len(r) and str(r.ours.iloc[0]).startswith("yes") else -1


def recipe_designs() -> list[tuple[float, float, float, float]]:
    """The designs of the README's "Your own designs" recipe: its loop's quoted "x1 y1 x2 y2"."""
    text = (ROOT / "README.md").read_text().split("## Your own designs", 1)[1].split("\n## ", 1)[0]
    loop = re.search(r"for d in ((?:\"[^\"]+\" ?)+); do", text)
    assert loop, "README's recipe lost its loop over designs"
    return [tuple(float(v) for v in d.split()) for d in re.findall(r"\"([^\"]+)\"", loop[1])]  # type: ignore[misc]


def recipe_grid() -> int:
    """The smallest grid.positions_per_axis that holds every coordinate of the recipe's designs."""
    from morphlearn.grid import grids_holding

    return grids_holding(sorted({v for d in recipe_designs() for v in d}))[0]


def spearman_within(t: pd.DataFrame, a: str, b: str) -> float:
    """Spearman's rho of two columns of one table over its designs."""
    return float(stats.spearmanr(t[a], t[b]).statistic)


def best_label() -> str:
    """The persistence table's label of the paper's best design (reproduction.claim_values)."""
    from morphlearn.figures.reproduction.claim_values import best_label as label_of

    return label_of(csv(TABLES["pers"]))


def screen_rule(by: str) -> Any:
    """The reproduction table's screen rule for ``by`` (stages.screen.ruled_out): the reduced
    model's map of all 6561 designs against ODE at the designs it refined."""
    from morphlearn.figures.reproduction.stages.screen import ruled_out

    return ruled_out(csv(TABLES["red_paper"]), csv(TABLES["screened"]), by)


def agree_weights() -> int:
    """The weights per synapse of results/agreement's comparison (its cells over its designs)."""
    t = csv(TABLES["agree"])
    return round(float(np.sqrt(t.cells_compared.iloc[0] / t.designs.iloc[0] / 4)))


def survey_check() -> dict[str, int]:
    """The ODE survey against the exhaustive runs at the designs both hold (tests/test_ode_bundles.py
    checks cell by cell that none was missed): designs, successes, generalists."""
    from morphlearn.analysis import compare

    both = csv(TABLES["ode"]).merge(csv(TABLES["survey"]), on=compare.COORDS, suffixes=("", "_s"))
    per_env = [f"n_{a}" for a in (45, 135, 225, 315)]
    successes, generalists = int(both[per_env].to_numpy().sum()), int(both.generalists.sum())
    return {"designs": len(both), "successes": successes, "generalists": generalists}


@cache
def _text_store() -> tuple[np.ndarray, np.ndarray, Any]:
    """(first-success times (design, env, w1, w2), weights, design grid) of the second sweep, read
    whole: the per-chunk digests are the bundle test's to check (reading design by design to verify
    them takes ~15 s here)."""
    from morphlearn import store
    from morphlearn.grid import DesignGrid

    ds = store.open_merged(ROOT / TEXT_MERGED)
    n = int(store.science_of(ds)["grid"]["positions_per_axis"])
    return np.asarray(ds["first_time"].values), np.asarray(ds["w1"].values), DesignGrid(n)


def text_science(dotted: str) -> Any:
    """A setting the second sweep ran with, from its store's record: ``text_science("theory.r")``."""
    from morphlearn import store

    node: Any = store.science_of(store.open_merged(ROOT / TEXT_MERGED))
    for part in dotted.split("."):
        node = node[part]
    return node


def text_horizons() -> tuple[float, ...]:
    """The horizons the reproduction table's second-sweep rows check their verdicts at."""
    from morphlearn.figures.reproduction.stages import text_sweep as stage

    return stage.HORIZONS


@cache
def text_span(key: str) -> tuple[float, float]:
    """The one span of :func:`text_horizons` over which the second sweep gives the paper's value of
    claim ``key`` (as the table's note computes it); (-1, -1) when it holds at none or in several."""
    from morphlearn.figures.reproduction.claims import CLAIMS
    from morphlearn.figures.reproduction.stages import text_sweep as stage
    from morphlearn.theory import text_sweep

    ft, _, g = _text_store()
    claim = {c.key: c for c in CLAIMS}[key]
    r, horizon = float(text_science("theory.r")), float(text_science("theory.horizon"))
    held = [
        h
        for h in stage.HORIZONS
        if h <= horizon and stage._held(claim, stage._value(key, text_sweep.text_values(ft, g, h, r), g)[1])
    ]
    step = stage.HORIZONS[1] - stage.HORIZONS[0]
    if not held or any(abs(b - a - step) > 1e-9 for a, b in pairwise(held)):
        return (-1.0, -1.0)
    return (held[0], held[-1])


@cache
def text_persistence() -> tuple[int, int, list[float]]:
    """The second sweep's canonical generalists integrated to its horizon, as the table's row does:
    (staying within the default near distance after success, generalists, their largest distances
    after success, sorted)."""
    from morphlearn.figures import data as fd
    from morphlearn.figures.reproduction.stages import text_sweep as stage

    ft, w, g = _text_store()
    s = fd.TheorySettings(
        r=float(text_science("theory.r")),
        horizon=float(text_science("theory.horizon")),
        radius=float(text_science("theory.success_radius")),
    )
    return stage.persistence(ft, w, g, s, float(default("figures.near_distance")))


def scan(r: float, horizon: float = 1000.0) -> pd.Series:
    """The row of results/theory-text-checks/r_scan.csv at light distance ``r`` and ``horizon`` (at
    r = 4 the row over all designs)."""
    t = csv(TABLES["r_scan"])
    m = t[np.isclose(t.r, r) & np.isclose(t.horizon, horizon)]
    return m.sort_values("designs_run").iloc[-1]


def namespace() -> dict[str, Any]:
    """The names an expression of tests/quoted_numbers.py may use."""

    class Tables(dict):
        def __missing__(self, name: str) -> Any:
            if name in TABLES:
                self[name] = csv(TABLES[name])
                return self[name]
            raise NameError(f"{name}: no such table or helper (tests/quoted_sources.py TABLES)")

    ns = Tables()
    ns.update({k: v for k, v in globals().items() if not k.startswith("_") and k not in ("TABLES", "namespace")})
    builtins = {f.__name__: f for f in (abs, len, max, min, round, sum, int, sorted)}
    ns.update({**builtins, "np": np})
    ns.update({"engines": json_file("results/mujoco/engines.json")})
    from morphlearn import grid as gridmod

    ns["gridmod"] = gridmod
    return ns
