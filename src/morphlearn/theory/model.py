"""One source of the theoretical model: right-hand side, integrator steps, one trajectory.

Every function here is plain Python over scalars and tuples. ``build(jit)`` compiles them with
a given decorator, so the CPU kernel (``numba.njit``) and the CUDA kernel
(``numba.cuda.jit(device=True)``) run the same code. State is ``(x, y, c, s)``: centre position
(light at the origin) and heading as a unit vector, renormalised after each step (2x cheaper
than trig; DESIGN section 2).

Integrators: adaptive Dormand-Prince 5(4) (FSAL, safety 0.9, step change clipped to [0.2, 10],
rms error norm with ``atol + rtol * max(|y|, |y_new|)``) and fixed-step RK4. Success is
detected on the chord between consecutive states (closest approach), and the first-success time
is where the chord first enters the success circle. The integration stops at success (terminal),
at the horizon, when the adaptive step falls below ``H_MIN`` (the model's singular designs), at
the step cap, or when the state stops being finite.
"""

from __future__ import annotations

import math
import types
from collections.abc import Callable
from typing import Any

from morphlearn.results import STATUS_NONFINITE, STATUS_OK, STATUS_STEP_CAP, STATUS_STEP_UNDERFLOW

#: Integrator codes.
METHOD_DP5 = 0
METHOD_RK4 = 1
#: Adaptive step control (scipy's ``_ivp/rk.py`` names): first step, step floor (below it the
#: trajectory is stopped and flagged STATUS_STEP_UNDERFLOW), safety factor, and the clip of the
#: step change per step; the error exponent is -1 / (order of the error estimate + 1).
H_FIRST = 0.01
H_MIN = 1e-12
SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0
ERROR_EXPONENT = -1.0 / 5.0

# Dormand-Prince 5(4) tableau.
A21 = 1.0 / 5.0
A31, A32 = 3.0 / 40.0, 9.0 / 40.0
A41, A42, A43 = 44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0
A51, A52, A53, A54 = 19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0
A61, A62, A63, A64, A65 = (
    9017.0 / 3168.0,
    -355.0 / 33.0,
    46732.0 / 5247.0,
    49.0 / 176.0,
    -5103.0 / 18656.0,
)
B1, B3, B4, B5, B6 = 35.0 / 384.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0
E1, E3, E4, E5, E6, E7 = (
    71.0 / 57600.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
)


def rhs(x, y, c, s, l1x, l1y, l2x, l2y, w1, w2, u1, u2):
    """Time derivative of (x, y, c, s) with the light at the origin: the paper's two crossed
    synapses (sensor 1 -> right wheel ``w1``, sensor 2 -> left wheel ``w2``); ``u1, u2`` are
    ignored (the two-weight model; its arithmetic is unchanged by the four-weight one)."""
    p1x = x + c * l1x - s * l1y
    p1y = y + s * l1x + c * l1y
    p2x = x + c * l2x - s * l2y
    p2y = y + s * l2x + c * l2y
    a1 = w1 / (p1x * p1x + p1y * p1y)
    a2 = w2 / (p2x * p2x + p2y * p2y)
    om = a1 - a2
    v = 0.5 * (a1 + a2)
    return v * c, v * s, -s * om, c * om


def rhs4(x, y, c, s, l1x, l1y, l2x, l2y, w1, w2, u1, u2):
    """The four-synapse controller: each sensor drives both wheels, the crossed weights ``w1``
    (sensor 1 -> right), ``w2`` (sensor 2 -> left) and the uncrossed ``u1`` (sensor 1 -> left),
    ``u2`` (sensor 2 -> right). The crossed terms are computed exactly as in :func:`rhs` and the
    uncrossed ones added: with ``u1 = u2 = 0`` each sum adds ``+0.0``, which leaves every finite
    nonzero value bit-identical (tested against :func:`rhs`)."""
    p1x = x + c * l1x - s * l1y
    p1y = y + s * l1x + c * l1y
    p2x = x + c * l2x - s * l2y
    p2y = y + s * l2x + c * l2y
    d1 = p1x * p1x + p1y * p1y
    d2 = p2x * p2x + p2y * p2y
    a1 = w1 / d1 + u2 / d2  # right wheel
    a2 = w2 / d2 + u1 / d1  # left wheel
    om = a1 - a2
    v = 0.5 * (a1 + a2)
    return v * c, v * s, -s * om, c * om


def _lin1(y, h, a1, k1):
    return (
        y[0] + h * (a1 * k1[0]),
        y[1] + h * (a1 * k1[1]),
        y[2] + h * (a1 * k1[2]),
        y[3] + h * (a1 * k1[3]),
    )


def _lin2(y, h, a1, k1, a2, k2):
    return (
        y[0] + h * (a1 * k1[0] + a2 * k2[0]),
        y[1] + h * (a1 * k1[1] + a2 * k2[1]),
        y[2] + h * (a1 * k1[2] + a2 * k2[2]),
        y[3] + h * (a1 * k1[3] + a2 * k2[3]),
    )


def _lin3(y, h, a1, k1, a2, k2, a3, k3):
    return (
        y[0] + h * (a1 * k1[0] + a2 * k2[0] + a3 * k3[0]),
        y[1] + h * (a1 * k1[1] + a2 * k2[1] + a3 * k3[1]),
        y[2] + h * (a1 * k1[2] + a2 * k2[2] + a3 * k3[2]),
        y[3] + h * (a1 * k1[3] + a2 * k2[3] + a3 * k3[3]),
    )


def _lin4(y, h, a1, k1, a2, k2, a3, k3, a4, k4):
    return (
        y[0] + h * (a1 * k1[0] + a2 * k2[0] + a3 * k3[0] + a4 * k4[0]),
        y[1] + h * (a1 * k1[1] + a2 * k2[1] + a3 * k3[1] + a4 * k4[1]),
        y[2] + h * (a1 * k1[2] + a2 * k2[2] + a3 * k3[2] + a4 * k4[2]),
        y[3] + h * (a1 * k1[3] + a2 * k2[3] + a3 * k3[3] + a4 * k4[3]),
    )


def _lin5(y, h, a1, k1, a2, k2, a3, k3, a4, k4, a5, k5):
    return (
        y[0] + h * (a1 * k1[0] + a2 * k2[0] + a3 * k3[0] + a4 * k4[0] + a5 * k5[0]),
        y[1] + h * (a1 * k1[1] + a2 * k2[1] + a3 * k3[1] + a4 * k4[1] + a5 * k5[1]),
        y[2] + h * (a1 * k1[2] + a2 * k2[2] + a3 * k3[2] + a4 * k4[2] + a5 * k5[2]),
        y[3] + h * (a1 * k1[3] + a2 * k2[3] + a3 * k3[3] + a4 * k4[3] + a5 * k5[3]),
    )


def _err_norm(y, yn, e, rtol, atol):
    acc = 0.0
    for i in range(4):
        sc = atol + rtol * max(abs(y[i]), abs(yn[i]))
        q = e[i] / sc
        acc += q * q
    return math.sqrt(acc / 4.0)


def _chord(x0, y0, x1, y1, t0, h, radius, dmin):
    """Closest approach of the chord to the light; first entry time into the success circle.

    Returns ``(new_dmin, t_hit)`` with ``t_hit = -1`` when the chord does not enter the circle.
    """
    dx = x1 - x0
    dy = y1 - y0
    dd = dx * dx + dy * dy
    pd = x0 * dx + y0 * dy
    u = 0.0
    if dd > 0.0:
        u = min(max(-pd / dd, 0.0), 1.0)
    cx = x0 + u * dx
    cy = y0 + u * dy
    d = math.sqrt(cx * cx + cy * cy)
    if d < dmin:
        dmin = d
    t_hit = -1.0
    if d <= radius:
        c0 = x0 * x0 + y0 * y0 - radius * radius
        if c0 <= 0.0 or dd == 0.0:
            t_hit = t0
        else:
            disc = max(pd * pd - dd * c0, 0.0)
            t_hit = t0 + h * min(max((-pd - math.sqrt(disc)) / dd, 0.0), 1.0)
    return dmin, t_hit


def _finite(y):
    return math.isfinite(y[0]) and math.isfinite(y[1]) and math.isfinite(y[2]) and math.isfinite(y[3])


def _normalise(y):
    n = math.sqrt(y[2] * y[2] + y[3] * y[3])
    return y[0], y[1], y[2] / n, y[3] / n


def _rk4_step(y, h, l1x, l1y, l2x, l2y, w1, w2, u1, u2):
    """One classical RK4 step (the fixed-step method)."""
    k1 = rhs(y[0], y[1], y[2], y[3], l1x, l1y, l2x, l2y, w1, w2, u1, u2)
    z = _lin1(y, h, 0.5, k1)
    k2 = rhs(z[0], z[1], z[2], z[3], l1x, l1y, l2x, l2y, w1, w2, u1, u2)
    z = _lin1(y, h, 0.5, k2)
    k3 = rhs(z[0], z[1], z[2], z[3], l1x, l1y, l2x, l2y, w1, w2, u1, u2)
    z = _lin1(y, h, 1.0, k3)
    k4 = rhs(z[0], z[1], z[2], z[3], l1x, l1y, l2x, l2y, w1, w2, u1, u2)
    return _lin4(y, h, 1.0 / 6.0, k1, 1.0 / 3.0, k2, 1.0 / 3.0, k3, 1.0 / 6.0, k4)


def _dp5_step(y, h, k1, l1x, l1y, l2x, l2y, w1, w2, u1, u2):
    """One Dormand-Prince 5(4) step from the tableau above: ``(y_new, k7, error estimate)``;
    ``k7`` is the next step's ``k1`` (FSAL)."""
    z = _lin1(y, h, A21, k1)
    k2 = rhs(z[0], z[1], z[2], z[3], l1x, l1y, l2x, l2y, w1, w2, u1, u2)
    z = _lin2(y, h, A31, k1, A32, k2)
    k3 = rhs(z[0], z[1], z[2], z[3], l1x, l1y, l2x, l2y, w1, w2, u1, u2)
    z = _lin3(y, h, A41, k1, A42, k2, A43, k3)
    k4 = rhs(z[0], z[1], z[2], z[3], l1x, l1y, l2x, l2y, w1, w2, u1, u2)
    z = _lin4(y, h, A51, k1, A52, k2, A53, k3, A54, k4)
    k5 = rhs(z[0], z[1], z[2], z[3], l1x, l1y, l2x, l2y, w1, w2, u1, u2)
    z = _lin5(y, h, A61, k1, A62, k2, A63, k3, A64, k4, A65, k5)
    k6 = rhs(z[0], z[1], z[2], z[3], l1x, l1y, l2x, l2y, w1, w2, u1, u2)
    yn = _lin5(y, h, B1, k1, B3, k3, B4, k4, B5, k5, B6, k6)
    k7 = rhs(yn[0], yn[1], yn[2], yn[3], l1x, l1y, l2x, l2y, w1, w2, u1, u2)
    e = (
        h * (E1 * k1[0] + E3 * k3[0] + E4 * k4[0] + E5 * k5[0] + E6 * k6[0] + E7 * k7[0]),
        h * (E1 * k1[1] + E3 * k3[1] + E4 * k4[1] + E5 * k5[1] + E6 * k6[1] + E7 * k7[1]),
        h * (E1 * k1[2] + E3 * k3[2] + E4 * k4[2] + E5 * k5[2] + E6 * k6[2] + E7 * k7[2]),
        h * (E1 * k1[3] + E3 * k3[3] + E4 * k4[3] + E5 * k5[3] + E6 * k6[3] + E7 * k7[3]),
    )
    return yn, k7, e


def _rk4_trajectory(y, dmin, l1x, l1y, l2x, l2y, w1, w2, u1, u2, radius, horizon, dt, max_steps):
    t = 0.0
    steps = 0
    while t < horizon:
        if steps >= max_steps:
            return math.nan, dmin, STATUS_STEP_CAP, steps
        h = min(dt, horizon - t)
        yn = _rk4_step(y, h, l1x, l1y, l2x, l2y, w1, w2, u1, u2)
        steps += 1
        if not _finite(yn):
            return math.nan, dmin, STATUS_NONFINITE, steps
        yn = _normalise(yn)
        dmin, t_hit = _chord(y[0], y[1], yn[0], yn[1], t, h, radius, dmin)
        if t_hit >= 0.0:
            return t_hit, dmin, STATUS_OK, steps
        y = yn
        t += h
    return math.nan, dmin, STATUS_OK, steps


def _dp5_trajectory(y, dmin, l1x, l1y, l2x, l2y, w1, w2, u1, u2, radius, horizon, rtol, atol, max_steps):
    t = 0.0
    steps = 0
    h = H_FIRST
    k1 = rhs(y[0], y[1], y[2], y[3], l1x, l1y, l2x, l2y, w1, w2, u1, u2)
    while t < horizon:
        if steps >= max_steps:
            return math.nan, dmin, STATUS_STEP_CAP, steps
        if h < H_MIN:
            return math.nan, dmin, STATUS_STEP_UNDERFLOW, steps
        last = h >= horizon - t
        if last:
            h = horizon - t
        yn, k7, e = _dp5_step(y, h, k1, l1x, l1y, l2x, l2y, w1, w2, u1, u2)
        steps += 1
        err = _err_norm(y, yn, e, rtol, atol)
        if not (err <= 1.0):  # also catches NaN: shrink and retry
            if not _finite(yn) or not math.isfinite(err):
                h = h * MIN_FACTOR
            else:
                h = h * max(MIN_FACTOR, SAFETY * err**ERROR_EXPONENT)
            continue
        if not _finite(yn):
            return math.nan, dmin, STATUS_NONFINITE, steps
        dmin, t_hit = _chord(y[0], y[1], yn[0], yn[1], t, h, radius, dmin)
        if t_hit >= 0.0:
            return t_hit, dmin, STATUS_OK, steps
        t = horizon if last else t + h
        # FSAL: k7 belongs to the unnormalised state; the difference is O(rtol) and within the
        # step's own error, while re-evaluating would cost a seventh stage per step.
        y = _normalise(yn)
        k1 = k7
        fac = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, max(MIN_FACTOR, SAFETY * err**ERROR_EXPONENT))
        h = h * fac
    return math.nan, dmin, STATUS_OK, steps


def trajectory(x0, y0, l1x, l1y, l2x, l2y, w1, w2, u1, u2, radius, horizon, method, rtol, atol, dt, max_steps):
    """Integrate one trajectory from ``(x0, y0)`` facing +x with the method ``method``; crossed
    weights ``w1, w2``, uncrossed ``u1, u2`` (used by the four-synapse build only).

    Returns ``(first_time, min_dist, status, steps)``; ``first_time`` is NaN without success.
    Status codes are ``morphlearn.results``'s.
    """
    y = (x0, y0, 1.0, 0.0)
    dmin = math.sqrt(x0 * x0 + y0 * y0)
    if dmin <= radius:
        return 0.0, dmin, STATUS_OK, 0
    if method == METHOD_RK4:
        return _rk4_trajectory(y, dmin, l1x, l1y, l2x, l2y, w1, w2, u1, u2, radius, horizon, dt, max_steps)
    return _dp5_trajectory(y, dmin, l1x, l1y, l2x, l2y, w1, w2, u1, u2, radius, horizon, rtol, atol, max_steps)


_FUNCS = (
    "rhs",
    "_lin1",
    "_lin2",
    "_lin3",
    "_lin4",
    "_lin5",
    "_err_norm",
    "_chord",
    "_finite",
    "_normalise",
    "_rk4_step",
    "_dp5_step",
    "_rk4_trajectory",
    "_dp5_trajectory",
    "trajectory",
)


#: Controllers: synapse count -> the right-hand side the integrators call as ``rhs``.
SYNAPSES = {2: "rhs", 4: "rhs4"}


def build(jit: Callable[[Any], Any], synapses: int = 2) -> Callable[..., tuple[float, float, int, int]]:
    """Compile the model with ``jit`` (e.g. ``numba.njit`` or ``cuda.jit(device=True)``) for the
    two- or four-synapse controller (``synapses``); the integrators are the same source for both.

    The functions refer to each other as module globals; compiling each into a fresh namespace
    makes every call site resolve to the compiled twin (``rhs`` resolves to ``rhs4`` for four).
    """
    if synapses not in SYNAPSES:
        raise ValueError(f"synapses must be one of {sorted(SYNAPSES)}, got {synapses!r}")
    ns: dict[str, Any] = dict(globals())
    for name in _FUNCS:
        ns[name] = jit(twin(globals()[SYNAPSES[synapses] if name == "rhs" else name], ns, synapses, name))
    return ns["trajectory"]


def twin(f: Callable[..., Any], ns: dict[str, Any], synapses: int, name: str | None = None) -> Callable[..., Any]:
    """``f``'s code as a function ``name`` (default: its own) whose globals are ``ns``, ready for a
    decorator: its calls then resolve to the compiled functions in ``ns``. numba's on-disk cache
    keys a function by file, line and qualname, so the four-synapse twins get names of their own,
    or they would load the two-synapse machine code."""
    name = name or f.__name__
    g = types.FunctionType(f.__code__, ns, name, f.__defaults__, f.__closure__)
    g.__qualname__ = name if synapses == 2 else f"{name}_synapses{synapses}"
    return g
