"""The reduced model's episodes behind a checked Python call: the same signature and outcomes as
:func:`morphlearn.ode.core.run` (the model it answers to)."""

from __future__ import annotations

from typing import Any

import numpy as np

from morphlearn.grid import light_positions
from morphlearn.physics.authors import success_radius
from morphlearn.physics.batch import Episodes, check_inputs
from morphlearn.physics.params import EmpiricalParams
from morphlearn.reduced.body import body

#: The kernels that run a batch: scalar numba, SIMD lanes (C), CUDA (numba).
BACKENDS = ("cpu", "cpu-simd", "cuda")


def run(
    p: EmpiricalParams,
    l1: Any,
    l2: Any,
    w: Any,
    env: Any,
    *,
    stop_at_success: bool = True,
    path: bool = False,
    backend: str = "cpu",
) -> tuple[Episodes, np.ndarray | None]:
    """Episodes of one design (sensor points ``l1``, ``l2``, project frame), weights ``w`` (n, 2),
    environments ``env`` (n,). ``path``: also the chassis centre at each step (n, steps, 2), NaN
    after the episode stopped. ``backend`` (:data:`BACKENDS`): ``cpu`` (the scalar numba kernel,
    parallel over cores), ``cpu-simd`` (eight episodes a core in SIMD lanes,
    :mod:`morphlearn.reduced.simd`; the same outcomes to the last bit) or ``cuda`` (one GPU thread
    an episode, :mod:`morphlearn.reduced.cuda`). Paths always come from the scalar kernel."""
    if backend not in BACKENDS:
        raise ValueError(f"backend = {backend!r} is invalid; allowed: {', '.join(map(repr, BACKENDS))}")
    if backend == "cuda":
        from morphlearn.reduced import cuda as kernel
    elif backend == "cpu-simd":
        from morphlearn.reduced import simd as kernel
    else:
        from morphlearn.reduced import cpu as kernel
    from morphlearn.reduced import cpu

    w, env, sensors = check_inputs(l1, l2, w, env)
    n = len(w)
    if sensors.shape[0] and not (sensors == sensors[0]).all():
        raise ValueError("the reduced model runs one design per call: l1 and l2 must be single points")
    pts = sensors[0] if n else np.zeros(4)
    b = body(p, (float(pts[0]), float(pts[1])), (float(pts[2]), float(pts[3])))
    lights = np.ascontiguousarray(light_positions(p.light_distance)[env])
    first = np.empty(n, np.int64)
    dmin = np.empty(n, np.float64)
    steps = np.empty(n, np.int64)
    finite = np.empty(n, np.bool_)
    args = (
        b.g,
        b.hm,
        b.kk,
        b.cen,
        float(p.dt),
        int(p.steps),
        float(p.max_speed),
        float(p.max_torque),
        success_radius(p),
        b.dz2,
    )
    track = None
    if path:
        track = np.full((n, p.steps, 2), np.nan)
        for i in range(n):
            first[i], dmin[i], steps[i], finite[i] = cpu.run_path(
                *args, lights[i], pts, w[i, 0], w[i, 1], bool(stop_at_success), track[i]
            )
            track[i, steps[i] :] = np.nan
    else:
        kernel.run_batch(*args, lights, np.ascontiguousarray(pts), w, bool(stop_at_success), first, dmin, steps, finite)
    return Episodes(first, dmin, steps, finite), track
