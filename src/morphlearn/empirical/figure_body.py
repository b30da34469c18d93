"""The bodies pybullet builds, as Fig. 1C draws them (:class:`morphlearn.physics.body.FigureBody`).

The project's robot, built by :func:`morphlearn.empirical.robot.build_world` exactly as its sweep
builds it (the two sensors added as red visual-only markers: it does not simulate them as
bodies), and the paper authors' robot, built by :class:`morphlearn.empirical.authors.AuthorsEpisodeRunner`
to ODE's geometry (docs/authors_robot.md: chassis, wheel spheres, a castor sphere as large as a
wheel, sensor spheres), which the ODE model simulates; an engine with no builder of its own for a
robot (ODE has no renderer) is drawn as this one (:func:`morphlearn.models.figure_body_path`).
Each is coloured here (body light grey, wheels black, castor grey, sensors red, light yellow);
the picture is the figure's (:mod:`morphlearn.figures.render`).
"""

from __future__ import annotations

from collections.abc import Sequence

import pybullet as pb

from morphlearn.empirical.authors import CASTOR as AUTHORS_CASTOR
from morphlearn.empirical.authors import LEFT, RIGHT, SENSOR1, SENSOR2, AuthorsEpisodeRunner
from morphlearn.empirical.robot import CASTOR, LEFT_WHEEL, RIGHT_WHEEL, build_world
from morphlearn.physics import authors
from morphlearn.physics.body import BLACK, CASTOR_GREY, GREY, RED, YELLOW, Built, FigureBody
from morphlearn.physics.params import EmpiricalParams

#: Link indices of the authors' robot as AuthorsEpisodeRunner builds it (ODE's creation order).
AUTHORS_LINKS = {
    "left wheel": LEFT,
    "right wheel": RIGHT,
    "sensor 1": SENSOR1,
    "sensor 2": SENSOR2,
    "castor": AUTHORS_CASTOR,
}


def project_robot(p: EmpiricalParams, l1: Sequence[float], l2: Sequence[float], light_xy: tuple[float, float]) -> Built:
    """The project's robot as its sweep builds it, coloured: (client, close, parts to label)."""
    world = build_world(p, light_xy)
    c, robot = world.client, world.robot
    r = p.wheel_radius
    pb.changeVisualShape(robot, -1, rgbaColor=GREY, physicsClientId=c)
    for link in (LEFT_WHEEL, RIGHT_WHEEL):
        pb.changeVisualShape(robot, link, rgbaColor=BLACK, physicsClientId=c)
    pb.changeVisualShape(robot, CASTOR, rgbaColor=CASTOR_GREY, physicsClientId=c)
    pb.changeVisualShape(world.light, -1, rgbaColor=YELLOW, physicsClientId=c)
    top = r + r / 4
    sensor = pb.createVisualShape(pb.GEOM_SPHERE, radius=0.06, rgbaColor=RED, physicsClientId=c)
    for q in (l1, l2):
        pb.createMultiBody(0, -1, sensor, basePosition=[q[0], q[1], top + 0.03], physicsClientId=c)
    sb = p.wheel_setback
    parts = {
        "sensor 1": (l1[0], l1[1], top + 0.03),
        "sensor 2": (l2[0], l2[1], top + 0.03),
        "left wheel": (-sb, 0.5 + r / 2, r * 1.6),
        "right wheel": (-sb, -0.5 - r / 2, r * 1.4),
        "castor": (0.5, 0.0, r / 2),
        "light": (light_xy[0], light_xy[1], 2 * p.light_radius),
    }
    return c, world.close, parts


def authors_robot(p: EmpiricalParams, l1: Sequence[float], l2: Sequence[float], light_xy: tuple[float, float]) -> Built:
    """The authors' robot in ODE's geometry, coloured, and the light (not a body in their world: a
    visual sphere at its height): (client, close, parts to label)."""
    runner = AuthorsEpisodeRunner(p)
    body = runner.build((float(l1[0]), float(l1[1])), (float(l2[0]), float(l2[1])))
    c, r = runner.client, p.wheel_radius
    colours = {"left wheel": BLACK, "right wheel": BLACK, "sensor 1": RED, "sensor 2": RED, "castor": CASTOR_GREY}
    pb.changeVisualShape(body, -1, rgbaColor=GREY, physicsClientId=c)
    for name, link in AUTHORS_LINKS.items():
        pb.changeVisualShape(body, link, rgbaColor=colours[name], physicsClientId=c)
    lz = max(authors.LIGHT_Z, p.light_radius)
    light = pb.createVisualShape(pb.GEOM_SPHERE, radius=p.light_radius, rgbaColor=YELLOW, physicsClientId=c)
    pb.createMultiBody(0, -1, light, basePosition=[light_xy[0], light_xy[1], lz], physicsClientId=c)
    zs = authors.sensor_height(p)
    sb = p.wheel_setback
    parts = {
        "sensor 1": (l1[0], l1[1], zs),
        "sensor 2": (l2[0], l2[1], zs),
        "left wheel": (-sb, authors.WHEEL_Y, 1.8 * r),
        "right wheel": (-sb, -authors.WHEEL_Y, 1.5 * r),
        "castor": (authors.CASTOR_X + 0.7 * r, 0.3 * r, 1.2 * r),  # its flank right of sensor 2, as seen
        "light": (light_xy[0], light_xy[1], lz + p.light_radius),
    }
    return c, runner.close, parts


PROJECT = FigureBody(
    build=project_robot,
    text="the project's own body, its chassis, two motorised sphere wheels (black), a passive frictionless "
    "castor at the front (grey, half a wheel's radius) and two light sensors (red markers; points, not simulated "
    "bodies)",
    offsets={
        "sensor 1": (90, -130),
        "sensor 2": (150, 120),
        "left wheel": (-110, -130),
        "right wheel": (-60, 190),
        "castor": (230, 30),
        "light": (0, -120),
    },
)
AUTHORS = FigureBody(
    build=authors_robot,
    text="the paper authors' robot (docs/ode.md): a 1 x 1 chassis, two motorised sphere wheels (black), a "
    "passive castor sphere as large as a wheel at the front (grey) and two sensor spheres held above the "
    "chassis (red)",
    offsets={
        "sensor 1": (60, -120),
        "sensor 2": (-40, 170),
        "left wheel": (-120, -110),
        "right wheel": (-40, 200),
        "castor": (240, 40),
        "light": (0, -120),
    },
)
