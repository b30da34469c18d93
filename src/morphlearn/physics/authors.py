"""The paper authors' robot and world: the facts every engine that builds it shares (docs/ode.md).

The ODE model (:mod:`morphlearn.ode`) builds this robot in the authors' own engine; MuJoCo and
pybullet build it as closely as each allows (``robot: authors``, docs/authors_robot.md). The body
parameters (masses, wheel radius, motor law, gravity, step) are the body file
``config/authors_body.yaml``; the facts here are the ones that are not parameters. All in the
project's frame: the robot starts at the origin facing +x, +y to its left (the authors' frame is
this one turned: x_a = -y, y_a = x).
"""

from __future__ import annotations

from morphlearn.physics.params import EmpiricalParams

#: Sensor spheres: radius, mass, and their centres' height above the wheel tops (z = 2 WR + 0.05).
SENSOR_RADIUS = 0.05
SENSOR_MASS = 1.0
SENSOR_LIFT = 0.05
#: The light: a sphere of ``light_radius`` and this mass, its centre this high (1 mm above the floor).
LIGHT_MASS = 1.0
LIGHT_Z = 0.201
#: The castor: a sphere as large as a wheel, this far ahead of the chassis centre, on a free hinge.
CASTOR_X = 0.5
#: Wheel centres at y = +-WHEEL_Y (left +), x = -wheel_setback.
WHEEL_Y = 0.5
#: ODE's force-dependent slip of every contact (m/s per N): mu = infinity, tangential slip
#: velocity = SLIP x tangential force, in both friction directions.
SLIP = 0.01
#: The authors' success test adds 2^-10 to the contact distance 0.5 + wheel radius + light radius.
SUCCESS_TOLERANCE = 2.0**-10


def success_radius(p: EmpiricalParams) -> float:
    """Centre-to-light distance (2D, the light as placed) that counts as success."""
    return p.contact_distance + SUCCESS_TOLERANCE


def sensor_height(p: EmpiricalParams) -> float:
    """Height of the sensor spheres' centres above the floor (the chassis centre is at WR)."""
    return 2.0 * p.wheel_radius + SENSOR_LIFT


def reach(p: EmpiricalParams) -> float:
    """The farthest any part of the robot that collides with the light reaches from the chassis
    centre, horizontally: the castor's and the wheels' outer points (a box corner is nearer).
    While ``reach + light_radius < success_radius`` an episode succeeds before the robot can touch
    the light, so an engine that stops at success need not build the light as a body."""
    wheel = (p.wheel_setback**2 + WHEEL_Y**2) ** 0.5 + p.wheel_radius
    return max(CASTOR_X + p.wheel_radius, wheel, (2 * 0.5**2) ** 0.5)
