"""A design's sweep over (env, w1, w2) in ODE: the signature and result of the other physics
models' ``evaluate_design``, with the levers that are exact or validated here.

- Every episode stops at its first success (exact: the outcome is decided; min_dist is then the
  distance at that step, as for the other engines).
- ``options.adaptive_weights``: the adaptive weight grid (the physics layer's sweep,
  :mod:`morphlearn.physics.sweep`), its miss rate measured at 121 x 121 against exhaustive runs (docs/ode.md).
- ``options.early_stop`` (the reach bound) is refused: its bound was derived for the pybullet body.

A design resumes inside itself (``partial``, :mod:`morphlearn.physics.partial`): at the paper's
121 x 121 weights a design is about half an hour of one core, too long a unit to lose to a kill.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from morphlearn.ode.core import run
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import EmpiricalParams
from morphlearn.physics.sweep import authors_robot_design
from morphlearn.results import DesignResult

Point = tuple[float, float]
#: Episodes per C call: progress is reported between calls; results do not depend on it.
CHUNK = 256


def evaluate_design(
    l1: Point,
    l2: Point,
    weights: np.ndarray,
    params: EmpiricalParams,
    progress: Callable[[int, int], None] | None = None,
    options: SweepOptions | None = None,
    partial: Path | None = None,
    screen: np.ndarray | None = None,
) -> DesignResult:
    """All (env, w1, w2) episodes of one design; arrays (4, m, m) [env, i_w1, i_w2]: the physics
    layer's sweep (:func:`morphlearn.physics.sweep.sweep`: adaptive grid, resume from ``partial``)
    over this engine's batches; ``screen``: cells its adaptive grid's first wave also simulates."""
    return authors_robot_design(
        run, l1, l2, weights, params, progress, options, partial, where="in the ode model", chunk=CHUNK, screen=screen
    )
