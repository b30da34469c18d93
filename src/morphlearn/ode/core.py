"""The C core (:mod:`morphlearn.ode._core`) behind a checked Python call.

:func:`run` runs a batch of episodes of the authors' robot (docs/ode.md), each in its own ODE
world, wholly in C; this module checks the inputs, lays out the buffers and names the missing
library in one line when the extension was not built (Debian's ``libode-dev`` absent at set-up).
"""

from __future__ import annotations

from types import ModuleType
from typing import Any

import numpy as np

from morphlearn.grid import light_positions
from morphlearn.physics.authors import success_radius
from morphlearn.physics.batch import Episodes, check_inputs
from morphlearn.physics.params import EmpiricalParams

INSTALL_HINT = (
    "the ode model needs the Open Dynamics Engine: install Debian's libode-dev "
    "(apt-get install libode-dev), then run bash tools/setup.sh to build morphlearn.ode._core"
)


class OdeUnavailableError(RuntimeError):
    """The C core is not built (no ODE library at set-up)."""


def core() -> ModuleType:
    """The compiled core, or OdeUnavailableError naming the package to install."""
    try:
        from morphlearn.ode import _core
    except ImportError as e:
        raise OdeUnavailableError(f"{INSTALL_HINT} ({e})") from None
    return _core


def available() -> bool:
    try:
        core()
    except OdeUnavailableError:
        return False
    return True


def params_tuple(p: EmpiricalParams) -> tuple[Any, ...]:
    """The body as the C core reads it (order fixed by ``_core.c``'s Params). wheel_friction and
    solver_iterations are not read: ODE's contacts have mu = infinity with force-dependent slip,
    and dWorldStep solves exactly."""
    return (
        float(p.body_mass),
        float(p.wheel_mass),
        float(p.castor_mass),
        float(p.wheel_radius),
        float(p.max_speed),
        float(p.max_torque),
        float(p.wheel_setback),
        float(p.light_radius),
        float(p.gravity),
        float(p.dt),
        int(p.steps),
        success_radius(p),
    )


def run(
    p: EmpiricalParams,
    l1: Any,
    l2: Any,
    w: Any,
    env: Any,
    *,
    stop_at_success: bool = True,
    path: bool = False,
    timing: dict[str, float] | None = None,
) -> tuple[Episodes, np.ndarray | None]:
    """Episodes of sensor points ``l1``, ``l2`` ((n, 2) or one point for all, project frame),
    weights ``w`` (n, 2) and environments ``env`` (n,), in that order. ``stop_at_success``: an
    episode ends at its first success (exact: nothing after it is read). ``path``: also the chassis
    (x, y) read at each step, (n, steps, 2), NaN after the episode stopped. ``timing``: a dict
    that receives the CPU seconds spent in dSpaceCollide and dWorldStep (benchmarks)."""
    w, env, sensors = check_inputs(l1, l2, w, env)
    n = len(w)
    lights = np.ascontiguousarray(light_positions(p.light_distance)[env])
    first = np.empty(n, np.int64)
    dmin = np.empty(n, np.float64)
    steps = np.empty(n, np.int64)
    finite = np.empty(n, np.uint8)
    track = np.full((n, p.steps, 2), np.nan) if path else None
    spent = core().run_batch(
        params_tuple(p),
        n,
        sensors,
        w,
        lights,
        first,
        dmin,
        steps,
        finite,
        bool(stop_at_success),
        track,
        timing is not None,
    )
    if timing is not None:
        timing.update(spent)
    return Episodes(first, dmin, steps, finite.astype(bool)), track
