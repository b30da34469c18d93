"""What a learner minimises, and the batched evaluation of arbitrary controllers.

Per-environment loss (informative before success, ordered by success):

- success: ``first_time / T`` in [0, 1] (faster is better);
- failure: ``1 + d_min / r`` in (1 + radius / r, 2], with ``d_min`` the closest approach of the
  whole trajectory to the light (the kernel's ``min_dist``; the start is at distance ``r``).

Why: before any success a controller that passes closer to the light is closer to succeeding, and
``d_min`` varies continuously with the weights over most of the plane, so an evolution strategy
gets a slope where a 0/1 success signal is flat; every success scores below every failure, so
improving the loss never trades a success for a near miss. Flagged (singular) trajectories are
failures, scored by their closest approach before they were stopped.

Joint loss over the four environments: ``n_failed + mean(per-env loss)``. The mean is in
[0, 2) and ``k`` failures bound it from below by ``k (1 + radius/r) / 4``, so the joint loss is
strictly ordered by the number of environments failed (every generalist scores below every
non-generalist) and graded within each count.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from morphlearn.grid import env_starts
from morphlearn.theory import TheoryParams
from morphlearn.theory import cpu as kernel

N_ENV = 4


def env_loss(first_time: np.ndarray, min_dist: np.ndarray, success: np.ndarray, horizon: float, r: float) -> np.ndarray:
    """Per-environment loss (module docstring)."""
    ok = np.asarray(success, bool)
    return np.where(ok, np.nan_to_num(first_time, nan=horizon) / horizon, 1.0 + np.asarray(min_dist) / r)


def joint_loss(losses: np.ndarray) -> np.ndarray:
    """(..., 4) per-environment losses -> number failed + mean loss (ordered by failures)."""
    losses = np.asarray(losses, dtype=np.float64)
    return (losses > 1.0).sum(axis=-1) + losses.mean(axis=-1)


@dataclass
class Evaluator:
    """Evaluates (design, environment, w1, w2) quadruples of one batch in one kernel call.

    ``designs`` are coordinates (nd, 4); ``trajectories`` counts what has been simulated.
    """

    designs: np.ndarray
    params: TheoryParams
    trajectories: int = field(default=0)

    def __post_init__(self) -> None:
        self.designs = np.ascontiguousarray(self.designs, dtype=np.float64).reshape(-1, 4)
        self.starts = env_starts(self.params.r)

    def __call__(self, design_idx: np.ndarray, env_idx: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Loss and success per quadruple; ``w`` is (k, 2)."""
        p = self.params
        w = np.asarray(w, dtype=np.float64).reshape(-1, 2)
        ft, dm, st = kernel.points(
            self.designs,
            self.starts,
            design_idx,
            env_idx,
            w[:, 0],
            w[:, 1],
            **p.kernel_kwargs(),
        )
        self.trajectories += len(ft)
        success = (st == 0) & np.isfinite(ft)
        return env_loss(ft, dm, success, p.horizon, p.r), success
