"""A bundle names the commit that made it, so it is made from committed code only (issue 41, item
2): the bundle rule refuses a dirty worktree, and shards whose designs were computed from one, also
when a later shard at a clean commit reuses those designs from the design cache."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT

from morphlearn import config, configure, models, store
from morphlearn.bundles import make as bundle
from morphlearn.workflow import rules

SMOKE = config.load(ROOT / "config.yaml", [ROOT / "config/smoke.yaml"])
#: A commit this history holds (the test runs in the repository: CI's clone holds HEAD).
HEAD = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True, check=True).stdout.strip()
#: A well-formed hash no repository holds (the shape of a mistyped one).
NOWHERE = "0" * 6 + "badc0ffee" * 3 + "1234567"


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
    monkeypatch.setenv("MORPHLEARN_GIT_COMMIT", HEAD)
    rules.run_shard(s, "theory", 0, shard)  # a clean commit, every design reused
    prov = json.loads(store.read_shard(shard).attrs["provenance_json"])
    assert prov["git_commit"] == HEAD and prov["design_commits"] == {"aaa-dirty": n}
    for i in range(1, 9):  # the other shards, computed at the clean commit
        rules.run_shard(s, "theory", i, results / "theory" / "shards" / f"shard_{i}.nc")
    shards = sorted((results / "theory" / "shards").glob("*.nc"))
    rules.run_merge(s, "theory", [str(p) for p in shards], results / "theory" / "merged.zarr")
    by = json.loads(store.open_merged(results / "theory" / "merged.zarr").attrs["provenance_json"])["shards"]
    assert by["git_commits"] == {HEAD: 9} and by["design_commits"]["aaa-dirty"] == n  # the shards alone hide it
    with pytest.raises(bundle.BundleError, match=rf"{n} design\(s\) or shard\(s\) were simulated at aaa-dirty"):
        bundle.check_committed(_made_by(HEAD, monkeypatch, results), results, ["theory"])
    bundle.check_committed(_made_by(HEAD, monkeypatch, results), results, [])  # read from a bundle: its record


def test_a_commit_outside_this_history_is_refused(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """MORPHLEARN_GIT_COMMIT can name any string: a record naming a commit this repository does not
    hold (a mistyped hash from a node without .git) is refused, for the bundle and for its designs."""
    from morphlearn import provenance

    monkeypatch.chdir(ROOT)  # the bundle rule asks the history of its working directory
    assert len(NOWHERE) == 40 and provenance.in_history(HEAD) is True and provenance.in_history(NOWHERE) is False
    # a ref or an option git would read as one is no commit of a record
    assert [provenance.in_history(c) for c in ("HEAD", "--help", HEAD[:6], HEAD.upper())] == [False] * 4
    with pytest.raises(bundle.BundleError, match=rf"commit '{NOWHERE}', named by the bundle, is not this repository's"):
        bundle.check_committed(_made_by(NOWHERE, monkeypatch, tmp_path), tmp_path, [])
    results = tmp_path / "results"
    s = configure.parse(config.deep_merge(SMOKE, {"results_dir": str(results), "sweep": {"shards": 9}}))
    monkeypatch.setenv("MORPHLEARN_GIT_COMMIT", NOWHERE)
    shards = [results / "theory" / "shards" / f"shard_{i}.nc" for i in range(9)]
    shards[0].parent.mkdir(parents=True)
    rules.run_shard(s, "theory", 0, shards[0])  # one shard's designs at the commit nobody holds
    monkeypatch.setenv("MORPHLEARN_GIT_COMMIT", HEAD)
    for i in range(1, 9):
        rules.run_shard(s, "theory", i, shards[i])
    with pytest.warns(UserWarning, match="shards come from 2 git commits"):
        rules.run_merge(s, "theory", [str(p) for p in shards], results / "theory" / "merged.zarr")
    with pytest.raises(bundle.BundleError, match=rf"commit '{NOWHERE}', named by \d+ design\(s\) or shard\(s\) of "):
        bundle.check_committed(_made_by(HEAD, monkeypatch, results), results, ["theory"])
    # a copy of the project without .git has no history to ask: nothing to refuse there
    copy = shutil.copytree(
        ROOT / "src" / "morphlearn", tmp_path / "copy" / "morphlearn", ignore=shutil.ignore_patterns("*.so")
    )
    assert provenance.in_history(NOWHERE, cwd=copy) is None
    monkeypatch.chdir(copy)  # a workflow copy, as the tests run it: its bundle rule is not refused
    bundle.check_committed(_made_by("test", monkeypatch, results), results, [])


def _named_commits(o: object, out: set[str]) -> set[str]:
    """Every commit a bundle.json names (its own, its shards', its designs')."""
    if isinstance(o, dict):
        for k, v in o.items():
            if k in ("git_commits", "design_commits") and isinstance(v, dict):
                out.update(v)
            elif k == "git_commit" and isinstance(v, str):
                out.add(v)
            else:
                _named_commits(v, out)
    elif isinstance(o, list):
        for v in o:
            _named_commits(v, out)
    return out


def test_every_commit_a_committed_bundle_names_is_in_this_history() -> None:
    """The reader's side of the check: each committed bundle names only commits of this history
    (a '-dirty' one's base included, should one be named: the test below refuses that too)."""
    from morphlearn import provenance

    shallow = subprocess.run(["git", "rev-parse", "--is-shallow-repository"], cwd=ROOT, capture_output=True, text=True)
    if shallow.stdout.strip() == "true":
        pytest.skip("a shallow clone lacks the history the bundles name")
    manifests = sorted((ROOT / "results").glob("*/bundle.json"))
    assert len(manifests) >= 10
    for m in manifests:
        named = _named_commits(json.loads(m.read_text()), set())
        assert named, m
        for c in named:
            assert provenance.in_history(c.removesuffix("-dirty")) is True, f"{m.parent.name} names {c}"


def test_no_committed_bundle_names_a_dirty_or_unknown_commit() -> None:
    """Issue 41: every committed bundle, its shards and its designs were made by a clean commit (the
    bundles once naming '-dirty' ones were re-made at clean commits); a bundle that names one again
    fails here, not only in the bundle rule of the machine that made it."""
    manifests = sorted((ROOT / "results").glob("*/bundle.json"))
    assert len(manifests) >= 10
    for m in manifests:
        bad = sorted(
            c for c in _named_commits(json.loads(m.read_text()), set()) if c.endswith("-dirty") or c == "unknown"
        )
        assert not bad, f"{m.parent.name} names {bad}"


def test_the_refine_folders_from_uncommitted_code_equal_their_clean_remake() -> None:
    """The three exhaustive MuJoCo folders of results/refine whose manifests name a '-dirty' commit
    (made by the tool before the workflow could) are kept as made, and vouched for by their re-make
    at a clean commit, results/refine-exhaustive-mujoco: every cell of the three arrays the same."""
    from morphlearn.figures import data as fd
    from morphlearn.refine import folder as refine_folder

    dirty = sorted(
        f.parent.name for f in (ROOT / "results/refine").glob("*/manifest.json") if "-dirty" in f.read_text()
    )
    assert dirty == ["mujoco_canonical_121", "mujoco_d120_121", "mujoco_d196_121"]  # a new one needs its re-make
    remake = fd.load_results(ROOT / "results/refine-exhaustive-mujoco", "mujoco")  # custody-checked
    assert remake is not None
    for name in dirty:
        a = refine_folder.assemble(ROOT / "results/refine" / name)
        assert a.complete, name
        job = refine_folder.job_from_manifest(a.manifest)
        ref = store.read_design(remake.ds, remake.position(job.l1, job.l2, why=name))
        for k in store.VARS:
            got = np.asarray(getattr(a.result, k))
            assert got.dtype == ref[k].dtype and got.tobytes() == ref[k].tobytes(), (name, k)


def test_results_are_outputs_not_code_for_the_dirty_check(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A rule re-making a committed result overwrites tracked files under results/: its record must
    still name the clean commit (results/agreement once named its own commit '-dirty' so), while an
    edit anywhere else, a config included, is dirty."""
    from morphlearn import provenance

    monkeypatch.delenv("MORPHLEARN_GIT_COMMIT", raising=False)
    git = ["git", "-c", "user.name=t", "-c", "user.email=t@t", "-c", "commit.gpgsign=false"]
    for f in ("src/code.py", "config/run.yaml", "results/agreement/table.csv"):
        (tmp_path / f).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / f).write_text("1\n")
    subprocess.run(["git", "init", "-q"], cwd=tmp_path, check=True)
    subprocess.run([*git, "add", "."], cwd=tmp_path, check=True)
    subprocess.run([*git, "commit", "-q", "-m", "x"], cwd=tmp_path, check=True)
    head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=tmp_path, capture_output=True, text=True).stdout.strip()
    sub = tmp_path / "src"  # asked from a subfolder, as the package asks from its own
    (tmp_path / "results/agreement/table.csv").write_text("2\n")
    assert provenance.git_commit(sub) == head
    for f in ("config/run.yaml", "src/code.py"):
        (tmp_path / f).write_text("2\n")
        assert provenance.git_commit(sub) == head + "-dirty", f
        subprocess.run(["git", "checkout", "-q", "--", f], cwd=tmp_path, check=True)
    assert provenance.git_commit(sub) == head
