"""A real, small end-to-end run of the workflow through snakemake."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import yaml
from conftest import TEST_COMMIT, copy_workflow, snakemake

from morphlearn import grid, store
from morphlearn.provenance import sha256_file


def test_smoke_outputs(smoke_run: Path) -> None:
    r = smoke_run / "results"
    ds = store.open_merged(r / "theory/merged.zarr")
    assert dict(ds.sizes) == {"design": 81, "env": 4, "w1": 5, "w2": 5}
    assert ds["env"].values.tolist() == [45, 135, 225, 315]
    t = pd.read_csv(r / "theory/metrics.csv")
    assert len(t) == 81 and t.design.tolist() == list(range(81))
    assert ((t.M_L >= 0) & (t.M_L <= 1) & (t.M_CF >= t.M_L)).all()
    assert (r / "summary.md").read_text().startswith("# Summary")
    for rule in ("merge", "metrics"):
        assert (r / f"logs/theory/{rule}.log").exists()
        assert (r / f"benchmarks/theory/{rule}.tsv").exists()
    prov = (r / "theory/metrics.provenance.json").read_text()
    assert f'"git_commit": "{TEST_COMMIT}"' in prov and "merged.zarr" in prov


def test_mirror_derived_equals_directly_evaluated(smoke_run: Path, tmp_path: Path) -> None:
    wd = copy_workflow(tmp_path / "nomirror")
    cfg = yaml.safe_load((wd / "config/smoke.yaml").read_text())
    cfg["sweep"]["mirror_symmetry"] = False
    (wd / "nomirror.yaml").write_text(yaml.safe_dump(cfg))
    snakemake(wd, "results/theory/merged.zarr", "--cores", "2", "--configfile", "nomirror.yaml")
    a = store.open_merged(smoke_run / "results/theory/merged.zarr")
    b = store.open_merged(wd / "results/theory/merged.zarr")
    g = grid.DesignGrid(3)
    derived = np.setdiff1d(np.arange(g.size), g.representatives())
    assert len(derived) == 36
    for v in store.VARS:
        np.testing.assert_array_equal(a[v].values, b[v].values)


def test_rerun_is_byte_identical(smoke_run: Path, tmp_path: Path) -> None:
    """The simulations, merges, metrics and summary of a second run in another folder, to the byte.
    (Its figures are not re-drawn here: that the rendering is deterministic is checked by
    test_bundle::test_render_from_bundle_alone, which re-renders every figure to the same bytes.)"""
    wd = copy_workflow(tmp_path / "again")
    snakemake(wd, "results/summary.json", "--cores", "2", "--configfile", "config/smoke.yaml")
    for rel in (
        "theory/merged.zarr",
        "theory/metrics.csv",
        "empirical/metrics.csv",
        "summary.json",
        "theory/shards/shard_0.nc",
        "empirical/shards/shard_0.nc",
    ):
        assert sha256_file(wd / "results" / rel) == sha256_file(smoke_run / "results" / rel), rel
