"""The reduced model as a plug-in of the model registry: the paper authors' robot reduced to its
planar motion (docs/reduced.md; :mod:`morphlearn.reduced.body` names every approximation), a
physics model on the shared base (the same config keys, sweep, store, metrics and custody as the
engines) that answers to ODE cell by cell at a few hundredths of a percent of its cost."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

from morphlearn.config import ConfigError
from morphlearn.model_interface import Resources
from morphlearn.physics.model import Physics, PhysicsSettings

if TYPE_CHECKING:
    from morphlearn.results import DesignResult
    from morphlearn.settings import Settings, Shared

#: ``reduced.backend``: the kernel that runs the episodes (morphlearn.reduced.core.BACKENDS)
BACKENDS = ("cpu", "cpu-simd", "cuda")


@dataclass(frozen=True)
class ReducedModelSettings(PhysicsSettings):
    """The ``reduced`` section: a physics model's settings and the kernel backend."""

    backend: str = "cpu"


class Reduced(Physics):
    name = "reduced"
    engine = "reduced"
    takes_screen = True  # its sweep is the physics layer's: adaptive_screen adds cells to the first wave
    engine_label = "reduced model"
    env_file = "envs/empirical.yaml"
    robots = ("authors",)
    levers_doc = "docs/reduced.md"

    def parse(self, sec: Mapping[str, Any], shared: Shared) -> ReducedModelSettings:
        backend = sec.get("backend", "cpu")
        if backend not in BACKENDS:  # the schema refuses it first; this guards direct callers
            raise ConfigError(f"reduced.backend = {backend!r} is invalid; allowed: {list(BACKENDS)}")
        if backend == "cpu-simd":
            from morphlearn.reduced import simd

            if sec.get("enabled") and not simd.available():
                raise ConfigError(
                    "reduced.backend = 'cpu-simd' needs the C kernel morphlearn.reduced._lanes, which is not "
                    "built; allowed: cpu, or rebuild (bash tools/setup.sh)"
                )
        base = super().parse(sec, shared)
        science = base.science
        if science is not None and backend == "cuda":
            # the GPU may fuse multiply-adds: outcomes can differ in the last bits, so they are the
            # run's own. cpu-simd is not recorded: its outcomes are the scalar kernel's to the bit
            # (tests/test_reduced_simd.py), so its results, digests and caches are cpu's.
            science = MappingProxyType({**science, "backend": backend})
        fields = {f.name: getattr(base, f.name) for f in dataclasses.fields(PhysicsSettings)}
        return ReducedModelSettings(**{**fields, "science": science}, backend=backend)

    @staticmethod
    def design_evaluator() -> Callable[..., DesignResult]:
        from morphlearn.reduced.episode import evaluate_design

        return evaluate_design

    def section_evaluator(self, e: PhysicsSettings) -> Callable[..., DesignResult]:
        from morphlearn.reduced.episode import evaluator

        return evaluator(getattr(e, "backend", "cpu"))

    def backend(self, s: Settings) -> dict[str, str]:
        b = self.settings(s).backend
        if b == "cpu":
            return super().backend(s)
        if b == "cpu-simd":
            from morphlearn.reduced import simd

            isa, tanh = simd.mode() if simd.available() else ("unbuilt", "")
            return {"backend": f"reduced-simd ({isa}, tanh {tanh})", "device": super().backend(s)["device"]}
        return {"backend": "reduced-cuda", "device": "cuda"}

    def resources(self, s: Settings) -> Resources:
        # backend cuda: one GPU per shard job, as for theory.backend cuda (docs/cluster.md)
        r = super().resources(s)
        return dataclasses.replace(r, gpu=1) if self.settings(s).backend == "cuda" else r
