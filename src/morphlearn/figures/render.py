"""Offscreen render of the simulated robot (Fig. 1C): pybullet DIRECT mode, ER_TINY_RENDERER.

The body is the engine's (:class:`morphlearn.physics.body.FigureBody`, which the registry names:
:func:`morphlearn.models.figure_body_path`): its builder builds the robot, coloured, and the
light in a pybullet client and says which parts to label. This module only draws it, whatever
the body: the camera, the light direction, the projection of the labels and the picture. No
window, no GPU: the software renderer is deterministic.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pybullet as pb

from morphlearn.physics import body as bodies
from morphlearn.physics.body import FigureBody
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


def figure_body(path: str) -> FigureBody:
    """The body at import path ``path`` (``module:attribute``, as the registry names it)."""
    return bodies.load(path)


def render_robot(
    body: FigureBody | str,
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
    """Picture of ``body`` (a :class:`FigureBody` or its import path) with sensors at ``l1``,
    ``l2`` and a light ``light_xy`` away."""
    if isinstance(body, str):
        body = figure_body(body)
    p = params or EmpiricalParams()
    c, close, parts = body.build(p, l1, l2, light_xy)
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
