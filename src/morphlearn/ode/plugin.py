"""The ODE model as a plug-in of the model registry: the paper authors' own robot and world in
the Open Dynamics Engine (docs/ode.md), a physics model (:class:`Physics`: the same config keys,
store, metrics and custody as pybullet and MuJoCo) whose body is the authors' constants
(``config/authors_body.yaml``) and whose success radius is the authors' (contact distance + 2^-10).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any

from morphlearn.config import ConfigError
from morphlearn.errors import UsageError
from morphlearn.ode.core import INSTALL_HINT, available
from morphlearn.physics.model import Physics

if TYPE_CHECKING:
    from morphlearn.results import DesignResult
    from morphlearn.settings import Shared


class Ode(Physics):
    name = "ode"
    engine = "ode"
    engine_label = "ODE"
    env_file = "envs/empirical.yaml"
    robots = ("authors",)
    paper_engine = True
    # the reproduction table's reason for a paper claim its results answer otherwise (docs/results.md)
    differs_because = ("The authors' robot in ODE, at the designs this run holds; see the section.", "differs-ode")
    figure_body = True  # Fig. 1C draws the robot the headline numbers use: the authors', in ODE
    resumes_inside_design = True  # ~30 core-minutes a design at 121 x 121: resume inside it
    takes_screen = True  # its sweep is the physics layer's: adaptive_screen adds cells to the first wave
    levers_doc = "docs/ode.md"

    def parse(self, sec: Mapping[str, Any], shared: Shared) -> Any:
        if sec.get("enabled") and sec.get("results_from") is None and not available():
            raise ConfigError(f"ode.enabled = true: {INSTALL_HINT}")
        return super().parse(sec, shared)

    @staticmethod
    def design_evaluator() -> Callable[..., DesignResult]:
        from morphlearn.ode.episode import evaluate_design

        return evaluate_design

    def describe(self, science: Mapping[str, Any], n_designs: int, m: int) -> str:
        pr = science.get("params", {})
        return (
            f"{n_designs} designs {self.how_made(science)} in ODE (the authors' robot and world, docs/ode.md) on the "
            f"{science.get('positions_per_axis')}-point grid, {m} weights per synapse; gravity "
            f"{pr.get('gravity')}, {pr.get('steps')} steps of dt = {pr.get('dt')}, every episode to its "
            "first success (contact distance + 2^-10)"
        )

    def evaluate_one(
        self, l1: tuple[float, float], l2: tuple[float, float], w: Any, a: argparse.Namespace
    ) -> DesignResult:
        if not available():
            raise UsageError(f"--model ode: {INSTALL_HINT}")
        return super().evaluate_one(l1, l2, w, a)
