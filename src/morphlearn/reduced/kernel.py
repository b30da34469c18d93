"""One source of the reduced model's episode: plain Python over scalars, compiled by ``build(jit)``.

The CPU kernel compiles it with ``numba.njit`` (episodes in parallel over cores, ``cpu.py``), the
CUDA kernel with ``numba.cuda.jit(device=True)`` (one thread an episode, ``cuda.py``), as the
theory's model does. The physics (what each constant means, every approximation) is in
:mod:`morphlearn.reduced.body`; this module only steps it.

State: the chassis centre (x, y), its heading as a unit vector (c, s), and the generalized
velocities in the body frame q = (u, v, om, spin_left, spin_right, spin_castor). One step of dt,
as ODE's dWorldStep takes it (semi-implicit Euler):

1. read the chassis centre and the sensors (state before the step); success test; controller;
2. new velocities: q_free = G q + om^2 C (momentum, the contacts' dampers implicit, the
   centripetal force of the offset centre of mass explicit), then the two motor rows
   (velocity targets, |torque| <= max_torque) solved exactly as a 2 x 2 box-constrained problem:
   q_new = q_free + H lam;
3. positions with the new velocities, the heading turned by 2 atan(dt om / 2) (ODE's quaternion
   step for a rotation about z), the body-frame velocities re-expressed in the turned frame.
"""

from __future__ import annotations

import math
import types
from collections.abc import Callable
from typing import Any

#: Most projected Gauss-Seidel sweeps of the motor solve (a body whose wheels couple strongly
#: converges more slowly; the authors' robot needs 2-3).
_SWEEPS = 100


def build(jit: Callable[..., Any]) -> Any:
    """The episode function compiled with ``jit`` (a numba decorator)."""

    @jit
    def capped(kk, r0, r1, tmax):
        """The same solution where the sweeps have not settled (a body whose wheels couple strongly,
        |k01| / k00 near 1: the sweeps then converge too slowly), exactly: the active set (one torque
        at a cap and the other free, or both at caps) that meets the optimality conditions."""
        k00, k01, k11 = kk[0], kk[1], kk[2]
        for which in range(4):  # one torque at a cap, the other free
            if which < 2:
                a = tmax if which == 0 else -tmax
                b = (r1 - k01 * a) * kk[7]
                g = k00 * a + k01 * b - r0
                if -tmax <= b <= tmax and ((a > 0.0 and g <= 0.0) or (a < 0.0 and g >= 0.0)):
                    return a, b
            else:
                b = tmax if which == 2 else -tmax
                a = (r0 - k01 * b) * kk[6]
                g = k01 * a + k11 * b - r1
                if -tmax <= a <= tmax and ((b > 0.0 and g <= 0.0) or (b < 0.0 and g >= 0.0)):
                    return a, b
        for corner in range(4):  # both at caps
            a = tmax if corner < 2 else -tmax
            b = tmax if corner % 2 == 0 else -tmax
            g0 = k00 * a + k01 * b - r0
            g1 = k01 * a + k11 * b - r1
            if ((a > 0.0 and g0 <= 0.0) or (a < 0.0 and g0 >= 0.0)) and (
                (b > 0.0 and g1 <= 0.0) or (b < 0.0 and g1 >= 0.0)
            ):
                return a, b
        return a, b

    @jit
    def motors(kk, r0, r1, tmax):
        """The two motor torques: the solution of K lam = r with |lam_i| <= tmax (K symmetric positive
        definite; a torque at its cap where its row's solution would pass it). ``kk``: K's entries,
        its inverse's and the reciprocals of its diagonal (body.py). Unconstrained when both fit (most
        steps: far from the light the motors hold their targets); else projected Gauss-Seidel to its
        fixed point: the wheels couple weakly through the chassis (|k01| / k00 ~ 1e-4 for the
        authors' robot), so two or three sweeps reach it to the last bit and the loop ends when a
        sweep changes nothing (at most ``_SWEEPS``; unsettled, :func:`capped` solves it exactly). The
        fixed point is the LCP's unique solution, the
        one ODE's Dantzig solver finds."""
        a = kk[3] * r0 + kk[4] * r1
        b = kk[4] * r0 + kk[5] * r1
        if -tmax <= a <= tmax and -tmax <= b <= tmax:
            return a, b
        k01 = kk[1]
        a = min(max(r0 * kk[6], -tmax), tmax)
        b = min(max((r1 - k01 * a) * kk[7], -tmax), tmax)
        for _ in range(_SWEEPS):
            a1 = min(max((r0 - k01 * b) * kk[6], -tmax), tmax)
            b1 = min(max((r1 - k01 * a1) * kk[7], -tmax), tmax)
            if a1 == a and b1 == b:
                return a, b
            a = a1
            b = b1
        return capped(kk, r0, r1, tmax)

    @jit
    def advance(
        g, hm, kk, cen, dt, vmax, tmax, dz2, dx, dy, l1x, l1y, l2x, l2y, w1, w2, x, y, c, s, q0, q1, q2, q3, q4, q5
    ):
        """One step from the state (x, y, c, s, q) with the centre at (dx, dy) from the light: the
        controller, the new velocities, the new positions; returns the new state."""
        # sensors: 3D distance to the light's centre (the height difference is constant)
        e1x = dx + c * l1x - s * l1y
        e1y = dy + s * l1x + c * l1y
        e2x = dx + c * l2x - s * l2y
        e2y = dy + s * l2x + c * l2y
        d1 = e1x * e1x + e1y * e1y + dz2
        d2 = e2x * e2x + e2y * e2y + dz2
        inv = 1.0 / (d1 * d2)  # one division for both readings 1 / d1, 1 / d2
        t_right = vmax * math.tanh(w1 * d2 * inv)
        t_left = vmax * math.tanh(w2 * d1 * inv)
        om2 = q2 * q2
        f0 = g[0] * q0 + g[1] * q1 + g[2] * q2 + g[3] * q3 + g[4] * q4 + g[5] * q5 + om2 * cen[0]
        f1 = g[6] * q0 + g[7] * q1 + g[8] * q2 + g[9] * q3 + g[10] * q4 + g[11] * q5 + om2 * cen[1]
        f2 = g[12] * q0 + g[13] * q1 + g[14] * q2 + g[15] * q3 + g[16] * q4 + g[17] * q5 + om2 * cen[2]
        f3 = g[18] * q0 + g[19] * q1 + g[20] * q2 + g[21] * q3 + g[22] * q4 + g[23] * q5 + om2 * cen[3]
        f4 = g[24] * q0 + g[25] * q1 + g[26] * q2 + g[27] * q3 + g[28] * q4 + g[29] * q5 + om2 * cen[4]
        f5 = g[30] * q0 + g[31] * q1 + g[32] * q2 + g[33] * q3 + g[34] * q4 + g[35] * q5 + om2 * cen[5]
        la, lb = motors(kk, t_left - f3, t_right - f4, tmax)
        q0 = f0 + hm[0] * la + hm[1] * lb
        q1 = f1 + hm[2] * la + hm[3] * lb
        q2 = f2 + hm[4] * la + hm[5] * lb
        q3 = f3 + hm[6] * la + hm[7] * lb
        q4 = f4 + hm[8] * la + hm[9] * lb
        q5 = f5 + hm[10] * la + hm[11] * lb
        x += dt * (c * q0 - s * q1)
        y += dt * (s * q0 + c * q1)
        # the turn of ODE's quaternion step: 2 atan(t), t = dt om / 2, as an exact rotation
        t = 0.5 * dt * q2
        n = 1.0 / (1.0 + t * t)
        cr = (1.0 - t * t) * n
        sr = 2.0 * t * n
        c, s = c * cr - s * sr, s * cr + c * sr
        q0, q1 = cr * q0 + sr * q1, cr * q1 - sr * q0
        return x, y, c, s, q0, q1, q2, q3, q4, q5

    @jit
    def episode(g, hm, kk, cen, dt, steps, vmax, tmax, radius, dz2, lx, ly, l1x, l1y, l2x, l2y, w1, w2, stop, path):
        """One episode from rest at the origin facing +x, the light at (lx, ly). ``g`` (36,),
        ``hm`` (12,), ``kk`` (8,), ``cen`` (6,): the body's constant matrices (body.py), row-major.
        Returns (first success step or -1, closest distance up to it, steps run, finite).
        ``path``: (steps, 2) receives the centre read at each step when it has rows."""
        x, y, c, s = 0.0, 0.0, 1.0, 0.0
        q0, q1, q2, q3, q4, q5 = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        best = math.inf  # squared: one square root per episode, not per step
        radius2 = radius * radius
        hit = -1
        record = path.shape[0] > 0
        for k in range(steps):
            if not (math.isfinite(x) and math.isfinite(y)):
                return hit, math.sqrt(best), k, False
            if record:
                path[k, 0] = x
                path[k, 1] = y
            dx = x - lx
            dy = y - ly
            d2 = dx * dx + dy * dy
            best = min(best, d2)
            if hit < 0 and d2 <= radius2:
                hit = k
                if stop:
                    return hit, math.sqrt(best), k, True
            x, y, c, s, q0, q1, q2, q3, q4, q5 = advance(
                g,
                hm,
                kk,
                cen,
                dt,
                vmax,
                tmax,
                dz2,
                dx,
                dy,
                l1x,
                l1y,
                l2x,
                l2y,
                w1,
                w2,
                x,
                y,
                c,
                s,
                q0,
                q1,
                q2,
                q3,
                q4,
                q5,
            )
        return hit, math.sqrt(best), steps, True

    return types.SimpleNamespace(motors=motors, capped=capped, advance=advance, episode=episode)
