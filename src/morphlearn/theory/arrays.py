"""Host-side arrays of a sweep, shared by the CPU and CUDA kernels: contiguous float64 inputs and
the four outputs over (design, env, w1, w2)."""

from __future__ import annotations

import numpy as np

Outputs = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def sweep_arrays(
    designs: np.ndarray, w: np.ndarray, starts: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, Outputs]:
    """(designs (nd, 4), w, starts, (first_time, min_dist, status int8, steps int64)), outputs empty."""
    designs = np.ascontiguousarray(designs, dtype=np.float64).reshape(-1, 4)
    w = np.ascontiguousarray(w, dtype=np.float64)
    starts = np.ascontiguousarray(starts, dtype=np.float64)
    shape = (designs.shape[0], starts.shape[0], w.size, w.size)
    out = (np.empty(shape), np.empty(shape), np.empty(shape, dtype=np.int8), np.empty(shape, dtype=np.int64))
    return designs, w, starts, out
