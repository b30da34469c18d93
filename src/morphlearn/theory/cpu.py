"""CPU kernel: the shared model compiled with numba, parallel over trajectories."""

from __future__ import annotations

import types
from typing import Any

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


#: Resolved per compiled twin by :func:`_points_kernel` (a placeholder for the source's global).
_trajectory_of_points: Any = None


def _points_source(coords, starts, ei, w, radius, horizon, method, rtol, atol, dt, max_steps, out_t, out_d, out_s):
    # compiled once per controller by _points_kernel: ``_trajectory_of_points`` is that
    # controller's trajectory (the two-synapse one ignores w[k, 2:])
    for k in numba.prange(ei.shape[0]):
        e = ei[k]
        ft, dm, st, _ = _trajectory_of_points(
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


def _points_kernel(trajectory: Any, synapses: int) -> Any:
    """The points loop compiled against one controller's trajectory, in a fresh namespace (as
    model.build does). numba's on-disk cache keys a function by file, line and qualname, so each
    controller's loop gets a qualname of its own: with one name the second would load the first's
    machine code."""
    ns: dict[str, Any] = dict(globals())
    ns["_trajectory_of_points"] = trajectory
    f = _points_source
    g = types.FunctionType(f.__code__, ns, f"_points_synapses{synapses}", f.__defaults__, f.__closure__)
    g.__qualname__ = f"_points_synapses{synapses}"
    return numba.njit(parallel=True, cache=True)(g)


_points2 = _points_kernel(_trajectory, 2)
_points4 = _points_kernel(_trajectory4, 4)


def _launch_points(
    kernel: Any,
    coords: np.ndarray,
    starts: np.ndarray,
    env_idx: np.ndarray,
    w: np.ndarray,
    radius: float,
    horizon: float,
    method: int,
    rtol: float,
    atol: float,
    dt: float,
    max_steps: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Run a points loop (:func:`_points_kernel`) on (n, 4) body coordinates and weights."""
    coords, starts, ei, w, (out_t, out_d, out_s) = points4_arrays(coords, starts, env_idx, w)
    if ei.shape[0]:
        with numba.parallel_chunksize(_CHUNK):
            kernel(
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
    # the four-synapse points' layout; the two-synapse loop never reads the zero columns
    w = np.zeros((a.size, 4))
    w[:, 0], w[:, 1] = a, b
    coords = designs[di.astype(np.int64)]
    return _launch_points(_points2, coords, starts, ei, w, radius, horizon, method, rtol, atol, dt, max_steps)


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
    return _launch_points(_points4, coords, starts, env_idx, w, radius, horizon, method, rtol, atol, dt, max_steps)
