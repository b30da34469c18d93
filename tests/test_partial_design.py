"""A pybullet design resumes inside itself (morphlearn.physics.partial): killed part-way, it
keeps its finished episodes and the next run simulates only the others, to the same bytes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import Killed, counting_runs

from morphlearn import config as cfgmod
from morphlearn import configure, models
from morphlearn.empirical import evaluate_design
from morphlearn.physics import design_cache
from morphlearn.physics import partial as partial_cells
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import EmpiricalParams, load_params
from morphlearn.results import STATUS_INFERRED, DesignResult
from morphlearn.workflow import rules

ROOT = Path(__file__).resolve().parents[1]
W = np.linspace(-1.0, 1.0, 5)
DESIGN = ((0.5, 0.5), (0.5, -0.5))
ADAPTIVE = SweepOptions(adaptive_weights=True)


@pytest.fixture(scope="module")
def params() -> EmpiricalParams:
    return load_params(ROOT / "config" / "empirical_morphology.yaml").replace(steps=400)


@pytest.fixture(scope="module")
def reference(params: EmpiricalParams) -> DesignResult:
    return evaluate_design(*DESIGN, W, params, options=ADAPTIVE)


def assert_same(a: DesignResult, b: DesignResult) -> None:
    for k in ("first_time", "min_dist", "status"):
        np.testing.assert_array_equal(getattr(a, k), getattr(b, k), err_msg=k)


def test_killed_design_resumes_to_the_same_bytes(
    params: EmpiricalParams, reference: DesignResult, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    simulated = int((reference.status != STATUS_INFERRED).sum())
    part = tmp_path / "design_7.partial.npz"
    counting_runs(monkeypatch, kill_at=30)
    with pytest.raises(Killed):
        evaluate_design(*DESIGN, W, params, options=ADAPTIVE, partial=part)
    ident = partial_cells.identity(*DESIGN, W, params, ADAPTIVE)
    kept = partial_cells.load(part, ident, (4, 5, 5))
    assert kept is not None and int(kept.simulated.sum()) == 29  # every finished episode, no more
    monkeypatch.undo()
    calls = counting_runs(monkeypatch)
    lines: list[tuple[int, int]] = []
    progress = lambda d, t: lines.append((d, t))  # noqa: E731
    resumed = evaluate_design(*DESIGN, W, params, progress, options=ADAPTIVE, partial=part)
    assert len(calls) == simulated - 29  # only the episodes not done before
    assert_same(resumed, reference)
    # its progress counts this run's episodes (so a time per episode is this run's) against the
    # 100 - 29 cells left, one line per episode, and ends at the whole design
    assert lines[:2] == [(1, 71), (2, 71)] and lines[-1] == (100, 100), (lines[:2], lines[-1])
    assert len(lines) == len(calls) + 1 and lines[-2] == (len(calls), 71)
    # a kill that no handler sees (SIGKILL, a lost node) loses only what followed the last
    # periodic save (here after every episode)
    monkeypatch.undo()
    part.unlink()
    monkeypatch.setattr(partial_cells, "CHECKPOINT_S", 0.0)
    on_disk: list[int] = []
    saved = lambda: on_disk.append(int(partial_cells.load(part, ident, (4, 5, 5)).simulated.sum()))  # noqa: E731
    counting_runs(monkeypatch, 45, saved)
    with pytest.raises(Killed):
        evaluate_design(*DESIGN, W, params, options=ADAPTIVE, partial=part)
    assert on_disk == [44]
    monkeypatch.undo()
    assert_same(evaluate_design(*DESIGN, W, params, options=ADAPTIVE, partial=part), reference)


def test_a_partial_file_of_something_else_is_not_resumed(
    params: EmpiricalParams, reference: DesignResult, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys
) -> None:
    part = tmp_path / "p.npz"
    counting_runs(monkeypatch, kill_at=20)
    with pytest.raises(Killed):  # a partial file of the exhaustive grid (other levers)
        evaluate_design(*DESIGN, W, params, partial=part)
    monkeypatch.undo()
    calls = counting_runs(monkeypatch)
    assert_same(evaluate_design(*DESIGN, W, params, options=ADAPTIVE, partial=part), reference)
    assert len(calls) == int((reference.status != STATUS_INFERRED).sum())  # nothing taken from it
    assert "made for another design, weights, body or levers" in capsys.readouterr().out
    # a flipped byte in a partial file of this very evaluation: not resumed either
    ident = partial_cells.identity(*DESIGN, W, params, ADAPTIVE)
    cells = partial_cells.Cells(reference.first_time, reference.min_dist, reference.status, reference.status >= 0)
    partial_cells.save(part, ident, cells)
    assert partial_cells.load(part, ident, (4, 5, 5)) is not None
    data = bytearray(part.read_bytes())
    at = data.index(np.ascontiguousarray(reference.min_dist).tobytes()[:16]) + 3
    data[at] ^= 0x01
    part.write_bytes(bytes(data))
    assert partial_cells.load(part, ident, (4, 5, 5)) is None
    assert "unreadable, not resumed (Bad CRC-32" in capsys.readouterr().out
    # an edited outcome re-packed with valid CRCs and the old record: its digest gives it away
    partial_cells.save(part, ident, cells)
    with np.load(part) as z:
        arrays = {k: z[k] for k in z.files}
    arrays["first_time"] = np.where(np.isnan(arrays["first_time"]), 5.0, arrays["first_time"])
    with part.open("wb") as fh:
        np.savez(fh, **arrays)
    assert partial_cells.load(part, ident, (4, 5, 5)) is None
    assert "do not match their digest" in capsys.readouterr().out


def test_workflow_keeps_the_running_design_in_the_design_cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The shard job (rules.run_shard) runs each pybullet design with its partial file in the run's
    design cache, and the cache removes it once it stores the design (design_cache.save)."""
    cfg = cfgmod.read(ROOT / "config.yaml", [ROOT / "config/smoke.yaml"])
    cfg["results_dir"] = str(tmp_path / "results")
    s = configure.parse(cfg)
    model = models.get("empirical")
    folder = design_cache.cache_dir(s.results_dir, "empirical", model.science(s))
    seen: list[Path] = []
    stored: list[bool] = []

    def fake(l1, l2, w, p, progress=None, options=None, partial=None) -> DesignResult:
        seen.append(partial)
        partial.parent.mkdir(parents=True, exist_ok=True)
        partial.write_bytes(b"running")
        shape = (4, len(w), len(w))
        return DesignResult(np.full(shape, np.nan), np.full(shape, 1.0), np.zeros(shape, np.int8))

    real_save = design_cache.save

    def save(folder: Path, design: int, *a, **k) -> None:
        stored.append(design_cache.partial_path(folder, design).is_file())  # still there when stored ...
        real_save(folder, design, *a, **k)

    monkeypatch.setattr(type(model), "design_evaluator", staticmethod(lambda: fake))
    monkeypatch.setattr(design_cache, "save", save)
    (d,) = model.shard_designs(s)[0]
    rules.run_shard(s, "empirical", 0, tmp_path / "shard.nc")
    assert seen == [design_cache.partial_path(folder, int(d))] and stored == [True]
    assert not seen[0].exists() and design_cache.design_path(folder, int(d)).is_file()  # ... removed after
