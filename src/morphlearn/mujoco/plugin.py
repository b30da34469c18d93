"""The MuJoCo model as a plug-in of the model registry (:mod:`morphlearn.models`): the same robot,
config section shape, success rule and levers as the pybullet model (:class:`Physics`), another
engine (see the package docstring for where the engines differ), and one more key, ``backend``:
``cpu`` (MuJoCo's C batch) or ``warp`` (MuJoCo Warp on a GPU, :mod:`.mjwarp`)."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np

from morphlearn.config import ConfigError
from morphlearn.model_interface import Done, PartialPath, Resources
from morphlearn.mujoco import mjwarp  # its names looked up per call (tests patch them)
from morphlearn.mujoco.episode import evaluate_design
from morphlearn.physics.model import Physics, PhysicsSettings

if TYPE_CHECKING:
    from morphlearn.physics.params import EmpiricalParams
    from morphlearn.results import DesignResult
    from morphlearn.settings import Settings, Shared

BACKENDS = ("cpu", "warp")


@dataclass(frozen=True)
class MujocoModelSettings(PhysicsSettings):
    """The ``mujoco`` section: a physics model's settings and the backend."""

    backend: str = "cpu"


class Mujoco(Physics):
    name = "mujoco"
    engine = "mujoco"
    robots = ("project", "authors")
    libraries = ("mujoco",)
    engine_label = "MuJoCo"
    env_file = "envs/empirical.yaml"  # the physics environment holds both engines (warp: docs/mujoco.md)

    def parse(self, sec: Mapping[str, Any], shared: Shared) -> MujocoModelSettings:
        backend = sec.get("backend", "cpu")
        if backend not in BACKENDS:  # the schema refuses it first; this guards direct callers
            raise ConfigError(f"mujoco.backend = {backend!r} is invalid; allowed: {list(BACKENDS)}")
        base = super().parse(sec, shared)
        if backend != "cpu" and base.robot != "project":
            raise ConfigError(
                f"mujoco.backend = {backend!r} builds the project's robot only; allowed with "
                f"mujoco.robot = {base.robot!r}: backend cpu"
            )
        science = base.science
        if science is not None and backend != "cpu":
            # warp computes in float32: its outcomes are its own (a cache or store never mixes
            # them with cpu ones). Absent for cpu, so the digests of cpu results made before hold.
            science = MappingProxyType({**science, "backend": backend})
        fields = {f.name: getattr(base, f.name) for f in dataclasses.fields(PhysicsSettings)}
        return MujocoModelSettings(**{**fields, "science": science}, backend=backend)

    def centre_paths(
        self, params: EmpiricalParams, l1: tuple[float, float], l2: tuple[float, float], w: tuple[float, float]
    ) -> tuple[list[float], list[np.ndarray]]:
        from morphlearn.mujoco.episode import BatchRunner

        rec: list[np.ndarray] = []
        closest = BatchRunner(params).run(l1, l2, np.tile(list(w), (4, 1)), np.arange(4), path=rec).min_dist.tolist()
        xy = np.stack(rec)  # (steps, 4, 2)
        return closest, [xy[~np.isnan(xy[:, e, 0]), e] for e in range(4)]

    @staticmethod
    def design_evaluator() -> Callable[..., DesignResult]:
        return evaluate_design

    def robot_evaluator(self, robot: str) -> Callable[..., DesignResult]:
        if robot == "authors":
            from morphlearn.mujoco import authors

            return authors.evaluate_design
        return super().robot_evaluator(robot)

    def evaluate(
        self, s: Settings, designs: np.ndarray, done: Done | None = None, partial: PartialPath | None = None
    ) -> list[DesignResult]:
        e = self.settings(s)
        if e.backend == "cpu":
            return super().evaluate(s, designs, done, partial)
        # one model on the GPU, its kernels compiled once; the episodes of as many designs as fill
        # a batch of NWORLD worlds share it (done is called as each batch of designs finishes)
        runner = mjwarp.WarpBatchRunner(e.params)
        return mjwarp.evaluate_designs(s.grid.designs.coords(designs), self.weights(s), runner, e.options, done)

    def backend(self, s: Settings) -> dict[str, str]:
        if self.settings(s).backend == "cpu":
            return super().backend(s)
        return {"backend": "mujoco-warp", "device": mjwarp.device_name(mjwarp.resolve_device(None))}

    def describe(self, science: Mapping[str, Any], n_designs: int, m: int) -> str:
        text = super().describe(science, n_designs, m)
        if science.get("backend") == "warp":  # captions say when the float32 GPU engine made it
            text += "; run on MuJoCo Warp (float32, GPU)"
        return text

    def resources(self, s: Settings) -> Resources:
        # backend warp: one GPU per shard job (the SLURM plugin submits --gpus=1, as for
        # theory.backend cuda; docs/cluster.md, docs/mujoco.md)
        r = super().resources(s)
        return dataclasses.replace(r, gpu=1) if self.settings(s).backend == "warp" else r
