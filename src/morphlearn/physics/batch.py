"""A batch of episodes of one of the authors' robot's engines: its checked inputs and its outcomes
(the ODE model and the reduced model take and give the same)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Episodes:
    """Outcomes of a batch, arrays of shape (n,)."""

    first_step: np.ndarray  # first step with the centre within the success radius (-1: none)
    min_dist: np.ndarray  # closest centre-to-light distance up to success (or the horizon)
    steps: np.ndarray  # steps simulated
    finite: np.ndarray  # False where the state became NaN/inf (stopped there)

    @property
    def success(self) -> np.ndarray:
        return self.first_step >= 0


def _points(name: str, v: Any, n: int) -> np.ndarray:
    a = np.broadcast_to(np.asarray(v, dtype=np.float64), (n, 2))
    if not np.isfinite(a).all() or np.abs(a).max(initial=0.0) > 0.5:
        raise ValueError(f"{name} = {np.asarray(v).tolist()!r} is off the body; allowed: finite x, y in [-0.5, 0.5]")
    return a


def check_inputs(l1: Any, l2: Any, w: Any, env: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Weights (n, 2), environments (n,) and sensor points (n, 4) of a batch, checked (one line
    naming the bad value and what is allowed)."""
    w = np.ascontiguousarray(np.atleast_2d(np.asarray(w, dtype=np.float64)))
    n = len(w)
    if w.shape != (n, 2):
        raise ValueError(f"weights must have shape (n, 2); got {w.shape}")
    if not np.isfinite(w).all() or np.abs(w).max(initial=0.0) > 1.0:
        bad = w[~(np.isfinite(w) & (np.abs(w) <= 1.0))][0]
        raise ValueError(f"weight {float(bad)!r} is invalid; allowed: finite values in [-1, 1]")
    env = np.broadcast_to(np.asarray(env, dtype=np.int64), (n,))
    if np.any((env < 0) | (env > 3)):
        raise ValueError(f"env {sorted(set(env.tolist()) - {0, 1, 2, 3})} invalid; allowed: 0..3")
    sensors = np.ascontiguousarray(np.concatenate([_points("l1", l1, n), _points("l2", l2, n)], axis=1))
    return w, env, sensors
