"""A design's sweep over (env, w1, w2) in the reduced model: the physics layer's sweep
(:func:`morphlearn.physics.sweep.sweep`: adaptive grid, resume, progress) over this model's batches,
with the signature and result of every physics model's ``evaluate_design``."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import EmpiricalParams
from morphlearn.physics.sweep import authors_robot_design
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
    return authors_robot_design(
        run, l1, l2, weights, params, progress, options, partial, where="in the reduced model", chunk=CHUNK
    )
