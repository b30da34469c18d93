"""MJCF of the robot, generated from :class:`~morphlearn.physics.params.EmpiricalParams`.

One robot per model (the batch runs many copies of it, each in its own simulation, see
:mod:`.episode`). Every number of the body comes from the parameters; the settings that exist
only in MuJoCo (the velocity loop's gain, the contact softness, the solver) are in
:class:`MujocoSettings`. Nothing is kept as a hand-written XML file.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

from morphlearn.physics.params import BODY_SIZE, EmpiricalParams

#: pybullet's friction of the floor (robot.add_floor) and the default lateral friction of the
#: box (pybullet's base default, measured with getDynamicsInfo): pybullet multiplies the two
#: bodies' frictions, so the contact pairs below carry the products.
FLOOR_FRICTION = 1.0
BOX_FRICTION = 0.5


@dataclass(frozen=True)
class MujocoSettings:
    """What MuJoCo needs beyond the shared parameters (documented in the package docstring)."""

    #: Velocity-actuator gain (N m s/rad). pybullet's velocity motor is a hard constraint row
    #: with a force limit; MuJoCo's is a force ``kv (target - qvel)`` clamped to the torque
    #: limit, integrated implicitly while unclamped. 100 makes the loop's time constant about one
    #: step (I_eff / kv ~ 0.05 s); at 200 and above the clamped steps overshoot the narrow unclamped
    #: band and the wheels chatter between +-max_torque (mirror symmetry of outcomes then breaks).
    kv: float = 100.0
    integrator: str = "implicitfast"  # implicit in the actuators' velocity derivative
    solver: str = "Newton"
    iterations: int = 100
    tolerance: float = 1e-8
    cone: str = "pyramidal"  # MuJoCo's default; traction stays far inside the cone here
    #: Contact softness: MuJoCo's default solref (0.02 s, 1), which its ``refsafe`` raises to
    #: 2 * dt = 0.1 s at dt = 0.05, and its default solimp. The body rests ~5 mm into the floor.
    solref: tuple[float, float] = (0.02, 1.0)
    solimp: tuple[float, float, float] = (0.9, 0.95, 0.001)

    def __post_init__(self) -> None:
        allowed = {
            "integrator": ("implicitfast", "implicit", "Euler", "RK4"),
            "solver": ("Newton", "CG", "PGS"),
            "cone": ("pyramidal", "elliptic"),
        }
        for k, options in allowed.items():
            if getattr(self, k) not in options:
                raise ValueError(f"mujoco setting {k} = {getattr(self, k)!r} is invalid; allowed: {options}")
        for k in ("kv", "tolerance"):
            v = getattr(self, k)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ValueError(f"mujoco setting {k} = {v!r} is invalid; allowed: a number > 0")
        if not (isinstance(self.iterations, int) and self.iterations >= 1):
            raise ValueError(f"mujoco setting iterations = {self.iterations!r} is invalid; allowed: integer >= 1")

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)


def _f(x: float) -> str:
    """Shortest repr of a float: the XML carries the parameters' exact values."""
    return repr(float(x))


def _v(*xs: float) -> str:
    return " ".join(_f(x) for x in xs)


#: Geoms collide only through the explicit floor pairs of a model's <contact> section.
NO_COLLISION = 'contype="0" conaffinity="0"'


def options_xml(p: EmpiricalParams, s: MujocoSettings) -> str:
    """The compiler and solver settings every model of the robot shares."""
    return f"""  <compiler angle="radian" autolimits="true"/>
  <option timestep="{_f(p.dt)}" gravity="0 0 {_f(-p.gravity)}" integrator="{s.integrator}"
          solver="{s.solver}" iterations="{s.iterations}" tolerance="{_f(s.tolerance)}" cone="{s.cone}">
    <flag autoreset="disable"/>
  </option>"""


def wheels_xml(p: EmpiricalParams, y: float) -> str:
    """The two sphere wheels at ``(-setback, +-y, 0)`` from the chassis centre, on hinges about +y
    (a positive rate rolls the robot forward)."""
    return "\n".join(
        f'      <body name="{side}_wheel" pos="{_v(-p.wheel_setback, sign * y, 0)}">\n'
        f'        <joint name="{side}" type="hinge" axis="0 1 0"/>\n'
        f'        <geom name="{side}_wheel" type="sphere" size="{_f(p.wheel_radius)}" '
        f'mass="{_f(p.wheel_mass)}" {NO_COLLISION}/>\n'
        "      </body>"
        for side, sign in (("left", 1.0), ("right", -1.0))
    )


def motors_xml(p: EmpiricalParams, s: MujocoSettings) -> str:
    """The wheels' velocity actuators (gain ``kv``, force clamped to ``max_torque``): ``right``
    (ctrl column RIGHT = 0), ``left`` (LEFT = 1)."""
    tau, vmax = p.max_torque, p.max_speed
    rows = "\n".join(
        f'    <velocity name="{j}" joint="{j}" kv="{_f(s.kv)}" ctrlrange="{_v(-vmax, vmax)}" '
        f'forcerange="{_v(-tau, tau)}"/>'
        for j in ("right", "left")
    )
    return f"  <actuator>\n{rows}\n  </actuator>"


def mjcf(params: EmpiricalParams, settings: MujocoSettings | None = None) -> str:
    """The robot as an MJCF string (frame and geometry as :mod:`morphlearn.empirical.robot`).

    - body: box ``1 x 1 x wheel_radius/2`` centred at ``z = wheel_radius``, free joint, mass
      ``body_mass``; its frame is its centre of mass (as pybullet's base) because the castor is a
      child body of its own;
    - wheels: spheres of radius ``wheel_radius`` on hinges about +y at ``(-setback, +-0.5, 0)``;
      a positive joint velocity rolls the robot forward; velocity actuators ``right`` (index 0)
      and ``left`` (index 1) with ``ctrlrange = +-max_speed`` and ``forcerange = +-max_torque``;
    - castor: frictionless sphere of radius ``wheel_radius/2`` at ``(0.5, 0, -wheel_radius/2)``.

    Collisions: every geom has contype = conaffinity = 0 and the only contacts are explicit
    floor pairs (wheels: friction ``wheel_friction * 1``; castor: condim 1, frictionless; box:
    ``0.5 * 1``), as pybullet's robot touches only the floor until it touches the light, when the
    episode ends (the light is not a body here; see the package docstring).
    """
    s = settings or MujocoSettings()
    p = params
    r, half = p.wheel_radius, 0.5 * BODY_SIZE
    mu_w = p.wheel_friction * FLOOR_FRICTION
    mu_b = BOX_FRICTION * FLOOR_FRICTION
    nocol = NO_COLLISION
    contact = f'solref="{_v(*s.solref)}" solimp="{_v(*s.solimp)}"'
    return f"""<mujoco model="morphlearn_robot">
  <!-- Generated by morphlearn.mujoco.model.mjcf from EmpiricalParams; do not edit. -->
{options_xml(p, s)}
  <worldbody>
    <geom name="floor" type="plane" size="0 0 1" {nocol}/>
    <body name="body" pos="0 0 {_f(r)}">
      <freejoint name="free"/>
      <geom name="box" type="box" size="{_v(half, half, r / 4)}" mass="{_f(p.body_mass)}" {nocol}/>
      <body name="castor" pos="{_v(half, 0, -r / 2)}">
        <geom name="castor" type="sphere" size="{_f(r / 2)}" mass="{_f(p.castor_mass)}" {nocol}/>
      </body>
{wheels_xml(p, half)}
    </body>
  </worldbody>
  <contact>
    <pair name="floor_left_wheel" geom1="floor" geom2="left_wheel" condim="3" friction="{_v(mu_w, mu_w)}" {contact}/>
    <pair name="floor_right_wheel" geom1="floor" geom2="right_wheel" condim="3" friction="{_v(mu_w, mu_w)}" {contact}/>
    <pair name="floor_castor" geom1="floor" geom2="castor" condim="1" {contact}/>
    <pair name="floor_box" geom1="floor" geom2="box" condim="3" friction="{_v(mu_b, mu_b)}" {contact}/>
  </contact>
{motors_xml(p, s)}
</mujoco>
"""


def build_model(params: EmpiricalParams, settings: MujocoSettings | None = None) -> Any:
    """Compile :func:`mjcf` into a ``mujoco.MjModel``."""
    import mujoco

    return mujoco.MjModel.from_xml_string(mjcf(params, settings))


#: Actuator indices (ctrl columns) and qpos layout of the compiled model.
RIGHT, LEFT = 0, 1
QPOS_XYZ, QPOS_QUAT = slice(0, 3), slice(3, 7)
