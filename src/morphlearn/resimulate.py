"""Re-simulating a bundle's theory designs and comparing them with its stored rows and arrays,
bit for bit (``morphlearn check-bundle --resimulate``)."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path

import numpy as np
import pandas as pd

from morphlearn import grid as gridmod
from morphlearn import metrics, provenance, store
from morphlearn.bundle import BundleError


def resimulate(out_dir: str | Path, which: Iterable[str] = ("canonical", "best_M_L")) -> list[str]:
    """Re-simulate theory designs of a bundle from its recorded science and compare with it.

    ``which``: ``canonical``, ``best_M_L``, ``best_M_CF``, a design index, or ``sample:K`` (K
    designs drawn at random, seed 0, from all rows). Each design's metrics row (counts per
    environment, generalists, flagged) and, when the bundle holds them, its stored outcome arrays
    must come out exactly; the problems found are returned (empty: every design agrees). The
    thresholds are the ones the bundle's metrics were computed with (its provenance record).
    """
    from morphlearn.theory import TheoryParams, evaluate

    out_dir = Path(out_dir)
    merged = store.open_merged(out_dir / "theory" / "merged.zarr")
    sci = store.science_of(merged)
    table = pd.read_csv(out_dir / "theory" / "metrics.csv")
    prov = provenance.read_record(out_dir / "theory" / "metrics.provenance.json")
    th = metrics.Thresholds(**prov["config"]["thresholds"])
    g = gridmod.DesignGrid(sci["grid"]["positions_per_axis"])
    params = TheoryParams.from_config(sci["theory"])
    wanted = [d for w in which for d in _designs_of(w, table, g)]
    held = set(int(d) for d in merged["design"].values)
    # any row of the table, held or not: an edited row of a design whose arrays the bundle does
    # not hold is caught too (a forger has to re-simulate); the arrays are compared where held
    problems = [f"design {d}: no row in {out_dir}/theory/metrics.csv" for d in wanted if d not in set(table.design)]
    todo = sorted({d for d in wanted if d in set(table.design)})
    if not todo:
        return problems
    results = evaluate(g.coords(np.array(todo)), gridmod.weights(sci["grid"]["weights"]), params)
    for d, res in zip(todo, results, strict=True):
        dm = metrics.design_metrics(metrics.success(res.first_time, res.min_dist, th), res.status)
        row = table[table.design == d].iloc[0]
        stored = [
            *(int(row[f"n_{a}"]) for a in gridmod.ENV_ANGLES_DEG),
            int(row.generalists),
            int(row.at_least_one),
            int(row.flagged),
        ]
        fresh = [*dm.per_env, dm.generalists, dm.at_least_one, dm.flagged]
        if stored != fresh:
            problems.append(
                f"design {d}: metrics row {stored} (per env, generalists, at least one, "
                f"flagged) but re-simulated {fresh}"
            )
        elif [row.M_L, row.M_CF] != [float(metrics.CSV_FLOAT_FORMAT % x) for x in (dm.M_L, dm.M_CF)]:
            problems.append(
                f"design {d}: metrics row M_L, M_CF = {row.M_L}, {row.M_CF} but re-simulated {dm.M_L}, {dm.M_CF}"
            )
        if d not in held:
            continue
        one = store.read_design(merged, list(merged["design"].values).index(d))
        for v in store.VARS:
            a, b = one[v], getattr(res, v)
            differ = a != b
            if a.dtype.kind == "f":  # NaN (never succeeded) equals NaN here
                differ &= ~(np.isnan(a) & np.isnan(b))
            if differ.any():
                problems.append(f"design {d}: stored {v} differs from the re-simulation in {int(differ.sum())} cells")
    return problems


def _designs_of(which: str, table: pd.DataFrame, g: gridmod.DesignGrid) -> list[int]:
    if which == "canonical":
        return [g.index_of(*gridmod.canonical_design())]
    if which in ("best_M_L", "best_M_CF"):
        return [int(metrics.rank_designs(table, which.removeprefix("best_")).design.iloc[0])]
    if which.isdigit():
        return [int(which)]
    k = which.removeprefix("sample:")
    if which.startswith("sample:") and k.isdigit() and 0 < int(k) <= len(table):
        rng = np.random.default_rng(0)
        return sorted(int(d) for d in rng.choice(table.design.to_numpy(), size=int(k), replace=False))
    raise BundleError(
        f"re-simulate {which!r}: allowed: canonical, best_M_L, best_M_CF, a design index or sample:K "
        f"(1 <= K <= {len(table)})"
    )
