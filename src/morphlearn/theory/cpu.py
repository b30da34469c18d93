"""CPU kernel: the shared model compiled with numba, parallel over trajectories."""

from __future__ import annotations

from typing import Any

import numba
import numpy as np

from morphlearn.theory import cells, model
from morphlearn.theory.arrays import points4_arrays, sweep_arrays

#: The two- and four-synapse controllers' cells (one trajectory each, read and written), compiled
#: for the CPU; the loops below are all this backend adds.
_CELLS = {s: cells.build(numba.njit(cache=True, inline="never"), synapses=s) for s in (2, 4)}
_sweep_cell = _CELLS[2].sweep

# Trajectory costs differ by 1000x; small dynamic chunks keep both cores busy to the end.
_CHUNK = 16


@numba.njit(parallel=True, cache=True)
def _sweep(designs, w, starts, params, out_t, out_d, out_s, out_n):
    for k in numba.prange(out_t.size):
        _sweep_cell(k, designs, w, starts, params, out_t, out_d, out_s, out_n)


def sweep(
    designs: np.ndarray,
    w: np.ndarray,
    starts: np.ndarray,
    *,
    radius: float,
    horizon: float,
    method: int,
    rtol: float,
    atol: float,
    dt: float,
    max_steps: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Evaluate designs (nd, 4) x envs x w x w. Returns (first_time, min_dist, status, steps)."""
    designs, w, starts, out = sweep_arrays(designs, w, starts)
    with numba.parallel_chunksize(_CHUNK):
        _sweep(designs, w, starts, cells.params(radius, horizon, method, rtol, atol, dt, max_steps), *out)
    return out


#: Resolved per compiled twin by :func:`_points_kernel` (a placeholder for the source's global).
_points_cell: Any = None


def _points_source(coords, starts, ei, w, params, out_t, out_d, out_s):
    # compiled once per controller by _points_kernel: ``_points_cell`` is that controller's cell
    for k in numba.prange(ei.shape[0]):
        _points_cell(k, coords, starts, ei, w, params, out_t, out_d, out_s)


def _points_kernel(synapses: int) -> Any:
    """The points loop compiled against one controller's cell, a twin of its own (model.twin)."""
    ns: dict[str, Any] = {**globals(), "_points_cell": _CELLS[synapses].points}
    return numba.njit(parallel=True, cache=True)(model.twin(_points_source, ns, synapses, "_points"))


_POINTS = {s: _points_kernel(s) for s in (2, 4)}


def _launch_points(
    synapses: int, coords: np.ndarray, starts: np.ndarray, env_idx: np.ndarray, w: np.ndarray, params: tuple
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Run a controller's points loop on (n, 4) body coordinates and weights (``cells.params``)."""
    coords, starts, ei, w, out = points4_arrays(coords, starts, env_idx, w)
    if ei.shape[0]:
        with numba.parallel_chunksize(_CHUNK):
            _POINTS[synapses](coords, starts, ei, w, params, *out)
    return out


def points(
    designs: np.ndarray,
    starts: np.ndarray,
    design_idx: np.ndarray,
    env_idx: np.ndarray,
    w1: np.ndarray,
    w2: np.ndarray,
    *,
    radius: float,
    horizon: float,
    method: int,
    rtol: float,
    atol: float,
    dt: float,
    max_steps: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Evaluate arbitrary trajectories ``k``: design ``designs[design_idx[k]]`` in environment
    ``env_idx[k]`` with weights ``(w1[k], w2[k])`` (continuous, not only grid points), the same
    compiled model as :func:`sweep`. The keywords: ``**TheoryParams.kernel_kwargs()``.
    Returns (first_time, min_dist, status) per trajectory."""
    designs = np.ascontiguousarray(designs, dtype=np.float64).reshape(-1, 4)
    di = np.asarray(design_idx)
    ei = np.asarray(env_idx)
    a = np.asarray(w1, dtype=np.float64)
    b = np.asarray(w2, dtype=np.float64)
    if not (di.shape == ei.shape == a.shape == b.shape) or di.ndim != 1:
        raise ValueError(
            f"points: design_idx, env_idx, w1, w2 must be 1-d of one length, got "
            f"{di.shape}, {ei.shape}, {a.shape}, {b.shape}"
        )
    # the four-synapse points' layout; the two-synapse trajectory ignores the zero columns
    w = np.zeros((a.size, 4))
    w[:, 0], w[:, 1] = a, b
    coords = designs[di.astype(np.int64)]
    return _launch_points(2, coords, starts, ei, w, cells.params(radius, horizon, method, rtol, atol, dt, max_steps))


def points4(
    coords: np.ndarray,
    starts: np.ndarray,
    env_idx: np.ndarray,
    w: np.ndarray,
    *,
    radius: float,
    horizon: float,
    method: int,
    rtol: float,
    atol: float,
    dt: float,
    max_steps: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Four-synapse trajectories ``k``: design coordinates ``coords[k] = (l1x, l1y, l2x, l2y)``
    (any point of the body square, so a co-optimised body needs no grid), environment
    ``env_idx[k]``, weights ``w[k] = (w1, w2, u1, u2)`` (crossed, then uncrossed).
    With ``u1 = u2 = 0`` this equals :func:`points` bit for bit (tested).
    Returns (first_time, min_dist, status)."""
    params = cells.params(radius, horizon, method, rtol, atol, dt, max_steps)
    return _launch_points(4, coords, starts, env_idx, w, params)
