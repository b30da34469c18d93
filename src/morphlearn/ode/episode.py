"""A design's sweep over (env, w1, w2) in ODE: the signature and result of the other physics
models' ``evaluate_design``, with the levers that are exact or validated here.

- Every episode stops at its first success (exact: the outcome is decided; min_dist is then the
  distance at that step, as for the other engines).
- ``options.adaptive_weights``: the adaptive weight grid (:func:`morphlearn.physics.refine.refine_waves`),
  its miss rate measured at 121 x 121 against exhaustive runs (docs/ode.md).
- ``options.early_stop`` (the reach bound) is refused: its bound was derived for the pybullet body.

A design resumes inside itself (``partial``, :mod:`morphlearn.physics.partial`): at the paper's
121 x 121 weights a design is about half an hour of one core, too long a unit to lose to a kill.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from morphlearn.ode.core import run
from morphlearn.physics import partial as partial_cells
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import EmpiricalParams
from morphlearn.physics.refine import refine_waves
from morphlearn.results import STATUS_INFERRED, STATUS_NONFINITE, DesignResult

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
) -> DesignResult:
    """All (env, w1, w2) episodes of one design; arrays (4, m, m) [env, i_w1, i_w2].

    ``partial``: a file keeping the episodes done so far (saved every ``CHECKPOINT_S`` seconds and
    when the design stops on an error or a kill); a design resumes from it without simulating them
    again, to the same bytes (the adaptive grid chooses cells from outcomes alone). The caller
    removes it once the design's result is stored."""
    options = options or SweepOptions()
    if options.early_stop:
        raise ValueError("early_stop (the reach bound) is not available in the ode model; allowed: false")
    w = np.asarray(weights, dtype=np.float64)
    m = len(w)
    ident, cells = partial_cells.resume(partial, l1, l2, w, params, options)
    first, dist, status, have = cells.first_time, cells.min_dist, cells.status, cells.simulated
    total = 4 * m * m
    near = options.near * params.contact_distance
    counted, saved = 0, time.monotonic()

    def simulate(wave: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        nonlocal counted, saved
        todo = wave[~have[tuple(wave.T)]]  # a resumed design's stored episodes are not run again
        for a in range(0, len(todo), CHUNK):
            e, i, j = todo[a : a + CHUNK].T
            ep, _ = run(params, l1, l2, np.stack([w[i], w[j]], 1), e)
            first[e, i, j] = np.where(ep.success, ep.first_step * params.dt, np.nan)
            dist[e, i, j] = ep.min_dist
            status[e[~ep.finite], i[~ep.finite], j[~ep.finite]] = STATUS_NONFINITE
            have[e, i, j] = True
            counted += len(e)
            if progress is not None and counted < total:
                progress(counted, total)
            if partial is not None and time.monotonic() - saved >= partial_cells.CHECKPOINT_S:
                partial_cells.save(partial, ident, cells)
                saved = time.monotonic()
        e, i, j = wave.T
        return ~np.isnan(first[e, i, j]), dist[e, i, j] <= near

    try:
        if options.adaptive_weights:
            sim = refine_waves(m, 4, simulate, options.stride)
            status[~sim] = STATUS_INFERRED
            first[~sim] = np.nan  # a partial file may hold cells this path never asks for
            dist[~sim] = np.nan
        else:
            simulate(np.argwhere(np.ones((4, m, m), bool)))
    except BaseException:  # Ctrl-C, SIGTERM turned into an exception, an error: keep what is done
        if partial is not None and have.any():
            partial_cells.save(partial, ident, cells)
        raise
    if progress is not None:
        progress(total, total)
    return DesignResult(first_time=first, min_dist=dist, status=status)
