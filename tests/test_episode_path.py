"""The ``path`` option of both engines' episode runners: the centre path it records, and episodes
that are the same with and without it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from morphlearn.grid import light_positions
from morphlearn.physics.params import load_params

PARAMS = load_params("config/empirical_morphology.yaml").replace(steps=300)
CANON = ((0.5, 0.5), (0.5, -0.5))


def test_pybullet_path_is_the_observed_centre_and_changes_nothing() -> None:
    from morphlearn.empirical.episode import EpisodeRunner

    light = light_positions(PARAMS.light_distance)[0]
    with EpisodeRunner(PARAMS) as runner:
        plain = runner.run(*CANON, 1.0, 1.0, 0)
        path: list[tuple[float, float]] = []
        ep = runner.run(*CANON, 1.0, 1.0, 0, path=path)
    assert ep == plain
    assert ep.success  # contact at step ep.steps, the last observed pose
    assert len(path) == ep.steps + 1
    d = [math.hypot(x - light[0], y - light[1]) for x, y in path]
    assert min(d) == pytest.approx(ep.min_dist, rel=1e-12) and d[-1] <= PARAMS.contact_distance < d[-2]
    assert path[0] == pytest.approx((0.0, 0.0), abs=1e-9)  # starts at the origin


def test_mujoco_path_per_episode_with_nan_after_its_stop() -> None:
    pytest.importorskip("mujoco")
    from morphlearn.mujoco.episode import CHUNK, BatchRunner

    runner = BatchRunner(PARAMS)
    w = np.array([[1.0, 1.0], [1.0, 1.0], [-0.4, 0.6]])
    env = np.array([0, 1, 2])
    plain = runner.run(*CANON, w, env)
    rec: list[np.ndarray] = []
    ep = runner.run(*CANON, w, env, path=rec)
    for f in plain.__dataclass_fields__:
        assert np.array_equal(getattr(ep, f), getattr(plain, f), equal_nan=True), f
    xy = np.stack(rec)  # (steps, n, 2)
    assert xy.shape == (ep.steps.max() + 1, 3, 2)
    lights = light_positions(PARAMS.light_distance)[env]
    for k in range(3):
        live = ~np.isnan(xy[:, k, 0])
        assert live.sum() == ep.steps[k] + 1 and live[: ep.steps[k] + 1].all()
        d = np.hypot(*(xy[live, k] - lights[k]).T)
        assert d.min() == pytest.approx(ep.min_dist[k], rel=1e-12)
    assert ep.success[0] and not ep.success[1]  # 300 steps: 45 deg is reached, 135 deg is not
    with pytest.raises(ValueError, match="CHUNK"):
        runner.run(*CANON, np.ones((CHUNK + 1, 2)), 0, path=[])
