"""The one sweep of the physics engines: a design's episodes over (env, w1, w2), or many designs'
at once. An engine is its batch function (the episodes of given weights and environments) plus
data; the levers live here once.

- ``options.adaptive_weights``: the adaptive weight grid (:func:`morphlearn.physics.refine.refine_waves`,
  its lattice stride and near-miss radius from ``options``); cells it never simulates get
  ``STATUS_INFERRED`` and NaN arrays.
- ``screen``: (4, m, m) cells the adaptive grid's first wave also simulates (a cheaper model's
  successes and near misses of the same design, :func:`morphlearn.physics.refine.screen_cells`).
- ``partial``: a file keeping the episodes done so far (saved every ``CHECKPOINT_S`` seconds and
  when the sweep stops on an error or a kill, :mod:`morphlearn.physics.partial`); a design resumes
  from it without simulating them again, to the same bytes (the adaptive grid chooses cells from
  outcomes alone). The design cache removes it once the design's result is stored
  (:func:`morphlearn.physics.design_cache.save`).
- ``progress(done, total)``: this run's episodes against those left (a resumed design's are done).

:func:`sweep_designs` runs several designs' maps in each batch call (a GPU wants thousands of
episodes per call where one design has 4 m^2, :mod:`morphlearn.mujoco.mjwarp`); :func:`sweep` is
one design's. An episode's outcome does not depend on the batch it runs in (each engine's tests
check it), so how the cells are cut into calls changes no result.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from pathlib import Path
from types import SimpleNamespace
from typing import Protocol

import numpy as np

from morphlearn.physics import partial as partial_cells
from morphlearn.physics.batch import Episodes
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import EmpiricalParams
from morphlearn.physics.refine import refine_waves
from morphlearn.results import STATUS_INFERRED, STATUS_NONFINITE, DesignResult

Point = tuple[float, float]


class Outcomes(Protocol):
    """A batch's outcomes, arrays of shape (n,)."""

    first_time: np.ndarray  # first success (NaN: none)
    min_dist: np.ndarray  # closest approach up to success or the end
    finite: np.ndarray  # False where the state became non-finite


#: ``batch(w, env)``: the episodes of weights ``w`` (n, 2) in environments ``env`` (n,).
Batch = Callable[[np.ndarray, np.ndarray], Outcomes]
#: ``batch(design, w, env)``: as :data:`Batch`, each episode of design ``design`` (n,) (an index
#: into the sweep's list of designs).
DesignsBatch = Callable[[np.ndarray, np.ndarray, np.ndarray], Outcomes]


def sweep(
    batch: Batch,
    l1: Point,
    l2: Point,
    weights: np.ndarray,
    params: EmpiricalParams,
    options: SweepOptions,
    progress: Callable[[int, int], None] | None = None,
    partial: Path | None = None,
    chunk: int | None = None,
    screen: np.ndarray | None = None,
) -> DesignResult:
    """All (env, w1, w2) episodes of one design by ``batch``; arrays (4, m, m) [env, i_w1, i_w2].
    ``chunk``: episodes per batch call (progress and checkpoints between calls); None: a whole
    wave of the adaptive grid (or the whole grid) per call."""
    (result,) = sweep_designs(
        lambda _design, w, env: batch(w, env),
        [(l1, l2)],
        weights,
        params,
        options,
        progress,
        [partial],
        chunk=chunk,
        screen=screen,
    )
    return result


def sweep_designs(
    batch: DesignsBatch,
    designs: Sequence[tuple[Point, Point]],
    weights: np.ndarray,
    params: EmpiricalParams,
    options: SweepOptions,
    progress: Callable[[int, int], None] | None = None,
    partials: Sequence[Path | None] | None = None,
    *,
    chunk: int | None = None,
    screen: np.ndarray | None = None,
) -> list[DesignResult]:
    """:func:`sweep` of every design ``(l1, l2)`` of ``designs`` at once: the maps (4 per design,
    map ``4 * design + env``) share each wave's batch calls. ``partials``: each design's partial
    file (or None); ``screen``: (4 * len(designs), m, m) cells the first wave also simulates."""
    w = np.asarray(weights, dtype=np.float64)
    m, nd = len(w), len(designs)
    partials = list(partials) if partials is not None else [None] * nd
    kept = [partial_cells.resume(p, l1, l2, w, params, options) for (l1, l2), p in zip(designs, partials, strict=True)]
    # one (4 nd, m, m) array per field; each design's partial file is saved from its slice of them
    first, dist, status, have = (np.concatenate([getattr(c, k) for _, c in kept]) for k in partial_cells.ARRAYS)

    def cells(d: int) -> partial_cells.Cells:
        sl = slice(4 * d, 4 * d + 4)
        return partial_cells.Cells(first[sl], dist[sl], status[sl], have[sl])

    def save() -> None:
        for d, ((ident, _), p) in enumerate(zip(kept, partials, strict=True)):
            if p is not None and have[4 * d : 4 * d + 4].any():
                partial_cells.save(p, ident, cells(d))

    total = 4 * nd * m * m
    # progress counts this run's episodes against what is left (a resumed design's are done)
    left = total - int(have.sum())
    near = options.near * params.contact_distance
    counted, saved = 0, time.monotonic()

    def simulate(wave: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        nonlocal counted, saved
        todo = wave[~have[tuple(wave.T)]]  # a resumed design's stored episodes are not run again
        step = chunk or max(len(todo), 1)
        for a in range(0, len(todo), step):
            mp, i, j = todo[a : a + step].T
            ep = batch(mp // 4, np.stack([w[i], w[j]], 1), mp % 4)
            first[mp, i, j] = ep.first_time
            dist[mp, i, j] = ep.min_dist
            status[mp[~ep.finite], i[~ep.finite], j[~ep.finite]] = STATUS_NONFINITE
            have[mp, i, j] = True
            counted += len(mp)
            if progress is not None and counted < left:
                progress(counted, left)
            if time.monotonic() - saved >= partial_cells.CHECKPOINT_S:
                save()
                saved = time.monotonic()
        mp, i, j = wave.T
        return ~np.isnan(first[mp, i, j]), dist[mp, i, j] <= near

    try:
        if options.adaptive_weights:
            sim = refine_waves(m, 4 * nd, simulate, options.stride, screen)
            status[~sim] = STATUS_INFERRED
            first[~sim] = np.nan  # a partial file may hold cells this path never asks for
            dist[~sim] = np.nan
        else:
            simulate(np.argwhere(np.ones((4 * nd, m, m), bool)))
    except BaseException:  # Ctrl-C, SIGTERM turned into an exception, an error: keep what is done
        save()
        raise
    if progress is not None:
        progress(total, total)
    return [DesignResult(*(a[4 * d : 4 * d + 4] for a in (first, dist, status))) for d in range(nd)]


def authors_robot_design(
    run: Callable[..., tuple[Episodes, object]],
    l1: Point,
    l2: Point,
    weights: np.ndarray,
    params: EmpiricalParams,
    progress: Callable[[int, int], None] | None = None,
    options: SweepOptions | None = None,
    partial: Path | None = None,
    *,
    where: str,
    chunk: int,
    screen: np.ndarray | None = None,
) -> DesignResult:
    """A design's sweep for an engine of the authors' robot whose ``run(params, l1, l2, w, env)``
    gives :class:`morphlearn.physics.batch.Episodes` (ODE, the reduced model): every episode to its
    first success (no reach bound: it was derived for the project's body), the first success as a
    time. ``where``: the engine, as the refusal of ``early_stop`` names it; ``screen``: cells the
    adaptive grid's first wave also simulates (:func:`sweep`)."""
    options = without_reach_bound(options, where)

    def batch(w: np.ndarray, env: np.ndarray) -> SimpleNamespace:
        ep, _ = run(params, l1, l2, w, env)
        first = np.where(ep.success, ep.first_step * params.dt, np.nan)
        return SimpleNamespace(first_time=first, min_dist=ep.min_dist, finite=ep.finite)

    return sweep(batch, l1, l2, weights, params, options, progress, partial, chunk=chunk, screen=screen)


def without_reach_bound(options: SweepOptions | None, where: str) -> SweepOptions:
    """The sweep options of an engine or robot the reach bound was not derived for (it was for the
    project's body): ``early_stop`` refused, naming ``where``; every episode stops at its first
    success instead, which changes no outcome."""
    options = options or SweepOptions()
    if options.early_stop:
        raise ValueError(f"early_stop (the reach bound) is not available {where}; allowed: false")
    return options
