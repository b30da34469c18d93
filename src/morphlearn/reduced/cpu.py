"""The reduced model's CPU kernel: the episode of kernel.py compiled with numba, episodes in
parallel over cores. (Stepping 8 episodes side by side on a core, to overlap their dependency
chains, measured 1.4x slower: the state then lives in memory, not registers. Across SIMD lanes it
is faster: :mod:`morphlearn.reduced.simd`, ``reduced.backend: cpu-simd``.)"""

from __future__ import annotations

import numba
import numpy as np

from morphlearn.reduced.kernel import build

_k = build(numba.njit(cache=True))
_episode = _k.episode


@numba.njit(parallel=True, cache=True)
def run_batch(g, hm, kk, cen, dt, steps, vmax, tmax, radius, dz2, lights, sen, w, stop, first, dmin, nsteps, finite):
    """Episodes i = 0..n-1 of weights ``w[i]`` with the light ``lights[i]``; one design's body."""
    n = w.shape[0]
    nopath = np.empty((0, 2))
    for i in numba.prange(n):
        first[i], dmin[i], nsteps[i], finite[i] = _episode(
            g,
            hm,
            kk,
            cen,
            dt,
            steps,
            vmax,
            tmax,
            radius,
            dz2,
            lights[i, 0],
            lights[i, 1],
            sen[0],
            sen[1],
            sen[2],
            sen[3],
            w[i, 0],
            w[i, 1],
            stop,
            nopath,
        )


@numba.njit(cache=True)
def run_path(g, hm, kk, cen, dt, steps, vmax, tmax, radius, dz2, light, sen, w1, w2, stop, path):
    """One episode with its path (the centre at each step)."""
    return _episode(
        g,
        hm,
        kk,
        cen,
        dt,
        steps,
        vmax,
        tmax,
        radius,
        dz2,
        light[0],
        light[1],
        sen[0],
        sen[1],
        sen[2],
        sen[3],
        w1,
        w2,
        stop,
        path,
    )
