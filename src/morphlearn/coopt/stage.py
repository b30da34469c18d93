"""The workflow stage (workflow/rules/coopt.smk): job names, one landscape job per design, one
runs job per setup and learner variant (its CSV is the stage's cache: a finished job is not rerun),
and the analysis. Light imports only: the Snakefile imports this module at parse time."""

from __future__ import annotations

import dataclasses
import json
import math
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from morphlearn import models, provenance, store
from morphlearn.metrics import CSV_FLOAT_FORMAT
from morphlearn.settings import CooptSettings, Settings

#: The designs of the four-weight landscape: the canonical one and the best two-weight designs.
LANDSCAPE_DESIGNS = ("canonical", "best_M_L", "best_M_CF")
#: What the analysis writes (run_analysis), which its sealed record names.
ANALYSIS_OUTPUTS = ("runs.csv", "summary.csv", "landscape.csv", "summary.md", "position_map.csv")
#: What it writes besides when the restart runs are on (coopt.restart).
RESTART_OUTPUTS = ("restart_runs.csv", "restart_summary.csv")
#: Run columns the tables are sorted by (the order of the rows is part of their bytes).
RUN_ORDER = ["setup", "learner", "sigma0", "protocol", "budget", "seed"]


def restart_settings(s: Settings) -> CooptSettings | None:
    """The restart runs' settings (``coopt.restart``): the stage's seeds, budgets, cycles and
    bootstrap with the restart section's learners, setups, steps and protocols; None when off."""
    # CooptSettings.science() leaves the restart section out, so turning restarts on re-runs none
    # of the other jobs
    r = s.coopt.restart
    if not r.learners:
        return None
    return dataclasses.replace(s.coopt, learners=r.learners, setups=r.setups, sigmas=r.sigmas, protocols=r.protocols)


def restart_science(s: Settings) -> dict[str, Any] | None:
    """What the restart runs' numbers depend on (None when off)."""
    r = restart_settings(s)
    return None if r is None else {**science(s), "restart": r.science()}


def bundle_dir(s: Settings) -> str | None:
    """The stage's committed bundle folder (``coopt.bundle_dir``), or None."""
    return s.coopt.bundle_dir


def variant_names(s: CooptSettings) -> list[str]:
    """Job names of the learner variants: ``random`` and ``<es>-<step>`` per step size."""
    return [
        lr if lr == "random" else f"{lr}-{sg:g}" for lr in s.learners for sg in (s.sigmas if lr != "random" else (0,))
    ]


def parse_variant(name: str) -> tuple[str, float]:
    lr, _, sg = name.partition("-")
    return (lr, math.nan) if lr == "random" else (lr, float(sg))


def science(s: Settings) -> dict[str, Any]:
    """What the stage's numbers depend on (the theory model's parameters and the coopt section)."""
    return {"model": "coopt", "theory": models.get("theory").science(s)["theory"], "coopt": s.coopt.science()}


def landscape_coords(s: CooptSettings, name: str) -> tuple[float, ...]:
    from morphlearn.coopt import experiment
    from morphlearn.coopt.setups import CANONICAL

    if name == "canonical":
        return CANONICAL
    return experiment.best_design(s.best_metrics)[name.removeprefix("best_")]["coords"]


def run_landscape(settings: Settings, name: str, out: str | Path) -> None:
    from morphlearn.coopt.landscape import landscape

    s = settings.coopt
    coords = landscape_coords(s, name)
    t0, c0 = time.perf_counter(), time.process_time()
    land = landscape(np.array(coords), s.landscape_weights, settings.models["theory"].params)
    rec = {
        "name": name,
        "coords": list(coords),
        "m": land.m,
        "controllers": land.controllers,
        "generalists": land.generalists,
        "at_least_one": land.at_least_one,
        "flagged": land.flagged,
        "generalists_2w": land.generalists_2w,
        "at_least_one_2w": land.at_least_one_2w,
        "M_L_4w": land.m_l,
        "M_CF_4w": land.m_cf,
        "M_L_2w": land.m_l_2w,
        "M_CF_2w": land.m_cf_2w,
    }
    print(f"landscape {name}: {time.perf_counter() - t0:.1f} s wall, {time.process_time() - c0:.1f} CPU-s", flush=True)
    with store.atomic_path(Path(out)) as tmp:
        tmp.write_text(json.dumps(rec, sort_keys=True, indent=1) + "\n")


def run_variant(settings: Settings, setup: str, variant: str, out: str | Path, restart: bool = False) -> None:
    """Every run of one setup and learner variant (``restart``: of the restart runs)."""
    from morphlearn.coopt import experiment
    from morphlearn.coopt.setups import paper_setups

    s = restart_settings(settings) if restart else settings.coopt
    if s is None:
        raise ValueError("coopt.restart.learners is empty: no restart runs to make")
    best = experiment.best_design(s.best_metrics)["M_L"]["coords"]
    setups = {x.name: (i, x) for i, x in enumerate(paper_setups(best))}
    i, st = setups[setup]
    t0, c0 = time.perf_counter(), time.process_time()
    runs = experiment.run_setup(s, st, i, settings.models["theory"].params, only=[parse_variant(variant)])
    print(f"runs {setup} {variant}: {time.perf_counter() - t0:.1f} s wall, {time.process_time() - c0:.1f} CPU-s")
    with store.atomic_path(Path(out)) as tmp:
        runs.to_csv(tmp, index=False, float_format=CSV_FLOAT_FORMAT)


def run_analysis(
    settings: Settings,
    landscapes: list[str],
    run_csvs: list[str],
    out_dir: str | Path,
    restart_csvs: list[str] | None = None,
) -> None:
    """runs.csv, summary.csv, landscape.csv, summary.md and position_map.csv in ``out_dir`` (with
    ``restart_csvs``: also restart_runs.csv and restart_summary.csv), and their sealed record
    summary.provenance.json (the inputs' digests and theirs). The figure is a registered figure
    notebook, notebooks/coopt.ipynb, that reads them."""
    from morphlearn.coopt import analysis, experiment

    s = settings.coopt
    out_dir = Path(out_dir)
    best = experiment.best_design(s.best_metrics)  # first: it checks the table's custody
    runs = pd.concat([pd.read_csv(p) for p in run_csvs], ignore_index=True)
    runs = runs.sort_values(RUN_ORDER, kind="stable")
    summary = analysis.sort_summary(experiment.summarise(runs, s))
    rows = []
    for p in landscapes:
        r = json.loads(Path(p).read_text())
        ref = best.get(r["name"].removeprefix("best_"))
        if ref is None:  # canonical: its row of the bundle
            m = pd.read_csv(s.best_metrics)
            c = r["coords"]
            hit = m[(m.l1x == c[0]) & (m.l1y == c[1]) & (m.l2x == c[2]) & (m.l2y == c[3])]
            ref = {"M_L": float(hit.M_L.iloc[0]), "M_CF": float(hit.M_CF.iloc[0])} if len(hit) else {}
        rows.append(
            {
                **{k: v for k, v in r.items() if k != "coords"},
                **dict(zip(("l1x", "l1y", "l2x", "l2y"), r["coords"], strict=True)),
                "M_L_bundle": ref.get("M_L", math.nan),
                "M_CF_bundle": ref.get("M_CF", math.nan),
            }
        )
    land = pd.DataFrame(rows)
    pmap = analysis.position_map(s.best_metrics)
    tables = [("runs.csv", runs), ("summary.csv", summary), ("landscape.csv", land), ("position_map.csv", pmap)]
    names = list(ANALYSIS_OUTPUTS)
    sci = science(settings)
    if restart_csvs:
        rs = restart_settings(settings)
        if rs is None:
            raise ValueError("restart runs given but coopt.restart.learners is empty")
        again = pd.concat([pd.read_csv(p) for p in restart_csvs], ignore_index=True)
        again = again.sort_values(RUN_ORDER, kind="stable")
        # the stage's seed, budgets and bootstrap: summarise reads only those of its settings
        tables += [
            ("restart_runs.csv", again),
            ("restart_summary.csv", analysis.sort_summary(experiment.summarise(again, rs))),
        ]
        names += list(RESTART_OUTPUTS)
        sci = restart_science(settings) or sci
    for name, table in tables:
        with store.atomic_path(out_dir / name) as tmp:
            table.to_csv(tmp, index=False, float_format=CSV_FLOAT_FORMAT)
    with store.atomic_path(out_dir / "summary.md") as tmp:
        tmp.write_text(analysis.summary_markdown(summary, land, s))
    outputs = [out_dir / n for n in names]
    # the learners simulate in the theory, the reference model: its libraries
    libs = models.get(models.REFERENCE).libraries
    rec = provenance.record(sci, [s.best_metrics, *landscapes, *run_csvs, *(restart_csvs or [])], libs)
    provenance.write_sealed(provenance.sidecar_of(out_dir / "summary.csv"), rec, outputs)
