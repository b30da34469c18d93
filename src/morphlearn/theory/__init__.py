"""The theoretical (ODE) model: fast batched evaluation and a scipy reference."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from tqdm import tqdm

from morphlearn.grid import env_starts
from morphlearn.results import DesignResult
from morphlearn.theory.model import METHOD_DP5, METHOD_RK4


@dataclass(frozen=True)
class TheoryParams:
    r: float = 4.0
    horizon: float = 500.0
    success_radius: float = 0.2
    integrator: str = "dp5"
    rtol: float = 1e-8
    atol: float = 1e-8
    dt: float = 0.01
    max_steps: int = 10_000
    #: Kernel backend: ``cpu``, ``cuda`` or ``auto`` (CUDA when numba sees a GPU). Not part of the
    #: science digest: both kernels compute the same model (see ``resolve_backend``).
    backend: str = "cpu"

    @classmethod
    def from_config(cls, th: dict[str, Any]) -> TheoryParams:
        return cls(**{k: th[k] for k in cls.__dataclass_fields__ if k in th})

    @property
    def method(self) -> int:
        return METHOD_DP5 if self.integrator == "dp5" else METHOD_RK4

    def kernel_kwargs(self) -> dict[str, Any]:
        """The keyword arguments every kernel launcher takes (``cpu``/``cuda`` ``sweep``,
        ``points``, ``points4``): one place that maps the parameters onto the kernels'."""
        return {
            "radius": self.success_radius,
            "horizon": self.horizon,
            "method": self.method,
            "rtol": self.rtol,
            "atol": self.atol,
            "dt": self.dt,
            "max_steps": self.max_steps,
        }


BACKENDS = ("auto", "cpu", "cuda")
#: Trajectories per kernel call when none is given: bounded memory and progress on the CPU; on the
#: GPU as many as possible in one launch (refill scheduling keeps the device busy to the end), 25
#: bytes of device memory each.
CPU_BATCH = 400_000
CUDA_BATCH = 64_000_000


def resolve_backend(backend: str) -> str:
    """``cpu`` or ``cuda`` for a configured backend; ``auto`` picks CUDA when a GPU is visible."""
    if backend not in BACKENDS:
        raise ValueError(f"theory backend must be one of {BACKENDS}, got {backend!r}")
    if backend == "cpu":
        return "cpu"
    from morphlearn.theory import cuda

    if cuda.available():
        return "cuda"
    if backend == "cuda":
        raise RuntimeError(
            "theory.backend is 'cuda' but numba sees no CUDA GPU (numba.cuda.is_available() is False): "
            "check the NVIDIA driver and that numba-cuda with the CUDA toolkit wheels is installed "
            "(numba-cuda[cu12]), or set theory.backend to 'cpu' or 'auto'"
        )
    return "cpu"


def evaluate(
    designs: np.ndarray,
    weights: np.ndarray,
    p: TheoryParams,
    *,
    progress: bool = False,
    batch_trajectories: int | None = None,
    return_steps: bool = False,
    done: Callable[[int, DesignResult], None] | None = None,
) -> list[DesignResult] | tuple[list[DesignResult], np.ndarray]:
    """Evaluate designs given as coordinates (nd, 4) over envs x weights x weights on the backend
    ``p.backend`` selects (CPU kernel, or CUDA kernel with one launch per batch).

    ``done(i, result)`` is called for each design as its batch finishes, so that a caller can save
    finished designs while a long shard is still running (a killed shard loses one batch)."""
    backend = resolve_backend(p.backend)
    if backend == "cuda":
        from morphlearn.theory import cuda as kernel
    else:
        from morphlearn.theory import cpu as kernel  # type: ignore[no-redef]
    if batch_trajectories is None:
        batch_trajectories = CUDA_BATCH if backend == "cuda" else CPU_BATCH

    designs = np.asarray(designs, dtype=np.float64).reshape(-1, 4)
    m = len(weights)
    per_batch = max(1, batch_trajectories // (4 * m * m))
    starts = env_starts(p.r)
    out: list[DesignResult] = []
    steps = []
    bar = tqdm(total=len(designs), unit="design", disable=not progress, mininterval=1.0)
    for a in range(0, len(designs), per_batch):
        ft, dm, st, n = kernel.sweep(
            designs[a : a + per_batch],
            weights,
            starts,
            **p.kernel_kwargs(),
        )
        for i in range(len(ft)):
            out.append(DesignResult(ft[i], dm[i], st[i]))
            if done:
                done(len(out) - 1, out[-1])
        if return_steps:
            steps.append(n)
        bar.update(len(ft))
    bar.close()
    if return_steps:
        return out, np.concatenate(steps) if steps else np.zeros((0, 4, m, m), np.int64)
    return out
