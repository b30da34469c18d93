"""The agreement stage (morphlearn.analysis.agreement; issue 42): its statistics on made-up surveys whose
answers are known, its refusals, and the committed comparison against the bundles it was made from."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from conftest import ode_only_config

from morphlearn.analysis import agreement as ag
from morphlearn.grid import DesignGrid, canonical_design

ROOT = Path(__file__).resolve().parents[1]
N = 5  # positions per axis: 625 designs


def _survey(model: str, ml: np.ndarray, mcf: np.ndarray, success: dict[int, np.ndarray], **science) -> ag.Survey:
    g = DesignGrid(N)
    d = np.arange(g.size)
    c = g.coords(d)
    t = pd.DataFrame(
        {"design": d, "l1x": c[:, 0], "l1y": c[:, 1], "l2x": c[:, 2], "l2y": c[:, 3], "M_L": ml, "M_CF": mcf}
    )
    t["generalists"] = np.rint(ml * 121).astype(int)
    # cells solved per environment: a generalist solves all four; a made-up share of the others
    for k, env in enumerate((45, 135, 225, 315)):
        t[f"n_{env}"] = t.generalists + np.rint(mcf * 40 * (k + 1)).astype(int)
    sci = {"weights": 11, "positions_per_axis": N, **science}
    return ag.Survey(ag.Source(f"results/{model}", model), t, sci, success, {})


def test_identical_surveys_agree_fully_and_a_shuffle_does_not() -> None:
    rng = np.random.default_rng(0)
    ml, mcf = rng.integers(0, 8, 625) / 121, rng.uniform(0, 0.5, 625)
    cells = {d: rng.random((4, 11, 11)) < 0.1 for d in range(0, 625, 7)}
    ref = _survey("ode", ml, mcf, cells)
    same = ag.compare(ref, _survey("mujoco", ml, mcf, cells, robot="authors"))
    assert same["rho_M_L"]["rho"] == pytest.approx(1.0) and same["rho_M_CF"]["rho"] == pytest.approx(1.0)
    assert same["top10_M_L"] == 10 and same["cells"]["share"] == 1.0 and same["cells"]["designs"] == len(cells)
    assert same["rho_solved"]["rho"] == pytest.approx(1.0)
    assert same["label"] == "MuJoCo, the authors' robot" and same["robot"] == "authors"
    # as a screen: its 10 best and their mirror images hold the reference's 10 best
    assert same["screen"]["reference_best_missed"] == [] and 10 <= same["screen"]["designs_refined"] <= 20
    assert "saved" not in same["screen"]  # no run cost recorded for these made-up bundles
    canon = DesignGrid(N).index_of(*canonical_design())
    assert same["canonical"]["design"] == canon
    assert same["canonical"]["rank_M_L_reference"] == same["canonical"]["rank_M_L_candidate"]
    # an unrelated survey: rho near 0 with an interval that holds 0; half the flipped cells differ
    flipped = {d: ~a for d, a in cells.items()}
    other = ag.compare(ref, _survey("empirical", rng.permutation(ml), rng.permutation(mcf), flipped))
    assert other["rho_M_CF"]["lo"] < 0 < other["rho_M_CF"]["hi"]
    assert other["cells"]["share"] == 0.0 and other["robot"] == "project"
    assert len(other["screen"]["reference_best_missed"]) > 5  # a shuffled screen finds few of them
    assert other["label"] == "pybullet, the project's body"


def test_ties_at_zero_are_not_best() -> None:
    """Most designs without a generalist (ODE at 11 x 11): the top lists and the screen count only
    designs with a positive value, and the bootstrap interval is still defined (the resamples in
    which a side is constant, rho undefined, are dropped, not made NaN)."""
    ml = np.zeros(625)
    ml[[3, 40, 77, 300, 620]] = [5, 4, 3, 2, 1]
    ml /= 121
    mcf = ml / 2
    ref = _survey("ode", ml, mcf, {})
    row = ag.compare(ref, _survey("mujoco", ml, mcf, {}))
    assert row["top10_M_L_sizes"] == {"reference": 5, "candidate": 5} and row["top10_M_L"] == 5
    assert row["screen"]["reference_best"] == [3, 40, 77, 300, 620]
    assert row["screen"]["reference_best_missed"] == []
    # ranks: 1 + the designs strictly better; the designs tied at 0 share rank 6
    assert row["canonical"]["rank_M_L_reference"] == 5 and row["canonical"]["tied_M_L_reference"] == 0
    flat = ag.compare(ref, _survey("mujoco", np.where(ml > 0, 1 / 121, 0), mcf, {}))
    assert flat["canonical"]["rank_M_L_candidate"] == 1 and flat["canonical"]["tied_M_L_candidate"] == 4
    assert flat["best_M_L"]["its_rank_in_candidate"] == 1 and row["best_M_L"]["reference_best"] == 3
    lo, hi = row["rho_M_L"]["lo"], row["rho_M_L"]["hi"]
    assert np.isfinite(lo) and np.isfinite(hi) and lo <= row["rho_M_L"]["rho"] <= hi
    other = ml.copy()
    other[[3, 40]] = 0  # the candidate loses the reference's two best
    row = ag.compare(ref, _survey("mujoco", other, other / 2, {}))
    assert row["top10_M_L"] == 3 and row["top10_M_L_sizes"]["candidate"] == 3
    assert row["best_M_L"]["its_rank_in_candidate"] == 4  # 3 lost its generalists: tied at 0, after 3
    refined = {77, 300, 620} | {int(DesignGrid(N).mirror(d)) for d in (77, 300, 620)}
    assert row["screen"]["designs_refined"] == len(refined)
    assert row["screen"]["reference_best_missed"] == [d for d in (3, 40) if d not in refined]


def test_levers_and_refusals() -> None:
    z = np.random.default_rng(1).uniform(0, 0.1, 625)
    ref = _survey("ode", z, z, {})
    adaptive = _survey("mujoco", z, z, {}, adaptive_weights={"near": 4.0}, early_stop=True)
    row = ag.compare(ref, adaptive)
    assert "adaptive weight grid (near 4.0" in row["levers"] and "early stop" in row["levers"]
    assert row["cells"]["share"] is None  # no outcome arrays in common: said, not 0
    with pytest.raises(ValueError, match="another weight or design grid"):
        ag.compare(ref, _survey("mujoco", z, z, {}, weights=121))
    short = _survey("mujoco", z, z, {})
    short = ag.Survey(short.source, short.table.iloc[:600], short.science, {}, {})
    with pytest.raises(ValueError, match="600 designs, the reference 625"):
        ag.compare(ref, short)


COMMITTED = ROOT / "results" / "agreement" / "agreement.json"


@pytest.mark.skipif(not COMMITTED.is_file(), reason="results/agreement not committed yet")
def test_committed_numbers_are_the_bundles() -> None:
    """The committed comparison is what its bundles give now (custody checked on every read)."""
    s = ag.AgreementSettings(
        True,
        ag.Source("results/authors-engines", "ode"),
        tuple(ag.Source(c["bundle"], c["model"]) for c in json.loads(COMMITTED.read_text())["candidates"]),
    )
    import os

    cwd = os.getcwd()
    os.chdir(ROOT)
    try:
        assert ag.numbers(s) == json.loads(COMMITTED.read_text())
        # the record names every table and bundle manifest it read, at their current digests (a
        # candidate bundle re-made since, with another run cost, would show here)
        from morphlearn import provenance

        rec = json.loads((COMMITTED.parent / "agreement.provenance.json").read_text())
        want = {f for src in s.sources() for f in src.files()}
        assert set(rec["inputs"]) == want
        assert all(rec["inputs"][f] == provenance.sha256_file(f) for f in want)
        # made from a commit of this history, not a worktree with changes (issue 41)
        assert not provenance.uncommitted(rec["git_commit"]), rec["git_commit"]
        assert provenance.in_history(rec["git_commit"], cwd=ROOT) in (True, None)
    finally:
        os.chdir(cwd)


def test_uncommitted_code_is_refused_and_nothing_written(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MORPHLEARN_GIT_COMMIT", "abc-dirty")
    s = ag.AgreementSettings(True, ag.Source("results/authors-engines", "ode"), (ag.Source("results/x", "mujoco"),))
    out = tmp_path / "agreement.csv", tmp_path / "agreement.json"
    with pytest.raises(ValueError, match=r"at abc-dirty: the agreement stage .* committed code only"):
        ag.write(s, *out)
    assert list(tmp_path.iterdir()) == []


def _ode_config(designs: object, **extra: object) -> object:
    return ode_only_config({"weights": 3, "designs": designs, **extra})


def test_designs_top_of_a_screening_survey() -> None:
    """``designs: {top_of: ...}``: the n best of a committed survey (and their mirror images)."""
    from morphlearn import metrics, models

    pytest.importorskip("morphlearn.ode._core")
    top = {"bundle": "results/survey-mujoco", "model": "mujoco", "by": "M_L", "n": 3}
    s = _ode_config({"top_of": top})
    table = pd.read_csv(ROOT / "results/survey-mujoco/mujoco/metrics.csv", comment="#")
    best = metrics.rank_designs(table, "M_L").design.head(3).to_numpy()
    g = DesignGrid(N)
    want = sorted({int(d) for d in np.concatenate([best, g.mirror(best)])})
    assert list(models.get("ode").settings(s).held) == want
    s = _ode_config({"top_of": top}, include_mirrors=False)
    assert list(models.get("ode").settings(s).held) == sorted(int(d) for d in best)
    from morphlearn.config import ConfigError

    with pytest.raises(ConfigError, match=r"ode\.designs\.top_of: results/nowhere/mujoco/metrics\.csv"):
        _ode_config({"top_of": {**top, "bundle": "results/nowhere"}})
    with pytest.raises(ConfigError, match=r"ode\.designs"):
        _ode_config({"top_of": {**top, "by": "speed"}})
    # a coarse survey of the authors' robot: n larger than its designs with a generalist gives those
    sparse = {"bundle": "results/authors-engines", "model": "mujoco", "by": "M_L", "n": 20}
    table = pd.read_csv(ROOT / "results/authors-engines/mujoco/metrics.csv", comment="#")
    held = models.get("ode").settings(_ode_config({"top_of": sparse}, include_mirrors=False)).held
    assert list(held) == sorted(int(d) for d in table.design[table.generalists > 0]) and 0 < len(held) < 20


def test_designs_top_of_a_survey_without_a_generalist(monkeypatch: pytest.MonkeyPatch) -> None:
    from morphlearn import metrics
    from morphlearn.config import ConfigError

    pytest.importorskip("morphlearn.ode._core")
    monkeypatch.setattr(metrics, "best_designs", lambda *a: [])
    top = {"bundle": "results/survey-mujoco", "model": "mujoco", "by": "M_CF", "n": 3}
    with pytest.raises(ConfigError, match=r"ode\.designs\.top_of: .* has no design with M_CF > 0"):
        _ode_config({"top_of": top})


def test_designs_random_and_several_metrics() -> None:
    """``designs: {random: {n, seed}}`` draws n distinct designs of the grid with numpy's
    default_rng(seed) (a screen's check), ``top_of.by`` a list gives the union of each metric's n
    best, and both keys together their union; n above the grid's size is a one-line error."""
    from morphlearn import metrics, models
    from morphlearn.config import ConfigError

    pytest.importorskip("morphlearn.ode._core")
    g = DesignGrid(N)
    held = models.get("ode").settings(_ode_config({"random": {"n": 7, "seed": 3}}, include_mirrors=False)).held
    want = np.random.default_rng(3).choice(g.size, 7, replace=False)
    assert list(held) == sorted(int(d) for d in want) and len(set(held)) == 7
    other = models.get("ode").settings(_ode_config({"random": {"n": 7, "seed": 4}}, include_mirrors=False)).held
    assert list(other) != list(held)
    with pytest.raises(ConfigError, match=r"ode\.designs\.random\.n = 626 exceeds the grid's 625 designs"):
        _ode_config({"random": {"n": 626, "seed": 3}})
    table = pd.read_csv(ROOT / "results/survey-mujoco/mujoco/metrics.csv", comment="#")
    top = {"bundle": "results/survey-mujoco", "model": "mujoco", "by": ["M_L", "M_CF"], "n": 3}
    by_l, by_cf = metrics.best_designs(table, "M_L", 3), metrics.best_designs(table, "M_CF", 3)
    assert set(by_l) != set(by_cf)  # else the union below proves nothing
    both = models.get("ode").settings(_ode_config({"top_of": top}, include_mirrors=False)).held
    assert list(both) == sorted(set(by_l) | set(by_cf))
    union = (
        models.get("ode")
        .settings(_ode_config({"top_of": top, "random": {"n": 7, "seed": 3}}, include_mirrors=False))
        .held
    )
    assert list(union) == sorted(set(both) | set(held))
    with pytest.raises(ConfigError, match=r"ode\.designs"):
        _ode_config({})


def test_sources_without_the_canonical_design_compare_without_its_rank() -> None:
    """A screen's best designs or a random sample need not hold the canonical design: the
    comparison says so (None, an empty cell in the table) instead of failing on it."""
    rng = np.random.default_rng(4)
    ml, mcf = rng.integers(0, 8, 625) / 121, rng.uniform(0, 0.5, 625)
    canon = DesignGrid(N).index_of(*canonical_design())
    ref, cand = _survey("ode", ml, mcf, {}), _survey("mujoco", ml, mcf, {}, robot="authors")
    ref, cand = (dataclasses.replace(s, table=s.table[s.table.design != canon]) for s in (ref, cand))
    out = ag.compare(ref, cand)
    assert out["canonical"] is None and out["rho_M_L"]["rho"] == pytest.approx(1.0)
