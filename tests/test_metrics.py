import numpy as np
import pytest

from morphlearn import metrics


def _succ(mats: list[list[list[int]]]) -> np.ndarray:
    return np.array(mats, dtype=bool)


def test_metrics_by_hand() -> None:
    # 2x2 controllers: (0,0) succeeds everywhere, (0,1) in two envs, (1,0) in one, (1,1) nowhere.
    s = _succ([[[1, 1], [1, 0]], [[1, 1], [0, 0]], [[1, 0], [0, 0]], [[1, 0], [0, 0]]])
    assert metrics.overlap(s).tolist() == [[4, 2], [1, 0]]
    dm = metrics.design_metrics(s, np.array([[[0, 0], [0, 1]]] * 4))
    assert dm.per_env == [3, 2, 1, 1]
    assert (dm.generalists, dm.at_least_one) == (1, 3)
    assert dm.M_L == pytest.approx(1 / 4)
    assert dm.M_CF == pytest.approx(1 / 3)
    assert dm.flagged == 4


def test_null_overlap_gives_zero_mcf() -> None:
    dm = metrics.design_metrics(np.zeros((4, 3, 3), bool))
    assert (dm.M_L, dm.M_CF, dm.at_least_one) == (0.0, 0.0, 0)


def test_success_from_times_and_distances() -> None:
    ft = np.array([10.0, np.nan, 400.0, 600.0])
    md = np.array([0.1, 0.25, 0.2, 0.15])
    th = metrics.Thresholds(horizon=500, radius=0.2, sim_horizon=1000, sim_radius=0.2)
    assert metrics.success(ft, md, th).tolist() == [True, False, True, False]
    th = metrics.Thresholds(horizon=300, radius=0.2, sim_horizon=1000, sim_radius=0.2)
    assert metrics.success(ft, md, th).tolist() == [True, False, False, False]
    th = metrics.Thresholds(horizon=1000, radius=0.3, sim_horizon=1000, sim_radius=0.2)
    assert metrics.success(ft, md, th).tolist() == [True, True, True, True]


@pytest.mark.parametrize(
    ("kw", "msg"),
    [
        ({"horizon": 600}, r"horizon = 600 must be in \(0, 500"),
        ({"radius": 0.1}, "below the simulated 0.2"),
        ({"radius": 0.3, "horizon": 100}, "only known at the simulated horizon"),
    ],
)
def test_thresholds_refuse_what_needs_a_new_simulation(kw: dict, msg: str) -> None:
    args = {"horizon": 500, "radius": 0.2, "sim_horizon": 500, "sim_radius": 0.2} | kw
    with pytest.raises(ValueError, match=msg):
        metrics.Thresholds(**args)
