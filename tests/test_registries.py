"""The registries: a new metric or a new model is a plug-in, picked up everywhere without edits.

The metric test adds one entry to ``metrics.METRICS`` (the one line a real new metric takes) and
follows it through the metrics table, the ranking, the summary, the comparison and the CLI. The
model test registers a second theory-like model under another name and runs a shard, the merge,
the metrics and the summary through the same rule bodies the workflow uses.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from morphlearn import config, configure, metrics, models, settings, store
from morphlearn.analysis import compare, summary
from morphlearn.apps import cli
from morphlearn.bundles import check as bundle_check
from morphlearn.bundles import make as bundle
from morphlearn.theory.plugin import Theory
from morphlearn.workflow import rules

ROOT = Path(__file__).resolve().parents[1]
#: A metric no module knows: the share of controllers that succeed at least once.
M_ANY = metrics.Metric("M_any", lambda c: c.at_least_one / c.cells, fmt=".3f", text="share succeeding once")


@pytest.fixture
def smoke_settings(tmp_path: Path) -> settings.Settings:
    raw = config.deep_merge(
        config.read(ROOT / "config.yaml", [ROOT / "config/smoke.yaml"]),
        {"results_dir": str(tmp_path / "results"), "sweep": {"shards": 1}},
    )
    return configure.parse(raw)


def _theory_run(s: settings.Settings, model: str, tmp_path: Path) -> Path:
    shard, merged, csv = tmp_path / f"{model}.nc", tmp_path / f"{model}.zarr", tmp_path / f"{model}.csv"
    rules.run_shard(s, model, 0, shard)
    rules.run_merge(s, model, [str(shard)], merged)
    rules.run_metrics(model, models.get(model).thresholds(s), merged, csv)
    return csv


def test_a_new_metric_is_one_registry_entry(
    smoke_settings: settings.Settings,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    monkeypatch.setitem(metrics.METRICS, "M_any", M_ANY)
    table = pd.read_csv(_theory_run(smoke_settings, "theory", tmp_path))
    # the table: a column after the paper's metrics, computed from the design's counts
    assert list(table.columns[-4:]) == ["M_L", "M_CF", "M_any", "flagged"]
    m = 5 * 5
    np.testing.assert_allclose(table.M_any, table.at_least_one / m)
    assert (table.M_any >= table.M_L).all()  # at least once >= in all four
    # ranking: best first by it, ties by the other metrics, then by design
    ranked = metrics.rank_designs(table, "M_any")
    assert ranked.M_any.is_monotonic_decreasing
    # the summary: its top designs, the canonical design's rank, a column in every table
    s = summary.summarise(table, top=3)
    assert len(s["top_M_any"]) == 3 and "rank_M_any" in s["canonical"]
    md = summary.summary_markdown({"positions_per_axis": 3, "weights": 5, "theory": {**s, "controllers": m}})
    assert "Top designs by M_any:" in md and "| M_L | M_CF | M_any | flagged |" in md
    # the comparison of two tables: a rank agreement for it too
    both = compare.joined(table, table)
    assert compare.agreement(both, n_resamples=50)["M_any"].rho == pytest.approx(1.0)
    # a bundle keeps the outcome arrays of its best designs too; check-bundle recomputes it from the counts
    best = int(metrics.rank_designs(table, "M_any").design.iloc[0])
    monkeypatch.delitem(metrics.METRICS, "M_any")
    without = set(bundle.drawn_designs(table, 3, top=1))
    monkeypatch.setitem(metrics.METRICS, "M_any", M_ANY)
    assert best not in without and best in bundle.drawn_designs(table, 3, top=1)  # kept for it alone
    assert bundle_check.row_problems(table, m) == []
    forged = table.assign(M_any=table.M_any.where(table.design != best, 0.0))
    problems = bundle_check.row_problems(forged, m)
    assert problems == [f"design {best}: M_any != its value from the counts (share succeeding once)"]
    # the CLI prints and returns it
    assert cli.main(["design", "--l1", "0.5", "0.5", "--l2", "0.5", "-0.5", "--weights", "3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert "M_any" in out and 0 <= out["M_any"] <= 1


class _Toy(Theory):
    """A second model: the theory under another name. A real model adds its section to the
    schema; this test double takes the theory's section (the schema has no 'toy' key)."""

    name = "toy"

    def __init__(self, section: dict) -> None:
        self.section = section

    def parse(self, section: dict, shared: settings.Shared) -> object:
        return super().parse(self.section, shared)


def test_a_new_model_is_one_registry_entry(
    smoke_settings: settings.Settings, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    toy = _Toy(dict(smoke_settings.source["theory"]))
    monkeypatch.setitem(models.MODELS, "toy", toy)
    s = configure.parse(dict(smoke_settings.source))  # parsed again: the registry has the toy now
    assert models.enabled(s) == ["theory", "empirical", "toy"] and "toy" in models.simulated(s)
    csv = _theory_run(s, "toy", tmp_path)
    ds = store.open_merged(tmp_path / "toy.zarr")
    assert ds.attrs["model"] == "toy" and json.loads(ds.attrs["science_json"])["model"] == "toy"
    toy_table = pd.read_csv(csv)
    theory_table = pd.read_csv(_theory_run(s, "theory", tmp_path))
    # the same science under another name: the same numbers
    pd.testing.assert_frame_equal(toy_table.drop(columns="model"), theory_table.drop(columns="model"))
    out_json, out_md = tmp_path / "summary.json", tmp_path / "summary.md"
    summary.run_summary(s, {"theory": str(tmp_path / "theory.csv"), "toy": str(csv)}, out_json, out_md)
    assert "## toy (" in out_md.read_text() and json.loads(out_json.read_text())["toy"]["designs"] == 81
    allowed = re.escape(str([*(n for n in models.MODELS if n != "toy"), "toy"]))
    with pytest.raises(ValueError, match=rf"unknown model 'nope'; allowed: {allowed}"):
        models.get("nope")
