"""The two physics engines compared design by design (issue 25; config/engines.yaml; rules in
workflow/rules/engines.smk; figures ``engines`` and ``disagreement``, notebooks/engines.ipynb and
notebooks/disagreement.ipynb).

- :func:`tables` joins the pybullet survey, the MuJoCo survey (both 625 designs at 11 x 11 weights)
  and the theory model's metrics of the same designs, one row per design with each model's
  M_L, M_CF and ranks; :func:`numbers` is every statistic the engines figure draws (Spearman with
  bootstrap intervals, each model's best design).
- :func:`disagreement` re-simulates the design whose generalist counts differ most between the
  engines in both, checks the counts against the tables, and records the four episodes of one
  controller that is a generalist in exactly one engine with their centre paths.

Light imports only at module level: the Snakefile imports this module at parse time.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from morphlearn import models
from morphlearn.grid import ENV_ANGLES_DEG, DesignGrid, canonical_design, weights
from morphlearn.physics.options import SweepOptions
from morphlearn.settings import EnginesSettings  # the stage's settings (configure.parse)

if TYPE_CHECKING:
    import pandas as pd

    from morphlearn.physics.params import EmpiricalParams

#: Controllers per design in both engine surveys (11 x 11 weights).
CELLS = 121
WEIGHTS = 11
#: Positions per axis of the surveys' design grid.
POSITIONS = 5
#: The figure's mark of each engine's top designs by M_L.
TOP = 10
#: The two engines compared, as their tables' columns and the records name them (the registry's
#: pair: pybullet and MuJoCo).
ENGINES: tuple[str, str] = models.compared_engines()
#: The reference model, whose ranking each engine's is set against (the theory).
REFERENCE = models.REFERENCE


def read_table(path: str | Path) -> pd.DataFrame:
    """A metrics table, checked against its record first (custody: a run's sealed record, or a
    committed bundle's ``bundle.json``)."""
    import pandas as pd

    from morphlearn import provenance

    provenance.check_derived(path)
    return pd.read_csv(path, comment="#")


def tables(first: pd.DataFrame, second: pd.DataFrame, reference: pd.DataFrame) -> pd.DataFrame:
    """One row per design: M_L, M_CF of both engines (:data:`ENGINES` order) and the reference
    model, with each one's ranks."""
    from morphlearn.analysis.compare import joined

    a, b = ENGINES
    engines = joined(first, second, names=ENGINES)
    ranks = joined(reference, first, names=(REFERENCE, a))
    keep = ["design", *(f"{c}_{REFERENCE}" for c in ("M_L", "M_CF", "rank_M_L"))]
    both = engines.merge(ranks[keep], on="design", validate="1:1")
    if len(both) != len(first) or len(both) != len(second):
        raise ValueError(
            f"the tables do not cover the same designs: {len(first)} {a}, {len(second)} {b}, {len(both)} in both"
        )
    return both


def canonical_index() -> int:
    return int(DesignGrid(POSITIONS).index_of(*canonical_design()))


def numbers(both: pd.DataFrame) -> dict[str, Any]:
    """Every statistic the engines figure draws (docs/results.md quotes them): Spearman's rho with
    its bootstrap 95 % interval (seeded) between the engines (all designs, and those non-zero in
    either) and of each engine's M_L with the theory's; each model's best design by M_L."""

    from morphlearn.analysis.compare import spearman_ci

    def rho(x: str, y: str, rows: pd.Series | None = None) -> dict[str, Any]:
        sub = both if rows is None else both[rows]
        r = spearman_ci(sub[x].to_numpy(), sub[y].to_numpy(), x.rsplit("_", 1)[0])
        return {"rho": r.rho, "lo": r.low, "hi": r.high, "n": r.n}

    a, b = ENGINES
    out: dict[str, Any] = {}
    for m in ("M_L", "M_CF"):
        nz = (both[f"{m}_{a}"] > 0) | (both[f"{m}_{b}"] > 0)
        out[f"{m} {a}-{b}"] = {
            "all": rho(f"{m}_{a}", f"{m}_{b}"),
            "nonzero_either": rho(f"{m}_{a}", f"{m}_{b}", nz),
        }
    for e in ENGINES:
        out[f"M_L {REFERENCE}-{e}"] = {"all": rho(f"M_L_{REFERENCE}", f"M_L_{e}")}
    best = {e: both.loc[both[f"rank_M_L_{e}"] == 1].iloc[0] for e in (*ENGINES, REFERENCE)}
    out["best_design_M_L"] = {
        e: {
            "design": int(r.design),
            "l1": [float(r.l1x), float(r.l1y)],
            "l2": [float(r.l2x), float(r.l2y)],
            "generalists_of_121": int(np.rint(r[f"M_L_{e}"] * CELLS)) if e != REFERENCE else None,
        }
        for e, r in best.items()
    }
    out["canonical_design"] = canonical_index()
    return out


def write_numbers(s: EnginesSettings, table_csv: str | Path, numbers_json: str | Path) -> dict[str, Any]:
    """The joined table (exact floats: pandas writes the shortest repr that reads back) and the
    statistics, from the three committed tables; custody: their sealed record
    ``engines.provenance.json`` (the tables' digests and theirs), which the figure checks."""
    from morphlearn import provenance, store

    t = s.tables()
    both = tables(*(read_table(t[k]) for k in (*ENGINES, REFERENCE)))
    stats = numbers(both)
    with store.atomic_path(Path(table_csv)) as tmp:
        both.to_csv(tmp, index=False)
    with store.atomic_path(Path(numbers_json)) as tmp:
        tmp.write_text(json.dumps(stats, indent=1) + "\n")
    rec = provenance.record(s.science(), list(t.values()))
    provenance.write_sealed(provenance.sidecar_of(table_csv), rec, [table_csv, numbers_json])
    return stats


def pick_design(first: pd.DataFrame, second: pd.DataFrame) -> int:
    """The design whose generalist counts differ most between the engines; ties: the larger sum
    of both, then the lower design index."""
    t = first[["design", "generalists"]].merge(second[["design", "generalists"]], on="design", suffixes=("_a", "_b"))
    t["diff"] = (t.generalists_a - t.generalists_b).abs()
    t["sum"] = t.generalists_a + t.generalists_b
    return int(t.sort_values(["diff", "sum", "design"], ascending=[False, False, True]).design.iloc[0])


def disagreement(s: EnginesSettings, params: EmpiricalParams) -> tuple[dict[str, Any], np.ndarray, np.ndarray]:
    """The design where the engines disagree most, simulated again in both.

    Its 4 x 11 x 11 episodes in each engine (exact early stop, as the surveys; no adaptive grid),
    the generalist counts checked against the tables; then the first controller (row-major) that
    is a generalist in exactly one engine, its four episodes run again in both engines to contact
    or horizon with the centre path recorded. Returns the record (``disagreement.json``), the
    successes (bool, engine x env x w1 x w2, engines in :data:`ENGINES` order) and the paths
    (float64 (N, 2): pybullet's four environments, then MuJoCo's, each ``steps + 1`` points).
    """

    from morphlearn.metrics import design_metrics

    t = s.tables()
    tabs = {e: read_table(t[e]) for e in ENGINES}
    d = pick_design(*tabs.values())
    c = DesignGrid(POSITIONS).coords(d)
    l1, l2 = (float(c[0]), float(c[1])), (float(c[2]), float(c[3]))
    w = weights(WEIGHTS)
    opts = SweepOptions(early_stop=True)
    engine = {e: models.compared_model(e) for e in ENGINES}
    succ = {e: ~np.isnan(m.design_evaluator()(l1, l2, w, params, options=opts).first_time) for e, m in engine.items()}
    gen = {e: (v.sum(axis=0) == 4) for e, v in succ.items()}
    for e, tab in tabs.items():
        want = int(tab.set_index("design").loc[d, "generalists"])
        got = design_metrics(succ[e]).generalists
        if got != want:
            raise RuntimeError(f"design {d} in {e}: {got} generalists simulated, {want} in the committed table")
    a, b = ENGINES
    only = np.argwhere(gen[a] != gen[b])
    i, j = (int(x) for x in only[0])
    w1, w2 = float(w[i]), float(w[j])

    # the four episodes of that controller, paths recorded, to contact or horizon (no early stop)
    closest, paths = {}, {}
    for e, m in engine.items():
        closest[e], paths[e] = m.centre_paths(params, l1, l2, (w1, w2))

    failed = {e: [ENV_ANGLES_DEG[k] for k in range(4) if not succ[e][k, i, j]] for e in succ}
    info = {
        "design": d,
        "l1": list(l1),
        "l2": list(l2),
        "generalists": {e: int(g.sum()) for e, g in gen.items()},
        "generalist_in_one_engine_only": {a: int((gen[a] & ~gen[b]).sum()), b: int((gen[b] & ~gen[a]).sum())},
        "cells_differing": int((succ[a] != succ[b]).sum()),
        "cells": int(succ[a].size),
        "controller": [round(w1, 12), round(w2, 12)],
        "envs_failed_deg": failed,
        "steps": {e: [len(p) - 1 for p in paths[e]] for e in paths},
        "closest_approach": {e: [round(float(x), 4) for x in v] for e, v in closest.items()},
        "contact_distance": round(params.contact_distance, 4),
    }
    success = np.stack([succ[e] for e in ENGINES])
    path_array = np.concatenate([np.asarray(p, dtype=np.float64).reshape(-1, 2) for e in ENGINES for p in paths[e]])
    return info, success, path_array


def write_disagreement(
    s: EnginesSettings, params: EmpiricalParams, info_json: str | Path, success_npy: str | Path, paths_npy: str | Path
) -> dict[str, Any]:
    """:func:`disagreement`'s record as JSON and its arrays as ``.npy`` (no timestamp inside, unlike
    ``.npz``: the same simulation gives the same bytes); custody: their sealed record
    ``disagreement.provenance.json`` (the body, the tables' digests and theirs)."""

    from morphlearn import provenance, store

    info, success, paths = disagreement(s, params)
    with store.atomic_path(Path(info_json)) as tmp:
        tmp.write_text(json.dumps(info, indent=1) + "\n")
    for path, arr in ((success_npy, success), (paths_npy, paths)):
        with store.atomic_path(Path(path)) as tmp, open(tmp, "wb") as f:
            np.save(f, arr)
    rec = provenance.record({**s.science(), "body": params.to_dict()}, [s.tables()[e] for e in ENGINES])
    provenance.write_sealed(provenance.sidecar_of(info_json), rec, [info_json, success_npy, paths_npy])
    return info


def split_paths(info: dict[str, Any], paths: np.ndarray) -> dict[str, list[np.ndarray]]:
    """The per-engine, per-environment centre paths of :func:`disagreement`'s concatenated array."""

    out: dict[str, list[np.ndarray]] = {}
    start = 0
    for e in ENGINES:
        out[e] = []
        for n in info["steps"][e]:
            out[e].append(paths[start : start + n + 1])
            start += n + 1
    if start != len(paths):
        raise ValueError(f"the paths hold {len(paths)} points, the record's steps {start}")
    return {e: [np.asarray(p) for p in v] for e, v in out.items()}
