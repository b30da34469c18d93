"""Another run's design cache seeds a config's partial files (morphlearn.refine.seed.seed_designs): an
exhaustive refinement of a design an adaptive survey simulated runs only the cells the survey did
not, to the bytes of a run that had no file. In ODE (the authors' robot, real episodes)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

core = pytest.importorskip("morphlearn.ode.core")
if not core.available():  # CI and tools/setup.sh install libode-dev; elsewhere say why it skips
    pytest.skip("morphlearn.ode._core not built (no libode-dev)", allow_module_level=True)

from morphlearn import config as cfgmod  # noqa: E402
from morphlearn import configure, models, store  # noqa: E402
from morphlearn.ode import episode  # noqa: E402
from morphlearn.physics import design_cache  # noqa: E402
from morphlearn.refine import folder as rz  # noqa: E402
from morphlearn.refine.seed import seed_designs  # noqa: E402
from morphlearn.results import STATUS_INFERRED, DesignResult  # noqa: E402
from morphlearn.settings import Settings  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
CANONICAL = [[0.5, 0.5], [0.5, -0.5]]
OTHER = [[-0.5, 0.5], [0.5, -0.5]]  # on both grids; the survey's second design


def _settings(tmp: Path, positions: int, **ode: Any) -> Settings:
    cfg = cfgmod.read(ROOT / "config.yaml", [ROOT / "config/smoke.yaml"])
    cfg["results_dir"] = str(tmp)
    cfg["grid"]["positions_per_axis"] = positions
    cfg["ode"] = {"enabled": True, "weights": 5, "designs": [CANONICAL], "include_mirrors": False, **ode}
    return configure.parse(cfg)


def _evaluate(s: Settings, monkeypatch: pytest.MonkeyPatch) -> tuple[list[DesignResult], int]:
    """The workflow's evaluation of the config's designs (as a shard job calls it), stored in its
    design cache as a shard job stores them, and how many episodes it simulated."""
    ran: list[int] = []
    real = episode.run
    monkeypatch.setattr(episode, "run", lambda *a, **k: ran.append(len(a[3])) or real(*a, **k))
    model = models.get("ode")
    designs = model.designs(s)
    folder = design_cache.cache_dir(s.results_dir, "ode", model.science(s))
    folder.mkdir(parents=True, exist_ok=True)

    def done(i: int, r: DesignResult) -> None:
        design_cache.save(
            folder, int(designs[i]), r, model="ode", grid=s.grid.designs, weights=model.weights(s),
            science=model.science(s), provenance={"git_commit": "test"},
        )  # fmt: skip

    out = model.evaluate(s, designs, done=done, partial=lambda d: design_cache.partial_path(folder, d))
    monkeypatch.undo()
    return out, sum(ran)


def _survey(tmp: Path, monkeypatch: pytest.MonkeyPatch) -> tuple[Path, DesignResult]:
    """An adaptive survey on the 3-point grid holding the canonical design and another: its cache."""
    s = _settings(tmp / "survey", 3, designs=[CANONICAL, OTHER], adaptive_weights=True)
    out, _ = _evaluate(s, monkeypatch)
    model = models.get("ode")
    canon = out[list(model.designs(s)).index(s.grid.designs.index_of(*map(tuple, CANONICAL)))]
    return design_cache.cache_dir(s.results_dir, "ode", model.science(s)), canon


def test_a_survey_seeds_an_exhaustive_refinement_to_the_same_bytes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    cache, surveyed = _survey(tmp_path, monkeypatch)
    on_path = int((surveyed.status != STATUS_INFERRED).sum())
    assert 0 < on_path < 100  # the adaptive grid skipped cells
    (ref,), simulated = _evaluate(_settings(tmp_path / "ref", 5), monkeypatch)  # no file: the plain run
    assert simulated == 100
    # the refinement (5-point grid: the canonical design's index differs) holds the canonical design only
    s = _settings(tmp_path / "refine", 5)
    (got,) = seed_designs(cache, s)
    assert (got.design, got.rows, got.seeded, got.kept, got.near_threshold, got.finished) == (
        int(models.get("ode").designs(s)[0]), on_path, on_path, 0, 0, False,
    )  # fmt: skip
    (r,), n = _evaluate(s, monkeypatch)
    assert n == 100 - on_path
    for k in ("first_time", "min_dist", "status"):
        assert getattr(r, k).tobytes() == getattr(ref, k).tobytes(), k
    assert not got.path.exists()  # the finished design replaced its partial file
    assert seed_designs(cache, s)[0].finished  # a finished design is left alone
    # a config that holds none of the cache's designs: nothing to seed
    assert seed_designs(cache, _settings(tmp_path / "none", 5, designs=[[[0.0, 0.0], [0.5, -0.5]]])) == []


def test_seed_designs_refuses_other_episodes_and_damaged_files(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    cache, _ = _survey(tmp_path, monkeypatch)
    with pytest.raises(rz.RefineError, match=r"made with other \['params'\] than this config"):
        seed_designs(cache, _settings(tmp_path / "a", 5, params={"steps": 2000}))
    with pytest.raises(rz.RefineError, match=r"made with other \['weights'\]"):
        seed_designs(cache, _settings(tmp_path / "b", 5, weights=3))
    with pytest.raises(rz.RefineError, match="does not simulate 'ode'"):
        seed_designs(cache, _settings(tmp_path / "c", 5, enabled=False))
    with pytest.raises(rz.RefineError, match=r"no design_<n>\.nc files"):
        seed_designs(tmp_path / "empty", _settings(tmp_path / "d", 5))
    f = sorted(cache.glob("design_*.nc"))[0]
    raw = f.read_bytes()
    at = raw.index(store.read_shard(f).arrays["min_dist"].astype(">f4").tobytes())  # netCDF-3: big-endian
    f.write_bytes(raw[:at] + bytes([raw[at] ^ 1]) + raw[at + 1 :])  # one bit of a closest approach
    mid = len(raw) // 2
    with pytest.raises(rz.RefineError, match=r"not a verified design file \(.*data checksum mismatch"):
        seed_designs(cache, _settings(tmp_path / "e", 5))
    f.write_bytes(raw[:mid])
    with pytest.raises(rz.RefineError, match=r"not a verified design file \(.*unreadable or truncated"):
        seed_designs(cache, _settings(tmp_path / "e", 5))
    assert not any((tmp_path / "e").rglob("*.partial.npz"))  # nothing half-written


def test_seed_cache_cli_bad_input_is_one_line(tmp_path: Path) -> None:
    import subprocess
    import sys

    out = subprocess.run(
        [sys.executable, "-m", "morphlearn.apps.cli", "refine", "seed-cache", str(tmp_path), "--configfile",
         "config/ode_paper.yaml"],
        capture_output=True, text=True, cwd=ROOT,
    )  # fmt: skip
    assert out.returncode == 2 and out.stdout == ""
    assert (
        out.stderr
        == f"morphlearn refine: error: {tmp_path}: no design_<n>.nc files (a run's <model>/designs/<digest>/ folder)\n"
    )
