"""Reference evaluator: scipy ``solve_ivp`` on the paper's (x, y, alpha) form, one trajectory.

Slow (tens of ms per trajectory) and independent of the fast kernels' code: it integrates the
angle with trig instead of a unit heading vector, finds success with a terminal event, and finds
closest approaches with an event on ``d|p|/dt = 0``. Used for spot checks, ``morphlearn verify``
and trajectory figures.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from morphlearn.results import STATUS_OK, STATUS_STEP_CAP, STATUS_STEP_UNDERFLOW


class _EvaluationCapError(Exception):
    """Raised inside the right-hand side when a trajectory exceeds its evaluation budget."""


@dataclass
class ReferenceTrajectory:
    first_time: float  # NaN if no success
    min_dist: float
    status: int
    t: np.ndarray  # sample times of the path
    path: np.ndarray  # (len(t), 3): x, y, alpha (light at the origin)


def velocities(x: float, y: float, c: float, s: float, l1, l2, w1: float, w2: float) -> list[float]:
    """The model's right-hand side (Eq. 1) at position (x, y), heading cosine ``c`` and sine
    ``s`` (the caller's own cos/sin, so each integrator keeps its bits): (dx/dt, dy/dt, da/dt)."""
    d1 = (x + c * l1[0] - s * l1[1]) ** 2 + (y + s * l1[0] + c * l1[1]) ** 2
    d2 = (x + c * l2[0] - s * l2[1]) ** 2 + (y + s * l2[0] + c * l2[1]) ** 2
    a1, a2 = w1 / d1, w2 / d2
    v = 0.5 * (a1 + a2)
    return [v * c, v * s, a1 - a2]


def _rhs(l1: np.ndarray, l2: np.ndarray, w1: float, w2: float, max_nfev: int):
    calls = [0]

    def f(_t: float, z: np.ndarray) -> list[float]:
        calls[0] += 1
        if calls[0] > max_nfev:
            raise _EvaluationCapError
        x, y, a = z
        return velocities(x, y, np.cos(a), np.sin(a), l1, l2, w1, w2)

    return f


def reference_trajectory(
    start: tuple[float, float],
    l1: tuple[float, float],
    l2: tuple[float, float],
    w1: float,
    w2: float,
    *,
    radius: float = 0.2,
    horizon: float = 500.0,
    method: str = "DOP853",
    tol: float = 1e-10,
    stop_at_success: bool = True,
    max_points: int = 20000,
    max_nfev: int = 2_000_000,
) -> ReferenceTrajectory:
    """Integrate one trajectory from ``start`` facing +x with the light at the origin.

    The model's singular trajectories (a sensor carried into the light) make any integrator
    stall; after ``max_nfev`` right-hand-side evaluations the trajectory is stopped and returned
    with ``STATUS_STEP_CAP`` (a failure), like the fast kernel's step cap.
    """
    f = _rhs(np.asarray(l1, float), np.asarray(l2, float), float(w1), float(w2), max_nfev)

    def hit(_t: float, z: np.ndarray) -> float:
        return float(np.hypot(z[0], z[1]) - radius)

    hit.terminal = stop_at_success  # type: ignore[attr-defined]
    hit.direction = -1  # type: ignore[attr-defined]

    def approach(_t: float, z: np.ndarray) -> float:
        # d|p|^2/dt has the sign of p . heading (times v); its zeros are local extrema of |p|.
        return float(z[0] * np.cos(z[2]) + z[1] * np.sin(z[2]))

    z0 = [float(start[0]), float(start[1]), 0.0]
    try:
        sol = solve_ivp(
            f, (0.0, horizon), z0, method=method, rtol=tol, atol=tol, events=(hit, approach), dense_output=False
        )
    except _EvaluationCapError:
        return ReferenceTrajectory(float("nan"), float("nan"), STATUS_STEP_CAP, np.zeros(0), np.zeros((0, 3)))
    status = STATUS_OK if sol.status >= 0 else STATUS_STEP_UNDERFLOW
    d = np.hypot(sol.y[0], sol.y[1])
    cand = [d.min()]
    for ev in sol.y_events:
        if len(ev):
            cand.append(np.hypot(ev[:, 0], ev[:, 1]).min())
    min_dist = float(min(cand))
    first = float(sol.t_events[0][0]) if len(sol.t_events[0]) else float("nan")
    if np.hypot(*z0[:2]) <= radius:
        first = 0.0
    t, path = sol.t, sol.y.T
    if len(t) > max_points:
        keep = np.linspace(0, len(t) - 1, max_points).astype(int)
        t, path = t[keep], path[keep]
    return ReferenceTrajectory(first, min_dist, status, t, path)
