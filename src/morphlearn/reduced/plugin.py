"""The reduced model as a plug-in of the model registry: the paper authors' robot reduced to its
planar motion (docs/reduced.md; :mod:`morphlearn.reduced.body` names every approximation), a
physics model on the shared base (the same config keys, sweep, store, metrics and custody as the
engines) that answers to ODE cell by cell at a few hundredths of a percent of its cost."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from morphlearn.physics.model import Physics
from morphlearn.physics.params import EmpiricalParams

if TYPE_CHECKING:
    from morphlearn.results import DesignResult


class Reduced(Physics):
    name = "reduced"
    engine = "reduced"
    takes_screen = True  # its sweep is the physics layer's: adaptive_screen adds cells to the first wave
    engine_label = "reduced model"
    env_file = "envs/empirical.yaml"
    robots = ("authors",)
    levers_doc = "docs/reduced.md"
    #: what the reduced model reads: not wheel_friction (mu is infinite), solver_iterations (its
    #: step is solved exactly), erp nor cfm (its joints are rigid; its motor rows mix motor_cfm)
    recorded_params = tuple(
        k
        for k in EmpiricalParams.__dataclass_fields__
        if k not in ("wheel_friction", "solver_iterations", "erp", "cfm")
    )

    @staticmethod
    def design_evaluator() -> Callable[..., DesignResult]:
        from morphlearn.reduced.episode import evaluate_design

        return evaluate_design
