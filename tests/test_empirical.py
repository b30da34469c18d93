"""Tests of the empirical (pybullet) model. Whole file: ~30 s on one core."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from morphlearn import configure
from morphlearn.empirical import EpisodeRunner, evaluate_design
from morphlearn.empirical.optimise import VARIABLES, optimise, select
from morphlearn.grid import ENV_MIRROR, canonical_design
from morphlearn.physics.params import EmpiricalParams, load_params

MORPHOLOGY = Path(__file__).resolve().parents[1] / "config" / "empirical_morphology.yaml"


@pytest.fixture(scope="module")
def params() -> EmpiricalParams:
    return load_params(MORPHOLOGY)


def _same(a: object, b: object) -> bool:
    """Equality that treats NaN as equal to NaN (episodes store NaN for 'no contact')."""
    return repr(a) == repr(b)


def test_episode_is_bit_for_bit_deterministic(params: EmpiricalParams) -> None:
    l1, l2 = (-0.5, -0.25), (0.5, 0.25)
    c1, c2 = canonical_design()
    cases = [
        (l1, l2, -0.8, 0.6, 2),
        (c1, c2, 0.0, 0.0, 1),  # ends at the start point: stale contacts would leak (below)
        (c1, c2, 1.0, 1.0, 1),
        (l1, l2, 0.5, -1.0, 3),
    ]
    with EpisodeRunner(params) as reused:
        first = [reused.run(*c, stop_at_contact=False) for c in cases]
        again = [reused.run(*c, stop_at_contact=False) for c in reversed(cases)][::-1]
    with EpisodeRunner(params, reuse=False) as fresh:
        new = [fresh.run(*c, stop_at_contact=False) for c in cases]
    assert all(_same(a, b) for a, b in zip(first, again, strict=True))
    assert all(_same(a, b) for a, b in zip(first, new, strict=True))
    # Stopping at contact changes nothing before it.
    with EpisodeRunner(params) as runner:
        stopped = runner.run(*cases[2])
    assert stopped.first_time == first[2].first_time and stopped.steps <= first[2].steps


def test_canonical_w11_reaches_all_four_lights(params: EmpiricalParams) -> None:
    l1, l2 = canonical_design()
    with EpisodeRunner(params) as runner:
        eps = [runner.run(l1, l2, 1.0, 1.0, env) for env in range(4)]
    assert [e.success for e in eps] == [True] * 4, eps
    assert all(e.finite and math.degrees(e.max_tilt) < 30 for e in eps)


def test_authors_body_reaches_only_the_front_lights() -> None:
    l1, l2 = canonical_design()
    with EpisodeRunner(EmpiricalParams()) as runner:
        ok = [runner.run(l1, l2, 1.0, 1.0, env).success for env in range(4)]
    assert ok == [True, False, False, True]  # 45 and 315 degrees are in front


def test_mirror_symmetry_on_a_coarse_grid(params: EmpiricalParams) -> None:
    # (l1, l2) with (w1, w2) in env k behaves as ((x2, -y2), (x1, -y1)) with (w2, w1) in
    # ENV_MIRROR[k]. Bullet solves the left wheel's constraints before the right one's, so
    # the physics is mirror-symmetric only to solver tolerance; success flags agree here.
    l1, l2 = (-0.5, -0.25), (0.5, 0.25)
    m1, m2 = (l2[0], -l2[1]), (l1[0], -l1[1])
    w = np.array([-1.0, 0.0, 1.0])
    a = evaluate_design(l1, l2, w, params)
    b = evaluate_design(m1, m2, w, params)
    b_mapped = b.first_time[list(ENV_MIRROR)].transpose(0, 2, 1)
    flips = int((np.isnan(a.first_time) != np.isnan(b_mapped)).sum())
    assert flips == 0
    assert a.status.max() == 0 and b.status.max() == 0


def test_evaluate_design_shapes_and_progress(params: EmpiricalParams) -> None:
    calls: list[tuple[int, int]] = []
    res = evaluate_design(*canonical_design(), np.array([0.0, 1.0]), params, lambda d, t: calls.append((d, t)))
    assert res.first_time.shape == res.min_dist.shape == res.status.shape == (4, 2, 2)
    assert calls[-1] == (16, 16) and len(calls) == 16
    assert np.all(np.isnan(res.first_time[:, 0, 0]))  # w = 0: the robot never moves
    # ... it only settles on its wheels and castor (millimetres) at the start
    assert np.allclose(res.min_dist[:, 0, 0], params.light_distance, atol=0.01)
    assert np.all(~np.isnan(res.first_time[:, 1, 1]))  # w = (1, 1) reaches every light


@pytest.mark.parametrize(
    ("values", "key"),
    [
        ({"body_mass": -1.0}, "body_mass"),
        ({"wheel_mass": 0.0}, "wheel_mass"),
        ({"wheel_radius": 0.0}, "wheel_radius"),
        ({"dt": -0.05}, "dt"),
        ({"steps": 0}, "steps"),
        ({"steps": 2.5}, "steps"),
        ({"wheel_radus": 0.2}, "wheel_radus"),
    ],
)
def test_bad_params_name_the_key(values: dict[str, float], key: str) -> None:
    with pytest.raises(ValueError, match=key) as err:
        EmpiricalParams.from_mapping(values)
    assert "allowed" in str(err.value)


def test_unknown_key_lists_allowed_keys() -> None:
    with pytest.raises(ValueError, match="body_mass"):
        EmpiricalParams.from_mapping({"colour": "red"})


def test_morphology_file_round_trips(params: EmpiricalParams) -> None:
    assert EmpiricalParams.from_mapping(params.to_dict()) == params
    assert params.contact_distance == 0.5 + params.wheel_radius + params.light_radius


def test_selection_rule_prefers_robust_cheapest_full_success() -> None:
    spec = [  # (lights reached, actuation, feasible, on the Pareto front)
        (4, 5.0, False, True),  # unstable: never chosen
        (4, 10.0, True, True),  # cheapest full success, but fragile
        (4, 20.0, True, True),  # robust: chosen
        (4, 30.0, True, True),  # not checked: a robust one came first
        (2, 1.0, True, True),
        (4, 8.0, True, False),  # off the front: only tried after every Pareto point
    ]
    rows = []
    for i, (n, act, feas, front) in enumerate(spec):
        # bodies told apart by their mass (the robustness stubs below read it); the other
        # variables stay physical (a wheel radius of 6 would start the robot touching the light)
        row = {k: 1.0 for k in VARIABLES} | {"body_mass": 1.0 + i}
        row.update(n_success=n, f_actuation=act, f_distance=1.0, feasible=feas, pareto=front)
        rows.append(row)
    table = pd.DataFrame(rows)
    table["robust"] = np.nan
    pick = select(table, lambda p: 12 if p.body_mass == 3.0 else 10)
    assert pick == 2
    assert table["robust"].tolist()[1:3] == [10, 12]
    assert table["robust"].isna().tolist() == [True, False, False, True, True, True]
    # No robust Pareto point: the off-front body is tried next, and wins if it is robust.
    table["robust"] = np.nan
    assert select(table, lambda p: 12 if p.body_mass == 6.0 else 11) == 5


def test_optimise_is_deterministic_for_a_seed() -> None:
    a, pa = optimise(4, seed=3, pop_size=4)
    b, pb_ = optimise(4, seed=3, pop_size=4)
    pd.testing.assert_frame_equal(a, b)
    assert pa == pb_
    assert set(VARIABLES) <= set(pa)


def test_episode_progress_lines_are_throttled(capsys: pytest.CaptureFixture[str]) -> None:
    """Shard logs get an episode-level line at most every ``every_s`` seconds, and one at the end."""
    from morphlearn.physics.progress import EpisodeProgress

    t = iter([0.0, 1.0, 29.0, 31.0, 32.0, 40.0])  # start, then one reading per episode
    log = EpisodeProgress("design 7 (1/2)", every_s=30.0, clock=lambda: next(t))
    for done in range(1, 6):
        log(done, 5)
    lines = capsys.readouterr().out.splitlines()
    assert lines == [
        "design 7 (1/2): 3/5 episodes, 10.333 s each, ~21 s left in this design",
        "design 7 (1/2): 5/5 episodes, 8.000 s each",
    ]
    t = iter([0.0, 30.0, 40.0])  # the adaptive grid: an upper bound, and the time left at most
    log = EpisodeProgress("design 1/2 (index 7)", every_s=30.0, clock=lambda: next(t), at_most=True)
    log(3, 5)
    log(5, 5)
    assert capsys.readouterr().out.splitlines() == [
        "design 1/2 (index 7): 3/5 episodes at most (adaptive weight grid), 30 s so far, "
        "at most ~20 s left in this design",
        "design 1/2 (index 7): done in 40 s (adaptive weight grid)",
    ]


def test_a_shard_says_its_time_left_from_the_designs_done(capsys: pytest.CaptureFixture[str]) -> None:
    """The adaptive grid's episode counts are an upper bound (the ODE workflow's log once gave
    '4451/58564 episodes at most' and no time left): the shard's time left comes from its designs."""
    from morphlearn.physics.progress import DesignsProgress

    t = iter([0.0, 100.0, 300.0, 330.0])
    log = DesignsProgress(3, clock=lambda: next(t))
    assert log(1) == "designs 1/3 done in 100 s, ~200 s left in this shard (at the mean of the designs done)"
    assert log(2) == "designs 2/3 done in 300 s, ~150 s left in this shard (at the mean of the designs done)"
    assert log(3) == "designs 3/3 done in 330 s"
    assert len(capsys.readouterr().out.splitlines()) == 3


def test_mirror_derive_simulates_one_of_each_pair(tmp_path: Path) -> None:
    """empirical.mirror_derive: the shard simulates one design of each mirror pair, the merge
    derives the other (env mirrored, w1 <-> w2); the science record says so; a config that would
    derive designs it does not list is refused by name."""
    from morphlearn import config as cfgmod
    from morphlearn import models, store
    from morphlearn.grid import DesignGrid
    from morphlearn.workflow import rules

    root = Path(__file__).resolve().parents[1]
    cfg = cfgmod.load(root / "config.yaml", [root / "config/smoke.yaml"])
    cfg = cfgmod.validate(
        cfgmod.deep_merge(
            cfg,
            {
                "results_dir": str(tmp_path),
                "grid": {"positions_per_axis": 5},
                "empirical": {"designs": [[[-0.5, -0.25], [0.5, 0.25]]], "mirror_derive": True},
            },
        )
    )
    g = DesignGrid(5)
    d = g.index_of((-0.5, -0.25), (0.5, 0.25))
    pair = sorted({d, int(g.mirror(d))})
    s, emp = configure.parse(cfg), models.get("empirical")
    assert emp.designs(s).tolist() == [pair[0]]
    assert emp.science(s)["mirror_derive"] is True
    off = configure.parse(cfgmod.deep_merge(cfg, {"empirical": {"mirror_derive": False}}))
    assert "mirror_derive" not in emp.science(off)  # old results keep their digest
    rules.run_shard(s, "empirical", 0, tmp_path / "shard_0.nc")
    rules.run_merge(s, "empirical", [str(tmp_path / "shard_0.nc")], tmp_path / "merged.zarr")
    ds = store.open_merged(tmp_path / "merged.zarr")
    assert ds["design"].values.tolist() == pair
    a, b = (store.read_design(ds, i) for i in range(2))
    for k, v in store.mirror_arrays(a).items():
        np.testing.assert_array_equal(v, b[k])
    with pytest.raises(cfgmod.ConfigError, match=r"empirical\.mirror_derive = true needs"):
        configure.parse(cfgmod.deep_merge(cfg, {"empirical": {"include_mirrors": False}}))


def test_committed_pareto_set_holds_both_bodies() -> None:
    """config/empirical_pareto.csv (regenerated with the committed budget and seed) holds the
    chosen body exactly, and the second body of the robustness check is one of its Pareto points."""
    from morphlearn.empirical.optimise import VARIABLES

    table = pd.read_csv(MORPHOLOGY.parent / "empirical_pareto.csv")
    chosen = table[table.chosen].iloc[0]
    body = load_params(MORPHOLOGY)
    assert all(float(chosen[k]) == getattr(body, k) for k in VARIABLES)
    body2 = load_params(MORPHOLOGY.parent / "empirical_morphology_body2.yaml")
    hit = table[np.logical_and.reduce([table[k] == getattr(body2, k) for k in VARIABLES])]
    assert len(hit) == 1 and bool(hit.iloc[0].pareto) and int(hit.iloc[0].n_success) == 4
