"""Stored results that cannot silently lie (issue 13): digests of the merged store checked on every
read path, a subset store for committed bundles, shard provenance across commits and backends,
``verify`` seeing lost successes, and the probe of bad inputs (refused with one line, exit 2)."""

from __future__ import annotations

import json
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import ROOT
from test_reliability import REL_CONFIG, SCIENCE, SHARD_DESIGNS, G, W, _results, _shards

from morphlearn import config, configure, metrics, models, provenance, store
from morphlearn.apps import cli
from morphlearn.provenance import sha256_file
from morphlearn.results import DesignResult
from morphlearn.workflow import rules

TH = metrics.Thresholds(500.0, 0.2, 500.0, 0.2)


def _merge(paths: list[Path], out: Path, provenance: dict | None = None) -> None:
    store.merge_shards(
        paths,
        out,
        model="theory",
        grid=G,
        weights=W,
        shard_designs=SHARD_DESIGNS,
        science=SCIENCE,
        mirror=True,
        provenance=provenance or {},
    )


@pytest.fixture
def merged(tmp_path: Path) -> Path:
    out = tmp_path / "merged.zarr"
    _merge(_shards(tmp_path), out)
    return out


def _chunk(m: Path, var: str, pos: int) -> Path:
    return m / var / "c" / str(pos) / "0" / "0" / "0"


def _metrics(m: Path, tmp_path: Path) -> tuple[Path, Exception | None]:
    csv = tmp_path / "metrics.csv"
    try:
        rules.run_metrics("theory", metrics.Thresholds(500.0, 0.2, 500.0, 0.2), m, csv)
    except store.IntegrityError as e:
        return csv, e
    return csv, None


@pytest.mark.parametrize("damage", ["deleted", "flipped bit", "truncated"])
def test_damaged_chunk_stops_metrics_by_name_before_anything_is_written(
    merged: Path, tmp_path: Path, damage: str
) -> None:
    pos = 7
    design = int(store.open_merged(merged)["design"].values[pos])
    chunk = _chunk(merged, "min_dist", pos)
    data = bytearray(chunk.read_bytes())
    if damage == "deleted":
        chunk.unlink()
    elif damage == "flipped bit":
        data[len(data) // 2] ^= 0x04
        chunk.write_bytes(bytes(data))
    else:
        chunk.write_bytes(bytes(data[: len(data) // 2]))
    csv, err = _metrics(merged, tmp_path)
    assert err is not None, "damage not detected"
    msg = str(err)
    assert msg.startswith(f"{merged}: min_dist of design {design} (position {pos}): ") and "\n" not in msg
    assert not csv.exists() and not csv.with_suffix(".provenance.json").exists()
    # verify: the same damage is unusable input (exit 2), one line naming it.
    proc = subprocess.run(
        [sys.executable, "-m", "morphlearn.apps.cli", "verify", "--merged", str(merged), "--samples", "2"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2 and f"min_dist of design {design}" in proc.stderr, proc.stderr
    assert proc.stderr.count("\n") == 1, proc.stderr


def test_metrics_provenance_records_the_overall_digest(merged: Path, tmp_path: Path) -> None:
    csv, err = _metrics(merged, tmp_path)
    assert err is None
    prov = json.loads(csv.with_suffix(".provenance.json").read_text())
    overall = store.open_merged(merged).attrs["integrity"]["overall"]
    assert prov["config"]["merged_sha256_overall"] == overall and len(overall) == 64


def test_altered_digest_record_or_coordinate_is_refused(merged: Path) -> None:
    meta = merged / "zarr.json"
    doc = json.loads(meta.read_text())
    doc["attributes"]["integrity"]["chunks"]["status"][0] = "0" * 64
    meta.write_text(json.dumps(doc))
    with pytest.raises(store.IntegrityError, match="does not match its overall digest"):
        store.open_merged(merged)


def test_merge_is_byte_deterministic(tmp_path: Path) -> None:
    paths = _shards(tmp_path)
    _merge(paths, tmp_path / "a.zarr")
    _merge(paths, tmp_path / "b.zarr")
    assert sha256_file(tmp_path / "a.zarr") == sha256_file(tmp_path / "b.zarr")
    store.write_subset(tmp_path / "a.zarr", [3, 40, 0], tmp_path / "sa.zarr")
    store.write_subset(tmp_path / "b.zarr", [0, 3, 40], tmp_path / "sb.zarr")
    assert sha256_file(tmp_path / "sa.zarr") == sha256_file(tmp_path / "sb.zarr")


def test_subset_keeps_digests_and_metrics_refuse_it(merged: Path, tmp_path: Path) -> None:
    src = store.open_merged(merged)
    sub = tmp_path / "sub.zarr"
    store.write_subset(merged, [40, 3, 0], sub)
    ds = store.open_merged(sub)
    assert ds["design"].values.tolist() == [0, 3, 40]
    assert ds.attrs["subset_of"] == src.attrs["integrity"]["overall"]
    assert ds.attrs["subset_source_designs"] == G.size
    where = {int(d): i for i, d in enumerate(src["design"].values)}
    for j, d in enumerate([0, 3, 40]):
        a, b = store.read_design(ds, j), store.read_design(src, where[d])
        for k in store.VARS:
            np.testing.assert_array_equal(a[k], b[k])
            assert ds.attrs["integrity"]["chunks"][k][j] == src.attrs["integrity"]["chunks"][k][where[d]]
    csv, err = _metrics(sub, tmp_path)
    assert err is not None and f"a subset of {G.size} designs" in str(err) and not csv.exists()
    with pytest.raises(store.IntegrityError, match=r"designs \[999\] are not in the store"):
        store.write_subset(merged, [999], tmp_path / "bad.zarr")


def _shard_with(path: Path, designs: np.ndarray, prov: dict, seed: int) -> None:
    store.write_shard(
        path,
        model="theory",
        grid=G,
        weights=W,
        designs=designs,
        results=_results(designs, 5, seed),
        science=SCIENCE,
        provenance=prov,
    )


def test_merge_records_and_warns_about_mixed_commits_and_backends(tmp_path: Path) -> None:
    provs = [
        {"git_commit": "aaa"},  # made before backends were recorded: the CPU
        {"git_commit": "aaa", "backend": "cpu", "device": "cpu (x86_64)"},
        {"git_commit": "bbb", "backend": "cuda", "device": "NVIDIA H100"},
    ]
    paths = [tmp_path / f"s{i}.nc" for i in range(3)]
    for i, (p, prov) in enumerate(zip(paths, provs, strict=True)):
        _shard_with(p, SHARD_DESIGNS[i], prov, i)
    with pytest.warns(UserWarning, match=r"2 git commits \['aaa', 'bbb'\].*2 backends"):
        _merge(paths, tmp_path / "m.zarr", {"git_commit": "ccc"})
    prov = json.loads(store.open_merged(tmp_path / "m.zarr").attrs["provenance_json"])["shards"]
    assert prov["git_commits"] == {"aaa": 2, "bbb": 1}
    assert prov["backends"] == {"cpu": 2, "cuda": 1}
    assert prov["devices"]["NVIDIA H100"] == 1
    # Same commit and backend everywhere, merged at another commit: recorded and warned, not refused.
    for i, p in enumerate(paths):
        _shard_with(p, SHARD_DESIGNS[i], {"git_commit": "aaa"}, i)
    with pytest.warns(UserWarning, match="made at commit aaa, merged at ccc"):
        _merge(paths, tmp_path / "m.zarr", {"git_commit": "ccc"})
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _merge(paths, tmp_path / "m.zarr", {"git_commit": "aaa"})


def test_shard_provenance_names_backend_and_device() -> None:
    s = configure.parse(config.deep_merge(yaml.safe_load((ROOT / "config.yaml").read_text()), REL_CONFIG))
    rec = models.get("theory").backend(s)
    assert rec["backend"] == "cpu" and rec["device"].startswith("cpu (")


def test_verify_counts_lost_successes(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    """A store whose first_time was wiped (digests consistent: a forged or buggy merge) while
    min_dist says the light was reached: exit 1 with the number of lost successes."""
    rng = np.random.default_rng(5)
    paths, lost = [], 0
    for i, d in enumerate(SHARD_DESIGNS):
        res = []
        for _ in d:
            md = rng.uniform(0.05, 3.0, (4, 5, 5)).astype(np.float32)
            res.append(DesignResult(np.full((4, 5, 5), np.nan), md, np.zeros((4, 5, 5))))
        paths.append(tmp_path / f"s{i}.nc")
        store.write_shard(
            paths[-1], model="theory", grid=G, weights=W, designs=d, results=res, science=SCIENCE, provenance={}
        )
    _merge(paths, tmp_path / "m.zarr")
    md_all = np.stack([store.read_design(store.open_merged(tmp_path / "m.zarr"), i)["min_dist"] for i in range(G.size)])
    lost = int((md_all < 0.2).sum())
    assert lost > 100
    rc = cli.main(["verify", "--merged", str(tmp_path / "m.zarr"), "--samples", "2", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert rc == 1 and out["lost_successes"] == lost and out["ok"] is False
    assert out["cells_checked"] == G.size * 4 * 25


def test_near_boundary_excuses_only_a_failing_side_that_came_close() -> None:
    from morphlearn.bundles.verify import Cell, near_boundary

    def cell(st_t: float, st_d: float, ref_t: float, ref_d: float) -> Cell:
        return Cell(0, 45, 0.0, 0.0, (0, 0), (0, 0), st_t, st_d, 0, ref_t, ref_d, 0)

    # Reference succeeds (its closest approach is the radius by construction), stored fails far off.
    assert not near_boundary(cell(np.nan, 1.5, 100.0, 0.2), 0.2, 500.0)
    assert near_boundary(cell(np.nan, 0.2005, 100.0, 0.2), 0.2, 500.0)  # stored just missed
    assert near_boundary(cell(np.nan, 1.5, 499.5, 0.2), 0.2, 500.0)  # success at the horizon
    assert not near_boundary(cell(100.0, 0.2, np.nan, 1.5), 0.2, 500.0)
    assert near_boundary(cell(100.0, 0.2, np.nan, 0.201), 0.2, 500.0)


def test_render_only_refuses_a_damaged_or_missing_input(merged: Path, tmp_path: Path) -> None:
    csv = merged.parent / "metrics.csv"
    with pytest.raises(store.IntegrityError, match=r"metrics\.csv: missing"):
        rules.check_render_inputs([str(csv), str(merged)])
    csv.write_text("x\n")
    # a table nothing vouches for is refused (issue 24: custody); one with its sealed record passes
    with pytest.raises(provenance.CustodyError, match=r"metrics\.csv: no provenance record"):
        rules.check_render_inputs([str(csv), str(merged)])
    overall = store.open_merged(merged).attrs["integrity"]["overall"]
    provenance.write_sealed(provenance.sidecar_of(csv), {"config": {"merged_sha256_overall": overall}}, [csv])
    rules.check_render_inputs([str(csv), str(merged)])
    _chunk(merged, "first_time", 2).unlink()
    with pytest.raises(store.IntegrityError, match=r"first_time of design \d+ \(position 2\): its chunk file is miss"):
        rules.check_render_inputs([str(csv), str(merged)])


# --- the probe: bad inputs tried as a hostile user would; each refused with one line, exit 2 ----

CLI_PROBES = [
    ["--l1", "0", "0", "--l2", "0", "0", "--r", "inf"],
    ["--l1", "0", "0", "--l2", "0", "0", "--r", "nan"],
    ["--l1", "0", "0", "--l2", "0", "0", "--horizon", "inf"],
    ["--l1", "0", "0", "--l2", "0", "0", "--dt", "inf"],
    ["--l1", "0", "0", "--l2", "0", "0", "--dt", "-1"],
    ["--l1", "nan", "0", "--l2", "0", "0"],
    ["--l1", "0", "0", "--l2", "0", "0", "--weights", "100000"],
    ["--model", "empirical", "--l1", "0", "0", "--l2", "0", "0", "--r", "4"],
    ["--model", "empirical", "--l1", "0", "0", "--l2", "0", "0", "--horizon", "5", "--dt", "0.1"],
    ["--l1", "0", "0", "--l2", "0", "0", "--morphology", "config/empirical_morphology.yaml"],
    ["--model", "empirical", "--l1", "0", "0", "--l2", "0", "0", "--morphology", "{bad_yaml}"],
    ["--model", "empirical", "--l1", "0", "0", "--l2", "0", "0", "--morphology", "{not_mapping}"],
]
CONFIG_PROBES = [
    ({"theory": {"r": float("inf")}}, "theory.r = inf is not a finite number"),
    ({"theory": {"r": float("nan")}}, "theory.r = nan is not a finite number"),
    ({"theory": {"horizon": float("inf")}}, "theory.horizon = inf"),
    ({"theory": {"dt": float("-inf")}}, "theory.dt = -inf"),
    ({"theory": {"integrator": "rk4"}}, "theory.max_steps = 10000 is below the 50000 steps"),
    ({"analysis": {"success_radius": float("nan")}}, "analysis.success_radius = nan"),
    ({"analysis": {"success_radius": 0.1}}, "analysis.success_radius = 0.1 is below theory.success_radius"),
    ({"analysis": {"success_radius": 0.5, "horizon": 100}}, "analysis.horizon = 100 with"),
    ({"theory": {"success_radius": 5.0}}, "theory.success_radius = 5.0 is not below theory.r"),
    ({"results_dir": ""}, "results_dir = ''"),
    ({"results_dir": "/"}, "results_dir = '/' is the file-system root"),
    ({"results_dir": "{file}"}, "is an existing file"),
    # A body file is read when its model is enabled, and Fig. 1C's (the registry's figure_body: the
    # ode model, the authors' robot the headline numbers use; issue 59) when figures are.
    ({"ode": {"morphology": "{bad_yaml}"}, "figures": {"enabled": True}}, "malformed YAML at line"),
    (
        {"ode": {"morphology": "nowhere.yaml"}, "figures": {"enabled": True}},
        "ode.morphology = 'nowhere.yaml': cannot read",
    ),
    (
        {"empirical": {"enabled": True, "results_from": None, "morphology": "nowhere.yaml"}},
        "empirical.morphology = 'nowhere.yaml': cannot read",
    ),
]


def test_probe_bad_inputs_refused_cleanly(
    tmp_path: Path, capsys: pytest.CaptureFixture, monkeypatch: pytest.MonkeyPatch
) -> None:
    bad_yaml, not_mapping, a_file = tmp_path / "bad.yaml", tmp_path / "list.yaml", tmp_path / "afile"
    bad_yaml.write_text("mass: [1, 2\n")
    not_mapping.write_text("- 1\n")
    a_file.write_text("")
    subs = {"{bad_yaml}": str(bad_yaml), "{not_mapping}": str(not_mapping), "{file}": str(a_file)}
    tried = clean = 0
    for args in CLI_PROBES:
        args = [subs.get(x, x) for x in args]
        monkeypatch.chdir(ROOT)
        rc = cli.main(["design", *args])  # in-process: a subprocess per probe costs seconds each
        out, err = capsys.readouterr()
        tried += 1
        ours = [line for line in err.splitlines() if line.startswith("morphlearn")]  # not pybullet's banner
        ok = rc == 2 and out == "" and len(ours) == 1 and ours[0].startswith("morphlearn design: error: ")
        clean += ok
        assert ok, (args, rc, err[-500:])
    base = config.deep_merge(yaml.safe_load((ROOT / "config.yaml").read_text()), REL_CONFIG)
    for patch, needle in CONFIG_PROBES:
        patch = json.loads(
            json.dumps(patch, allow_nan=True).replace(*next(iter(subs.items()))).replace("{file}", str(a_file))
        )
        tried += 1
        with pytest.raises(config.ConfigError) as e:
            configure.parse(config.deep_merge(base, patch))
        ok = needle in str(e.value) and "\n" not in str(e.value)
        clean += ok
        assert ok, (patch, str(e.value))
    print(f"\nprobe: {tried} bad inputs tried, {clean} refused cleanly (one line, exit 2 / ConfigError)")
    assert clean == tried == len(CLI_PROBES) + len(CONFIG_PROBES)


def test_cli_accepts_exponent_negative_numbers_and_json_has_flagged(capsys: pytest.CaptureFixture) -> None:
    assert cli.main(["design", "--l1", "-5e-1", "0.5", "--l2", "0.5", "-0.5", "--weights", "3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["per_env"] and isinstance(out["flagged"], int)  # "-5e-1" parsed as a number
    # l2 = (0, -0.5): singular trajectories (docs/model.md) are stopped and counted in "flagged".
    assert cli.main(["design", "--l1", "0.5", "0.5", "--l2", "0", "-0.5", "--weights", "11", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["flagged"] > 0
    # RK4 follows its step count (horizon / dt), and a step far too small for any run is refused.
    assert cli.main(["design", "--l1", "0", "0", "--l2", "0", "0", "--weights", "2", "--dt", "1e-9"]) == 2
    assert "allowed: --dt >= 5e-05" in capsys.readouterr().err
