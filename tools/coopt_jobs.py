"""The coopt stage's learner runs split finer than its Snakemake jobs, for a shared 2-core machine:
(setup, learner variant, [(protocol, budget)]) jobs in priority order, each written atomically to
its own CSV (a killed run loses one job), then assembled into the stage's layout and analysed.

A run's numbers depend only on its identity (seeded per run; tests/test_coopt.py checks that
batching does not change them), so these jobs give the rows the stage's ``coopt_runs`` jobs give.

    nohup nice -n 10 .venv/bin/python tools/coopt_jobs.py run OUT WORKER NWORKERS &   # per worker
    .venv/bin/python tools/coopt_jobs.py assemble OUT LANDSCAPE_JSON BUNDLE_DIR
    .venv/bin/python tools/coopt_jobs.py manifest BUNDLE_DIR "COMMAND"
"""

from __future__ import annotations

import json
import math
import os
import sys
import time
from pathlib import Path

import pandas as pd

from morphlearn import configure, settings
from morphlearn.coopt import experiment as ex
from morphlearn.coopt import stage
from morphlearn.coopt.setups import paper_setups

CONFIG = "config/coopt.yaml"


def jobs(s: settings.CooptSettings) -> list[tuple[int, int, tuple[str, float], list[tuple[str, int]]]]:
    """Priority order: the default step with joint (largest budget) and the two smaller sequential
    budgets; then the other steps; then the largest sequential budget (the most expensive)."""
    top = max(s.budgets)
    small = [("joint", top)] + [("sequential", b) for b in s.budgets if b != top]
    first = [v for v in ex.variants(s) if math.isnan(v[1]) or v[1] == s.sigmas[0]]
    rest = [v for v in ex.variants(s) if v not in first]
    out = []
    for phase, (vs, ro) in enumerate(((first, small), (rest, small), (first + rest, [("sequential", top)]))):
        for name in s.setups:
            for v in vs:
                out.append((phase, "abcde".index(name), v, ro))
    return out


def run(out: Path, worker: int, nworkers: int) -> None:
    cfg = configure.load("config.yaml", [CONFIG])
    s = cfg.coopt
    best = ex.best_design(s.best_metrics)["M_L"]["coords"]
    setups = paper_setups(best)
    out.mkdir(parents=True, exist_ok=True)
    for n, (phase, i, v, ro) in enumerate(jobs(s)):
        if n % nworkers != worker:
            continue
        path = out / f"p{phase}_{setups[i].name}_{v[0]}_{v[1]}.csv"
        if path.exists():
            continue
        t0, c0 = time.perf_counter(), time.process_time()
        runs = ex.run_setup(s, setups[i], i, cfg.models["theory"].params, only=[v], runs_of=ro)
        runs.to_csv(str(path) + ".tmp", index=False, float_format="%.10g")
        os.replace(str(path) + ".tmp", path)
        print(path, "wall", round(time.perf_counter() - t0, 1), "cpu", round(time.process_time() - c0, 1), flush=True)


def assemble(out: Path, landscape_json: Path, bundle: Path) -> None:
    """Per (setup, variant) CSVs and landscape JSONs in the stage's layout under ``out/stage``,
    then the stage's analysis into ``bundle``."""
    cfg = configure.load("config.yaml", [CONFIG])
    s = cfg.coopt
    files = sorted(out.glob("p*_*.csv"))
    runs = pd.concat([pd.read_csv(p) for p in files], ignore_index=True)
    csvs = []
    for name in s.setups:
        for v in stage.variant_names(s):
            lr, sg = stage.parse_variant(v)
            part = runs[(runs.setup == name) & (runs.learner == lr)]
            part = part[part.sigma0.isna()] if math.isnan(sg) else part[part.sigma0 == sg]
            p = out / "stage" / "runs" / f"{name}_{v}.csv"
            p.parent.mkdir(parents=True, exist_ok=True)
            part.to_csv(p, index=False, float_format="%.10g")
            csvs.append(str(p))
    # The landscape as computed by coopt.landscape.landscape (the stage's rule calls the same function).
    rec = json.loads(landscape_json.read_text())
    lands = []
    for name, key in zip(stage.LANDSCAPE_DESIGNS, rec, strict=True):
        r = rec[key]
        j = {
            "name": name,
            "coords": r["coords"],
            "m": r["m"],
            "controllers": r["m"] ** 4,
            "generalists": r["generalists"],
            "at_least_one": r["at_least_one"],
            "flagged": r["flagged"],
            "generalists_2w": r["g2"],
            "at_least_one_2w": r["a2"],
            "M_L_4w": r["M_L"],
            "M_CF_4w": r["M_CF"],
            "M_L_2w": r["M_L_2w"],
            "M_CF_2w": r["M_CF_2w"],
        }
        assert list(map(float, j["coords"])) == list(stage.landscape_coords(s, name)), (name, key)
        p = out / "stage" / "landscape" / f"{name}.json"
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(json.dumps(j, sort_keys=True, indent=1) + "\n")
        lands.append(str(p))
    stage.run_analysis(cfg, lands, csvs, bundle)


def manifest(bundle: Path, command: str) -> None:
    """bundle.json: the SHA-256 of every file (``morphlearn check-bundle`` reads it), the command,
    commit and library versions."""
    from morphlearn import provenance

    files = sorted(p for p in bundle.rglob("*") if p.is_file() and p.name != "bundle.json")
    rec = {
        "files": {str(p.relative_to(bundle)): provenance.sha256_file(p) for p in files},
        "made_by": {
            "command": command,
            "git_commit": provenance.git_commit(),
            "libraries": provenance.library_versions(),
        },
    }
    (bundle / "bundle.json").write_text(json.dumps(rec, sort_keys=True, indent=1) + "\n")


if __name__ == "__main__":
    if sys.argv[1] == "run":
        run(Path(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]))
    elif sys.argv[1] == "assemble":
        assemble(Path(sys.argv[2]), Path(sys.argv[3]), Path(sys.argv[4]))
    elif sys.argv[1] == "manifest":
        manifest(Path(sys.argv[2]), sys.argv[3])
    else:
        raise SystemExit(f"usage: {__doc__}")
