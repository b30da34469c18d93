"""The committed paper-resolution bundle (results/paper/): intact, reproducible, re-renderable."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from conftest import ROOT, copy_workflow, job_stats, snakemake

from morphlearn import bundle, metrics, store
from morphlearn import grid as gridmod
from morphlearn.theory import TheoryParams, evaluate

BUNDLE = ROOT / "results" / "paper"


def _science() -> dict:
    return json.loads(store.open_merged(BUNDLE / "theory/merged.zarr").attrs["science_json"])


def test_bundle_is_intact() -> None:
    assert bundle.check(BUNDLE) == []
    manifest = json.loads((BUNDLE / bundle.MANIFEST).read_text())
    table = pd.read_csv(BUNDLE / "theory/metrics.csv")
    assert len(table) == 6561 and _science()["grid"] == {"positions_per_axis": 9, "weights": 121}
    # The subset holds what the figures draw, no more.
    held = manifest["subsets"]["theory"]["designs"]
    assert held == bundle.drawn_designs(table, 9, 10).tolist()
    ds = store.open_merged(BUNDLE / "theory/merged.zarr")
    assert ds["design"].values.tolist() == held


def test_check_notices_damage(tmp_path: Path) -> None:
    copy = tmp_path / "paper"
    shutil.copytree(BUNDLE, copy)
    chunk = next(p for p in sorted((copy / "theory/merged.zarr/first_time").rglob("*")) if p.is_file())
    data = bytearray(chunk.read_bytes())
    data[len(data) // 2] ^= 0x01
    chunk.write_bytes(bytes(data))
    (copy / "summary.md").unlink()
    (copy / "theory/stray.csv").write_text("x\n")
    problems = "\n".join(bundle.check(copy))
    assert str(chunk) in problems and "changed or damaged" in problems
    assert "summary.md: listed in bundle.json but missing" in problems
    assert "stray.csv: not listed" in problems


@pytest.mark.parametrize("which", ["canonical", "best_M_L"])
def test_resimulated_design_matches_committed_row(which: str) -> None:
    """Re-simulate a committed design at full resolution: the same row, the same arrays."""
    table = pd.read_csv(BUNDLE / "theory/metrics.csv")
    g = gridmod.DesignGrid(9)
    d = g.index_of(*gridmod.canonical_design()) if which == "canonical" else int(
        metrics.rank_designs(table, "M_L").design.iloc[0]
    )
    sci = _science()
    params = TheoryParams.from_config(sci["theory"])
    res = evaluate(g.coords(np.array([d])), gridmod.weights(sci["grid"]["weights"]), params)[0]
    th = metrics.Thresholds(params.horizon, params.success_radius, params.horizon, params.success_radius)
    dm = metrics.design_metrics(metrics.success(res.first_time, res.min_dist, th), res.status)
    row = table[table.design == d].iloc[0]
    assert [int(row[f"n_{a}"]) for a in gridmod.ENV_ANGLES_DEG] == dm.per_env
    assert (int(row.generalists), int(row.at_least_one), int(row.flagged)) == (
        dm.generalists, dm.at_least_one, dm.flagged)  # fmt: skip
    assert (row.M_L, row.M_CF) == pytest.approx((dm.M_L, dm.M_CF), rel=1e-9)
    stored = store.open_merged(BUNDLE / "theory/merged.zarr").sel(design=d)
    for v in store.VARS:
        np.testing.assert_array_equal(stored[v].values, getattr(res, v), err_msg=v)


def _without_commit(text: str) -> str:
    """A caption minus what names the commit and checksums that made it (a re-render differs there)."""
    return "\n".join(line for line in text.splitlines() if "commit" not in line and "sha256" not in line)


def test_render_from_bundle(tmp_path: Path) -> None:
    """The README's reviewer command re-renders every figure and the table, simulating nothing."""
    wd = copy_workflow(tmp_path / "clone")
    out = wd / "results" / "paper"
    shutil.copytree(BUNDLE, out)
    proc = snakemake(wd, "--cores", "2", "--configfile", "config/paper.yaml", "--config",
                     "render_only=True", "results_dir=results/paper", "--forceall", timeout=600)  # fmt: skip
    jobs = job_stats(proc.stdout + proc.stderr)
    assert set(jobs) == {*(f"figure_fig{i}" for i in range(1, 8)), "reproduction", "all"}, jobs
    committed = pd.read_csv(BUNDLE / "reproduction.csv")
    pd.testing.assert_frame_equal(pd.read_csv(out / "reproduction.csv"), committed)
    for i in range(1, 8):
        for ext in ("png", "pdf", "html"):
            assert (out / f"figures/fig{i}.{ext}").stat().st_size > 1000, (i, ext)
        cap = f"figures/fig{i}.caption.md"
        assert _without_commit((out / cap).read_text()) == _without_commit((BUNDLE / cap).read_text())
