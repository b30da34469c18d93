"""CUDA kernel: the shared model compiled for the GPU, one thread per trajectory, refill scheduling.

The device code is ``cells.build(cuda.jit(device=True))``: the CPU kernel's cells (a trajectory's
inputs read, ``model.build``'s trajectory run, its outputs written), in float64, with the whole
state in registers; this module adds only the refill loop, the launch and the transfers. Adaptive
step counts differ by up to 1000x between trajectories, so a thread that finishes one trajectory
takes the next index from a global atomic counter ("refill") instead of idling until the slowest
thread of its warp is done; all designs of a call go into one launch whose grid is sized to what
the device keeps resident (DESIGN section 2: plain one-thread-one-trajectory >150 s, refill 54 s
for the full sweep on an H100).

Outputs and signature match :func:`morphlearn.theory.cpu.sweep`; :func:`points4` is the
four-synapse launcher (the four-synapse cells, the CPU ``cpu.points4``'s source) for arbitrary
(body coordinates, environment, four weights) points, with the same refill loop. Results may
differ from the CPU kernel in the last bits (the GPU compiler contracts ``a * b + c`` into fused
multiply-adds), which can flip a trajectory that passes within rounding of the success radius; the
CUDA simulator test (``tests/test_cuda_sim.py``) checks the kernel logic against the CPU kernel
without a GPU.
"""

from __future__ import annotations

from typing import Any, TypeVar

import numpy as np
from numba import cuda  # a module global: the CUDA simulator swaps it in the kernel's globals

from morphlearn.theory import cells
from morphlearn.theory.arrays import points4_arrays, sweep_arrays

_THREADS_PER_BLOCK = 128
_FALLBACK_BLOCKS_PER_SM = 8
_compiled: dict[str, Any] = {}
#: A launch's host outputs (a sweep's four, a points call's three).
_Out = TypeVar("_Out", bound=tuple[np.ndarray, ...])


def available() -> bool:
    """True when numba can see a CUDA GPU (or runs under the CUDA simulator)."""
    try:
        return bool(cuda.is_available())
    except Exception:  # pragma: no cover - broken driver
        return False


def _kernels() -> dict[str, Any]:
    """Compile (once per process) the device cells and the refill kernels that loop over them: a
    thread that finishes its trajectory takes the next index from the global counter."""
    if _compiled:
        return _compiled
    sweep_cell = cells.build(cuda.jit(device=True)).sweep
    points4_cell = cells.build(cuda.jit(device=True), synapses=4).points

    @cuda.jit
    def _sweep(designs, w, starts, params, counter, out_t, out_d, out_s, out_n):
        k = cuda.atomic.add(counter, 0, 1)
        while k < out_t.size:
            sweep_cell(k, designs, w, starts, params, out_t, out_d, out_s, out_n)
            k = cuda.atomic.add(counter, 0, 1)  # refill: next trajectory for this thread

    @cuda.jit
    def _points4(coords, starts, ei, w, params, counter, out_t, out_d, out_s):
        k = cuda.atomic.add(counter, 0, 1)
        while k < out_t.size:
            points4_cell(k, coords, starts, ei, w, params, out_t, out_d, out_s)
            k = cuda.atomic.add(counter, 0, 1)  # refill, as in the sweep

    _compiled.update(sweep=_sweep, points4=_points4)
    return _compiled


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


def _launch(kernel: Any, inputs: tuple[np.ndarray, ...], params: tuple, out: _Out) -> _Out:
    """One refill launch of ``kernel(*inputs, params, counter, *out)``: the inputs copied to the
    device, the counter zeroed, the outputs copied back into ``out`` (returned)."""
    total = out[0].size
    if total == 0:
        return out
    d_out = [cuda.device_array(a.shape, dtype=a.dtype) for a in out]
    args = (*(cuda.to_device(a) for a in inputs), params, cuda.to_device(np.zeros(1, dtype=np.int64)), *d_out)
    kernel[_grid_blocks(kernel, args, total), _THREADS_PER_BLOCK](*args)
    cuda.synchronize()
    for dev_arr, host in zip(d_out, out, strict=True):
        dev_arr.copy_to_host(host)
    return out


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
    designs, w, starts, out = sweep_arrays(designs, w, starts)
    params = cells.params(radius, horizon, method, rtol, atol, dt, max_steps)
    return _launch(_kernels()["sweep"], (designs, w, starts), params, out)


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
    coords, starts, ei, w, out = points4_arrays(coords, starts, env_idx, w)
    params = cells.params(radius, horizon, method, rtol, atol, dt, max_steps)
    return _launch(_kernels()["points4"], (coords, starts, ei, w), params, out)


def device_description() -> str:
    """Name and compute capability of the current device (for benchmarks and logs)."""
    dev = cuda.get_current_device()
    name = dev.name.decode() if isinstance(dev.name, bytes) else str(dev.name)
    return f"{name} (compute capability {dev.compute_capability[0]}.{dev.compute_capability[1]})"
