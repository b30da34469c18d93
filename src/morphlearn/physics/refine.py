"""Adaptive weight grid (an option, off by default): simulate where successes can be.

Successes of one design in one environment form a few compact regions of the (w1, w2) grid
(same-sign weights strong enough to steer to the light). Instead of all ``m x m`` episodes:

1. simulate a coarse lattice (every ``stride``-th weight on both axes, and the last);
2. simulate every unsimulated 8-neighbour of a cell that succeeded or came near the light
   (closest approach within ``near`` times the contact distance), and repeat until nothing new.

Cells never simulated are taken as failures (stored with status ``STATUS_INFERRED``, NaN
``first_time`` and ``min_dist``), so a success region that no lattice cell or near miss touches is
missed: the miss rate is measured (``benchmarks/validate_levers.py``, docs/empirical.md) and the
results' science record and the figure captions say the grid was refined adaptively.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

DEFAULT_STRIDE = 2
#: No success missed at 4 in 20,328 exhaustive episodes (benchmarks/validate_levers.py); 1.5 missed 34 %.
DEFAULT_NEAR = 4.0


def lattice(m: int, stride: int) -> np.ndarray:
    """(m, m) mask of the coarse lattice: indices divisible by ``stride`` and the last one."""
    if stride < 1:
        raise ValueError(f"stride = {stride} must be >= 1")
    on = np.zeros(m, bool)
    on[::stride] = True
    on[-1] = True
    return on[:, None] & on[None, :]


def first_wave(m: int, stride: int, shape: tuple[int, ...], first: np.ndarray | None = None) -> np.ndarray:
    """The adaptive grid's first wave on maps of ``shape`` (..., m, m): the lattice on each, and the
    cells of ``first`` (a screen's successes and near misses, :func:`screen_cells`) where given."""
    start = np.broadcast_to(lattice(m, stride), shape)
    return start if first is None else start | np.asarray(first, bool)


def replay_mask(seeds: np.ndarray, stride: int = DEFAULT_STRIDE, first: np.ndarray | None = None) -> np.ndarray:
    """The cells :func:`refine_waves` simulates, replayed on exhaustive maps (..., m, m) at once,
    vectorised, from ``seeds`` = success | promising: the refinement explores exactly the
    8-connected regions of seed cells that touch its first wave (the lattice, and ``first`` where
    given: a screen's cells) and simulates them with a one-cell fringe, besides the first wave (a
    test checks it equals :func:`refine_waves` and the grid simulated one cell at a time)."""
    from scipy import ndimage

    seeds = np.asarray(seeds, bool)
    m = seeds.shape[-1]
    start = first_wave(m, stride, seeds.shape, first)
    out = np.empty(seeds.shape, bool)
    flat_in, flat_start, flat_out = seeds.reshape(-1, m, m), start.reshape(-1, m, m), out.reshape(-1, m, m)
    eight = np.ones((3, 3), bool)
    for k, s in enumerate(flat_in):
        lab, _ = ndimage.label(s, structure=eight)
        hit = np.unique(lab[flat_start[k] & s])
        reached = np.isin(lab, hit[hit > 0])
        flat_out[k] = flat_start[k] | ndimage.binary_dilation(reached, structure=eight)
    return out


def simulated_mask(
    success: np.ndarray,
    min_dist: np.ndarray,
    contact: float,
    near: float,
    stride: int = DEFAULT_STRIDE,
    first: np.ndarray | None = None,
) -> np.ndarray:
    """(4, m, m) cells the adaptive grid at ``near`` simulates, replayed on exhaustive outcomes
    (``first``: the screen's cells its first wave also holds)."""
    return replay_mask(success | (min_dist <= near * contact), stride, first)


def misses(
    success: np.ndarray,
    min_dist: np.ndarray,
    contact: float,
    near: float,
    stride: int = DEFAULT_STRIDE,
    first: np.ndarray | None = None,
) -> dict[str, float]:
    """What the adaptive grid at ``near`` would have missed on exhaustive (4, m, m) outcomes
    (env, w1, w2) of one design, replayed without simulating (``min_dist`` as simulated with the
    same early-stop setting, so the replay makes the adaptive run's choices): the share of episodes
    it simulates, the successes, the generalists and the controllers solving at least one
    environment (M_CF's denominator) it loses. ``first``: a screen's cells (:func:`screen_cells`)."""
    simulated = simulated_mask(success, min_dist, contact, near, stride, first)
    kept = success & simulated
    gen, gen_kept = success.all(axis=0), kept.all(axis=0)
    one, one_kept = success.any(axis=0), kept.any(axis=0)
    return {
        "near": near,
        "stride": stride,
        "episodes": int(success.size),
        "simulated_share": float(simulated.mean()),
        "successes": int(success.sum()),
        "successes_missed": int((success & ~simulated).sum()),
        "generalists": int(gen.sum()),
        "generalists_missed": int((gen & ~gen_kept).sum()),
        "at_least_one": int(one.sum()),
        "at_least_one_missed": int((one & ~one_kept).sum()),
    }


def screen_cells(first_time: np.ndarray, min_dist: np.ndarray, contact: float, near: float) -> np.ndarray:
    """The cells a screen (a cheaper model's outcomes of the same design, e.g. the reduced model's
    for ODE) calls a success or a near miss: the adaptive grid's first wave also simulates them,
    so an isolated success that no lattice cell or near miss touches is found where the screen
    finds it. Cells the screen did not simulate (NaN) add nothing."""
    with np.errstate(invalid="ignore"):
        return ~np.isnan(first_time) | (min_dist <= near * contact)


def refine_waves(
    m: int,
    n_maps: int,
    simulate: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]],
    stride: int,
    first: np.ndarray | None = None,
) -> np.ndarray:
    """The adaptive grid (the module docstring's steps) on ``n_maps`` (m, m) maps at once: each
    wave of every map is simulated in one call ``simulate(cells)`` (cells (k, 3) = map, i, j, in
    row-major order) returning ``(success, promising)``; a wave is simulated whole before its
    outcomes are looked at, so the cells per map do not depend on the other maps (tested against
    the grid simulated one cell at a time). ``first``: (n_maps, m, m) cells the first wave holds
    besides the lattice (a screen's successes and near misses, :func:`screen_cells`). Returns the
    (n_maps, m, m) simulated mask. The physics sweep (:mod:`morphlearn.physics.sweep`) runs it."""
    done = np.zeros((n_maps, m, m), bool)
    wave = np.argwhere(first_wave(m, stride, (n_maps, m, m), first))
    while len(wave):
        done[tuple(wave.T)] = True
        ok, promising = simulate(wave)
        seeds = np.zeros((n_maps, m, m), bool)
        seeds[tuple(wave[ok | promising].T)] = True
        grow = seeds.copy()  # 8-neighbourhood of the seeds
        grow[:, 1:, :] |= seeds[:, :-1, :]
        grow[:, :-1, :] |= seeds[:, 1:, :]
        grow2 = grow.copy()
        grow2[:, :, 1:] |= grow[:, :, :-1]
        grow2[:, :, :-1] |= grow[:, :, 1:]
        wave = np.argwhere(grow2 & ~done)
    return done
