"""The committed paper-resolution bundle (results/paper/): intact, within its size budget, its
designs re-simulate to the same bytes, and the README's command re-renders every figure and the
reproduction table from it alone, simulating nothing, to the committed bytes. And every committed
workflow bundle's documented re-render (results/README.md) starts from what a fresh clone holds
(its start check passes) and renders its reproduction table to the committed bytes."""

from __future__ import annotations

import json
import re
import shlex
import shutil
from pathlib import Path

import pandas as pd
import pytest
from conftest import ROOT, copy_paper_sources, copy_workflow, job_stats, snakemake

from morphlearn.bundles import check as bundle_check
from morphlearn.bundles import make as bundle
from morphlearn.bundles import resimulate
from morphlearn.workflow import rules

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


# -- every committed workflow bundle: its documented re-render starts on a fresh clone ---------

#: A results/README.md row's re-render command of a workflow bundle (issue 38: results/survey's
#: failed at start on a fresh clone while CI rendered only results/paper).
RENDER_COMMAND = re.compile(r"`\.venv/bin/snakemake ([^`]*render_only=True results_dir=(results/[\w-]+) --forceall)`")


def documented_renders() -> dict[str, list[str]]:
    """Bundle folder -> the Snakemake arguments of its re-render command, as results/README.md gives them."""
    text = (ROOT / "results" / "README.md").read_text()
    return {m.group(2): shlex.split(m.group(1)) for m in RENDER_COMMAND.finditer(text)}


def copy_as_cloned(wd: Path) -> None:
    """Every committed bundle into the workflow copy ``wd`` as a fresh clone holds it: bundle.json
    and the files it lists, nothing a render left beside them (a re-render's own record of an
    older bundle is not committed: .gitignore)."""
    for manifest in sorted((ROOT / "results").glob("*/" + bundle.MANIFEST)):
        rel = manifest.parent.relative_to(ROOT)
        shutil.rmtree(wd / rel, ignore_errors=True)
        for name in [bundle.MANIFEST, *json.loads(manifest.read_text())["files"]]:
            (wd / rel / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(manifest.parent / name, wd / rel / name)


@pytest.fixture(scope="module")
def clone(tmp_path_factory: pytest.TempPathFactory) -> Path:
    wd = copy_workflow(tmp_path_factory.mktemp("clone") / "wd")
    copy_as_cloned(wd)
    return wd


def test_every_workflow_bundle_with_figures_has_a_documented_render() -> None:
    """The bundles the workflow made that hold figures (a render re-makes them) are exactly those
    results/README.md gives a re-render command for; each command is its config's."""
    drawn = {
        f"results/{m.parent.name}"
        for m in (ROOT / "results").glob("*/" + bundle.MANIFEST)
        if json.loads(m.read_text()).get("made_by", {}).get("command", "").startswith("snakemake")
        and any(r.startswith("figures/") for r in json.loads(m.read_text())["files"])
    }
    renders = documented_renders()
    assert set(renders) == drawn and {"results/paper", "results/survey"} <= drawn, (sorted(renders), sorted(drawn))
    for rel, args in renders.items():
        made = json.loads((ROOT / rel / bundle.MANIFEST).read_text())["made_by"]["configs"]
        assert args[args.index("--configfile") + 1] in made, (rel, args)


@pytest.mark.parametrize("rel", sorted(documented_renders()))
def test_documented_render_starts_and_renders_the_table_to_the_committed_bytes(clone: Path, rel: str) -> None:
    """The README's command, as a dry run (the start check that reads the stored results runs
    at parse), then its reproduction table (and, with it, the persistence table it reads or
    makes) rendered for real: the bundle checks out unchanged. About 5 s per bundle; the paper
    bundle's every figure: test_readme_command_renders_committed_bundle."""
    args = documented_renders()[rel]
    dry = snakemake(clone, *args, "-n", check=False)
    assert dry.returncode == 0, dry.stderr[-2000:]
    jobs = job_stats(dry.stdout + dry.stderr)
    assert "reproduction" in jobs and all(j.startswith("figure_") for j in set(jobs) - {"reproduction", "all"}), jobs
    proc = snakemake(clone, *args, f"{rel}/reproduction.md", check=False)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert set(job_stats(proc.stdout + proc.stderr)) == {"reproduction"}
    assert bundle_check.check(clone / rel) == []


def test_a_bundle_without_a_reproduction_record_is_vouched_for_by_its_manifest(tmp_path: Path) -> None:
    """results/survey predates reproduction.provenance.json: its bundle.json vouches for the
    stored persistence table instead; an edit of the table is still refused by name, and a table
    with neither a record nor a bundle around it still is (nothing vouches for it)."""
    b = tmp_path / "survey"
    b.mkdir()
    for name in (bundle.MANIFEST, "persistence.csv"):
        shutil.copy2(ROOT / "results/survey" / name, b / name)
    assert "reproduction.provenance.json" not in json.loads((b / bundle.MANIFEST).read_text())["files"]
    rules.check_stored_persistence(b / "persistence.csv")  # as committed: vouched for
    with (b / "persistence.csv").open("a") as f:
        f.write("0,0,0\n")
    with pytest.raises(ValueError, match=r"survey/persistence\.csv: SHA-256 \w+ differs from bundle\.json"):
        rules.check_stored_persistence(b / "persistence.csv")
    (b / bundle.MANIFEST).unlink()
    with pytest.raises(ValueError, match=r"no provenance record reproduction\.provenance\.json beside it"):
        rules.check_stored_persistence(b / "persistence.csv")
