"""Physical parameters and solver settings of the empirical (pybullet) model.

Units are SI as pybullet reads them: metres, kilograms, seconds, radians, newton-metres.
The body is a 1 x 1 box (sensor coordinates in [-0.5, 0.5] are on it), so lengths are in
body widths as well. Defaults are the paper authors' tuned base morphology; the morphology
this project uses comes from :mod:`morphlearn.empirical.optimise` and lives in
``config/empirical_morphology.yaml`` (load it with :func:`load_params`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

#: Side of the square body (m). Fixed: the sensor grid is defined on it.
BODY_SIZE = 1.0


@dataclass(frozen=True)
class EmpiricalParams:
    """Body, actuation, environment and solver settings. Frozen: safe as a cache key."""

    body_mass: float = 999.973  # kg, the box
    wheel_mass: float = 117.519  # kg, each of the two driven sphere wheels
    castor_mass: float = 0.00666  # kg, the passive frictionless front castor sphere
    wheel_radius: float = 0.260017  # m; body height = wheel_radius / 2, centre at z = wheel_radius
    max_speed: float = 2.59115 * math.pi  # rad/s, wheel angular speed at |motor| = 1
    max_torque: float = 1.95026 * math.pi  # N m, velocity-motor force limit per wheel
    wheel_setback: float = 0.025  # m, wheel axle behind the body centre (0 tips the body back)
    wheel_friction: float = 1.0  # lateral friction of wheels (and the floor); castor has 0
    light_radius: float = 0.2  # m
    light_distance: float = 4.0 * math.sqrt(2.0)  # m, start-to-light distance r
    gravity: float = 9.81  # m/s^2, magnitude (acts along -z)
    dt: float = 0.05  # s, physics step
    steps: int = 2500  # steps per episode (horizon = steps * dt = 125 s)
    solver_iterations: int = 100  # 50 flips outcomes; 100 makes results mirror-symmetric

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            _check(f.name, getattr(self, f.name))
        if self.light_distance <= self.contact_distance:  # every episode would succeed at t = 0
            raise ValueError(
                f"light_distance = {self.light_distance!r} is not beyond the contact distance "
                f"{self.contact_distance:g} (0.5 + wheel_radius + light_radius): the robot would start "
                f"touching the light; allowed: light_distance > {self.contact_distance:g}"
            )

    @property
    def contact_distance(self) -> float:
        """Centre-to-light distance that counts as touching the light (success)."""
        return 0.5 * BODY_SIZE + self.wheel_radius + self.light_radius

    @property
    def horizon(self) -> float:
        return self.steps * self.dt

    @classmethod
    def from_mapping(cls, values: Mapping[str, Any]) -> EmpiricalParams:
        """Defaults overridden by ``values``; unknown keys and out-of-range values raise."""
        allowed = [f.name for f in dataclasses.fields(cls)]
        unknown = [k for k in values if k not in allowed]
        if unknown:
            more = f" (and {len(unknown) - 1} more)" if len(unknown) > 1 else ""
            raise ValueError(f"unknown empirical parameter {_short(unknown[0])}{more}; allowed: {allowed}")
        return cls(**dict(values))

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)

    def replace(self, **changes: Any) -> EmpiricalParams:
        return dataclasses.replace(self, **changes)


def _ranges_from_schema() -> dict[str, tuple[float, bool, float | None, bool]]:
    """name -> (lower bound, lower bound exclusive?, upper bound, integer?), from the one place the
    ranges are given and argued for: the ``params`` properties of the physics section of
    ``config_schema.yaml`` (the config's ``<model>.params`` are checked against the same schema)."""
    from morphlearn.config import schema

    props = schema()["properties"]["empirical"]["properties"]["params"]["properties"]
    out: dict[str, tuple[float, bool, float | None, bool]] = {}
    for name, s in props.items():
        excl = "exclusiveMinimum" in s
        out[name] = (s["exclusiveMinimum"] if excl else s["minimum"], excl, s.get("maximum"), s["type"] == "integer")
    return out


#: name -> (lower bound, lower bound exclusive?, upper bound or None, integer?): one range per
#: parameter, read from config_schema.yaml (where each bound's reason is given).
_RANGES: dict[str, tuple[float, bool, float | None, bool]] = _ranges_from_schema()


def _allowed(name: str) -> str:
    lo, excl, hi, integer = _RANGES[name]
    kind = "integer" if integer else "number"
    hi_s = f" and <= {hi:g}" if hi is not None else ""
    return f"{kind} {'>' if excl else '>='} {lo:g}{hi_s}"


def _check(name: str, value: Any) -> None:
    lo, excl, hi, integer = _RANGES[name]
    ok_type = isinstance(value, int) if integer else isinstance(value, (int, float))
    if isinstance(value, bool) or not ok_type:
        raise ValueError(f"{name} = {_short(value)} is invalid; allowed: {_allowed(name)}")
    try:
        v = float(value)
    except OverflowError:  # an integer beyond a double: out of every range
        v = math.inf
    bad = not math.isfinite(v) or (v <= lo if excl else v < lo) or (hi is not None and v > hi)
    if bad:
        raise ValueError(f"{name} = {_short(value)} is out of range; allowed: {_allowed(name)}")


def _short(value: Any) -> str:
    """``value`` as the message shows it: at most 60 characters (a 5,000-digit integer is not
    printed whole, and Python refuses to print one of more than 4,300 digits)."""
    big = isinstance(value, int) and value.bit_length() > 160
    try:
        text = f"an integer of {value.bit_length()} bits" if big else repr(value)
    except ValueError:  # a list holding such an integer
        text = f"a {type(value).__name__} too large to print"
    return text if len(text) <= 60 else f"{text[:50]}... ({len(text)} characters)"


def load_params(path: str | Path) -> EmpiricalParams:
    """Read a YAML mapping of parameter names (e.g. ``config/empirical_morphology.yaml``).

    Every way the file can be bad (unreadable, malformed YAML, not a mapping, a bad value) raises
    ValueError with one line saying what, for the config check and the CLI to prefix.
    """
    from morphlearn.config import yaml_mapping

    data = yaml_mapping(path, "empirical parameters")
    try:
        return EmpiricalParams.from_mapping(data)
    except (ValueError, TypeError) as e:
        raise ValueError(str(e).splitlines()[0]) from None
