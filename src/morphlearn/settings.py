"""Settings: the validated config as frozen, typed objects (plain data: this module reads no
bundle and imports no model).

The edge is the Snakefile (``workflow/rules/common.smk``), each rule script's entry
(``workflow/scripts/_entry.py``) and the CLI. They call :func:`morphlearn.configure.parse` (or
``load``) once; everything below receives a :class:`Settings` (or the part of it it needs), never
the raw dict. Here: the types and the parsers of the shared sections.

Each model's section is parsed by the model's own plug-in (:mod:`morphlearn.models`), so adding a
model adds no field here: ``settings.models[name]``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass, fields
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

from morphlearn import config as cfgmod
from morphlearn.grid import DesignGrid


@dataclass(frozen=True)
class GridSettings:
    """``grid``: sensor positions per axis per sensor, and theory weights per synapse."""

    positions_per_axis: int
    weights: int

    @cached_property
    def designs(self) -> DesignGrid:
        """The design grid, built once (frozen dataclasses allow cached_property)."""
        return DesignGrid(self.positions_per_axis)


@dataclass(frozen=True)
class SweepSettings:
    """``sweep``: how the theory sweep is sharded and run (not part of its science)."""

    shards: int
    mirror_symmetry: bool
    threads: int


@dataclass(frozen=True)
class AnalysisSettings:
    """``analysis``: thresholds applied to stored results (None: the simulated ones) and the top-N."""

    horizon: float | None
    success_radius: float | None
    top: int


@dataclass(frozen=True)
class FigureSettings:
    """``figures``: whether figures are drawn, and the options notebooks take from the config."""

    enabled: bool
    near_distance: float
    persistence_controllers: int
    fig2_design: Any
    fig2_envs: tuple[int, ...]

    def option(self, name: str) -> Any:
        """A figure option by its config key (registry ``options``), as the notebook receives it."""
        v = getattr(self, name)
        return list(v) if isinstance(v, tuple) else v


@dataclass(frozen=True)
class LearnerSettings:
    """``learners``: real learners on the theory model (config_schema.yaml)."""

    enabled: bool
    learners: tuple[str, ...]
    protocols: tuple[str, ...]
    seeds: int
    seed: int
    budget: int
    cycles: int
    per_phase: int
    sigma0: float
    max_designs: int | None
    shards: int
    threads: int
    chunk: int
    bootstrap: int

    def science(self) -> dict[str, Any]:
        """What determines a design's learner numbers (not sharding, threads, batching, bootstrap)."""
        keep = ("learners", "protocols", "seeds", "seed", "budget", "cycles", "per_phase", "sigma0")
        return {k: list(v) if isinstance(v, tuple) else v for k, v in asdict(self).items() if k in keep}


@dataclass(frozen=True)
class CooptRestartSettings:
    """``coopt.restart``: the opt-in restarting evolution strategies (off while ``learners`` is empty)."""

    learners: tuple[str, ...]
    setups: tuple[str, ...]
    sigmas: tuple[float, ...]
    protocols: tuple[str, ...]


@dataclass(frozen=True)
class CooptSettings:
    """``coopt``: co-optimising the body against a four-synapse controller (issue 27; schema)."""

    enabled: bool
    setups: tuple[str, ...]
    learners: tuple[str, ...]
    sigmas: tuple[float, ...]
    protocols: tuple[str, ...]
    budgets: tuple[int, ...]
    cycles: int
    seeds: int
    seed: int
    landscape_weights: int
    best_metrics: str
    bootstrap: int
    #: the restart runs (their own jobs) and the stage's committed bundle folder: not science, so
    #: turning restarts on re-runs none of the other jobs
    restart: CooptRestartSettings = CooptRestartSettings((), (), (), ())  # off
    bundle_dir: str | None = None

    def science(self) -> dict[str, Any]:
        """What determines the stage's numbers (not the bootstrap of the summary, the restart runs
        or the bundle folder)."""
        skip = ("bootstrap", "restart", "bundle_dir")
        return {
            f.name: list(v) if isinstance(v := getattr(self, f.name), tuple) else v
            for f in fields(self)
            if f.name not in skip
        }


@dataclass(frozen=True)
class EnginesSettings:
    """``engines``: the committed metrics tables the engine comparison reads (config_schema.yaml),
    by the engine (or reference model) whose survey each is."""

    enabled: bool
    pybullet: str
    mujoco: str
    theory: str

    def tables(self) -> dict[str, str]:
        """Each table by its key, in the section's order (the record's and the rule's inputs)."""
        return {f.name: getattr(self, f.name) for f in fields(self) if f.name != "enabled"}

    def science(self) -> dict[str, Any]:
        return {"tables": self.tables()}


@dataclass(frozen=True)
class Source:
    """One survey: a committed bundle and the model whose results it holds."""

    bundle: str
    model: str

    @property
    def table(self) -> Path:
        return Path(self.bundle) / self.model / "metrics.csv"

    @property
    def merged(self) -> Path:
        return Path(self.bundle) / self.model / "merged.zarr"

    def files(self) -> list[str]:
        return [str(self.table), str(Path(self.bundle) / "bundle.json")]


@dataclass(frozen=True)
class AgreementSettings:
    """``agreement``: the reference survey and the candidates (config_schema.yaml)."""

    enabled: bool
    reference: Source
    candidates: tuple[Source, ...]

    def sources(self) -> list[Source]:
        return [self.reference, *self.candidates]

    def inputs(self) -> dict[str, str]:
        """The rule's inputs: every source's metrics table and bundle manifest."""
        out = {}
        for i, src in enumerate(self.sources()):
            table, manifest = src.files()
            out[f"s{i}_table"], out[f"s{i}_bundle"] = table, manifest
        return out

    def science(self) -> dict[str, Any]:
        return {"reference": vars(self.reference), "candidates": [vars(c) for c in self.candidates]}


@dataclass(frozen=True)
class SurveySettings:
    """A committed bundle a run reads a physics model's results from (None: none), the model, and
    the thresholds its metrics were made with: ``survey_from`` (a survey of every design of the
    grid, or of a coarser grid whose positions are the grid's), and each part of ``screen_from``."""

    bundle: str | None
    model: str
    thresholds: Mapping[str, float] | None

    @property
    def folder(self) -> str:
        """Where the run keeps its copy of a survey, under results_dir (``survey/<model>``)."""
        from morphlearn.store import SURVEY_DIR

        return f"{SURVEY_DIR}/{self.model}"


#: ``screen_from``: a fast model's map of every design of the grid and the paper's engine at its
#: best designs, each read where it is (None: no screen).
Screen = tuple[SurveySettings, SurveySettings] | None


@dataclass(frozen=True)
class Shared:
    """The typed sections a model's parse may read besides its own (Model.parse)."""

    grid: GridSettings
    sweep: SweepSettings
    figures: FigureSettings


@dataclass(frozen=True)
class Settings:
    """The whole validated config, typed. ``source`` is the validated mapping itself (read-only),
    kept for what works on configs as data: scenario overrides (deep merges) and digests."""

    source: Mapping[str, Any]
    results_dir: str
    design_cache: bool
    grid: GridSettings
    sweep: SweepSettings
    analysis: AnalysisSettings
    figures: FigureSettings
    learners: LearnerSettings
    coopt: CooptSettings
    engines: EnginesSettings
    agreement: AgreementSettings
    #: model name -> that model's parsed section (the model plug-in's own settings type)
    models: Mapping[str, Any]
    bundle_dir: str | None
    bundle_designs: str  # drawn | all: whose outcome arrays a bundle keeps
    #: the largest physics survey, read from its bundle (``survey_from``)
    survey: SurveySettings
    #: the best-design claims answered by a screen and its refinement (``screen_from``)
    screen: Screen
    #: a theory bundle of every design at another weight grid and horizon (``text_sweep_from``)
    text_sweep: str | None
    scenarios: str | list[str] | None
    scenario_file: str
    render_only: bool

    def weights(self, model: str) -> np.ndarray:
        """The weight values per synapse of a model's sweep."""
        from morphlearn.grid import weights

        return weights(self.models[model].weights)


def check_theory(th: Mapping[str, Any], name: Callable[[str], str | None]) -> None:
    """The one rule for physically meaningful theory settings, for the config (``theory.*``) and the
    CLI (``morphlearn design --r/--horizon/--dt``): ``th`` holds r, horizon, success_radius,
    integrator, dt and (config only) max_steps; ``name(key)`` is how the caller spells a key, None
    for a value the caller fixes (the CLI's success radius). Raises ConfigError (a ValueError)."""
    r, rad, horizon = th["r"], th["success_radius"], th["horizon"]
    if rad >= r:  # the light within the success radius at the start: every controller succeeds at t = 0
        if name("success_radius") is None:
            raise cfgmod.ConfigError(
                f"{name('r')} = {r} is not beyond the success radius {rad}; allowed: {name('r')} > {rad} "
                "(the robot would start inside the light)"
            )
        raise cfgmod.ConfigError(
            f"{name('success_radius')} = {rad} is not below {name('r')} = {r}; allowed: < {r} "
            "(the robot would start inside the light)"
        )
    if th["integrator"] != "rk4":
        return
    dt = th["dt"]
    if dt >= horizon:  # one step (or none) over the whole horizon: no trajectory is simulated
        raise cfgmod.ConfigError(
            f"{name('dt')} = {dt} is not shorter than {name('horizon')} = {horizon}; allowed: "
            f"{name('dt')} < {horizon} (a fixed step at least the horizon simulates nothing)"
        )
    need = math.ceil(horizon / dt)
    if th.get("max_steps") is not None and th["max_steps"] < need:  # the cap would cut every trajectory short
        raise cfgmod.ConfigError(
            f"{name('max_steps')} = {th['max_steps']} is below the {need} steps that {name('integrator')} "
            f"= rk4 takes (horizon / dt); allowed: max_steps >= {need}, or a larger dt"
        )


def section(cls: type, sec: Mapping[str, Any]) -> Any:
    """A dataclass from a config section: lists become tuples (frozen, hashable)."""
    return cls(**{k: tuple(sec[k]) if isinstance(sec[k], list) else sec[k] for k in cls.__dataclass_fields__})


def coopt_section(sec: Mapping[str, Any]) -> CooptSettings:
    """The ``coopt`` section, its ``restart`` subsection typed too."""
    plain = {k: v for k, v in sec.items() if k != "restart"}
    restart = section(CooptRestartSettings, sec["restart"])
    return section(CooptSettings, {**plain, "restart": restart})


def agreement_section(sec: Mapping[str, Any]) -> AgreementSettings:
    return AgreementSettings(
        enabled=bool(sec["enabled"]),
        reference=Source(**sec["reference"]),
        candidates=tuple(Source(**c) for c in sec["candidates"]),
    )


def check_coopt(c: CooptSettings) -> None:
    """Cross-checks of the ``coopt`` section the schema cannot state."""
    bad = [b for b in c.budgets if b % c.cycles]
    if bad:
        raise cfgmod.ConfigError(
            f"coopt.budgets = {list(c.budgets)}: {bad[0]} is not a multiple of coopt.cycles = {c.cycles}; "
            "allowed: budgets divisible by cycles (the sequential protocol splits a budget into cycles x 4 phases)"
        )
    if c.landscape_weights % 2 == 0:
        raise cfgmod.ConfigError(
            f"coopt.landscape_weights = {c.landscape_weights} is even; allowed: odd numbers >= 3 "
            "(so that the uncrossed weights' zero, the two-weight controllers, is on the grid)"
        )
