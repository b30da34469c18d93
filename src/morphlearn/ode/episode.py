"""A design's sweep over (env, w1, w2) in ODE: the signature and result of the other physics
models' ``evaluate_design``, with the levers that are exact or validated here.

- Every episode stops at its first success (exact: the outcome is decided; min_dist is then the
  distance at that step, as for the other engines).
- ``options.adaptive_weights``: the adaptive weight grid (:func:`morphlearn.empirical.refine.refine_waves`),
  its miss rate measured at 121 x 121 against exhaustive runs (docs/ode.md).
- ``options.early_stop`` (the reach bound) is refused: its bound was derived for the pybullet body.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from morphlearn.empirical.options import SweepOptions
from morphlearn.empirical.params import EmpiricalParams
from morphlearn.empirical.refine import refine_waves
from morphlearn.ode.core import run
from morphlearn.results import STATUS_INFERRED, STATUS_NONFINITE, STATUS_OK, DesignResult

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
) -> DesignResult:
    """All (env, w1, w2) episodes of one design; arrays (4, m, m) [env, i_w1, i_w2]."""
    options = options or SweepOptions()
    if options.early_stop:
        raise ValueError("early_stop (the reach bound) is not available in the ode model; allowed: false")
    w = np.asarray(weights, dtype=np.float64)
    m = len(w)
    first = np.full((4, m, m), np.nan)
    dist = np.full((4, m, m), np.nan)
    status = np.full((4, m, m), STATUS_OK, dtype=np.int8)
    total = 4 * m * m
    near = options.near * params.contact_distance
    counted = 0

    def simulate(cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        nonlocal counted
        ok = np.zeros(len(cells), bool)
        promising = np.zeros(len(cells), bool)
        for a in range(0, len(cells), CHUNK):
            e, i, j = cells[a : a + CHUNK].T
            ep, _ = run(params, l1, l2, np.stack([w[i], w[j]], 1), e)
            first[e, i, j] = np.where(ep.success, ep.first_step * params.dt, np.nan)
            dist[e, i, j] = ep.min_dist
            status[e[~ep.finite], i[~ep.finite], j[~ep.finite]] = STATUS_NONFINITE
            ok[a : a + CHUNK] = ep.success
            promising[a : a + CHUNK] = ep.min_dist <= near
            counted += len(e)
            if progress is not None and counted < total:
                progress(counted, total)
        return ok, promising

    if options.adaptive_weights:
        sim = refine_waves(m, 4, simulate, options.stride)
        status[~sim] = STATUS_INFERRED
    else:
        simulate(np.argwhere(np.ones((4, m, m), bool)))
    if progress is not None:
        progress(total, total)
    return DesignResult(first_time=first, min_dist=dist, status=status)
