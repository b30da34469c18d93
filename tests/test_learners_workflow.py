"""The learner stage in the workflow (issue 15), on the smoke grid: shards, per-design cache,
analysis, its figure and its rows in the reproduction table; bad learner config refused."""

from __future__ import annotations

import shutil
from pathlib import Path

import pandas as pd
from conftest import copy_workflow, job_stats, snakemake, written_results

from morphlearn.figures.reproduction.claims import BEYOND

TINY = (
    "learners: {enabled: true, seeds: 2, budget: 4, cycles: 1, per_phase: 4, max_designs: 3, shards: 2, "
    "threads: 1, bootstrap: 100}\n"
)
ARGS = ("--cores", "2", "--configfile", "config/smoke.yaml", "tiny_learners.yaml")


def test_learner_stage_runs_caches_and_reports(smoke_run: Path, tmp_path: Path) -> None:
    # Turning the stage on in a finished run adds the learner jobs and remakes the table only:
    # nothing is simulated again and no other figure is redrawn.
    wd = tmp_path / "wd"
    shutil.copytree(smoke_run, wd, symlinks=True)
    (wd / "tiny_learners.yaml").write_text(TINY)
    targets = ("results/learners/summary.md", "results/figures/learners.png", "results/reproduction.md")
    proc = snakemake(wd, *targets, *ARGS)
    ran = job_stats(proc.stdout + proc.stderr)
    assert set(ran) == {"learners_shard", "learners_analysis", "figure_learners", "reproduction"}, ran
    runs = pd.read_csv(wd / "results/learners/runs.csv")
    assert runs.design.nunique() == 3 and len(runs) == 3 * 3 * 2  # designs x learners x protocols
    assert runs.p_generalist.between(0, 1).all() and runs.M_L.notna().all()
    corr = pd.read_csv(wd / "results/learners/correlations.csv")
    assert set(zip(corr.learner, corr.protocol, strict=True)) == {
        (lr, pr) for lr in ("random", "one_plus_one", "cmaes") for pr in ("joint", "sequential")
    }
    table = pd.read_csv(wd / "results/reproduction.csv")
    beyond = table[table.key.str.startswith("learners_")]
    assert len(beyond) == 6 + 3 + 4 and (beyond.paper == BEYOND).all()  # rho M_L, rho M_CF, advantage
    assert "Do the metrics predict learning?" in (wd / "results/figures/learners.caption.md").read_text()
    # A shard rerun (deleted output) reuses every design from the per-design cache. The shard is
    # the target: Snakemake does not remake a missing intermediate file whose consumers are current.
    shard = wd / "results/learners/shards/shard_0.csv"
    before = shard.read_bytes()
    shard.unlink()
    snakemake(wd, "results/learners/shards/shard_0.csv", *ARGS)
    assert "reused 2, to run 0" in (wd / "results/logs/learners/shard_0.log").read_text()
    assert shard.read_bytes() == before  # deterministic
    # custody (issue 24): the analysis is sealed; an edited correlation stops the next start, exit 2
    corr = wd / "results/learners/correlations.csv"
    corr.write_text(corr.read_text().replace("0.", "0.9", 1))
    refused = snakemake(wd, *targets, "-n", *ARGS, check=False)
    assert refused.returncode == 2 and "learners/correlations.csv: SHA-256" in refused.stderr, refused.stderr[-2000:]


def test_bad_learner_config_stops_with_one_line(tmp_path: Path) -> None:
    wd = copy_workflow(tmp_path / "wd")
    (wd / "bad.yaml").write_text("learners: {enabled: true, budget: 0}\n")
    proc = snakemake(wd, "-n", "--configfile", "config/smoke.yaml", "bad.yaml", check=False)
    assert proc.returncode == 2
    assert "learners.budget = 0 is invalid" in proc.stderr
    assert written_results(wd) == []
