"""The Warp kernels of :mod:`morphlearn.mujoco.mjwarp` (imported only by it, when the warp backend
runs: importing this module imports ``warp``). No ``from __future__ import annotations`` here: Warp
reads the kernels' annotations as types."""

import warp as wp

from morphlearn.mujoco.model import LEFT, RIGHT

f64 = wp.float64
RIGHT_ = wp.constant(RIGHT)
LEFT_ = wp.constant(LEFT)


@wp.kernel(module="unique", enable_backward=False)
def observe_control(
    kstep: wp.array(dtype=wp.int32),
    nsteps: wp.int32,
    stop_at_contact: wp.int32,
    c2: f64,
    z0: f64,
    vmax: f64,
    qpos: wp.array2d(dtype=wp.float32),
    light: wp.array2d(dtype=f64),
    sens: wp.array2d(dtype=f64),
    weight: wp.array2d(dtype=f64),
    active: wp.array(dtype=wp.int32),
    first_k: wp.array(dtype=wp.int32),
    min_d2: wp.array(dtype=f64),
    tilt_c: wp.array(dtype=f64),
    lift: wp.array(dtype=f64),
    steps: wp.array(dtype=wp.int32),
    finite: wp.array(dtype=wp.int32),
    ctrl: wp.array2d(dtype=wp.float32),
):
    i = wp.tid()
    k = kstep[0]
    if active[i] == 0:
        ctrl[i, 0] = wp.float32(0.0)
        ctrl[i, 1] = wp.float32(0.0)
        return
    ok = wp.int32(1)
    for j in range(qpos.shape[1]):
        if not wp.isfinite(qpos[i, j]):
            ok = wp.int32(0)
    if ok == 0:
        finite[i] = 0
        steps[i] = k
        active[i] = 0
        return
    px = f64(qpos[i, 0])
    py = f64(qpos[i, 1])
    pz = f64(qpos[i, 2])
    qw = f64(qpos[i, 3])
    qx = f64(qpos[i, 4])
    qy = f64(qpos[i, 5])
    qz = f64(qpos[i, 6])
    one = f64(1.0)
    two = f64(2.0)
    dx = px - light[i, 0]
    dy = py - light[i, 1]
    d2 = dx * dx + dy * dy
    min_d2[i] = wp.min(min_d2[i], d2)
    tilt_c[i] = wp.min(tilt_c[i], one - two * (qx * qx + qy * qy))
    lift[i] = wp.max(lift[i], wp.abs(pz - z0))
    if d2 <= c2 and first_k[i] < 0:
        first_k[i] = k
        if stop_at_contact != 0:
            steps[i] = k
            active[i] = 0
            return
    if k >= nsteps:
        steps[i] = k
        active[i] = 0
        return
    # body x and y axes on the floor (rotation-matrix columns), sensors 1/d^2, tanh motors
    ax = one - two * (qy * qy + qz * qz)
    ay = two * (qx * qy + qz * qw)
    bx = two * (qx * qy - qz * qw)
    by = one - two * (qx * qx + qz * qz)
    e1x = dx + ax * sens[i, 0] + bx * sens[i, 1]
    e1y = dy + ay * sens[i, 0] + by * sens[i, 1]
    e2x = dx + ax * sens[i, 2] + bx * sens[i, 3]
    e2y = dy + ay * sens[i, 2] + by * sens[i, 3]
    s1 = one / (e1x * e1x + e1y * e1y)
    s2 = one / (e2x * e2x + e2y * e2y)
    ctrl[i, RIGHT_] = wp.float32(wp.tanh(weight[i, 0] * s1) * vmax)
    ctrl[i, LEFT_] = wp.float32(wp.tanh(weight[i, 1] * s2) * vmax)


@wp.kernel(module="unique", enable_backward=False)
def advance(kstep: wp.array(dtype=wp.int32)):
    kstep[0] = kstep[0] + 1
