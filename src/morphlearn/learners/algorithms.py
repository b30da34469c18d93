"""Learners over controller weights ``(w1, w2)`` in the box [-1, 1]^2 (or any ``dim``: the
co-optimisation stage searches weights and sensor positions together), as ask/tell objects.

Each learner draws from its own ``numpy.random.Generator`` (CMA-ES included: its sampler is
replaced by the learner's generator), so a run's numbers depend only on its seed, not on which
other runs are batched beside it. Incumbents and budgets are the protocol's business
(``protocols``); ``rescore`` tells a learner that the objective changed under its current point.
"""

from __future__ import annotations

import math
from typing import Protocol

import cma
import numpy as np

LO, HI = -1.0, 1.0
#: The learners, in a fixed order (their index enters the run seeds).
NAMES = ("random", "one_plus_one", "cmaes", "one_plus_one_restart", "cmaes_restart")


class Learner(Protocol):
    def ask(self) -> np.ndarray: ...  # (k, 2) candidates
    def tell(self, x: np.ndarray, f: np.ndarray) -> None: ...
    def rescore(self, f: float) -> None: ...


def _uniform(rng: np.random.Generator, k: int = 1, dim: int = 2) -> np.ndarray:
    return rng.uniform(LO, HI, size=(k, dim))


class RandomSearch:
    """Uniform samples of the box, one per ask: one sample is a generalist with probability
    equal to the share of the weight plane that succeeds everywhere (M_L in the grid's limit)."""

    def __init__(self, rng: np.random.Generator, sigma0: float, dim: int = 2) -> None:
        self.rng = rng
        self.dim = dim

    def ask(self) -> np.ndarray:
        return _uniform(self.rng, dim=self.dim)

    def tell(self, x: np.ndarray, f: np.ndarray) -> None:
        pass

    def rescore(self, f: float) -> None:
        pass


class OnePlusOne:
    """(1+1)-ES with the 1/5th success rule (step x e^{1/3} on success, x e^{-1/12} otherwise:
    stationary at a success rate of 1/5), offspring clipped to the box, ties accepted (moves
    along plateaus). The first ask is the uniformly drawn parent itself."""

    UP, DOWN = math.exp(1.0 / 3.0), math.exp(-1.0 / 12.0)
    SIGMA_MIN, SIGMA_MAX = 1e-3, 1.0

    def __init__(self, rng: np.random.Generator, sigma0: float, dim: int = 2) -> None:
        self.rng = rng
        self.sigma = sigma0
        self.sigma0 = sigma0
        self.x = _uniform(rng, dim=dim)[0]
        self.f = math.inf

    def ask(self) -> np.ndarray:
        if not math.isfinite(self.f):
            return self.x[None, :].copy()
        return np.clip(self.x + self.sigma * self.rng.standard_normal(self.x.size), LO, HI)[None, :]

    def tell(self, x: np.ndarray, f: np.ndarray) -> None:
        first = not math.isfinite(self.f)
        if f[0] <= self.f:
            if not first:
                self.sigma = min(self.sigma * self.UP, self.SIGMA_MAX)
            self.x, self.f = np.asarray(x[0], dtype=np.float64).copy(), float(f[0])
        else:
            self.sigma = max(self.sigma * self.DOWN, self.SIGMA_MIN)
            if self.RESTART and self.sigma <= self.SIGMA_MIN:
                self._restart()

    RESTART = False

    def _restart(self) -> None:
        """A new uniform parent with the initial step (the variant ``one_plus_one_restart``)."""
        self.x = _uniform(self.rng, dim=self.x.size)[0]
        self.f = math.inf
        self.sigma = self.sigma0

    def rescore(self, f: float) -> None:
        self.f = float(f)


class CMAES:
    """CMA-ES of the ``cma`` package (default population 4 + 3 ln(dim): 6 in 2-d, box bounds), started at a
    uniform point with step ``sigma0``; restarted from its last mean with ``sigma0`` when ``cma``'s
    own termination criteria fire (a collapsed step cannot follow a changed objective)."""

    def __init__(self, rng: np.random.Generator, sigma0: float, dim: int = 2) -> None:
        self.rng = rng
        self.sigma0 = sigma0
        self._start(_uniform(rng, dim=dim)[0])

    def _start(self, x0: np.ndarray) -> None:
        opts = {
            "bounds": [LO, HI],
            "seed": math.nan,
            "verbose": -9,
            "verb_log": 0,
            "verb_disp": 0,
            "randn": lambda lam, n: self.rng.standard_normal((lam, n)),
            "tolfun": 1e-9,
            "tolx": 1e-6,
            "maxfevals": math.inf,
        }
        self.es = cma.CMAEvolutionStrategy(np.asarray(x0, dtype=np.float64).tolist(), self.sigma0, opts)
        self._pending: list[np.ndarray] = []

    RESTART = False

    def ask(self) -> np.ndarray:
        if self.es.stop():
            # restart from the last mean; the variant cmaes_restart from a new uniform point
            self._start(_uniform(self.rng, dim=self.es.N)[0] if self.RESTART else np.clip(self.es.mean, LO, HI))
        self._pending = self.es.ask()
        return np.array(self._pending, dtype=np.float64)

    def tell(self, x: np.ndarray, f: np.ndarray) -> None:
        if len(f) == len(self._pending):  # a generation cut short by the budget is not told
            self.es.tell(self._pending, [float(v) for v in f])

    def rescore(self, f: float) -> None:
        pass  # CMA-ES keeps no fitness of its mean: it follows the new objective from its samples


class OnePlusOneRestart(OnePlusOne):
    """The (1+1)-ES restarted at a new uniform point with the initial step when its step has
    shrunk to ``SIGMA_MIN`` (stagnation: ~75 failures in a row from step 0.5)."""

    RESTART = True


class CMAESRestart(CMAES):
    """CMA-ES restarted at a new uniform point (not its last mean) when ``cma`` stops."""

    RESTART = True


CLASSES: dict[str, type] = {
    "random": RandomSearch,
    "one_plus_one": OnePlusOne,
    "cmaes": CMAES,
    "one_plus_one_restart": OnePlusOneRestart,
    "cmaes_restart": CMAESRestart,
}


def make(name: str, rng: np.random.Generator, sigma0: float, dim: int = 2) -> Learner:
    if name not in CLASSES:
        raise ValueError(f"learner {name!r} unknown; allowed: {list(NAMES)}")
    return CLASSES[name](rng, sigma0, dim)
