"""The learner stage: which designs, their shards, one shard's runs, the per-design cache.

Designs: one of each mirror pair of the theory grid (``DesignGrid.representatives``). A mirror
pair has the same M_L and M_CF, and in the joint protocol the same learner statistics in
distribution (every learner here treats w1 and w2 alike), so counting both would double each
point of the correlations without adding information; the sequential protocol's fixed order is
reversed by the mirror, so its mirror images are not derivable and are not run.
"""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from morphlearn import models, provenance, store
from morphlearn.grid import split_shards
from morphlearn.metrics import CSV_FLOAT_FORMAT
from morphlearn.physics import design_cache
from morphlearn.settings import LearnerSettings, Settings

if TYPE_CHECKING:
    from morphlearn.learners import protocols

# The learners, the kernel and cma are imported where runs are made: the Snakefile imports this
# module at parse time for the shard lists only.


def science(s: Settings) -> dict[str, Any]:
    """The config subset that determines the learner stage's per-design numbers."""
    th = models.get("theory").science(s)
    return {
        "model": "learners",
        "theory": th["theory"],
        "grid": {"positions_per_axis": s.grid.positions_per_axis},
        "learners": s.learners.science(),
    }


def designs(s: Settings) -> np.ndarray:
    """Designs the stage runs, in run order: the mirror representatives, shuffled with the base
    seed (so a shard's first designs, or ``max_designs``, are an unbiased sample)."""
    lr = s.learners
    order = np.random.default_rng([lr.seed, 15]).permutation(s.grid.designs.representatives())
    return order[: lr.max_designs] if lr.max_designs else order


def shards(s: Settings) -> list[np.ndarray]:
    return split_shards(designs(s), s.learners.shards)


def run_seed(s: LearnerSettings, design: int, learner: str, protocol: str, k: int) -> np.random.Generator:
    """The generator of one run: a function of the base seed and the run's identity only."""
    from morphlearn.learners import algorithms, protocols

    ident = [s.seed, int(design), algorithms.NAMES.index(learner), protocols.PROTOCOLS.index(protocol), k]
    return np.random.default_rng(ident)


def make_run(s: LearnerSettings, design: int, learner: str, protocol: str, k: int) -> protocols.Run:
    from morphlearn.learners import algorithms, protocols

    lrn = algorithms.make(learner, run_seed(s, design, learner, protocol, k), s.sigma0)
    if protocol == "joint":
        return protocols.joint(lrn, s.budget)
    return protocols.sequential(lrn, s.per_phase, s.cycles)


def run_designs(settings: Settings, design_ids: np.ndarray) -> pd.DataFrame:
    """Every run of ``design_ids`` (all learners, protocols, seeds) batched together; one
    summary row per design x learner x protocol (stats.COLUMNS)."""
    from morphlearn.learners import protocols, stats
    from morphlearn.learners.objective import Evaluator

    s = settings.learners
    coords = settings.grid.designs.coords(np.asarray(design_ids, dtype=np.int64))
    ev = Evaluator(coords, settings.models["theory"].params)
    keys = [(i, int(d), lr, pr) for i, d in enumerate(design_ids) for lr in s.learners for pr in s.protocols]
    runs = [(i, make_run(s, d, lr, pr, k)) for (i, d, lr, pr) in keys for k in range(s.seeds)]
    results = protocols.drive(ev, runs)
    rows = [
        stats.summarise_runs(d, lr, pr, results[j * s.seeds : (j + 1) * s.seeds])
        for j, (_, d, lr, pr) in enumerate(keys)
    ]
    return pd.DataFrame(rows, columns=list(stats.COLUMNS))


def _cached(path: Path, science: dict[str, Any]) -> pd.DataFrame | None:
    """A cached design's rows, if the file is whole and was made by the same science."""
    from morphlearn.learners import stats

    try:
        rec = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    if rec.get("science") != science:
        return None
    return pd.DataFrame(rec["rows"], columns=list(stats.COLUMNS))


def run_shard(settings: Settings, shard: int, out: str | Path) -> None:
    """Run one shard's designs ``chunk`` at a time, reusing and writing the per-design cache
    (one JSON file per design, written atomically), then write the shard's table."""
    s = settings.learners
    sci = science(settings)
    mine = shards(settings)[shard]
    folder = design_cache.cache_dir(settings.results_dir, "learners", sci) if settings.design_cache else None
    done: dict[int, pd.DataFrame] = {}
    if folder:
        folder.mkdir(parents=True, exist_ok=True)
        for d in mine:
            rows = _cached(folder / f"design_{int(d)}.json", sci)
            if rows is not None:
                done[int(d)] = rows
    todo = [int(d) for d in mine if int(d) not in done]
    print(f"learners shard {shard}: {len(mine)} designs, reused {len(done)}, to run {len(todo)}", flush=True)
    for a in range(0, len(todo), s.chunk):
        part = todo[a : a + s.chunk]
        t0, c0 = time.perf_counter(), time.process_time()
        table = run_designs(settings, np.array(part, dtype=np.int64))
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        for d in part:
            rows = table[table.design == d]
            done[d] = rows
            if folder:
                rec = {"science": sci, "rows": json.loads(rows.to_json(orient="records"))}
                with store.atomic_path(folder / f"design_{d}.json") as tmp:
                    tmp.write_text(json.dumps(rec, sort_keys=True) + "\n")
        print(
            f"learners shard {shard}: {a + len(part)}/{len(todo)} designs run ({wall:.1f} s wall, "
            f"{cpu:.1f} CPU-s for {len(part)})",
            flush=True,
        )
    table = pd.concat([done[int(d)] for d in mine], ignore_index=True)
    with store.atomic_path(Path(out)) as tmp:
        table.to_csv(tmp, index=False, float_format=CSV_FLOAT_FORMAT)


def run_analysis(
    settings: Settings,
    shard_csvs: list[str],
    metrics_csv: str,
    out_runs: str | Path,
    out_corr: str | Path,
    out_md: str | Path,
    out_record: str | Path | None = None,
) -> None:
    """Merge the shards (one row per design x learner x protocol, with the design's coordinates,
    M_L and M_CF), correlate (stats.correlations) and write a short summary; with ``out_record``
    its sealed record (the inputs' digests and the outputs', provenance.write_sealed)."""
    from morphlearn.learners import stats

    s = settings.learners
    provenance.check_derived(metrics_csv)  # custody: the table its metrics rule wrote
    runs = pd.concat([pd.read_csv(p) for p in shard_csvs], ignore_index=True)
    metrics = pd.read_csv(metrics_csv)
    cols = ["design", "l1x", "l1y", "l2x", "l2y", "M_L", "M_CF"]
    merged = runs.merge(metrics[cols], on="design", how="left", validate="many_to_one")
    if merged.M_L.isna().any():
        missing = sorted(merged.design[merged.M_L.isna()].unique())[:5]
        raise ValueError(
            f"{metrics_csv}: no theory metrics for learner designs {missing}: the learner "
            "stage and the theory sweep must use the same grid"
        )
    merged = merged.sort_values(["design", "learner", "protocol"], kind="stable")
    corr = stats.correlations(merged, metrics, n_boot=s.bootstrap, seed=s.seed)
    for path, table in ((out_runs, merged), (out_corr, corr)):
        with store.atomic_path(Path(path)) as tmp:
            table.to_csv(tmp, index=False, float_format=CSV_FLOAT_FORMAT)
    with store.atomic_path(Path(out_md)) as tmp:
        tmp.write_text(summary_markdown(corr, s, merged.design.nunique()))
    if out_record is not None:
        rec = provenance.record(science(settings), [metrics_csv, *shard_csvs], models.get(models.REFERENCE).libraries)
        provenance.write_sealed(out_record, rec, [out_runs, out_corr, out_md])


def _ci(r: pd.Series, key: str) -> str:
    v = r.get(key)
    if v is None or pd.isna(v):
        return "n/a"
    return f"{v:+.3f} [{r[key + '_lo']:+.3f}, {r[key + '_hi']:+.3f}]"


def _pos(r: pd.Series, key: str, n_key: str) -> str:
    n = r.get(n_key)
    return "n/a" if n is None or pd.isna(n) else f"{_ci(r, key)} (n = {int(n)})"


def summary_markdown(corr: pd.DataFrame, s: LearnerSettings, n_designs: int) -> str:
    lines = [
        "# Learners on the theory model (beyond the paper)",
        "",
        f"{n_designs} designs (one of each mirror pair), {s.seeds} seeds per design, learner and "
        f"protocol; joint budget {s.budget} evaluations (x 4 environments), sequential {s.cycles} "
        f"cycles x 4 environments x {s.per_phase} evaluations. Spearman rho with 95 % bootstrap "
        f"intervals over designs ({s.bootstrap} resamples).",
        "",
        "| learner | protocol | mean P(generalist) | rho(M_L, P(generalist)) | same, M_L > 0 "
        "| rho(M_CF, 1 - forgetting) | same, M_CF > 0 | mean forgetting rate | P(generalist) - random |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for _, r in corr.iterrows():
        fr = r.get("mean_forgetting_rate")
        lines.append(
            f"| {r.learner} | {r.protocol} | {r.mean_p_generalist:.3f} | {_ci(r, 'rho_ML_success')} | "
            f"{_ci(r, 'rho_ML_success_pos')} (n = {int(r.designs_ML_pos)}) | "
            f"{_ci(r, 'rho_MCF_retention')} | {_pos(r, 'rho_MCF_retention_pos', 'designs_MCF_pos')} | "
            f"{'n/a' if fr is None or pd.isna(fr) else f'{fr:.3f}'} | "
            f"{_ci(r, 'advantage_vs_random')} |"
        )
    return "\n".join(lines) + "\n"
