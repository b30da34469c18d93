"""CUDA kernel: the shared model compiled for the GPU, one thread per trajectory, refill scheduling.

The device code is ``model.build(cuda.jit(device=True))``: the same source as the CPU kernel, in
float64, with the whole state in registers. Adaptive step counts differ by up to 1000x between
trajectories, so a thread that finishes one trajectory takes the next index from a global atomic
counter ("refill") instead of idling until the slowest thread of its warp is done; all designs of
a call go into one launch whose grid is sized to what the device keeps resident (DESIGN section 2:
plain one-thread-one-trajectory >150 s, refill 54 s for the full sweep on an H100).

Outputs and signature match :func:`morphlearn.theory.cpu.sweep`; :func:`points4` is the
four-synapse launcher (``model.build(cuda.jit(device=True), synapses=4)``, the CPU
``cpu.points4``'s source) for arbitrary (body coordinates, environment, four weights) points, with
the same refill loop. Results may differ from the CPU
kernel in the last bits (the GPU compiler contracts ``a * b + c`` into fused multiply-adds), which
can flip a trajectory that passes within rounding of the success radius; the CUDA simulator test
(``tests/test_cuda_sim.py``) checks the kernel logic against the CPU kernel without a GPU.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numba import cuda  # a module global: the CUDA simulator swaps it in the kernel's globals

from morphlearn.theory import model
from morphlearn.theory.arrays import points4_arrays, sweep_arrays

_THREADS_PER_BLOCK = 128
_FALLBACK_BLOCKS_PER_SM = 8
_compiled: dict[str, Any] = {}


def available() -> bool:
    """True when numba can see a CUDA GPU (or runs under the CUDA simulator)."""
    try:
        return bool(cuda.is_available())
    except Exception:  # pragma: no cover - broken driver
        return False


def _kernel() -> Any:
    """Compile (once per process) the device model and the refill kernel."""
    if "sweep" in _compiled:
        return _compiled["sweep"]
    trajectory = model.build(cuda.jit(device=True))

    @cuda.jit
    def _sweep(
        designs, w, starts, radius, horizon, method, rtol, atol, dt, max_steps, counter, out_t, out_d, out_s, out_n
    ):
        m = w.shape[0]
        mm = m * m
        per_design = starts.shape[0] * mm
        total = designs.shape[0] * per_design
        k = cuda.atomic.add(counter, 0, 1)
        while k < total:
            di = k // per_design
            r = k - di * per_design
            e = r // mm
            r2 = r - e * mm
            i = r2 // m
            j = r2 - i * m
            ft, dm, st, n = trajectory(
                starts[e, 0],
                starts[e, 1],
                designs[di, 0],
                designs[di, 1],
                designs[di, 2],
                designs[di, 3],
                w[i],
                w[j],
                0.0,  # uncrossed weights: the two-synapse build ignores them
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
            k = cuda.atomic.add(counter, 0, 1)  # refill: next trajectory for this thread

    _compiled["sweep"] = _sweep
    return _sweep


def _kernel4() -> Any:
    """Compile (once per process) the four-synapse device model and its refill kernel over points."""
    if "points4" in _compiled:
        return _compiled["points4"]
    trajectory4 = model.build(cuda.jit(device=True), synapses=4)

    @cuda.jit
    def _points4(
        coords, starts, ei, w, radius, horizon, method, rtol, atol, dt, max_steps, counter, out_t, out_d, out_s
    ):
        total = ei.shape[0]
        k = cuda.atomic.add(counter, 0, 1)
        while k < total:
            e = ei[k]
            ft, dm, st, _ = trajectory4(
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
            k = cuda.atomic.add(counter, 0, 1)  # refill, as in the sweep

    _compiled["points4"] = _points4
    return _points4


def _grid_blocks(kernel: Any, args: tuple, total: int) -> int:
    """Blocks to launch: as many as the device keeps resident at once (each thread then loops),
    but no more than the trajectories need."""
    dev = cuda.get_current_device()
    sms = int(getattr(dev, "MULTIPROCESSOR_COUNT", 1))
    blocks = sms * _FALLBACK_BLOCKS_PER_SM
    try:  # resident blocks for this kernel's register use (occupancy)
        compiled = kernel.compile(tuple(kernel.typeof_pyval(a) for a in args))
        blocks = int(compiled.max_cooperative_grid_blocks(_THREADS_PER_BLOCK)) or blocks
    except Exception:
        pass
    need = -(-total // _THREADS_PER_BLOCK)
    return max(1, min(blocks, need))


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
    """Evaluate designs (nd, 4) x envs x w x w on the GPU in one launch.

    Returns (first_time, min_dist, status, steps) as host arrays, like ``cpu.sweep``.
    """
    designs, w, starts, (out_t, out_d, out_s, out_n) = sweep_arrays(designs, w, starts)
    shape = out_t.shape
    total = out_t.size
    if total == 0:
        return out_t, out_d, out_s, out_n
    kernel = _kernel()
    d_out = [cuda.device_array(shape, dtype=a.dtype) for a in (out_t, out_d, out_s, out_n)]
    args = (
        cuda.to_device(designs),
        cuda.to_device(w),
        cuda.to_device(starts),
        np.float64(radius),
        np.float64(horizon),
        np.int64(method),
        np.float64(rtol),
        np.float64(atol),
        np.float64(dt),
        np.int64(max_steps),
        cuda.to_device(np.zeros(1, dtype=np.int64)),
        *d_out,
    )
    blocks = _grid_blocks(kernel, args, total)
    kernel[blocks, _THREADS_PER_BLOCK](*args)
    cuda.synchronize()
    for dev_arr, host in zip(d_out, (out_t, out_d, out_s, out_n), strict=True):
        dev_arr.copy_to_host(host)
    return out_t, out_d, out_s, out_n


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
    """Four-synapse trajectories on the GPU in one launch; arguments and returns as
    :func:`morphlearn.theory.cpu.points4` (coords (n, 4), env_idx (n,), w (n, 4) = (w1, w2, u1, u2))."""
    coords, starts, ei, w, (out_t, out_d, out_s) = points4_arrays(coords, starts, env_idx, w)
    n = ei.shape[0]
    if n == 0:
        return out_t, out_d, out_s
    kernel = _kernel4()
    d_out = [cuda.device_array(a.shape, dtype=a.dtype) for a in (out_t, out_d, out_s)]
    args = (
        cuda.to_device(coords),
        cuda.to_device(starts),
        cuda.to_device(ei),
        cuda.to_device(w),
        np.float64(radius),
        np.float64(horizon),
        np.int64(method),
        np.float64(rtol),
        np.float64(atol),
        np.float64(dt),
        np.int64(max_steps),
        cuda.to_device(np.zeros(1, dtype=np.int64)),
        *d_out,
    )
    blocks = _grid_blocks(kernel, args, n)
    kernel[blocks, _THREADS_PER_BLOCK](*args)
    cuda.synchronize()
    for dev_arr, host in zip(d_out, (out_t, out_d, out_s), strict=True):
        dev_arr.copy_to_host(host)
    return out_t, out_d, out_s


def device_description() -> str:
    """Name and compute capability of the current device (for benchmarks and logs)."""
    dev = cuda.get_current_device()
    name = dev.name.decode() if isinstance(dev.name, bytes) else str(dev.name)
    return f"{name} (compute capability {dev.compute_capability[0]}.{dev.compute_capability[1]})"
