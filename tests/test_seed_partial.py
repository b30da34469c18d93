"""An exhaustive refine folder (the committed format, morphlearn.refine.folder) seeds a workflow
design's partial file (morphlearn.refine.seed):
the workflow's adaptive run then simulates only the cells of its path the folder lacks, to the
bytes of a run that had no file."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import counting_runs
from refine_folders import write_folder

pytest.importorskip("pybullet")

from morphlearn import config as cfgmod
from morphlearn import configure, models
from morphlearn.empirical import evaluate_design
from morphlearn.physics import design_cache
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import load_params
from morphlearn.refine import folder as rz
from morphlearn.refine.seed import seed
from morphlearn.results import STATUS_INFERRED, DesignResult
from morphlearn.settings import Settings

ROOT = Path(__file__).resolve().parents[1]
BODY = ROOT / "config" / "empirical_morphology.yaml"
STEPS = 300  # contacts of w = (1, 1) at 9.05 s: successes in a test's time
L1, L2 = (0.5, 0.5), (0.5, -0.5)


def _settings(tmp: Path, **emp: Any) -> Settings:
    cfg = cfgmod.read(ROOT / "config.yaml", [ROOT / "config/smoke.yaml"])
    cfg["results_dir"] = str(tmp / "results")
    cfg["empirical"].update(
        {
            "weights": 5,
            "params": {"steps": STEPS},
            "designs": [[list(L1), list(L2)]],
            "include_mirrors": False,
            "early_stop": True,
            "adaptive_weights": True,
            "adaptive_near": 4.0,
            **emp,
        }
    )
    return configure.parse(cfg)


def _folder(tmp: Path, max_rows: int | None = None, **job: Any) -> Path:
    """A folder of the canonical design's exhaustive episodes (early stop on, as the old runner
    made them; its rows were evaluate_design's bit for bit), holding its first ``max_rows`` rows
    in the runner's order (0, 4, 2, 1, 3)."""
    kw: dict[str, Any] = {
        "l1": L1,
        "l2": L2,
        "m": 5,
        "params": load_params(BODY).replace(steps=STEPS),
        "options": SweepOptions(early_stop=True),
        "engine_identity": {"pybullet": "test"},
    }
    j = rz.Job(**{**kw, **job})
    r = evaluate_design(j.l1, j.l2, j.weights, j.params, options=j.options)
    arrays = {k: getattr(r, k) for k in ("first_time", "min_dist", "status")} | {"steps": np.zeros((4, 5, 5))}
    rows = [0, 4, 2, 1, 3][:max_rows]
    return write_folder(tmp / "folder", j, arrays, rows=rows, body_file=BODY)


def _evaluate(s: Settings, monkeypatch: pytest.MonkeyPatch) -> tuple[DesignResult, int]:
    """The workflow's evaluation of the config's one design (as a shard job calls it), and how many
    episodes it simulated."""
    calls = counting_runs(monkeypatch)
    model = models.get("empirical")
    cache = design_cache.cache_dir(s.results_dir, "empirical", model.science(s))
    designs = model.designs(s)

    def done(i: int, r: DesignResult) -> None:  # the shard job's: store the design in the cache
        design_cache.save(
            cache, int(designs[i]), r, model="empirical", grid=s.grid.designs, weights=model.weights(s),
            science=model.science(s), provenance={"git_commit": "test"},
        )  # fmt: skip

    (r,) = model.evaluate(s, designs, done=done, partial=lambda d: design_cache.partial_path(cache, d))
    monkeypatch.undo()
    return r, len(calls)


def _same(a: DesignResult, b: DesignResult) -> None:
    for k in ("first_time", "min_dist", "status"):
        assert getattr(a, k).dtype == getattr(b, k).dtype and getattr(a, k).tobytes() == getattr(b, k).tobytes(), k


def test_seeded_design_simulates_only_what_the_folder_lacks(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    ref, simulated = _evaluate(_settings(tmp_path / "ref"), monkeypatch)  # no file: the plain run
    assert 0 < simulated < 100 and (ref.status == STATUS_INFERRED).any()
    # a complete folder: the seeded run simulates nothing and gives the plain run's bytes (the
    # folder's cells off the adaptive path are inferred, as in the plain run)
    s = _settings(tmp_path / "full")
    got = seed(_folder(tmp_path / "full"), s)
    assert (got.rows, got.seeded, got.kept, got.near_threshold, got.finished) == (5, 100, 0, 0, False)
    r, n = _evaluate(s, monkeypatch)
    assert n == 0
    _same(r, ref)
    assert not got.path.exists()  # the evaluation's caller (done) stored it: the cache removed it
    # two of five rows: it simulates the path's cells in the other three only
    s = _settings(tmp_path / "part")
    folder = _folder(tmp_path / "part", max_rows=2)
    done_rows = rz.assemble(folder).rows_done
    got = seed(folder, s)
    assert (got.rows, got.seeded) == (2, 40)
    r, n = _evaluate(s, monkeypatch)
    on_path = ref.status != STATUS_INFERRED
    assert n == int(on_path[:, ~done_rows].sum()) < simulated
    _same(r, ref)


def test_seed_keeps_the_workflows_own_episodes_and_skips_a_finished_design(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from morphlearn.physics import partial as partial_cells

    s = _settings(tmp_path)
    model = models.get("empirical")
    d = int(model.designs(s)[0])
    cache = design_cache.cache_dir(s.results_dir, "empirical", model.science(s))
    path = design_cache.partial_path(cache, d)
    ident = model.partial_identity(s, d)
    mark = partial_cells.Cells(
        np.full((4, 5, 5), np.nan), np.full((4, 5, 5), np.nan), np.zeros((4, 5, 5), np.int8), np.zeros((4, 5, 5), bool)
    )
    mark.simulated[0, 0, 0], mark.min_dist[0, 0, 0] = True, 123.0  # one episode the workflow ran
    cache.mkdir(parents=True)
    partial_cells.save(path, ident, mark)
    got = seed(_folder(tmp_path), s)
    assert (got.seeded, got.kept) == (99, 1)
    assert partial_cells.load(path, ident, (4, 5, 5)).min_dist[0, 0, 0] == 123.0
    design_cache.design_path(cache, d).write_bytes(b"stored")  # a finished design: left alone
    path.unlink()
    assert seed(tmp_path / "folder", s).finished and not path.exists()


def test_seed_refuses_another_body_weights_levers_or_design(tmp_path: Path) -> None:
    folder = _folder(tmp_path, max_rows=1)
    with pytest.raises(rz.RefineError, match=r"another body parameters \['steps'\]"):
        seed(folder, _settings(tmp_path, params={"steps": STEPS + 1}))
    with pytest.raises(rz.RefineError, match=r"another weights 5 per synapse \(the config's: 3\)"):
        seed(folder, _settings(tmp_path, weights=3))
    with pytest.raises(rz.RefineError, match=r"another early_stop = True \(the config's: False\)"):
        seed(folder, _settings(tmp_path, early_stop=False))
    with pytest.raises(rz.RefineError, match=r"design 78 .* is not one this config simulates; allowed: \[6\]"):
        seed(folder, _settings(tmp_path, designs=[[[-0.5, -0.5], [0.5, -0.5]]]))
    with pytest.raises(rz.RefineError, match="model 'theory' keeps no partial designs"):
        seed(folder, _settings(tmp_path), model="theory")


def test_seed_takes_the_model_from_the_folders_engine(tmp_path: Path) -> None:
    """A MuJoCo folder is refused as MuJoCo's (no partial designs), not as a config that does not
    simulate pybullet (the message named the wrong model before)."""
    folder = _folder(tmp_path, max_rows=1, engine="mujoco", engine_identity={"engine": "mujoco"})
    refused = r"model 'mujoco' keeps no partial designs; allowed: \['empirical', 'ode'\]"
    with pytest.raises(rz.RefineError, match=refused):
        seed(folder, _settings(tmp_path))


def test_status_of_a_run_says_what_its_design_cache_holds(tmp_path: Path) -> None:
    """``morphlearn refine status --configfile``: a run's designs finished, and the episodes a
    design in progress holds (here: seeded from a folder), from its design cache."""
    from morphlearn.refine.cli import run_progress

    s = _settings(tmp_path)
    model = models.get("empirical")
    d = int(model.designs(s)[0])
    assert "empirical: 0 of 1 designs finished in " in run_progress(s)[0]
    assert not any(ln.startswith("  design") for ln in run_progress(s))
    got = seed(_folder(tmp_path, max_rows=2), s)
    assert f"  design {d}: in progress, 40 of 100 episodes in {got.path.name}" in run_progress(s)
    got.path.write_bytes(b"damaged")
    assert f"  design {d}: {got.path.name} is unreadable or another run's (not used" in " ".join(run_progress(s))
    design_cache.design_path(got.path.parent, d).write_bytes(b"stored")
    lines = [ln for ln in run_progress(s) if "empirical" in ln or ln.startswith("  design")]
    assert len(lines) == 1 and "empirical: 1 of 1 designs finished" in lines[0], lines
