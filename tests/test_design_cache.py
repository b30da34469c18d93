"""Finished work survives re-sharding and killed shards (design_cache), and results of another
config or sharding in results_dir are re-planned at start (results_check)."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import ROOT, copy_workflow, job_stats, snakemake

from morphlearn import config, configure, models, settings, store
from morphlearn.physics import design_cache
from morphlearn.workflow import rules

SMOKE = config.load(ROOT / "config.yaml", [ROOT / "config/smoke.yaml"])
# smoke, with two empirical designs (plus mirror images) so that both models can be re-sharded
RESHARD = {"empirical": {"designs": [[[0.5, 0.5], [0.5, -0.5]], [[-0.5, 0.0], [0.5, 0.5]]], "shards": 1}}
MERGED = ["results/theory/merged.zarr", "results/empirical/merged.zarr"]


def _computed(wd: Path) -> dict[str, int]:
    """Designs each model's shard jobs computed (not reused), from the shard logs (then removed, so
    that the next run's logs are counted alone)."""
    out = {}
    for model in ("theory", "empirical"):
        logs = sorted((wd / f"results/logs/{model}").glob("shard_*.log"))
        counts = [int(m) for p in logs for m in re.findall(r"to compute (\d+)", p.read_text())]
        assert len(counts) == len(logs), f"{model}: a shard log without its design count"
        out[model] = sum(counts)
        for p in logs:
            p.unlink()
    return out


def _data(wd: Path) -> dict[str, str]:
    """Digest of each merged store's arrays (its provenance names the shard files, which differ)."""
    out = {}
    for p in MERGED:
        ds = store.open_merged(wd / p)
        out[p] = store.data_digest({k: ds[k].values for k in store.VARS}) + str(ds["design"].values.tolist())
    return out


def _flip_byte(p: Path) -> None:
    """Change one low mantissa byte of ``min_dist`` (still a finite number; the checksum breaks)."""
    data = bytearray(p.read_bytes())
    needle = store.read_shard(p).arrays["min_dist"].astype(">f4").tobytes()
    at = data.find(needle)
    assert at > 0
    data[at + 3] ^= 0x01
    p.write_bytes(bytes(data))


@pytest.mark.slow
def test_reshard_recomputes_nothing_and_merges_the_same_bytes(tmp_path: Path) -> None:
    wd = copy_workflow(tmp_path / "wd")
    (wd / "a.yaml").write_text(yaml.safe_dump(config.deep_merge(RESHARD, {"sweep": {"shards": 3}})))
    snakemake(wd, *MERGED, "--cores", "2", "--configfile", "config/smoke.yaml", "a.yaml")
    first = _computed(wd)
    assert first["theory"] == 45 and first["empirical"] == 3  # 45 mirror representatives of 81
    merged = _data(wd)

    # Other shard counts, with Snakemake's metadata (params changed) ...
    (wd / "b.yaml").write_text(
        yaml.safe_dump(config.deep_merge(RESHARD, {"sweep": {"shards": 2}, "empirical": {"shards": 3}}))
    )
    proc = snakemake(wd, *MERGED, "--cores", "2", "--configfile", "config/smoke.yaml", "b.yaml")
    assert job_stats(proc.stdout + proc.stderr)["theory_shard"] == 2
    assert _computed(wd) == {"theory": 0, "empirical": 0}
    assert _data(wd) == merged

    # ... and without it (results copied elsewhere): one clear line at start instead of a merge
    # refusal later; with the stale shards deleted, nothing is recomputed either.
    shutil.rmtree(wd / ".snakemake")
    (wd / "c.yaml").write_text(
        yaml.safe_dump(config.deep_merge(RESHARD, {"sweep": {"shards": 4}, "empirical": {"shards": 2}}))
    )
    args = [*MERGED, "--cores", "2", "--configfile", "config/smoke.yaml", "c.yaml"]
    proc = snakemake(wd, *args, check=False)
    assert proc.returncode == 2, proc.stderr[-2000:]
    assert "results/theory/merged.zarr was made by another science config or shard count" not in proc.stderr
    assert re.search(
        r"^morphlearn: results/theory/shards/shard_\d+\.nc was made by another science "
        r"config or shard count and Snakemake has no record",
        proc.stderr,
        re.M,
    ), proc.stderr
    for model in ("theory", "empirical"):  # what the message says to do
        shutil.rmtree(wd / f"results/{model}/shards")
        shutil.rmtree(wd / f"results/{model}/merged.zarr")
    proc = snakemake(wd, *args)
    assert job_stats(proc.stdout + proc.stderr) == {"theory_shard": 4, "empirical_shard": 2, "merge": 2}
    assert _computed(wd) == {"theory": 0, "empirical": 0}
    assert _data(wd) == merged

    # The scenario: a reduced run's results present, no metadata. The full config's dry
    # run plans every shard in its own results folder, and stops at start when pointed at this one.
    shutil.rmtree(wd / ".snakemake")
    proc = snakemake(wd, "-n", "--cores", "1", "--configfile", "config/full.yaml")
    stats = job_stats(proc.stdout + proc.stderr)
    assert (stats["theory_shard"], stats["empirical_shard"]) == (24, 6561), stats
    proc = snakemake(
        wd, "-n", "--cores", "1", "--configfile", "config/full.yaml", "--config", "results_dir=results", check=False
    )
    assert proc.returncode == 2 and "has no record of it" in proc.stderr, proc.stderr[-2000:]


def test_killed_shard_resumes_and_damaged_designs_are_recomputed(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    # 9 shards of the 45 smoke designs: 5 in shard 0 (seconds)
    s = configure.parse(config.deep_merge(SMOKE, {"results_dir": str(tmp_path / "results"), "sweep": {"shards": 9}}))
    theory = models.get("theory")
    out = tmp_path / "shard_0.nc"
    rules.run_shard(s, "theory", 0, out)
    first = out.read_bytes()
    designs = theory.shard_designs(s)[0]
    assert "reused 0, to compute 5" in capsys.readouterr().out
    folder = design_cache.cache_dir(s.results_dir, "theory", theory.science(s))
    assert sorted(folder.iterdir()) == sorted(design_cache.design_path(folder, d) for d in designs)

    out.unlink()  # as if the job was killed before it wrote its shard, with one design unfinished
    design_cache.design_path(folder, designs[1]).unlink()
    _flip_byte(design_cache.design_path(folder, designs[2]))
    rules.run_shard(s, "theory", 0, out)
    log = capsys.readouterr().out
    assert "reused 3, to compute 2" in log and "data checksum mismatch (damaged)" in log, log
    assert out.read_bytes() == first

    # another science config never reuses these designs: it has its own folder
    other = configure.parse(config.deep_merge(dict(s.source), {"theory": {"horizon": 400.0}}))
    assert design_cache.cache_dir(s.results_dir, "theory", theory.science(other)) != folder
    assert np.array_equal(designs, theory.shard_designs(other)[0])


def test_theory_shard_saves_each_batch_as_it_finishes(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A theory shard killed mid-way keeps the designs of its finished batches (not only of
    finished shards): the kernel reports each batch, and the cache saves it at once."""
    s = configure.parse(config.deep_merge(SMOKE, {"results_dir": str(tmp_path / "results"), "sweep": {"shards": 9}}))
    designs = models.get("theory").shard_designs(s)[0]
    folder = design_cache.cache_dir(s.results_dir, "theory", models.get("theory").science(s))
    import morphlearn.theory as theory
    from morphlearn.theory import cpu

    real, real_sweep = theory.evaluate, cpu.sweep
    # one design per batch; the run is "killed" while the third batch's design is being saved
    monkeypatch.setattr(theory, "evaluate", lambda *a, **k: real(*a, **k, batch_trajectories=1))
    batches: list[int] = []
    monkeypatch.setattr(cpu, "sweep", lambda d, *a, **k: batches.append(len(d)) or real_sweep(d, *a, **k))
    saved: list[int] = []
    real_save = design_cache.save

    def save(folder: Path, design: int, *a: object, **k: object) -> None:
        if len(saved) == 2:
            assert batches == [1, 1, 1]  # saved before the remaining batches run, not after
            raise KeyboardInterrupt
        real_save(folder, design, *a, **k)
        saved.append(design)

    monkeypatch.setattr(design_cache, "save", save)
    with pytest.raises(KeyboardInterrupt):
        rules.run_shard(s, "theory", 0, tmp_path / "shard_0.nc")
    assert sorted(folder.iterdir()) == sorted(design_cache.design_path(folder, d) for d in designs[:2])
    assert not (tmp_path / "shard_0.nc").exists()


def test_adding_designs_to_a_physics_run_reuses_the_designs_done(
    tmp_path: Path, capsys: pytest.CaptureFixture, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A physics run's science lists its designs; the cache is keyed without that list, so a run
    with more designs (issue 26: candidates added to the refinement) recomputes only the new ones,
    and designs kept under the old key (the digest of the whole science) are still reused."""
    pytest.importorskip("mujoco")
    one, two = [[[0.5, 0.5], [0.0, -0.5]]], [[[0.5, 0.5], [0.0, -0.5]], [[-0.5, 0.0], [0.5, 0.5]]]
    mj = models.get("mujoco")

    def parse(designs: list) -> settings.Settings:
        section = {"enabled": True, "results_from": None, "weights": 2, "designs": designs, "shards": 1}
        section |= {"include_mirrors": False, "params": {"light_distance": 2.5, "steps": 100}}
        cfg = {"results_dir": str(tmp_path / "r"), "grid": {"positions_per_axis": 3}, "mujoco": section}
        cfg |= {"figures": {"enabled": False}, "empirical": {"enabled": False}}
        return configure.parse(config.deep_merge(SMOKE, cfg))

    monkeypatch.chdir(ROOT)  # the body file is named relative to the project root
    a, b = parse(one), parse(two)
    assert mj.science(a) != mj.science(b)  # the design list is part of the run's science ...
    folder = design_cache.cache_dir(a.results_dir, "mujoco", mj.science(a))
    assert folder == design_cache.cache_dir(b.results_dir, "mujoco", mj.science(b))  # ... not of the key
    rules.run_shard(a, "mujoco", 0, tmp_path / "a.nc")
    assert "reused 0, to compute 1" in capsys.readouterr().out
    rules.run_shard(b, "mujoco", 0, tmp_path / "b.nc")
    assert "reused 1, to compute 1" in capsys.readouterr().out
    # a design kept under the old key is reused from there
    legacy = design_cache.legacy_dir(b.results_dir, "mujoco", mj.science(b))
    assert legacy is not None and legacy != folder
    legacy.mkdir(parents=True)
    d = int(mj.designs(b)[1])
    sh = store.read_shard(design_cache.design_path(folder, d))
    store.write_shard(
        design_cache.design_path(legacy, d),
        model="mujoco",
        grid=b.grid.designs,
        weights=mj.weights(b),
        designs=np.array([d]),
        results=[design_cache.DesignResult(*(sh.arrays[k][0] for k in store.VARS))],
        science=mj.science(b),
        provenance={},
    )
    design_cache.design_path(folder, d).unlink()
    rules.run_shard(b, "mujoco", 0, tmp_path / "b2.nc")
    assert "reused 2, to compute 0" in capsys.readouterr().out
    assert store.read_shard(tmp_path / "b2.nc").arrays["min_dist"].tobytes() == (
        store.read_shard(tmp_path / "b.nc").arrays["min_dist"].tobytes()
    )
