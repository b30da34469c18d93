"""The C core (:mod:`morphlearn.ode._core`) behind a checked Python call.

:func:`run` runs a batch of episodes of the authors' robot (docs/ode.md), each in its own ODE
world, wholly in C; this module checks the inputs, lays out the buffers and names the missing
library in one line when the extension was not built (Debian's ``libode-dev`` absent at set-up).
"""

from __future__ import annotations

import sys
from collections import Counter
from types import ModuleType
from typing import Any

import numpy as np

from morphlearn.errors import EngineError
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


class OdeEngineError(EngineError):
    """ODE stopped with an error or a failed internal assertion (its handler in ``_core.c`` jumps
    out of the episode instead of letting ODE abort the interpreter): one line, the engine's own."""


#: ODE's messages (dMessage, e.g. "LCP internal error") this process was given: number -> count.
MESSAGES: Counter[int] = Counter()


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
    try:
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
    except RuntimeError as e:
        raise OdeEngineError(f"the ODE engine failed on these body values: {e}") from None
    spent = spent or {}  # a core built before it returned its messages (rebuild: bash tools/setup.sh)
    _report(spent, n)
    if timing is not None:
        timing.update({k: spent[k] for k in ("collide", "world_step")})
    return Episodes(first, dmin, steps, finite.astype(bool)), track


def _report(spent: dict[str, Any], n: int) -> None:
    """ODE's messages of a batch, counted in :data:`MESSAGES` and said once per message number per
    process (one line on stderr): a message repeated every step is one line, not one per step."""
    count, num = int(spent.get("messages", 0)), int(spent.get("message_num", 0))
    if not count:
        return
    first = num not in MESSAGES
    MESSAGES[num] += count
    if first:
        text = " ".join(str(spent.get("message", "")).split())
        print(
            f"morphlearn: ODE message {num}: {text} ({count} times in a batch of {n} episodes; "
            "said once per process, counted in morphlearn.ode.core.MESSAGES)",
            file=sys.stderr,
        )
