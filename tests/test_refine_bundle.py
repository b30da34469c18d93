"""The refine results are the workflow's bundles (issue 58: one results pipeline): the committed
refine bundles verify and were made by the workflow's rules, damage in them is caught, a bundle
claiming another maker is refused, and the committed refine folders (read-only history) hold the
very episodes of those bundles, checksums verified."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from morphlearn import store
from morphlearn.bundles import check as bundle_check
from morphlearn.bundles.make import MANIFEST, BundleError
from morphlearn.figures import data as fd
from morphlearn.refine import folder as rf
from morphlearn.results import STATUS_INFERRED

ROOT = Path(__file__).resolve().parents[1]
#: The committed refine bundles, by the model whose results they hold.
BUNDLES = {"refine-pybullet": "empirical", "refine-mujoco": "mujoco", "refine-exhaustive-mujoco": "mujoco"}
FOLDERS = sorted(p.parent for p in (ROOT / "results" / "refine").glob("*/manifest.json"))


@pytest.mark.parametrize("name", sorted(BUNDLES))
def test_the_refine_bundles_verify_and_were_made_by_the_workflow(name: str) -> None:
    b = ROOT / "results" / name
    assert bundle_check.check(b) == []
    by = json.loads((b / MANIFEST).read_text())["made_by"]
    assert "tool" not in by and by["command"].startswith("snakemake ") and by["configs"], by


def test_damage_in_a_refine_bundle_is_caught(tmp_path: Path) -> None:
    out = tmp_path / "bundle"
    shutil.copytree(ROOT / "results" / "refine-exhaustive-mujoco", out)
    chunk = out / "mujoco" / "merged.zarr" / "first_time" / "c" / "0" / "0" / "0" / "0"
    data = bytearray(chunk.read_bytes())
    data[len(data) // 2] ^= 0x01
    chunk.write_bytes(bytes(data))
    problems = bundle_check.check(out)
    assert "first_time/c/0/0/0/0: checksum differs" in problems[0], problems
    # and the damaged chunk read beside the table (issue 57: every chunk read, never skipped)
    assert len(problems) == 2 and "first_time of design 720" in problems[1], problems
    with pytest.raises(BundleError, match="problem"):
        run = {k: tmp_path / "run" / k for k in ("metrics", "provenance", "merged")}
        bundle_check.extract_model(out, "mujoco", run)
    assert not (tmp_path / "run").exists()


def test_a_bundle_claiming_another_maker_is_refused(tmp_path: Path) -> None:
    """The old refine bundles' maker (``made_by.tool``, morphlearn.refine_bundle, deleted) is no
    longer a maker: every bundle is the workflow's."""
    out = tmp_path / "bundle"
    shutil.copytree(ROOT / "results" / "refine-mujoco", out)
    man = json.loads((out / MANIFEST).read_text())
    man["made_by"]["tool"] = "tools/refine_design.py bundle"
    (out / MANIFEST).write_text(json.dumps(man, indent=1, sort_keys=True) + "\n")
    problems = bundle_check.check(out)
    assert any("made_by.tool = " in p and "allowed: none (a bundle the workflow made)" in p for p in problems), problems


@pytest.mark.parametrize("folder", FOLDERS, ids=[f.name for f in FOLDERS])
def test_each_committed_folder_holds_its_workflow_bundles_episodes(folder: Path) -> None:
    """Each folder's rows verify (their SHA-256) and equal, bit for bit, every cell of its design
    that the workflow's refine bundle simulated in a row the folder has: all cells for MuJoCo (the
    exhaustive re-make), the adaptive path's for pybullet (seeded from these folders)."""
    a = rf.assemble(folder)
    job = rf.job_from_manifest(a.manifest)
    name = "refine-exhaustive-mujoco" if job.engine == "mujoco" else "refine-pybullet"
    res = fd.load_results(ROOT / "results" / name, BUNDLES[name])  # custody-checked
    assert res is not None
    ref = store.read_design(res.ds, res.position(job.l1, job.l2, why=folder.name))
    both = (ref["status"] != STATUS_INFERRED) & a.rows_done[None, :, None]
    assert both.sum() >= (4 * 121 * 121 if job.engine == "mujoco" else 4 * 121 * 11), int(both.sum())
    for k in store.VARS:
        got, want = np.asarray(getattr(a.result, k)), np.asarray(ref[k])
        assert got.dtype == want.dtype, k
        view = np.uint8 if k == "status" else np.uint32  # the stored bits: NaN equals NaN
        assert (got.view(view)[both] == want.view(view)[both]).all(), (folder.name, k)
