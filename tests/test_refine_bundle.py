"""A results bundle from complete refine folders (morphlearn.refine_bundle): its metrics are the
folders', the workflow's reader accepts it, bad folders and foreign out folders are refused, damage
is caught, and re-simulation agrees."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from conftest import TEST_COMMIT

from morphlearn import bundle_check, configure, metrics, models, provenance, refine_bundle, store
from morphlearn import config as cfgmod
from morphlearn import resumable as rz
from morphlearn.bundle import BundleError
from morphlearn.figures import options
from morphlearn.grid import DesignGrid, canonical_design
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import load_params

ROOT = Path(__file__).resolve().parents[1]
BODY = ROOT / "config" / "empirical_morphology.yaml"
OTHER = ((-0.5, 0.5), (0.5, -0.5))  # design 720 of the 9-position grid


def _job(l1: tuple[float, float], l2: tuple[float, float], m: int = 3, steps: int = 300) -> rz.Job:
    return rz.Job(l1=l1, l2=l2, m=m, params=load_params(BODY).replace(steps=steps), options=SweepOptions(True))


def _folder(path: Path, design: tuple = canonical_design(), *, seed: int = 0, rows: int | None = None, **kw) -> Path:  # type: ignore[type-arg]
    """A refine folder written with the module's own writers; made-up outcomes (no physics): each
    cell succeeds with probability 0.85 (first-contact time within the horizon) or fails (NaN)."""
    job = _job(*design, **kw)
    key = rz.open_folder(path, job, BODY)
    rng = np.random.default_rng(seed)
    horizon = job.params.horizon
    done = rz.row_order(job.m)[: job.m if rows is None else rows]
    # each row's commit, as the runner logs it: a bundle names the commits that computed its rows,
    # and check-bundle requires commits of this history (issue 57)
    log = {"commit": TEST_COMMIT, "episodes": 4 * job.m, "wall_s": 1.0, "cpu_s": 1.0}
    (path / "progress.jsonl").write_text("".join(json.dumps({"row": int(r), **log}) + "\n" for r in done))
    for r in done:
        ok = rng.random((4, job.m)) < 0.85
        rz.write_chunk(
            path,
            r,
            key,
            {
                "first_time": np.where(ok, rng.uniform(1, horizon, (4, job.m)), np.nan),
                "min_dist": rng.uniform(0.1, 3.0, (4, job.m)),
                "status": np.zeros((4, job.m)),
                "steps": rng.integers(10, job.params.steps, (4, job.m)),
            },
        )
    return path


def test_bundle_holds_the_folders_metrics_and_the_workflow_reads_it(tmp_path: Path) -> None:
    a, b = _folder(tmp_path / "a"), _folder(tmp_path / "b", OTHER, seed=1)
    out = tmp_path / "bundle"
    man = refine_bundle.build([b, a], out)
    g = DesignGrid(9)
    designs = [g.index_of(*OTHER), g.index_of(*canonical_design())]
    assert man["subsets"]["empirical"]["designs"] == sorted(designs)
    assert bundle_check.check(out) == []
    table = pd.read_csv(out / "empirical" / "metrics.csv")
    th = rz.thresholds(load_params(BODY).replace(steps=300))
    for folder, d in ((a, designs[1]), (b, designs[0])):
        asm = rz.assemble(folder)
        # independently of the bundle's code path: the success array of the folder's own rows
        want = metrics.design_metrics(metrics.success(asm.result.first_time, asm.result.min_dist, th))
        row = table[table.design == d].iloc[0]
        assert [int(row[f"n_{e}"]) for e in (45, 135, 225, 315)] == want.per_env
        assert (int(row.generalists), int(row.at_least_one)) == (want.generalists, want.at_least_one)
        assert row.M_L == float(metrics.CSV_FLOAT_FORMAT % (want.generalists / 9))
        assert want.generalists > 0  # the comparison means something
    # the record: what was run, readable by the model plug-in
    ds = store.open_merged(out / "empirical" / "merged.zarr")
    sci = store.science_of(ds)
    assert sci["weights"] == 3 and sci["early_stop"] and "adaptive_weights" not in sci and "mirror_derive" not in sci
    assert sci["refine"]["body_file_sha256"] == provenance.sha256_file(BODY)
    assert sci["refine"]["engine_identity"].keys() == {"pybullet"} and not sci["refine"]["mirror_derive"]
    assert sci["refine"]["run_keys"] == {
        str(designs[1]): rz.read_manifest(a)["run_key"],
        str(designs[0]): rz.read_manifest(b)["run_key"],
    }
    assert "NaN" not in ds.attrs["provenance_json"]  # strict JSON (the folders logged no cost)
    assert models.get("empirical").positions_of(sci) == 9
    assert (
        "2 designs simulated one by one, every cell, by tools/refine_design.py (run keys in the store's "
        "record) on the 9-point grid, 3 weights per synapse" in models.get("empirical").describe(sci, 2, 3)
    )
    # the workflow's reader: config on the 9-position grid, then the rule's copy and the figures' load
    cfg = cfgmod.deep_merge(
        cfgmod.load(ROOT / "config.yaml"),
        {"grid": {"positions_per_axis": 9}, "empirical": {"results_from": str(out), "weights": 11}},
    )
    s = configure.parse(cfg)
    assert len(s.weights("empirical")) == 3  # the bundle's weights, not the section's 11
    # it holds two designs: not a survey, so no theory-against-physics survey figure
    assert s.models["empirical"].held == tuple(sorted(designs)) and not options.empirical_survey(s)
    run = tmp_path / "run" / "empirical"
    bundle_check.extract_model(
        out,
        "empirical",
        {"metrics": run / "metrics.csv", "provenance": run / "metrics.provenance.json", "merged": run / "merged.zarr"},
    )
    from morphlearn.figures.data import load_results

    res = load_results(tmp_path / "run", "empirical")
    assert res is not None and sorted(res.table.design) == sorted(designs)


def test_refusals_name_the_folder_and_the_key(tmp_path: Path) -> None:
    good = _folder(tmp_path / "good")
    cases = {
        "partial": (_folder(tmp_path / "partial", OTHER, rows=2), "2 of 3 rows verified"),
        "steps": (_folder(tmp_path / "steps", OTHER, steps=200), "params = .* differs from"),
        "off": (_folder(tmp_path / "off", ((0.1, 0.5), (0.5, -0.5))), r"l1=\[0.1, 0.5\] .* not on the 9-position"),
        "twin": (_folder(tmp_path / "twin", seed=3), "design 6552 is already given by"),
    }
    for name, (folder, why) in cases.items():
        with pytest.raises(rz.RefineError, match=why):
            refine_bundle.build([good, folder], tmp_path / f"out_{name}")
        assert not (tmp_path / f"out_{name}").exists(), name  # nothing written
    # a damaged row is a missing row: the folder is incomplete, and the message says which file
    flipped = _folder(tmp_path / "flipped", OTHER)
    p = rz.row_path(flipped, 1)
    data = bytearray(p.read_bytes())
    data[len(data) // 2] ^= 0xFF
    p.write_bytes(bytes(data))
    with pytest.raises(rz.RefineError, match=r"2 of 3 rows verified; damaged: .*row_001"):
        refine_bundle.build([good, flipped], tmp_path / "out_flipped")


def test_out_folder_foreign_content_is_never_replaced(tmp_path: Path) -> None:
    a = _folder(tmp_path / "a")
    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / "notes.txt").write_text("mine")
    with pytest.raises(rz.RefineError, match="did not make"):
        refine_bundle.build([a], foreign)
    assert [p.name for p in foreign.iterdir()] == ["notes.txt"]
    out = tmp_path / "out"
    refine_bundle.build([a], out)
    first = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    # the same model again (e.g. with a folder more): replaced whole; the same input, the same bytes
    refine_bundle.build([a], out)
    assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == first
    # a workflow bundle (another tool) is refused
    paper = tmp_path / "paper"
    shutil.copytree(ROOT / "results" / "paper", paper)
    with pytest.raises(rz.RefineError, match="did not make"):
        refine_bundle.build([a], paper)
    assert bundle_check.check(paper) == []


def test_damage_in_the_bundle_is_caught(tmp_path: Path) -> None:
    out = tmp_path / "bundle"
    refine_bundle.build([_folder(tmp_path / "a")], out)
    chunk = out / "empirical" / "merged.zarr" / "first_time" / "c" / "0" / "0" / "0" / "0"
    data = bytearray(chunk.read_bytes())
    data[len(data) // 2] ^= 0x01
    chunk.write_bytes(bytes(data))
    problems = bundle_check.check(out)
    assert "first_time/c/0/0/0/0: checksum differs" in problems[0]
    # and the damaged chunk read beside the table (issue 57: every chunk read, never skipped)
    assert len(problems) == 2 and "first_time of design" in problems[1] and "(damaged)" in problems[1], problems
    with pytest.raises(BundleError, match="2 problem"):
        bundle_check.extract_model(
            out, "empirical", {k: tmp_path / "run" / k for k in ("metrics", "provenance", "merged")}
        )
    assert not (tmp_path / "run").exists()


def test_resimulation_agrees_and_refuses_another_engine_version(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pytest.importorskip("pybullet")
    from morphlearn import resimulate

    job = _job(*canonical_design(), m=3)
    rz.run(tmp_path / "real", job, body_file=BODY, log=lambda msg: None)
    out = tmp_path / "bundle"
    refine_bundle.build([tmp_path / "real"], out)
    assert resimulate.resimulate(out, ["empirical:canonical"]) == []
    real = rz.ENGINES["pybullet"]
    monkeypatch.setitem(rz.ENGINES, "pybullet", rz.Engine(lambda: {"pybullet": "0.0"}, real.runner, real.row))
    (problem,) = resimulate.resimulate(out, ["empirical:canonical"])
    assert "cannot re-simulate" in problem and "would not be the recorded run" in problem
