"""Offscreen render of the simulated robot (Fig. 1C): pybullet DIRECT mode, ER_TINY_RENDERER.

Either robot an engine builds (``robot``, a key of ``physics.model.ROBOT_BODIES``): the project's,
built by :func:`morphlearn.empirical.robot.build_world` exactly as its sweep builds it (the two
sensors added as red visual-only markers: it does not simulate them as bodies), or the paper
authors', built by :class:`morphlearn.empirical.authors.AuthorsEpisodeRunner` to ODE's geometry
(docs/authors_robot.md: chassis, wheel spheres, a castor sphere as large as a wheel, sensor
spheres), which the ODE model simulates; ODE has no renderer, so pybullet's draws it. This module
only colours it (body light grey, wheels black, castor grey, sensors red), adds a yellow light and
takes a picture. No window, no GPU: the software renderer is deterministic.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import pybullet as pb

from morphlearn.empirical.robot import CASTOR, LEFT_WHEEL, RIGHT_WHEEL, build_world
from morphlearn.physics import authors
from morphlearn.physics.params import EmpiricalParams

#: Link indices of the authors' robot as AuthorsEpisodeRunner builds it (ODE's creation order).
AUTHORS_LINKS = {"left wheel": 0, "right wheel": 1, "sensor 1": 2, "sensor 2": 3, "castor": 4}
GREY, BLACK, CASTOR_GREY, RED, YELLOW = (
    [0.86, 0.86, 0.84, 1],
    [0.08, 0.08, 0.08, 1],
    [0.55, 0.55, 0.55, 1],
    [0.85, 0.05, 0.05, 1],
    [1.0, 0.82, 0.1, 1],
)


@dataclass
class Render:
    rgb: np.ndarray  # (h, w, 3) uint8
    labels: dict[str, tuple[float, float]]  # part -> pixel (col, row) to annotate


def _project(view: Sequence[float], proj: Sequence[float], p: Sequence[float], w: int, h: int) -> tuple[float, float]:
    v = np.asarray(view, dtype=np.float64).reshape(4, 4, order="F")
    pr = np.asarray(proj, dtype=np.float64).reshape(4, 4, order="F")
    c = pr @ v @ np.array([*p, 1.0])
    ndc = c[:3] / c[3]
    return (ndc[0] + 1) * 0.5 * w, (1 - ndc[1]) * 0.5 * h


#: What a robot builder returns: (client, close it, parts to label: name -> point in the world).
Built = tuple[int, Callable[[], None], dict[str, tuple[float, float, float]]]


def _project_robot(
    p: EmpiricalParams, l1: Sequence[float], l2: Sequence[float], light_xy: tuple[float, float]
) -> Built:
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


def _authors_robot(
    p: EmpiricalParams, l1: Sequence[float], l2: Sequence[float], light_xy: tuple[float, float]
) -> Built:
    """The authors' robot in ODE's geometry, coloured, and the light (not a body in their world: a
    visual sphere at its height): (client, close, parts to label)."""
    from morphlearn.empirical.authors import AuthorsEpisodeRunner

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


def render_robot(
    params: EmpiricalParams | None = None,
    l1: Sequence[float] = (0.5, 0.5),
    l2: Sequence[float] = (0.5, -0.5),
    *,
    robot: str = "project",
    width: int = 960,
    height: int = 720,
    light_xy: tuple[float, float] = (2.0, 0.9),
    eye: Sequence[float] = (0.9, -3.1, 2.1),
    target: Sequence[float] = (0.75, 0.3, 0.05),
) -> Render:
    """Picture of ``robot`` ("project" or "authors") with sensors at ``l1``, ``l2`` and a light
    ``light_xy`` away."""
    builders = {"project": _project_robot, "authors": _authors_robot}
    if robot not in builders:
        raise ValueError(f"robot = {robot!r}; allowed: {sorted(builders)}")
    p = params or EmpiricalParams()
    c, close, parts = builders[robot](p, l1, l2, light_xy)
    try:
        view = pb.computeViewMatrix(list(eye), list(target), [0, 0, 1], physicsClientId=c)
        proj = pb.computeProjectionMatrixFOV(fov=38, aspect=width / height, nearVal=0.1, farVal=30, physicsClientId=c)
        img = pb.getCameraImage(
            width,
            height,
            view,
            proj,
            renderer=pb.ER_TINY_RENDERER,
            lightDirection=[1.0, 2.0, 3.0],
            shadow=1,
            physicsClientId=c,
        )
        rgb = np.reshape(np.asarray(img[2], dtype=np.uint8), (height, width, 4))[:, :, :3].copy()
        labels = {k: _project(view, proj, v, width, height) for k, v in parts.items()}
        return Render(rgb, labels)
    finally:
        close()
