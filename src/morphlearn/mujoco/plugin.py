"""The MuJoCo model as a plug-in of the model registry (:mod:`morphlearn.models`): the same robot,
config section shape, success rule and levers as the pybullet model (:class:`Physics`), another
engine (see the package docstring for where the engines differ)."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from morphlearn.empirical.plugin import Physics

if TYPE_CHECKING:
    from morphlearn.results import DesignResult


class Mujoco(Physics):
    name = "mujoco"
    engine = "mujoco"
    engine_label = "MuJoCo"
    env_file = "envs/empirical.yaml"  # the physics environment holds both engines

    @staticmethod
    def design_evaluator() -> Callable[..., DesignResult]:
        from morphlearn.mujoco.episode import evaluate_design

        return evaluate_design
