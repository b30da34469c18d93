"""Host-side arrays shared by the CPU and CUDA kernels: a sweep's contiguous float64 inputs and
its four outputs over (design, env, w1, w2); the four-synapse points' inputs and outputs."""

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


def points4_arrays(
    coords: np.ndarray, starts: np.ndarray, env_idx: np.ndarray, w: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """(coords (n, 4), starts, env_idx (n,) int64, w (n, 4), (first_time, min_dist, status int8))
    of four-synapse points, outputs empty; refuses inputs of other shapes."""
    coords = np.ascontiguousarray(coords, dtype=np.float64)
    starts = np.ascontiguousarray(starts, dtype=np.float64)
    ei = np.ascontiguousarray(env_idx, dtype=np.int64)
    w = np.ascontiguousarray(w, dtype=np.float64)
    n = ei.shape[0] if ei.ndim == 1 else -1
    if ei.ndim != 1 or coords.shape != (n, 4) or w.shape != (n, 4):
        raise ValueError(
            f"points4: env_idx must be 1-d (n,), coords and w (n, 4); got {ei.shape}, {coords.shape}, {w.shape}"
        )
    return coords, starts, ei, w, (np.empty(n), np.empty(n), np.empty(n, dtype=np.int8))
