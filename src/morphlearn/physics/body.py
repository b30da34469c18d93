"""A robot's body as Fig. 1C draws it: what an engine supplies for the figure.

An engine names, per robot it builds, a :class:`FigureBody` (``Physics.figure_bodies``): a builder
that builds that body in a pybullet DIRECT client, coloured, with the light, and says which of its
parts to label and where; the caption's words for it; where labels go so that they do not cover
it. The figure module (:mod:`morphlearn.figures.render`) supplies the drawing: camera, light,
label projection and the picture (pybullet's deterministic software renderer, the one drawing
tool, whatever engine simulates the robot). Builders share the palette here so that every body
reads alike.

Light imports only: the registry reads ``figure_bodies`` (import paths) at parse time; a body's
module, and pybullet, are imported when a figure draws it.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from morphlearn.physics.params import EmpiricalParams

#: What a body builder returns: (pybullet client, close it, parts to label: name -> point in the world).
Built = tuple[int, Callable[[], None], dict[str, tuple[float, float, float]]]
#: A body builder: ``(params, l1, l2, light_xy) -> Built``, the robot of design ``(l1, l2)`` with
#: a light ``light_xy`` away.
BodyBuilder = Callable[["EmpiricalParams", Sequence[float], Sequence[float], tuple[float, float]], Built]

#: The palette (RGBA): chassis, motorised wheels, castor, sensors, light.
GREY, BLACK, CASTOR_GREY, RED, YELLOW = (
    [0.86, 0.86, 0.84, 1],
    [0.08, 0.08, 0.08, 1],
    [0.55, 0.55, 0.55, 1],
    [0.85, 0.05, 0.05, 1],
    [1.0, 0.82, 0.1, 1],
)


@dataclass(frozen=True)
class FigureBody:
    """One robot's body for Fig. 1C, as the engine that builds it supplies it."""

    build: BodyBuilder
    #: What the caption says the body is (after "the simulated robot in the canonical design: ").
    text: str
    #: Label offsets in render pixels (Fig. 1C's 960 x 720 picture), chosen per body so that labels
    #: do not cover it; a part not named here gets the figure's default.
    offsets: Mapping[str, tuple[float, float]]


def load(path: str) -> FigureBody:
    """The :class:`FigureBody` at import path ``module:attribute`` (``Physics.figure_bodies``)."""
    module, attr = path.split(":")
    body = getattr(importlib.import_module(module), attr)
    if not isinstance(body, FigureBody):
        raise TypeError(f"{path} is a {type(body).__name__}; allowed: a morphlearn.physics.body.FigureBody")
    return body
