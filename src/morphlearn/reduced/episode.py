"""A design's sweep over (env, w1, w2) in the reduced model: the physics layer's sweep
(:func:`morphlearn.physics.sweep.sweep`: adaptive grid, resume, progress) over this model's batches,
with the signature and result of every physics model's ``evaluate_design``."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import EmpiricalParams
from morphlearn.physics.sweep import sweep, without_reach_bound
from morphlearn.reduced.core import run
from morphlearn.results import DesignResult

Point = tuple[float, float]
#: Episodes per kernel call: progress is reported between calls; results do not depend on it.
CHUNK = 8192


def evaluate_design(
    l1: Point,
    l2: Point,
    weights: np.ndarray,
    params: EmpiricalParams,
    progress: Callable[[int, int], None] | None = None,
    options: SweepOptions | None = None,
    partial: Path | None = None,
) -> DesignResult:
    """All (env, w1, w2) episodes of one design; arrays (4, m, m) [env, i_w1, i_w2]."""
    options = without_reach_bound(options, "in the reduced model")

    def batch(w: np.ndarray, env: np.ndarray) -> SimpleNamespace:
        ep, _ = run(params, l1, l2, w, env)
        return SimpleNamespace(
            first_time=np.where(ep.success, ep.first_step * params.dt, np.nan), min_dist=ep.min_dist, finite=ep.finite
        )

    return sweep(batch, l1, l2, weights, params, options, progress, partial, chunk=CHUNK)
