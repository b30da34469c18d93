"""``morphlearn refine ACTION FOLDER``: read and check a committed refine folder (one physics design
on an exhaustive weight grid, stored row by row: ``results/refine/*``, read-only history read by
:mod:`morphlearn.refine.folder`), and seed a workflow run from it or from another run's design cache.

Actions: ``status`` (progress, cost, metrics; with ``--configfile``, a workflow run's progress from
its design cache: designs finished, episodes of a design in progress), ``assemble`` (every row verified, the design's
metrics as JSON), ``adaptive`` (the adaptive weight grid replayed on a complete folder: the
successes it would miss and the levers' cost), ``survey-check`` (the folder against a survey's
merged store on the weights both share), ``seed`` (the folder's episodes as its design's partial
file in a workflow config's design cache, so a workflow run simulates only the rest);
``seed-cache`` does the same from another workflow run's design cache (e.g. an adaptive survey's
``<results_dir>/<model>/designs/<digest>/``) for every design of it the config simulates.

Refine runs are workflow runs (``config/refine_pybullet.yaml``, ``config/refine_mujoco.yaml``,
``config/refine_exhaustive.yaml``, ``config/ode_paper.yaml``), sealed as bundles by the workflow's
``bundle`` rule (their export); a run in progress resumes inside a design from its design cache.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

#: Default near thresholds of the adaptive replay (contact distances).
DEFAULT_NEAR = (4.0, 1.5)


def _log(msg: str) -> None:
    print(f"[{datetime.now(UTC).strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


def _folder(path: Path) -> Path:
    from morphlearn.refine import folder as rz

    if not path.is_dir():
        raise ValueError(f"{path}: no such folder (a refine folder holds manifest.json and rows/)")
    if not rz.manifest_path(path).is_file():
        raise ValueError(f"{path}: not a refine folder (no {rz.manifest_path(path).name})")
    return path


def time_left(finished: list[float], left: int, last: int = 10) -> str:
    """ ", ~T left at the pace of the last designs finished" from the finishing times (file times)
    of the designs done: the mean gap between the last ``last`` finishes (wall time, all shards
    together), gaps over 6 times their median left out (a run paused between sessions); "" when
    fewer than 2 designs are done or none is left."""
    times = sorted(finished)[-(last + 1) :]
    if left <= 0 or len(times) < 2:
        return ""
    gaps = np.diff(times)
    gaps = gaps[gaps <= 6 * np.median(gaps)] if np.median(gaps) > 0 else gaps
    secs = float(gaps.mean()) * left
    when = f"{secs / 3600:.1f} h" if secs >= 5400 else f"{secs / 60:.0f} min"
    return f"; ~{when} left at the pace of the last {len(gaps)} designs finished (wall time, every shard)"


def run_progress(s: Any) -> list[str]:
    """Where a workflow run (settings ``s``) stands, from its design cache: per simulated physics
    model, the designs finished and, for a design in progress, the episodes its partial file holds
    (the run resumes from them). One line per model and per design in progress."""
    from morphlearn import models
    from morphlearn.physics import design_cache
    from morphlearn.physics import partial as partial_cells

    lines = []
    for name in models.physics():
        plugin = models.get(name)
        if not plugin.simulates(s):
            continue
        designs = [int(d) for d in plugin.designs(s)]
        m = len(plugin.weights(s))
        cache = design_cache.cache_dir(s.results_dir, name, plugin.science(s))
        done = [d for d in designs if design_cache.design_path(cache, d).is_file()]
        pace = time_left([design_cache.design_path(cache, d).stat().st_mtime for d in done], len(designs) - len(done))
        lines.append(f"{name}: {len(done)} of {len(designs)} designs finished in {cache}{pace}")
        for d in designs:
            path = design_cache.partial_path(cache, d)
            if d in done or not path.is_file():
                continue
            cells = partial_cells.load(path, plugin.partial_identity(s, d), (4, m, m))
            if cells is None:
                lines.append(
                    f"  design {d}: {path.name} is unreadable or another run's (not used: the run starts afresh)"
                )
            else:
                lines.append(
                    f"  design {d}: in progress, {int(cells.simulated.sum())} of {4 * m * m} episodes in {path.name}"
                )
    return lines


def status(a: argparse.Namespace) -> int:
    from morphlearn.refine import folder as rz

    if a.configfile:
        if a.folder is not None:
            raise ValueError("give a refine FOLDER or --configfile (a workflow run), not both")
        from morphlearn import configure

        print("\n".join(run_progress(configure.load(a.base, a.configfile))))
        return 0
    if a.folder is None:
        raise ValueError("no FOLDER; allowed: a refine folder, or --configfile for a workflow run's progress")
    asm = rz.assemble(_folder(a.folder), log=_log)
    s, c = rz.summary(asm), rz.cost(a.folder)
    ident = asm.manifest["identity"]
    print(
        f"{a.folder}: design l1={ident['design']['l1']} l2={ident['design']['l2']}, "
        f"{ident['weights']} x {ident['weights']} weights, levers {ident['levers'] or 'none'}"
    )
    print(
        f"  rows {s['rows_done']}/{s['rows']} ({s['fraction_done']:.1%}), {s['episodes']} episodes, "
        f"{'complete' if s['complete'] else 'PARTIAL'}"
    )
    if c["rows_logged"]:
        left = (s["rows"] - s["rows_done"]) * 4 * s["rows"] / c["episodes_per_wall_s"]
        print(
            f"  cost: {c['episodes_per_wall_s']:.2f} episodes/wall-s, {c['episodes_per_cpu_s']:.2f} episodes/CPU-s "
            f"over {c['rows_logged']} rows logged; ~{left / 3600:.2f} h left at that rate"
        )
    dm = s["metrics_over_rows_done"]
    print(
        f"  over the rows done: generalists {dm['generalists']} of {s['episodes'] // 4} cells, "
        f"at least one {dm['at_least_one']}, per env {dm['per_env']}, M_L {dm['M_L']:.6g}, "
        f"M_CF {dm['M_CF']:.6g}, flagged {dm['flagged']}; {s['steps_per_episode']:.0f} steps/episode"
    )
    if "mirror" in s:
        mi = s["mirror"]
        print(
            f"  mirror (self-mirror design): {mi['pairs_flipped']} of {mi['pairs_compared']} cell pairs "
            "differ in success"
        )
    return 0


def _summary(folder: Path) -> tuple[Any, dict[str, Any]]:
    """The assembled folder (every row verified) and its summary as ``assemble`` prints it."""
    from morphlearn.refine import folder as rz

    asm = rz.assemble(_folder(folder), log=_log)
    return asm, rz.summary(asm) | {"cost": rz.cost(folder), "run_key": asm.manifest["run_key"]}


def assemble(a: argparse.Namespace) -> int:
    """Every row verified; the design's summary as JSON on stdout (the folder's summary.json)."""
    print(json.dumps(_summary(a.folder)[1], indent=1, sort_keys=True))
    return 0


def adaptive(a: argparse.Namespace) -> int:
    """The adaptive weight grid's misses at each ``--near``, replayed on a complete folder."""
    from morphlearn import metrics
    from morphlearn.physics.refine import misses, simulated_mask
    from morphlearn.refine import folder as rz
    from morphlearn.results import STATUS_OK

    if not all(v > 0 and np.isfinite(v) for v in a.near):
        raise ValueError(f"--near {a.near}: every threshold must be a finite number > 0 (contact distances)")
    asm = rz.assemble(_folder(a.folder), log=_log)
    if not asm.complete:
        raise ValueError(f"{a.folder}: {int(asm.rows_done.sum())} of {len(asm.rows_done)} rows; the replay needs all")
    job = rz.job_from_manifest(asm.manifest)
    r = asm.result
    succ = metrics.success(r.first_time, r.min_dist, rz.thresholds(job.params))
    out = [misses(succ, r.min_dist, job.params.contact_distance, near) for near in a.near]
    # The levers' cost from the physics steps each cell took (the rows record them) at the
    # folder's measured CPU-s per step: with early stop off a failure runs the whole horizon and a
    # success stops at contact as it does now; the adaptive grid runs only the cells it simulates.
    steps = asm.steps.astype(np.int64)
    horizon = round(job.params.horizon / job.params.dt)
    ended_early = succ | (r.status != STATUS_OK)
    no_levers = int(np.where(ended_early, steps, horizon).sum())
    summary_file = a.folder / "summary.json"
    cost = json.loads(summary_file.read_text())["cost"] if summary_file.exists() else {}
    per_step = cost.get("cpu_s", float("nan")) / int(steps.sum())
    levers = {
        "cpu_s_per_step": per_step,
        "exhaustive_no_early_stop": {"steps": no_levers, "cpu_s": no_levers * per_step},
        "exhaustive_early_stop": {"steps": int(steps.sum()), "cpu_s": int(steps.sum()) * per_step},
    }
    for near in a.near:
        sim = simulated_mask(succ, r.min_dist, job.params.contact_distance, near)
        n = int(steps[sim].sum())
        levers[f"adaptive_near_{near:g}_early_stop"] = {"steps": n, "cpu_s": n * per_step}
    report = {"folder": str(a.folder), "engine": job.engine, "weights": job.m, "replays": out, "cost": levers}
    print(json.dumps(report, indent=1))
    return 0


def survey_check(folder: Path, merged: str | Path) -> dict[str, object]:
    """A refine folder against a survey's merged store on the weights both share: every cell the
    survey simulated (status not ``inferred``) on a weight of both grids, in a row the folder has,
    must agree bit for bit when both used the same body and exact levers (early stop is exact; the
    adaptive grid only skips cells); the survey's inferred cells, where its adaptive grid could
    miss successes, are counted apart."""
    from morphlearn import metrics, store
    from morphlearn.refine import folder as rz
    from morphlearn.results import STATUS_INFERRED

    asm = rz.assemble(_folder(folder))
    job = rz.job_from_manifest(asm.manifest)
    ds = store.open_merged(merged)
    if store.science_of(ds).get("params") != job.params.to_dict():
        raise ValueError(f"{merged}: simulated with other body parameters than {folder}")
    cols = ["l1x", "l1y", "l2x", "l2y"]
    want = (*job.l1, *job.l2)
    hit = np.flatnonzero(np.all([ds[c].values == v for c, v in zip(cols, want, strict=True)], axis=0))
    if hit.size != 1:
        raise ValueError(f"{merged}: holds no design l1={job.l1} l2={job.l2}")
    sv = ds["w1"].values if "w1" in ds else ds["weight"].values
    fine = job.weights
    # linspace(-1, 1, 11) is not bit-exact every 12th of linspace(-1, 1, 121) (+-0.4 differ by an
    # ulp): matched within 1e-12, and bit-identical outcomes are expected only where both weights
    # of a cell are exactly equal.
    near = [np.flatnonzero(np.isclose(fine, w, rtol=0, atol=1e-12)) for w in sv]
    if not all(n.size for n in near):
        raise ValueError(f"{merged}: its weights are not a subset of the folder's {job.m}-point grid")
    idx = [int(n[0]) for n in near]
    exact_w = fine[idx] == sv
    s = store.read_design(ds, int(hit[0]))
    ix = np.ix_(range(4), idx, idx)
    rows_ok = asm.rows_done[idx]
    keys = ("first_time", "min_dist", "status")
    mine = {k: getattr(asm.result, k)[ix][:, rows_ok] for k in keys}
    theirs = {k: s[k][:, rows_ok] for k in keys}
    exact = np.broadcast_to((exact_w[rows_ok][:, None] & exact_w[None, :])[None], theirs["status"].shape)
    sim = theirs["status"] != STATUS_INFERRED
    both = sim & exact
    th = rz.thresholds(job.params)
    succ_m = metrics.success(mine["first_time"], mine["min_dist"], th)
    succ_t = metrics.success(theirs["first_time"], theirs["min_dist"], th)

    def same(k: str) -> int:  # bit for bit: compare the stored bytes, so NaN equals NaN
        view = np.uint8 if k == "status" else np.uint32
        return int((mine[k][both].view(view) == theirs[k][both].view(view)).sum())

    return {
        "survey_rows_in_folder": int(rows_ok.sum()),
        "survey_rows": len(idx),
        "cells_compared": int(rows_ok.sum()) * len(idx) * 4,
        "survey_simulated": int(sim.sum()),
        "survey_simulated_with_bit_equal_weights": int(both.sum()),
        "bit_identical_there": {k: same(k) for k in keys},
        "success_disagreements_where_survey_simulated": int((succ_m != succ_t)[sim].sum()),
        "success_disagreements_there_weights_1ulp_apart": int((succ_m != succ_t)[sim & ~exact].sum()),
        "successes_folder": int(succ_m.sum()),
        "successes_survey": int(succ_t.sum()),
        "successes_survey_missed_inferred": int((succ_m & ~sim).sum()),
        "generalists_folder_on_subgrid": int(succ_m.all(axis=0).sum()),
        "generalists_survey_on_these_rows": int(succ_t.all(axis=0).sum()),
        "survey_generalists_whole_11x11": int(metrics.success(s["first_time"], s["min_dist"], th).all(axis=0).sum()),
        "complete_on_subgrid": bool(rows_ok.all()),
    }


def _survey_check(a: argparse.Namespace) -> int:
    print(json.dumps(survey_check(a.folder, a.merged), indent=1))
    return 0


def seed(a: argparse.Namespace) -> int:
    """The folder's episodes as the partial file of its design in a workflow config's design cache."""
    from morphlearn import configure
    from morphlearn.refine.seed import seed as seed_cache

    s = configure.load(a.base, a.configfile)
    r = seed_cache(_folder(a.folder), s)
    if r.finished:
        print(f"design {r.design} is already finished in the design cache; nothing written", file=sys.stderr)
        return 0
    print(
        f"design {r.design}: {r.rows} complete rows in {a.folder}; {r.seeded} episodes seeded, {r.kept} already "
        f"in the partial file, {r.near_threshold} left to simulate (float32 closest approach at the "
        f"near threshold) -> {r.path}",
        file=sys.stderr,
    )
    return 0


def seed_cache(a: argparse.Namespace) -> int:
    """Another run's design cache's simulated cells as the partial files of the designs this
    config simulates (one line per design, on stderr)."""
    from morphlearn import configure
    from morphlearn.refine.seed import seed_designs

    s = configure.load(a.base, a.configfile)
    found = seed_designs(a.cache, s)
    for r in found:
        what = "finished already; nothing written" if r.finished else f"{r.seeded} episodes seeded -> {r.path}"
        print(f"design {r.design}: {r.rows} simulated cells in {a.cache}; {what}", file=sys.stderr)
    print(f"{len(found)} designs of {a.cache} are designs this config simulates", file=sys.stderr)
    return 0


def run(a: argparse.Namespace) -> int:
    """The action; a refine folder that fails its checks is a usage error (one line, exit 2)."""
    from morphlearn.refine import folder as rz

    try:
        return int(a.refine_func(a))
    except (rz.RefineError, rz.ChunkError) as e:
        raise ValueError(str(e)) from None


def terminal_text(doc: str) -> str:
    """A docstring as a terminal shows it: reStructuredText's roles (``:mod:`x```) and literals
    (````x````) as their plain text."""
    return re.sub(r"``([^`]+)``", r"\1", re.sub(r":[a-z]+:`~?([^`]+)`", r"\1", doc))


def add_parser(sub: Any) -> argparse.ArgumentParser:
    """The ``refine`` verb and its actions, on the ``morphlearn`` parser's subparsers ``sub``."""
    p = sub.add_parser(
        "refine",
        help="read or check a committed refine folder (one design, exhaustive weights), or seed a "
        "workflow run from it: status, assemble, adaptive, survey-check, seed, seed-cache",
        description=terminal_text(__doc__ or ""),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    acts = p.add_subparsers(dest="action", required=True, metavar="ACTION", help="what to do with the folder")
    folder_help = "a refine folder (manifest.json, rows/; e.g. results/refine/canonical_121)"

    s = acts.add_parser(
        "status", help="a folder's progress, cost and metrics; or, with --configfile, a workflow run's progress"
    )
    s.add_argument("folder", type=Path, nargs="?", metavar="FOLDER", help=folder_help)
    s.add_argument(
        "--configfile", type=Path, nargs="+", help="a workflow run's config file(s): its designs finished and partial"
    )
    s.add_argument("--base", type=Path, default=Path("config.yaml"), help="the base config (default: config.yaml)")
    s.set_defaults(refine_func=status)

    m = acts.add_parser("assemble", help="verify every row; the design's metrics as JSON")
    m.add_argument("folder", type=Path, metavar="FOLDER", help=folder_help)
    m.set_defaults(refine_func=assemble)

    ad = acts.add_parser("adaptive", help="replay the adaptive weight grid on a complete folder: what it misses")
    ad.add_argument("folder", type=Path, metavar="FOLDER", help=folder_help + "; complete")
    ad.add_argument(
        "--near",
        type=float,
        nargs="+",
        default=list(DEFAULT_NEAR),
        metavar="K",
        help="near thresholds in contact distances (default: %(default)s)",
    )
    ad.set_defaults(refine_func=adaptive)

    sc = acts.add_parser("survey-check", help="the folder against a survey's merged store on the shared weights")
    sc.add_argument("folder", type=Path, metavar="FOLDER", help=folder_help)
    sc.add_argument(
        "merged", metavar="MERGED", help="a survey's merged.zarr (e.g. results/survey/empirical/merged.zarr)"
    )
    sc.set_defaults(refine_func=_survey_check)

    sd = acts.add_parser("seed", help="the folder's episodes as its design's partial file in a workflow's design cache")
    sd.add_argument("folder", type=Path, metavar="FOLDER", help=folder_help)
    sd.add_argument(
        "--configfile", type=Path, nargs="+", required=True, help="the workflow run's config file(s), as given to it"
    )
    sd.add_argument("--base", type=Path, default=Path("config.yaml"), help="the base config (default: config.yaml)")
    sd.set_defaults(refine_func=seed)

    sc2 = acts.add_parser(
        "seed-cache", help="another run's design cache's episodes as partial files in a workflow's design cache"
    )
    sc2.add_argument(
        "cache",
        type=Path,
        metavar="CACHE",
        help="a run's design cache folder (<results_dir>/<model>/designs/<digest>/, design_<n>.nc files)",
    )
    sc2.add_argument(
        "--configfile", type=Path, nargs="+", required=True, help="the workflow run's config file(s), as given to it"
    )
    sc2.add_argument("--base", type=Path, default=Path("config.yaml"), help="the base config (default: config.yaml)")
    sc2.set_defaults(refine_func=seed_cache)
    p.set_defaults(func=run)
    return p
