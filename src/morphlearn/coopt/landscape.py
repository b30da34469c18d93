"""M_L and M_CF over the four-synapse controller space of one design, on a grid of weights.

The grid is ``weights(m)`` per weight (crossed ``w1, w2`` and uncrossed ``u1, u2``), so for odd
``m`` it contains the two-synapse controllers (``u1 = u2 = 0``) as a slice: their M_L / M_CF on
the same ``m x m`` grid come from the same trajectories and are reported beside the four-weight
values. Success is the metrics module's: first entry into the success circle within the horizon,
flagged trajectories failing.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from morphlearn.grid import env_starts, weights
from morphlearn.theory import TheoryParams

N_ENV = 4


@dataclass(frozen=True)
class Landscape:
    m: int
    controllers: int
    generalists: int
    at_least_one: int
    flagged: int
    generalists_2w: int  # the slice u1 = u2 = 0 (m x m controllers)
    at_least_one_2w: int

    @property
    def m_l(self) -> float:
        return self.generalists / self.controllers

    @property
    def m_cf(self) -> float:
        return self.generalists / self.at_least_one if self.at_least_one else 0.0

    @property
    def m_l_2w(self) -> float:
        return self.generalists_2w / self.m**2

    @property
    def m_cf_2w(self) -> float:
        return self.generalists_2w / self.at_least_one_2w if self.at_least_one_2w else 0.0


def successes(coords: np.ndarray, m: int, p: TheoryParams, *, chunk: int = 200_000) -> tuple[np.ndarray, int]:
    """Success (4, m, m, m, m) over (env, w1, w2, u1, u2) of design ``coords`` (4,), and the number
    of flagged trajectories."""
    from morphlearn.theory import cpu

    w = weights(m)
    grid = np.stack(np.meshgrid(w, w, w, w, indexing="ij"), axis=-1).reshape(-1, 4)
    n = grid.shape[0]
    ok = np.empty((N_ENV, n), dtype=bool)
    flagged = 0
    starts = env_starts(p.r)
    step = max(1, chunk // N_ENV)
    for a in range(0, n, step):
        g = grid[a : a + step]
        k = len(g)
        env = np.repeat(np.arange(N_ENV), k)
        ft, _, st = cpu.points4(
            np.broadcast_to(np.asarray(coords, dtype=np.float64), (N_ENV * k, 4)),
            starts,
            env,
            np.tile(g, (N_ENV, 1)),
            **p.kernel_kwargs(),
        )
        with np.errstate(invalid="ignore"):
            ok[:, a : a + k] = ((st == 0) & (ft <= p.horizon)).reshape(N_ENV, k)
        flagged += int((st != 0).sum())
    return ok.reshape(N_ENV, m, m, m, m), flagged


def landscape(coords: np.ndarray, m: int, p: TheoryParams) -> Landscape:
    """Counts of one design's four-weight landscape (and of its two-weight slice)."""
    if m < 3 or m % 2 == 0:
        raise ValueError(f"landscape grid: m must be odd and >= 3 (so u = 0 is on it), got {m}")
    ok, flagged = successes(coords, m, p)
    o = ok.sum(axis=0)
    s2 = o[:, :, m // 2, m // 2]
    return Landscape(
        m=m,
        controllers=m**4,
        generalists=int((o == N_ENV).sum()),
        at_least_one=int((o >= 1).sum()),
        flagged=flagged,
        generalists_2w=int((s2 == N_ENV).sum()),
        at_least_one_2w=int((s2 >= 1).sum()),
    )
