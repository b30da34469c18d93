"""The pybullet engine as a plug-in of the model registry (:mod:`morphlearn.models`), registered as
``empirical`` (the name its committed results carry): data on the physics base
(:class:`morphlearn.physics.model.Physics`)."""

from __future__ import annotations

from collections.abc import Callable
from types import MappingProxyType
from typing import TYPE_CHECKING

import numpy as np

from morphlearn.physics.model import Physics

if TYPE_CHECKING:
    from morphlearn.physics.params import EmpiricalParams
    from morphlearn.results import DesignResult


class Pybullet(Physics):
    """The reference engine (docs/empirical.md), registered as ``empirical``."""

    name = "empirical"
    engine = "pybullet"
    libraries = ("pybullet",)
    env_file = "envs/empirical.yaml"
    resumes_inside_design = True
    robots = ("project", "authors")
    # Fig. 1C's bodies: both robots as this engine builds them (the authors' robot also for ODE,
    # which has no renderer)
    figure_bodies = MappingProxyType(
        {
            "project": "morphlearn.empirical.figure_body:PROJECT",
            "authors": "morphlearn.empirical.figure_body:AUTHORS",
        }
    )

    @staticmethod
    def design_evaluator() -> Callable[..., DesignResult]:
        from morphlearn.empirical.episode import evaluate_design

        return evaluate_design

    def robot_evaluator(self, robot: str) -> Callable[..., DesignResult]:
        if robot == "authors":
            from morphlearn.empirical.authors import evaluate_design

            return evaluate_design
        return super().robot_evaluator(robot)

    def centre_paths(
        self, params: EmpiricalParams, l1: tuple[float, float], l2: tuple[float, float], w: tuple[float, float]
    ) -> tuple[list[float], list[np.ndarray]]:
        from morphlearn.empirical.episode import EpisodeRunner

        closest, paths = [], []
        with EpisodeRunner(params) as runner:
            for env in range(4):
                p: list[tuple[float, float]] = []
                closest.append(runner.run(l1, l2, w[0], w[1], env, path=p).min_dist)
                paths.append(np.array(p))
        return closest, paths
