"""The committed scenario-set bundle (results/scenario-set; morphlearn.bundles.scenario): its figure
renders from the bundle alone, to the same bytes, and a damaged bundle is told apart."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pandas as pd
import pytest
from conftest import TEST_COMMIT

from morphlearn.bundles import check as bundle_check
from morphlearn.bundles import make as bundle
from morphlearn.bundles import scenario as scenario_bundle

ROOT = Path(__file__).resolve().parents[1]
BUNDLE = ROOT / "results" / "scenario-set"


def test_committed_bundle_checks_out() -> None:
    assert bundle_check.check(BUNDLE) == []
    manifest = json.loads((BUNDLE / "bundle.json").read_text())
    comp = pd.read_csv(BUNDLE / "comparison.csv")
    assert manifest["scenarios"] == list(comp.scenario) and "base" in manifest["scenarios"]
    for name in manifest["scenarios"]:
        table = pd.read_csv(BUNDLE / name / "theory" / "metrics.csv")
        assert len(table) == 625  # the default run's grid: 5 positions per axis
    assert manifest["made_by"]["command"] == scenario_bundle.COMMAND


def test_figure_renders_from_the_bundle_alone_to_the_same_bytes(tmp_path: Path) -> None:
    copy = tmp_path / "results" / "scenario-set"  # a bundle lives in <project>/results/<name>
    shutil.copytree(BUNDLE, copy, ignore=shutil.ignore_patterns("logs"))
    for name in ("comparison.png", "comparison.pdf", "comparison.caption.md"):
        (copy / name).unlink()
    seconds, problems = scenario_bundle.render(copy, ROOT)
    assert problems == [], problems
    assert seconds > 0 and (copy / "logs" / "comparison.ipynb").is_file()


def test_a_changed_table_is_found(tmp_path: Path) -> None:
    copy = tmp_path / "scenario-set"
    shutil.copytree(BUNDLE, copy)
    p = copy / "comparison.csv"
    p.write_text(p.read_text().replace("base", "BASE", 1))
    assert any("comparison.csv: checksum differs" in x for x in bundle_check.check(copy))


def test_build_round_trip_and_refusal(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A bundle built from a scenario folder (here: the committed bundle, which has its layout)
    holds the same data files and checks out. The figure's rendering is the test above's: here it
    copies the committed figure (a papermill run less)."""

    def copy_figure(out: Path, _root: object) -> float:
        for name in scenario_bundle.FIGURE:
            shutil.copy2(BUNDLE / name, out / name)
        return 0.0

    monkeypatch.setattr(scenario_bundle, "_render", copy_figure)
    made_by = {"results_dir": "x", "command": scenario_bundle.COMMAND, "git_commit": TEST_COMMIT, "version": "0"}
    out = tmp_path / "results" / "scenario-set"
    m = scenario_bundle.build(BUNDLE, out, made_by)
    assert bundle_check.check(out) == []
    old = json.loads((BUNDLE / "bundle.json").read_text())["files"]
    assert set(m["files"]) == set(old) - {bundle.COST}  # the bundle holds no benchmark files to sum
    # the same bytes but the README, which names who made it
    assert all(m["files"][k] == old[k] for k in m["files"] if k != "README.md"), m["files"]
    (tmp_path / "empty").mkdir()
    with pytest.raises(bundle.BundleError, match=r"no comparison\.csv"):
        scenario_bundle.build(tmp_path / "empty", tmp_path / "never", made_by)
    assert not (tmp_path / "never").exists()
