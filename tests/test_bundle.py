"""Results bundles (morphlearn.bundles.make, rule `bundle`): built from a real smoke run, checked,
attacked, re-simulated and re-rendered from the bundle alone."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from conftest import TEST_COMMIT, copy_workflow, job_stats, snakemake

from morphlearn import grid as gridmod
from morphlearn import metrics, store
from morphlearn.apps import cli
from morphlearn.bundles import check as bundle_check
from morphlearn.bundles import make as bundle
from morphlearn.bundles import render as bundle_rerender
from morphlearn.bundles import resimulate
from morphlearn.workflow import rules


@pytest.fixture(scope="module")
def smoke_bundle(smoke_run: Path) -> Path:
    """The bundle of the shared smoke run, made by the workflow's own rule."""
    snakemake(
        smoke_run,
        "bundle",
        "--cores",
        "1",
        "--configfile",
        "config/smoke.yaml",
        "--config",
        "bundle_dir=results/bundle",
    )
    return smoke_run / "results" / "bundle"


def test_bundle_holds_what_the_figures_draw(smoke_bundle: Path, smoke_run: Path) -> None:
    assert bundle_check.check(smoke_bundle) == []
    manifest = json.loads((smoke_bundle / bundle.MANIFEST).read_text())
    assert manifest["made_by"]["command"] == "snakemake --cores 2 --configfile config/smoke.yaml"
    table = pd.read_csv(smoke_bundle / "theory/metrics.csv")
    pd.testing.assert_frame_equal(table, pd.read_csv(smoke_run / "results/theory/metrics.csv"))
    held = manifest["subsets"]["theory"]["designs"]
    assert manifest["subsets"]["theory"]["simulated_by"]["git_commits"] == {TEST_COMMIT: 3}  # 3 shards
    g = gridmod.DesignGrid(3)
    top = {int(metrics.rank_designs(table, by).design.iloc[0]) for by in ("M_L", "M_CF")}
    want = {g.index_of(*gridmod.canonical_design())} | top
    assert want | {int(g.mirror(d)) for d in want} <= set(held) and len(held) < len(table)
    sub = store.open_merged(smoke_bundle / "theory/merged.zarr")
    full = store.open_merged(smoke_run / "results/theory/merged.zarr")
    assert sub["design"].values.tolist() == held
    for v in store.VARS:  # the subset's arrays are the full run's, bit for bit
        np.testing.assert_array_equal(sub[v].values, full[v].sel(design=held).values)
    cost = pd.read_csv(smoke_bundle / bundle.COST)  # what each job of the run cost
    bench = smoke_run / "results/benchmarks"
    ran = {str(p.relative_to(bench))[:-4] for p in bench.rglob("*.tsv")}  # (other tests add jobs)
    assert {f"theory/shard_{i}" for i in range(3)} | {"theory/metrics"} <= set(cost.job) <= ran
    assert (cost.cpu_s > 0).all() and "| theory/shard |" in (smoke_bundle / "README.md").read_text()
    for name in ("summary.md", "reproduction.csv", "figures/fig6.png", "figures/fig6.caption.md"):
        assert (smoke_bundle / name).read_bytes() == (smoke_run / "results" / name).read_bytes()


def test_check_notices_damage(smoke_bundle: Path, tmp_path: Path) -> None:
    copy = tmp_path / "bundle"
    shutil.copytree(smoke_bundle, copy)
    chunk = next(p for p in sorted((copy / "theory/merged.zarr/first_time").rglob("*")) if p.is_file())
    data = bytearray(chunk.read_bytes())
    data[len(data) // 2] ^= 0x01
    chunk.write_bytes(bytes(data))
    (copy / "summary.md").unlink()
    (copy / "theory/stray.csv").write_text("x\n")
    problems = "\n".join(bundle_check.check(copy))
    assert f"{chunk}: checksum differs from bundle.json (changed or damaged)" in problems
    assert "summary.md: listed in bundle.json but missing" in problems
    assert "stray.csv: not listed in bundle.json" in problems
    # and the damaged chunk read beside the table (issue 57: every chunk read, never skipped)
    assert "theory/merged.zarr: first_time of design" in problems and "(damaged)" in problems
    assert len(bundle_check.check(copy)) == 4
    assert cli.main(["check-bundle", str(copy)]) == 1
    assert cli.main(["check-bundle", str(smoke_bundle)]) == 0
    assert cli.main(["check-bundle", str(tmp_path / "nowhere")]) == 2


def test_resimulated_designs_match_bundle(smoke_bundle: Path, tmp_path: Path) -> None:
    """Re-simulate bundled designs from their recorded science: the same rows, the same arrays;
    an edited metrics row is noticed."""
    assert resimulate.resimulate(smoke_bundle, ["canonical", "best_M_L", "best_M_CF"]) == []
    copy = tmp_path / "bundle"
    shutil.copytree(smoke_bundle, copy)
    table = pd.read_csv(copy / "theory/metrics.csv")
    d = int(metrics.rank_designs(table, "M_L").design.iloc[0])
    table.loc[table.design == d, "n_45"] += 1
    table.to_csv(copy / "theory/metrics.csv", index=False, float_format="%.10g")
    problems = resimulate.resimulate(copy, [str(d)])
    # a held design: its row disagrees with the bundle's arrays (bundle_check.meaning_problems),
    # and with its re-simulation
    assert len(problems) == 2, problems
    assert problems[0].endswith(f"design {d}: its row's counts differ from the merged store's arrays"), problems
    assert problems[1].startswith(f"theory design {d}: metrics row"), problems
    c = gridmod.DesignGrid(3).index_of(*gridmod.canonical_design())
    table.loc[table.design == c, "M_L"] += 1e-6  # counts intact, the metric edited
    table.to_csv(copy / "theory/metrics.csv", index=False, float_format="%.10g")
    again = resimulate.resimulate(copy, ["canonical"])
    assert any(p.startswith(f"theory design {c}: metrics row M_L, M_CF") for p in again), again
    held = set(json.loads((copy / bundle.MANIFEST).read_text())["subsets"]["theory"]["designs"])
    absent = min(set(table.design) - held)
    again = resimulate.resimulate(copy, [str(absent)])  # re-simulated though not held (issue 24)
    assert not [p for p in again if f"design {absent}:" in p or f"design {absent} " in p], again
    with pytest.raises(bundle.BundleError, match=r"allowed: \[MODEL:\]WHICH"):
        resimulate.resimulate(copy, ["best"])
    assert cli.main(["check-bundle", str(smoke_bundle), "--resimulate", "canonical"]) == 0
    assert cli.main(["check-bundle", str(copy), "--resimulate", str(d)]) == 1


def test_render_from_bundle_alone(smoke_bundle: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A fresh clone holding only the bundle re-renders every figure and the table, simulating
    nothing, to the same bytes (captions name data paths relative to the results folder)."""
    wd = copy_workflow(tmp_path / "clone")
    out = wd / "results" / "paper"
    shutil.copytree(smoke_bundle, out)
    # the command `morphlearn rerender-bundle` runs: the README's render-only command with the
    # configs the bundle was made with
    manifest = json.loads((out / bundle.MANIFEST).read_text())
    cmd = bundle_rerender.render_command("results/paper", manifest, cores=2)
    assert cmd[cmd.index("--configfile") + 1 : cmd.index("--config")] == ["config/smoke.yaml"], cmd
    proc = snakemake(wd, *cmd[1:], timeout=600)
    jobs = job_stats(proc.stdout + proc.stderr)
    assert set(jobs) == {*(f"figure_fig{i}" for i in range(1, 8)), "reproduction", "all"}, jobs
    for i in range(1, 8):
        assert (out / f"figures/fig{i}.html").stat().st_size > 1000
    assert bundle_check.check(out) == []  # every re-rendered figure, caption and table byte-identical
    assert not (out / "theory/shards").exists()  # nothing simulated, no shard made
    # and the report of that run (the reviewer's one-page view of the stored results)
    snakemake(
        wd,
        "--configfile",
        "config/smoke.yaml",
        "--config",
        "render_only=True",
        "results_dir=results/paper",
        "--report",
        "results/report.html",
    )
    html = (wd / "results/report.html").read_text()
    assert "Overlapped binary success matrices" in html and "Reproduction" in html
    # a figure's code changes: `morphlearn rerender-bundle` re-renders the bundle (that command,
    # run above; here a render that draws fig1 anew) and re-seals exactly the rendered files that
    # changed, the data untouched
    data = {r: d for r, d in manifest["files"].items() if "figures/" not in r}
    redrawn = ["figures/fig1.caption.md", "figures/fig1.png"]

    def render(cmd_: list[str], root: Path, target: Path) -> None:
        # the same command, rendering into a copy beside the bundle (atomic: swapped in after)
        assert root == wd and target.parent == Path("results") and target.name.startswith(".rerender-paper-")
        assert cmd_ == [*cmd[:-2], f"results_dir={target}", "--forceall"], cmd_
        for rel in redrawn:
            (root / target / rel).write_bytes((root / target / rel).read_bytes() + b"\n")

    monkeypatch.setattr(bundle_rerender, "_render", render)
    assert bundle_rerender.rerender("results/paper", wd) == redrawn
    manifest = json.loads((out / bundle.MANIFEST).read_text())
    assert manifest["rendered_by"]["files"] == redrawn and bundle_check.check(out) == []
    assert manifest["rendered_by"]["command"].endswith("results_dir=results/paper --forceall")
    assert {r: d for r, d in manifest["files"].items() if "figures/" not in r} == data
    assert not list((wd / "results").glob(".rerender-*"))  # the copy is gone
    # a render that changes what it does not make (the data) re-seals nothing, changes nothing
    before = {p: p.read_bytes() for p in sorted(out.rglob("*")) if p.is_file()}
    monkeypatch.setattr(
        bundle_rerender, "_render", lambda _, root, target: (root / target / "summary.md").write_text("edited\n")
    )
    with pytest.raises(bundle.BundleError, match=r"summary\.md, which it does not make"):
        bundle_rerender.rerender("results/paper", wd)
    assert {p: p.read_bytes() for p in sorted(out.rglob("*")) if p.is_file()} == before
    # a bundle that is not whole is not re-rendered (nothing re-sealed over an edit): the render's
    # own start check refuses it, said of the bundle (not of its working copy)
    monkeypatch.undo()
    (out / "summary.md").write_text("edited\n")
    before = {p: p.read_bytes() for p in sorted(out.rglob("*")) if p.is_file()}
    refused = r"^results/paper: not re-rendered: .*results/paper does not match its bundle\.json.*summary\.md: checksum"
    with pytest.raises(bundle.BundleError, match=refused):
        bundle_rerender.rerender("results/paper", wd)
    assert {p: p.read_bytes() for p in sorted(out.rglob("*")) if p.is_file()} == before
    assert not list((wd / "results").glob(".rerender-*"))


def test_prune_empty_backups_removes_only_empty_folders(tmp_path: Path) -> None:
    """What a render-only run leaves under .snakemake/backups (the empty folders of its figures'
    backups) goes before the next run, so a bundle run into that folder can back it up; a
    backup with content stays."""
    root = tmp_path / "backups"
    (root / "results/paper/figures").mkdir(parents=True)
    (root / "results/other").mkdir(parents=True)
    (root / "results/other/fig1.png").write_bytes(b"kept")
    removed = rules.prune_empty_backups(root)
    assert set(removed) == {root / "results/paper/figures", root / "results/paper"}
    assert (root / "results/other/fig1.png").read_bytes() == b"kept"
    assert rules.prune_empty_backups(tmp_path / "absent") == []
