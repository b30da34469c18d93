"""CPU kernel: the shared model compiled with numba, parallel over trajectories."""

from __future__ import annotations

import numba
import numpy as np

from morphlearn.theory import model
from morphlearn.theory.arrays import points4_arrays, sweep_arrays

_trajectory = model.build(numba.njit(cache=True, inline="never"))
#: The four-synapse controller, the same integrator source (``model.build(..., synapses=4)``).
_trajectory4 = model.build(numba.njit(cache=True, inline="never"), synapses=4)

# Trajectory costs differ by 1000x; small dynamic chunks keep both cores busy to the end.
_CHUNK = 16


@numba.njit(parallel=True, cache=True)
def _sweep(designs, w, starts, radius, horizon, method, rtol, atol, dt, max_steps, out_t, out_d, out_s, out_n):
    nd = designs.shape[0]
    m = w.shape[0]
    ne = starts.shape[0]
    per_design = ne * m * m
    for k in numba.prange(nd * per_design):
        di = k // per_design
        r = k % per_design
        e = r // (m * m)
        i = (r // m) % m
        j = r % m
        ft, dm, st, n = _trajectory(
            starts[e, 0],
            starts[e, 1],
            designs[di, 0],
            designs[di, 1],
            designs[di, 2],
            designs[di, 3],
            w[i],
            w[j],
            0.0,
            0.0,
            radius,
            horizon,
            method,
            rtol,
            atol,
            dt,
            max_steps,
        )
        out_t[di, e, i, j] = ft
        out_d[di, e, i, j] = dm
        out_s[di, e, i, j] = st
        out_n[di, e, i, j] = n


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
    designs, w, starts, (out_t, out_d, out_s, out_n) = sweep_arrays(designs, w, starts)
    with numba.parallel_chunksize(_CHUNK):
        _sweep(
            designs,
            w,
            starts,
            float(radius),
            float(horizon),
            int(method),
            float(rtol),
            float(atol),
            float(dt),
            int(max_steps),
            out_t,
            out_d,
            out_s,
            out_n,
        )
    return out_t, out_d, out_s, out_n


@numba.njit(parallel=True, cache=True)
def _points(designs, starts, di, ei, w1, w2, radius, horizon, method, rtol, atol, dt, max_steps, out_t, out_d, out_s):
    for k in numba.prange(di.shape[0]):
        d = di[k]
        e = ei[k]
        ft, dm, st, _ = _trajectory(
            starts[e, 0],
            starts[e, 1],
            designs[d, 0],
            designs[d, 1],
            designs[d, 2],
            designs[d, 3],
            w1[k],
            w2[k],
            0.0,
            0.0,
            radius,
            horizon,
            method,
            rtol,
            atol,
            dt,
            max_steps,
        )
        out_t[k] = ft
        out_d[k] = dm
        out_s[k] = st


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
    compiled model as :func:`sweep`. Returns (first_time, min_dist, status) per trajectory."""
    designs = np.ascontiguousarray(designs, dtype=np.float64).reshape(-1, 4)
    starts = np.ascontiguousarray(starts, dtype=np.float64)
    di = np.ascontiguousarray(design_idx, dtype=np.int64)
    ei = np.ascontiguousarray(env_idx, dtype=np.int64)
    a = np.ascontiguousarray(w1, dtype=np.float64)
    b = np.ascontiguousarray(w2, dtype=np.float64)
    if not (di.shape == ei.shape == a.shape == b.shape) or di.ndim != 1:
        raise ValueError(
            f"points: design_idx, env_idx, w1, w2 must be 1-d of one length, got "
            f"{di.shape}, {ei.shape}, {a.shape}, {b.shape}"
        )
    n = di.shape[0]
    out_t, out_d, out_s = np.empty(n), np.empty(n), np.empty(n, dtype=np.int8)
    if n:
        with numba.parallel_chunksize(_CHUNK):
            _points(
                designs,
                starts,
                di,
                ei,
                a,
                b,
                float(radius),
                float(horizon),
                int(method),
                float(rtol),
                float(atol),
                float(dt),
                int(max_steps),
                out_t,
                out_d,
                out_s,
            )
    return out_t, out_d, out_s


@numba.njit(parallel=True, cache=True)
def _points4(coords, starts, ei, w, radius, horizon, method, rtol, atol, dt, max_steps, out_t, out_d, out_s):
    for k in numba.prange(ei.shape[0]):
        e = ei[k]
        ft, dm, st, _ = _trajectory4(
            starts[e, 0],
            starts[e, 1],
            coords[k, 0],
            coords[k, 1],
            coords[k, 2],
            coords[k, 3],
            w[k, 0],
            w[k, 1],
            w[k, 2],
            w[k, 3],
            radius,
            horizon,
            method,
            rtol,
            atol,
            dt,
            max_steps,
        )
        out_t[k] = ft
        out_d[k] = dm
        out_s[k] = st


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
    ``env_idx[k]``, weights ``w[k] = (w1, w2, u1, u2)`` (crossed, then uncrossed). With ``u1 = u2 =
    0`` this equals :func:`points` bit for bit (tested). Returns (first_time, min_dist, status)."""
    coords, starts, ei, w, (out_t, out_d, out_s) = points4_arrays(coords, starts, env_idx, w)
    if ei.shape[0]:
        with numba.parallel_chunksize(_CHUNK):
            _points4(
                coords,
                starts,
                ei,
                w,
                float(radius),
                float(horizon),
                int(method),
                float(rtol),
                float(atol),
                float(dt),
                int(max_steps),
                out_t,
                out_d,
                out_s,
            )
    return out_t, out_d, out_s
