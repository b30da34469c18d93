"""The committed paper-resolution bundle (results/paper/): intact, within its size budget, its
designs re-simulate to the same bytes, and the README's command re-renders every figure and the
reproduction table from it alone, simulating nothing, to the committed bytes."""

from __future__ import annotations

import json
import shlex
import shutil
from pathlib import Path

import pandas as pd
from conftest import ROOT, copy_paper_sources, copy_workflow, job_stats, snakemake

from morphlearn import bundle, bundle_check, resimulate

BUNDLE = ROOT / "results" / "paper"
#: What the bundle may weigh in git (issue 11).
BUDGET_BYTES = 25 * 2**20


def _committed() -> Path:
    assert (BUNDLE / bundle.MANIFEST).is_file(), (
        f"{BUNDLE} is committed with the project; remake it with "
        "`snakemake all bundle --cores 2 --configfile config/paper.yaml`"
    )
    return BUNDLE


def readme_render_command() -> list[str]:
    """The README's one command that re-renders the paper bundle (so the test runs what the
    README tells a reviewer, not a copy of it)."""
    lines = [
        ln.strip()
        for ln in (ROOT / "README.md").read_text().splitlines()
        if "snakemake" in ln and "render_only=True" in ln and "results_dir=results/paper " in ln + " "
    ]
    assert lines, "README.md names the command that re-renders results/paper"
    words = shlex.split(lines[0])
    return words[words.index(next(w for w in words if w.endswith("snakemake"))) + 1 :]


def test_committed_bundle_is_whole_and_small() -> None:
    b = _committed()
    assert bundle_check.check(b) == []
    size = sum(
        p.stat().st_size
        for p in b.rglob("*")
        if p.is_file() and p.relative_to(b).parts[0] not in ("logs", "benchmarks", ".snakemake")
    )
    assert size <= BUDGET_BYTES, f"{size / 2**20:.1f} MiB"
    manifest = json.loads((b / bundle.MANIFEST).read_text())
    assert manifest["subsets"]["theory"]["of"] == 6561  # every design of the paper's grid
    table = pd.read_csv(b / "theory/metrics.csv")
    assert sorted(table.design) == list(range(6561))
    assert manifest["made_by"]["command"] == "snakemake --cores 2 --configfile config/paper.yaml"
    for i in range(1, 8):
        assert (b / f"figures/fig{i}.png").is_file() and (b / f"figures/fig{i}.caption.md").is_file()


def test_committed_designs_resimulate_exactly() -> None:
    """The canonical design and the best designs by M_L and by M_CF, at paper resolution (121 x
    121 weights, 4 environments): the committed rows and arrays, bit for bit."""
    assert resimulate.resimulate(_committed(), ["canonical", "best_M_L", "best_M_CF"]) == []


def test_readme_command_renders_committed_bundle(tmp_path: Path) -> None:
    wd = copy_workflow(tmp_path / "clone")
    copy_paper_sources(wd)  # a clone holds the bundles config/paper.yaml reads
    out = wd / "results" / "paper"
    shutil.copytree(_committed(), out)
    proc = snakemake(wd, *readme_render_command(), timeout=900)
    jobs = job_stats(proc.stdout + proc.stderr)
    # nothing simulated, merged or recomputed: only the figures (the paper's seven and the
    # survey's) and the table
    figures = {f"figure_{p.name.removesuffix('.caption.md')}" for p in (out / "figures").glob("*.caption.md")}
    assert {f"figure_fig{i}" for i in range(1, 8)} <= figures
    assert set(jobs) == {*figures, "reproduction", "all"}, jobs
    for i in range(1, 8):
        assert (out / f"figures/fig{i}.html").stat().st_size > 1000
    assert not (out / "theory" / "shards").exists() and not (out / "theory" / "designs").exists()
    # every figure, caption and table re-rendered to the committed bytes
    assert bundle_check.check(out) == []
