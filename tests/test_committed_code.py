"""A bundle names the commit that made it, so it is made from committed code only (issue 41, item
2): the bundle rule refuses a dirty worktree, and shards whose designs were computed from one, also
when a later shard at a clean commit reuses those designs from the design cache."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from conftest import ROOT

from morphlearn import bundle, config, configure, models, rules, store

SMOKE = config.load(ROOT / "config.yaml", [ROOT / "config/smoke.yaml"])


def _made_by(commit: str, monkeypatch: pytest.MonkeyPatch, results: Path) -> dict:
    monkeypatch.setenv("MORPHLEARN_GIT_COMMIT", commit)
    return bundle.made_by(["config.yaml"], str(results))


def test_a_dirty_worktree_is_refused(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    with pytest.raises(bundle.BundleError, match=r"at abc-dirty: a bundle is made from committed code only"):
        bundle.check_committed(_made_by("abc-dirty", monkeypatch, tmp_path), tmp_path, [])
    with pytest.raises(bundle.BundleError, match=r"at unknown"):
        bundle.check_committed(_made_by("unknown", monkeypatch, tmp_path), tmp_path, [])


def test_designs_reused_from_dirty_code_are_refused(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    results = tmp_path / "results"
    s = configure.parse(config.deep_merge(SMOKE, {"results_dir": str(results), "sweep": {"shards": 9}}))
    n = len(models.get("theory").shard_designs(s)[0])
    shard = results / "theory" / "shards" / "shard_0.nc"
    shard.parent.mkdir(parents=True)
    monkeypatch.setenv("MORPHLEARN_GIT_COMMIT", "aaa-dirty")
    rules.run_shard(s, "theory", 0, shard)  # computes the designs (cached at aaa-dirty)
    shard.unlink()
    monkeypatch.setenv("MORPHLEARN_GIT_COMMIT", "bbb")
    rules.run_shard(s, "theory", 0, shard)  # a clean commit, every design reused
    prov = json.loads(store.read_shard(shard).attrs["provenance_json"])
    assert prov["git_commit"] == "bbb" and prov["design_commits"] == {"aaa-dirty": n}
    for i in range(1, 9):  # the other shards, computed at the clean commit
        rules.run_shard(s, "theory", i, results / "theory" / "shards" / f"shard_{i}.nc")
    shards = sorted((results / "theory" / "shards").glob("*.nc"))
    rules.run_merge(s, "theory", [str(p) for p in shards], results / "theory" / "merged.zarr")
    by = json.loads(store.open_merged(results / "theory" / "merged.zarr").attrs["provenance_json"])["shards"]
    assert by["git_commits"] == {"bbb": 9} and by["design_commits"]["aaa-dirty"] == n  # the shards alone hide it
    with pytest.raises(bundle.BundleError, match=rf"{n} design\(s\) or shard\(s\) were simulated at aaa-dirty"):
        bundle.check_committed(_made_by("bbb", monkeypatch, results), results, ["theory"])
    bundle.check_committed(_made_by("bbb", monkeypatch, results), results, [])  # read from a bundle: its record
