"""The learners' search spaces of the paper's comparison, and their evaluator.

A setup is a body (a fixed design, or ``coopt``: both sensor positions continuous on the body
square) and a controller (2 or 4 synapses). A learner searches the box [-1, 1]^dim:

- fixed body: ``x = (w1, w2)`` or ``(w1, w2, u1, u2)``;
- co-optimised body: ``x = (2 l1x, 2 l1y, 2 l2x, 2 l2y, weights...)`` (positions are half the
  search coordinates, so the box maps onto the body square [-0.5, 0.5]^2 per sensor, and one
  step size serves positions and weights alike).

Every trajectory goes through the four-synapse kernel (``theory.cpu.points4``); two-synapse
setups pass ``u1 = u2 = 0``, which is bit-identical to the two-synapse kernel (tested).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from morphlearn.grid import env_starts
from morphlearn.learners.objective import env_loss
from morphlearn.theory import TheoryParams, cpu

#: The paper's canonical design, l1 = (0.5, 0.5), l2 = (0.5, -0.5).
CANONICAL = (0.5, 0.5, 0.5, -0.5)
BODIES = ("canonical", "coopt", "best")


@dataclass(frozen=True)
class Setup:
    name: str  # a, b, c, d, e
    body: str  # canonical | coopt | best
    synapses: int  # 2 | 4
    coords: tuple[float, float, float, float] | None  # fixed body; None when co-optimised

    @property
    def dim(self) -> int:
        return self.synapses + (4 if self.coords is None else 0)

    @property
    def label(self) -> str:
        body = {"canonical": "canonical body", "coopt": "co-optimised body", "best": "best 2-weight design"}
        return f"({self.name}) {body[self.body]}, {self.synapses} weights"


def paper_setups(best: tuple[float, float, float, float]) -> tuple[Setup, ...]:
    """(a)-(e) of issue 27; ``best`` is the best two-weight design's coordinates."""
    return (
        Setup("a", "canonical", 2, CANONICAL),
        Setup("b", "canonical", 4, CANONICAL),
        Setup("c", "coopt", 2, None),
        Setup("d", "coopt", 4, None),
        Setup("e", "best", 2, tuple(float(v) for v in best)),  # type: ignore[arg-type]
    )


def decode(setup: Setup, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Search points (k, dim) -> design coordinates (k, 4) and weights (k, 4)."""
    x = np.asarray(x, dtype=np.float64).reshape(-1, setup.dim)
    k = len(x)
    if setup.coords is None:
        coords, w = 0.5 * x[:, :4], x[:, 4:]
    else:
        coords, w = np.tile(np.asarray(setup.coords, dtype=np.float64), (k, 1)), x
    if setup.synapses == 2:
        w = np.hstack([w, np.zeros((k, 2))])
    return coords, w


@dataclass
class SetupEvaluator:
    """The protocols' evaluator (``learners.protocols.drive``) for runs of one setup."""

    setup: Setup
    params: TheoryParams
    trajectories: int = 0

    def __call__(self, design_idx: np.ndarray, env_idx: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        p = self.params
        coords, w = decode(self.setup, x)
        ft, dm, st = cpu.points4(
            coords,
            env_starts(p.r),
            env_idx,
            w,
            **p.kernel_kwargs(),
        )
        self.trajectories += len(ft)
        success = (st == 0) & np.isfinite(ft)
        return env_loss(ft, dm, success, p.horizon, p.r), success
