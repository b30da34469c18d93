"""Early stop: a lower bound on the time an episode still needs to reach the light.

Most episodes fail and run the whole horizon (2500 steps). An episode may stop early once the
body provably cannot come within the contact distance ``c`` in the time left. The bound:

- A wheel's target speed is ``tanh(w * s) * max_speed`` with ``s = 1/d_s^2``; a sensor sits at
  most ``rho`` (its distance from the body centre) closer to the light than the centre, so at
  centre distance ``x`` every target rim speed is at most ``V tanh(w_max / (x - rho)^2)``
  (``V = max_speed * wheel_radius``). The body centre moves at most ``1.05`` times the faster
  rim (the axle sits ``wheel_setback`` behind the centre: ``1 + 2 * setback / track`` <= 1.05).
- Momentum: the body may move faster than its wheels' current targets (it was closer a moment
  ago, or the solver overshoots). Its speed beyond the targets only decays (velocity motors
  brake toward the target), so the current speed ``u`` bounds it.
- Both are multiplied by a safety ``margin`` (default 2): the speed bound along the way is
  ``margin * max(u, 1.05 V tanh(w_max / (x - rho)^2))``.

The time to go from ``d`` to ``c`` at that speed is a lower bound on the true time; the episode
stops when it exceeds the time left. The integral is tabulated per episode with left Riemann
sums of an increasing integrand (a lower bound), read at the grid point below ``d`` (lower again).

What it changes: nothing about success or first-contact time (validated: docs/empirical.md); an
early-stopped episode's ``min_dist`` is the closest approach up to the stop, not up to the
horizon, so an empirical success radius larger than simulated would need full episodes (the
empirical metrics always use the simulated contact distance).
"""

from __future__ import annotations

import math

import numpy as np

from morphlearn.physics.params import BODY_SIZE, EmpiricalParams

#: Steps between two checks of the bound (0.5 s at dt = 0.05): a check costs a velocity query
#: and a table lookup, a few per cent of a step if done every step.
CHECK_EVERY = 10


#: Body-centre speed over the faster rim speed: the axle is ``wheel_setback`` behind the centre,
#: so yaw adds at most ``2 * setback / track`` (track = body width); 0.025 gives 1.05.
def centre_factor(params: EmpiricalParams) -> float:
    return 1.0 + 2.0 * abs(params.wheel_setback) / BODY_SIZE


class ReachBound:
    """``hopeless(d, u, t_left)``: True when the light cannot be reached in ``t_left`` seconds."""

    STEP = 0.01  # m, table resolution
    EXTENT = 60.0  # m beyond the contact distance covered by the table (then extrapolated)

    def __init__(self, params: EmpiricalParams, w_max: float, rho: float, margin: float = 2.0) -> None:
        if margin < 1.0:
            raise ValueError(f"margin = {margin} must be >= 1 (it scales a speed bound up)")
        self.c = params.contact_distance
        self.w_max, self.rho, self.margin = abs(float(w_max)), float(rho), float(margin)
        self.k = margin * centre_factor(params) * params.max_speed * params.wheel_radius
        x = self.c + self.STEP * np.arange(int(self.EXTENT / self.STEP) + 1)
        self.speed = self._targets(x)  # non-increasing in x
        with np.errstate(divide="ignore"):
            inv = 1.0 / self.speed  # a zero speed bound: +inf (never reached)
        self.inv = inv
        # time[i]: lower bound of the time from x[i] to c at the target bound alone (left sums).
        self.time = np.concatenate([[0.0], np.cumsum(inv[:-1] * self.STEP)])

    def _targets(self, x: np.ndarray) -> np.ndarray:
        if self.w_max == 0.0:
            return np.zeros_like(x)
        a = np.maximum(x - self.rho, 1e-9)
        return self.k * np.tanh(self.w_max / (a * a))

    def lower_time(self, d: float, u: float) -> float:
        """Lower bound of the time to come from centre distance ``d`` to ``c`` with speed ``u`` now."""
        if d <= self.c:
            return 0.0
        mu = self.margin * abs(u)
        i = int((d - self.c) / self.STEP)
        n = len(self.speed)
        if i >= n:  # beyond the table the speed bound is at most max(mu, its last entry)
            last = self.c + self.STEP * (n - 1)
            return self._below(n - 1, mu) + (d - last) / max(mu, float(self.speed[-1]), 1e-300)
        return self._below(i, mu)

    def _below(self, i: int, mu: float) -> float:
        """Lower bound of the time from x[i] to c at speed max(mu, target bound)."""
        if mu <= 0.0:
            return float(self.time[i])
        if mu >= self.speed[0]:
            return i * self.STEP / mu
        # Targets exceed mu up to index j (they fall with x); beyond it, mu is the bound.
        j = int(np.searchsorted(-self.speed[: i + 1], -mu, side="right"))  # first index with speed < mu
        if j > i:
            return float(self.time[i])
        return float(self.time[j]) + (i - j) * self.STEP / mu

    def hopeless(self, d: float, u: float, t_left: float) -> bool:
        return self.lower_time(d, u) > t_left


def sensor_reach(l1: tuple[float, float], l2: tuple[float, float]) -> float:
    """Largest sensor distance from the body centre (``rho`` of the bound)."""
    return max(math.hypot(*l1), math.hypot(*l2))
