"""The reduced model's CUDA kernel: the episode of kernel.py compiled for the GPU
(``build(cuda.jit(device=True))``: the same source as the CPU kernel, float64, the state in
registers), one thread an episode over a grid-stride loop. Outputs and signature match
:func:`morphlearn.reduced.cpu.run_batch`. The GPU compiler may contract ``a * b + c`` into fused
multiply-adds, so results can differ from the CPU kernel in the last bits (an episode that passes
within rounding of the success radius can flip); ``tests/test_reduced.py`` checks the kernel's
logic against the CPU kernel under numba's CUDA simulator, without a GPU. Not yet wired to a
config key: call :func:`morphlearn.reduced.core.run` with ``backend="cuda"``."""

from __future__ import annotations

from typing import Any

import numpy as np
from numba import cuda  # a module global: the CUDA simulator swaps it in

from morphlearn.reduced.kernel import build

_THREADS_PER_BLOCK = 128
_compiled: dict[str, Any] = {}


def available() -> bool:
    """True when numba can see a CUDA GPU (or runs under the CUDA simulator)."""
    try:
        return bool(cuda.is_available())
    except Exception:  # pragma: no cover - a broken driver
        return False


def _kernel() -> Any:
    if "batch" in _compiled:
        return _compiled["batch"]
    episode = build(cuda.jit(device=True)).episode

    @cuda.jit
    def batch(
        g, hm, kk, cen, dt, steps, vmax, tmax, radius, dz2, lights, sen, w, stop, nopath, first, dmin, nsteps, ok
    ):
        i = cuda.grid(1)
        stride = cuda.gridsize(1)
        while i < w.shape[0]:
            h, b, k, good = episode(
                g, hm, kk, cen, dt, steps, vmax, tmax, radius, dz2, lights[i, 0], lights[i, 1],
                sen[0], sen[1], sen[2], sen[3], w[i, 0], w[i, 1], stop, nopath,
            )  # fmt: skip
            first[i] = h
            dmin[i] = b
            nsteps[i] = k
            ok[i] = good
            i += stride

    _compiled["batch"] = batch
    return batch


def run_batch(g, hm, kk, cen, dt, steps, vmax, tmax, radius, dz2, lights, sen, w, stop, first, dmin, nsteps, finite):
    """:func:`morphlearn.reduced.cpu.run_batch` on the GPU: inputs copied in, outputs copied back."""
    n = w.shape[0]
    if n == 0:
        return
    d = {
        k: cuda.to_device(np.ascontiguousarray(v))
        for k, v in dict(g=g, hm=hm, kk=kk, cen=cen, lights=lights, sen=sen, w=w).items()
    }
    outs = [cuda.device_array(n, dtype=a.dtype) for a in (first, dmin, nsteps, finite)]
    blocks = (n + _THREADS_PER_BLOCK - 1) // _THREADS_PER_BLOCK
    _kernel()[blocks, _THREADS_PER_BLOCK](
        d["g"], d["hm"], d["kk"], d["cen"], dt, steps, vmax, tmax, radius, dz2, d["lights"], d["sen"], d["w"], stop,
        cuda.to_device(np.zeros((0, 2))), *outs,
    )  # fmt: skip
    for host, dev in zip((first, dmin, nsteps, finite), outs, strict=True):
        host[:] = dev.copy_to_host()
