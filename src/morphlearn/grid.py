"""The design grid: sensor positions, controller weights, environments, shards, mirror map.

Conventions (body frame +x forward, +y left; robot starts at the origin facing +x).
A design is ``(l1, l2)`` with ``l = (x, y)`` in [-0.5, 0.5]^2. Positions are indexed on a
grid of ``n`` values per axis; the flat design index is ``((i1x * n + i1y) * n + i2x) * n + i2y``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

#: Light angles in degrees, in the storage order of the ``env`` dimension.
ENV_ANGLES_DEG: tuple[int, ...] = (45, 135, 225, 315)
#: Environment index -> index of its mirror image (y -> -y): 45 <-> 315, 135 <-> 225.
ENV_MIRROR: tuple[int, ...] = (3, 2, 1, 0)


def symmetric_linspace(lo: float, hi: float, n: int) -> np.ndarray:
    """``linspace(lo, hi, n)`` with ``lo == -hi`` made exactly symmetric about zero.

    ``numpy.linspace`` is not always bit-exact symmetric; mirror symmetry of the model is only
    exact when ``x[n - 1 - k] == -x[k]``, so the upper half is copied from the lower.
    """
    if n < 2:
        raise ValueError(f"need at least 2 grid points, got {n}")
    x = np.linspace(lo, hi, n)
    if lo == -hi:
        half = n // 2
        x[n - half :] = -x[:half][::-1]
        if n % 2:
            x[half] = 0.0
    return x


def positions(n: int) -> np.ndarray:
    """Sensor coordinates per axis: ``linspace(-0.5, 0.5, n)``."""
    return symmetric_linspace(-0.5, 0.5, n)


def is_subgrid(p: int, n: int) -> bool:
    """Whether every position of the ``p``-point grid is one of the ``n``-point grid's (every
    ``(n - 1) / (p - 1)``-th: the 5-point grid inside the 9-point one), so that a survey on the
    ``p``-point grid covers designs of an ``n``-point run."""
    return 2 <= p <= n and (n - 1) % (p - 1) == 0


def weights(m: int) -> np.ndarray:
    """Controller weights per synapse: ``linspace(-1, 1, m)``."""
    return symmetric_linspace(-1.0, 1.0, m)


def env_starts(r: float) -> np.ndarray:
    """Robot start points, shape (4, 2), with the light at the origin.

    The robot starts at ``-(r cos phi, r sin phi)``; built as exact mirror pairs ``(+-a, +-a)``
    because ``cos(deg2rad(315))`` is not bit-exact the mirror of 45 degrees.
    """
    a = r / np.sqrt(2.0)
    signs = np.array([[1, 1], [-1, 1], [-1, -1], [1, -1]], dtype=np.float64)  # 45,135,225,315
    return -a * signs


def light_positions(r: float) -> np.ndarray:
    """Light positions (4, 2) in a frame where the robot starts at the origin facing +x."""
    return -env_starts(r)


@dataclass(frozen=True)
class DesignGrid:
    """All designs for ``n`` positions per axis per sensor."""

    n: int

    def __post_init__(self) -> None:
        if self.n < 2:
            raise ValueError(f"positions_per_axis must be >= 2, got {self.n}")

    @property
    def size(self) -> int:
        return self.n**4

    @property
    def axis(self) -> np.ndarray:
        return positions(self.n)

    def indices(self, design: np.ndarray | int) -> np.ndarray:
        """Flat design index -> (..., 4) position indices (i1x, i1y, i2x, i2y)."""
        d = np.asarray(design, dtype=np.int64)
        n = self.n
        return np.stack([d // n**3, (d // n**2) % n, (d // n) % n, d % n], axis=-1)

    def flat(self, idx: np.ndarray) -> np.ndarray:
        """(..., 4) position indices -> flat design index."""
        idx = np.asarray(idx, dtype=np.int64)
        n = self.n
        return ((idx[..., 0] * n + idx[..., 1]) * n + idx[..., 2]) * n + idx[..., 3]

    def coords(self, design: np.ndarray | int) -> np.ndarray:
        """Flat design index -> (..., 4) coordinates (l1x, l1y, l2x, l2y)."""
        return self.axis[self.indices(design)]

    def index_of(self, l1: tuple[float, float], l2: tuple[float, float]) -> int:
        """Design index of exact grid coordinates; raises ValueError if not on the grid."""
        out = []
        for name, v in zip(("l1.x", "l1.y", "l2.x", "l2.y"), (*l1, *l2), strict=True):
            hit = np.flatnonzero(np.isclose(self.axis, v, atol=1e-12))
            if hit.size != 1:
                raise ValueError(f"{name}={v} is not on the {self.n}-point grid {self.axis.tolist()}")
            out.append(int(hit[0]))
        return int(self.flat(np.array(out)))

    def mirror(self, design: np.ndarray | int) -> np.ndarray:
        """Mirror image under y -> -y: ``(l1, l2) -> ((x2, -y2), (x1, -y1))``.

        Design ``d`` with weights ``(w1, w2)`` in environment ``k`` behaves exactly as
        ``mirror(d)`` with ``(w2, w1)`` in ``ENV_MIRROR[k]``.
        """
        i = self.indices(design)
        m = self.n - 1
        return self.flat(np.stack([i[..., 2], m - i[..., 3], i[..., 0], m - i[..., 1]], -1))

    def same_pair(self, a: int, b: int) -> bool:
        """``a`` and ``b`` are one design, or mirror images of each other (one body, mirrored)."""
        return int(a) == int(b) or int(self.mirror(int(a))) == int(b)

    def representatives(self) -> np.ndarray:
        """One design of each mirror pair (the smaller index), sorted."""
        d = np.arange(self.size)
        return d[d <= self.mirror(d)]


#: The most sensor positions per axis a config may ask (grid.positions_per_axis, the config schema).
MAX_POSITIONS = 33


def grids_holding(values: Sequence[float], n_max: int = MAX_POSITIONS) -> list[int]:
    """The grids ``positions(n)``, n <= ``n_max``, that hold every one of ``values`` (a researcher's
    off-grid sensor positions: which ``grid.positions_per_axis`` would take them)."""
    return [n for n in range(2, n_max + 1) if all(np.isclose(positions(n), v, atol=1e-9).any() for v in values)]


def canonical_design() -> tuple[tuple[float, float], tuple[float, float]]:
    """Front-left and front-right corners."""
    return (0.5, 0.5), (0.5, -0.5)


#: The paper's best theory design by M_L (its mirror image ties with it).
PAPER_BEST_DESIGN: tuple[tuple[float, float], tuple[float, float]] = ((-0.5, -0.25), (0.5, 0.25))


def split_shards(designs: np.ndarray, n_shards: int) -> list[np.ndarray]:
    """Split a design list into ``n_shards`` contiguous, near-equal parts."""
    if n_shards < 1:
        raise ValueError(f"shards must be >= 1, got {n_shards}")
    if n_shards > len(designs):
        raise ValueError(f"shards={n_shards} exceeds the {len(designs)} designs to evaluate")
    return np.array_split(np.asarray(designs, dtype=np.int64), n_shards)
