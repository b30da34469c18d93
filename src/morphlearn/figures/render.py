"""Offscreen render of the simulated robot (Fig. 1C): pybullet DIRECT mode, ER_TINY_RENDERER.

The robot is built by :func:`morphlearn.empirical.robot.build_world` exactly as the sweep builds
it; this module only colours it (body light grey, wheels black, castor grey), adds the two
sensors as red visual-only markers (the sweep does not simulate them as bodies) and a yellow
light, and takes a picture. No window, no GPU: the software renderer is deterministic.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pybullet as pb

from morphlearn.empirical.robot import CASTOR, LEFT_WHEEL, RIGHT_WHEEL, build_world
from morphlearn.physics.params import EmpiricalParams


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


def render_robot(
    params: EmpiricalParams | None = None,
    l1: Sequence[float] = (0.5, 0.5),
    l2: Sequence[float] = (0.5, -0.5),
    *,
    width: int = 960,
    height: int = 720,
    light_xy: tuple[float, float] = (2.0, 0.9),
    eye: Sequence[float] = (0.9, -3.1, 2.1),
    target: Sequence[float] = (0.75, 0.3, 0.05),
) -> Render:
    """Picture of the robot with sensors at ``l1``, ``l2`` and a light ``light_xy`` away."""
    p = params or EmpiricalParams()
    world = build_world(p, light_xy)
    c, robot = world.client, world.robot
    try:
        r = p.wheel_radius
        pb.changeVisualShape(robot, -1, rgbaColor=[0.86, 0.86, 0.84, 1], physicsClientId=c)
        for link in (LEFT_WHEEL, RIGHT_WHEEL):
            pb.changeVisualShape(robot, link, rgbaColor=[0.08, 0.08, 0.08, 1], physicsClientId=c)
        pb.changeVisualShape(robot, CASTOR, rgbaColor=[0.55, 0.55, 0.55, 1], physicsClientId=c)
        pb.changeVisualShape(world.light, -1, rgbaColor=[1.0, 0.82, 0.1, 1], physicsClientId=c)
        top = r + r / 4
        sensor = pb.createVisualShape(pb.GEOM_SPHERE, radius=0.06, rgbaColor=[0.85, 0.05, 0.05, 1], physicsClientId=c)
        for q in (l1, l2):
            pb.createMultiBody(0, -1, sensor, basePosition=[q[0], q[1], top + 0.03], physicsClientId=c)
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
        sb = p.wheel_setback
        parts = {
            "sensor 1": (l1[0], l1[1], top + 0.03),
            "sensor 2": (l2[0], l2[1], top + 0.03),
            "left wheel": (-sb, 0.5 + r / 2, r * 1.6),
            "right wheel": (-sb, -0.5 - r / 2, r * 1.4),
            "castor": (0.5, 0.0, r / 2),
            "light": (light_xy[0], light_xy[1], 2 * p.light_radius),
        }
        labels = {k: _project(view, proj, v, width, height) for k, v in parts.items()}
        return Render(rgb, labels)
    finally:
        world.close()
