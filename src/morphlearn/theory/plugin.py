"""The theory model as a plug-in of the model registry (:mod:`morphlearn.models`)."""

from __future__ import annotations

import argparse
import math
import os
import platform
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np

from morphlearn import grid as gridmod
from morphlearn import theory as kernels  # its evaluate looked up per call (tests patch it)
from morphlearn.config import ConfigError
from morphlearn.errors import UsageError
from morphlearn.model_interface import Done, Model, PartialPath, Resources
from morphlearn.settings import check_theory
from morphlearn.theory import TheoryParams

if TYPE_CHECKING:
    from morphlearn.metrics import Thresholds
    from morphlearn.results import DesignResult
    from morphlearn.settings import Settings, Shared

#: The CLI's defaults where it is not given (the paper-matching settings, docs/model.md).
CLI_HORIZON = 500.0
CLI_R = 4.0
CLI_RADIUS = 0.2
#: Most fixed RK4 steps per trajectory the CLI takes (10^7: tens of seconds per trajectory).
MAX_RK4_STEPS = 10_000_000


@dataclass(frozen=True)
class TheorySettings:
    """The ``theory`` section with the ``sweep`` and ``grid`` values the theory sweep uses."""

    enabled: bool
    params: TheoryParams
    weights: int
    shards: int
    threads: int
    mirror_symmetry: bool
    designs: tuple[int, ...]  # simulated: one of each mirror pair with mirror_symmetry
    science: Mapping[str, Any]
    results_from: str | None = None  # a bundle its results are read from instead (same science)
    #: the section as validated (defaults filled), kept as data: a scenario's record names it whole
    section: Mapping[str, Any] = field(default_factory=lambda: MappingProxyType({}))


class Theory(Model):
    name = "theory"
    env_file = "envs/theory.yaml"
    cli_options = ("r", "horizon", "dt")
    libraries = ("numba",)
    path_keys = ("results_from",)

    def parse(self, section: Mapping[str, Any], shared: Shared) -> TheorySettings:
        grid, sw = shared.grid, shared.sweep
        keys = ["r", "horizon", "success_radius", "integrator", "max_steps"]
        keys += ["rtol", "atol"] if section["integrator"] == "dp5" else ["dt"]
        science = {
            "model": self.name,
            "grid": {"positions_per_axis": grid.positions_per_axis, "weights": grid.weights},
            "theory": {k: section[k] for k in keys},
            "mirror_symmetry": sw.mirror_symmetry,
        }
        g = grid.designs
        designs = g.representatives() if sw.mirror_symmetry else np.arange(g.size)
        if sw.shards > len(designs):
            raise ConfigError(
                f"sweep.shards = {sw.shards} exceeds the {len(designs)} designs evaluated; allowed: 1..{len(designs)}"
            )
        results_from = section.get("results_from")
        if section["enabled"] and results_from is not None:
            self._check_results_from(results_from, science)
        return TheorySettings(
            results_from=results_from,
            enabled=bool(section["enabled"]),
            params=TheoryParams.from_config(section),
            weights=grid.weights,
            shards=sw.shards,
            threads=sw.threads,
            mirror_symmetry=bool(sw.mirror_symmetry),
            designs=tuple(int(d) for d in designs),
            science=MappingProxyType(science),
            section=MappingProxyType(dict(section)),
        )

    def _check_results_from(self, path: str, science: Mapping[str, Any]) -> None:
        """A bundle holding theory results made with exactly this config's science (its
        checksums are checked when they are copied, by the rule theory_from_bundle)."""
        from morphlearn import config, store

        key = "theory.results_from"
        merged = Path(path) / self.name / "merged.zarr"
        need = [Path(path) / "bundle.json", Path(path) / self.name / "metrics.csv", merged]
        missing = [str(p) for p in need if not p.exists()]
        if missing:
            raise ConfigError(
                f"{key} = {path!r}: {missing[0]} is missing; allowed: a results bundle with theory "
                "results (e.g. results/paper), or null to simulate"
            )
        try:
            held = store.science_of(store.open_merged(merged))
        except Exception as e:  # a damaged store: say which and why, in one line
            raise ConfigError(f"{key} = {path!r}: unreadable theory results ({e})") from None
        flat_held, flat_want = config.flatten(held), config.flatten(dict(science))
        differ = sorted(k for k in flat_held.keys() | flat_want.keys() if flat_held.get(k) != flat_want.get(k))
        if differ:
            k = differ[0]
            raise ConfigError(
                f"{key} = {path!r} holds theory results made with {k} = {flat_held.get(k)!r}, this config "
                f"has {flat_want.get(k)!r}; allowed: a bundle made with this config's theory and grid settings"
            )

    def results_from(self, s: Settings) -> str | None:
        return self.settings(s).results_from

    def designs(self, s: Settings) -> np.ndarray:
        return np.array(self.settings(s).designs, dtype=np.int64)

    def mirror_derived(self, s: Settings) -> bool:
        return self.settings(s).mirror_symmetry

    def thresholds(self, s: Settings) -> Thresholds:
        from morphlearn.metrics import Thresholds

        p, a = self.settings(s).params, s.analysis
        return Thresholds(
            horizon=a.horizon if a.horizon is not None else p.horizon,
            radius=a.success_radius if a.success_radius is not None else p.success_radius,
            sim_horizon=p.horizon,
            sim_radius=p.success_radius,
        )

    def evaluate(
        self, s: Settings, designs: np.ndarray, done: Done | None = None, partial: PartialPath | None = None
    ) -> list[DesignResult]:
        # partial unused: the kernel's batches (~6 designs at paper resolution) are the unit a kill loses
        return kernels.evaluate(
            s.grid.designs.coords(designs), self.weights(s), self.settings(s).params, progress=True, done=done
        )

    def resimulate(self, science: Mapping[str, Any], designs: np.ndarray) -> list[DesignResult]:
        g = gridmod.DesignGrid(self.positions_of(science))
        w = gridmod.weights(science["grid"]["weights"])
        return kernels.evaluate(g.coords(designs), w, TheoryParams.from_config(science["theory"]))

    def backend(self, s: Settings) -> dict[str, str]:
        """CPU and CUDA may differ in boundary cases, so the merge records and compares them."""
        b = kernels.resolve_backend(self.settings(s).params.backend)
        if b == "cuda":
            try:
                from numba import cuda

                name = cuda.get_current_device().name
                device = name.decode() if isinstance(name, bytes) else str(name)
            except Exception as e:  # the name is a record, not a requirement
                device = f"cuda (name unavailable: {type(e).__name__})"
        else:
            device = f"cpu ({platform.machine()}, {os.cpu_count()} cores)"
        return {"backend": b, "device": device}

    def resources(self, s: Settings) -> Resources:
        # backend cuda: one GPU per shard job (the SLURM plugin submits --gpus=1; add gpu_model or
        # a GPU partition with --set-resources, docs/cluster.md). auto asks for none.
        t = self.settings(s)
        return Resources(threads=t.threads, runtime=60, mem_mb=2000, gpu=1 if t.params.backend == "cuda" else 0)

    def positions_of(self, science: Mapping[str, Any]) -> int:
        return int(science["grid"]["positions_per_axis"])

    def describe(self, science: Mapping[str, Any], n_designs: int, m: int) -> str:
        g, th = science.get("grid", {}), science.get("theory", {})
        tol = f"rtol = atol = {th.get('rtol')}" if th.get("integrator") == "dp5" else f"dt = {th.get('dt')}"
        return (
            f"grid {g.get('positions_per_axis')} positions per axis per sensor, {g.get('weights')} "
            f"weights per synapse; r = {th.get('r')}, T = {th.get('horizon')}, success radius "
            f"{th.get('success_radius')}, integrator {th.get('integrator')} ({tol}), step cap "
            f"{th.get('max_steps')}, mirror symmetry {science.get('mirror_symmetry')}"
        )

    def check_cli(self, a: argparse.Namespace) -> None:
        # the config's rule (settings.check_theory), with the CLI's defaults
        th = {
            "r": CLI_R if a.r is None else a.r,
            "horizon": CLI_HORIZON if a.horizon is None else a.horizon,
            "success_radius": CLI_RADIUS,
            "integrator": "dp5" if a.dt is None else "rk4",
            "dt": a.dt,
        }
        flags = {"r": "--r", "horizon": "--horizon", "dt": "--dt"}
        check_theory(th, flags.get)

    def evaluate_one(
        self, l1: tuple[float, float], l2: tuple[float, float], w: np.ndarray, a: argparse.Namespace
    ) -> DesignResult:
        horizon = a.horizon if a.horizon is not None else CLI_HORIZON
        # RK4 takes horizon / dt steps: the step cap (meant for the adaptive integrator) follows.
        steps = TheoryParams.max_steps if a.dt is None else max(TheoryParams.max_steps, math.ceil(horizon / a.dt))
        if steps > MAX_RK4_STEPS:
            raise UsageError(
                # :.3g: the count of --dt 1e-300 has 300 digits
                f"--dt {a.dt:g} needs {steps:.3g} RK4 steps per trajectory over the horizon {horizon:g}; "
                f"allowed: --dt >= {horizon / MAX_RK4_STEPS:g}"
            )
        p = TheoryParams(
            r=a.r if a.r is not None else CLI_R,
            horizon=horizon,
            success_radius=CLI_RADIUS,
            integrator="rk4" if a.dt is not None else "dp5",
            dt=a.dt if a.dt is not None else 0.01,
            max_steps=steps,
        )
        return kernels.evaluate(np.array([[*l1, *l2]]), w, p, progress=not a.json)[0]
