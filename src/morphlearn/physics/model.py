"""The physics model base: what every rigid-body engine model shares, on which an engine is data.

:class:`Physics` is what every rigid-body engine model shares: the same config section shape
(``enabled``, ``morphology``, ``params``, ``weights``, ``designs``, mirrors, levers, ``results_from``,
``shards``), the same success rule (touching the light within the episode) and the same record.
An engine is a subclass naming its engine and its per-design evaluator (as scipy's
``integrate._ivp`` methods are data on one base): pybullet (:mod:`morphlearn.empirical`, the
registry's ``empirical``), MuJoCo (:mod:`morphlearn.mujoco`) and ODE (:mod:`morphlearn.ode`).
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from morphlearn import bounded
from morphlearn import grid as gridmod
from morphlearn.config import ConfigError
from morphlearn.errors import UsageError, c_stdout_to_stderr
from morphlearn.model_interface import Done, Model, PartialPath, Resources
from morphlearn.physics.authors import success_radius
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import EmpiricalParams, load_params
from morphlearn.physics.progress import DesignsProgress, EpisodeProgress
from morphlearn.results import DesignResult

if TYPE_CHECKING:
    from morphlearn.grid import DesignGrid
    from morphlearn.metrics import Thresholds
    from morphlearn.settings import Settings, Shared

DEFAULT_MORPHOLOGY = "config/empirical_morphology.yaml"
#: The robots an engine can build (``<model>.robot``) and the body file each reads when the section
#: names none: the project's own body (re-optimised for pybullet, docs/empirical.md) and the paper
#: authors' robot (docs/ode.md; in engines other than ODE, docs/authors_robot.md).
ROBOT_BODIES = {"project": DEFAULT_MORPHOLOGY, "authors": "config/authors_body.yaml"}
#: The robots as prose names them (tables, captions).
ROBOT_LABELS = {"project": "the project's own body", "authors": "the authors' robot"}


def off_grid_hint(designs: Sequence[Sequence[Sequence[float]]]) -> str:
    """How to run designs off the config's grid: the smallest grid.positions_per_axis whose grid
    holds every coordinate given (the workflow stores designs on one grid), or morphlearn design,
    which takes any coordinates."""
    from morphlearn.grid import grids_holding

    coords = sorted({float(v) for d in designs for point in d for v in point})
    fits = grids_holding(coords)
    grid = (
        f"grid.positions_per_axis: {fits[0]} holds them all ({fits[0] ** 4} designs)"
        if fits
        else "no grid.positions_per_axis up to 33 holds them all"
    )
    return (
        f"allowed: positions on the grid; {grid}; any coordinates: morphlearn design --model MODEL "
        "--l1 X Y --l2 X Y --save FILE.npz --plot FILE.png (README, 'Your own designs')"
    )


def other_robots_body(robot: str, morphology: str | Path) -> str | None:
    """Why body file ``morphology`` is not for ``robot`` (None when it may be): it is another
    robot's own body file. One robot's geometry with another robot's body file is no robot of
    either (it once ran unnoticed: the authors' robot with the project's masses, motor and
    gravity); the config (``<model>.morphology``) and ``morphlearn design --morphology`` refuse it."""

    def same(a: str | Path, b: str | Path) -> bool:  # also ./x, an absolute path or a symlink to it
        try:
            return Path(a).resolve() == Path(b).resolve()
        except (OSError, ValueError):  # a name the file system cannot hold is no one's body file
            return False

    other = [r for r, f in ROBOT_BODIES.items() if r != robot and same(f, morphology)]
    return f"is the {other[0]} robot's body file" if other else None


@dataclass(frozen=True)
class PhysicsSettings:
    """A physics model's section, typed, with its body file read (once)."""

    enabled: bool
    robot: str  # a key of ROBOT_BODIES
    morphology: str
    #: the body file's parameters with the section's ``params`` overrides (None when not read:
    #: the model is off and no figure draws the body)
    params: EmpiricalParams | None
    weights: int
    held: tuple[int, ...]  # designs its results hold
    simulated: tuple[int, ...]  # designs it simulates (with mirror_derive one of each pair)
    mirror_derive: bool
    results_from: str | None
    #: the thresholds a bundle's metrics were made with (results_from), else None
    bundle_thresholds: Mapping[str, float] | None
    options: SweepOptions
    shards: int
    optimise: Mapping[str, int]
    science: Mapping[str, Any] | None


class Physics(Model):
    """A rigid-body engine's model of the robot (see the module docstring)."""

    #: The engine, as records and captions name it.
    engine: ClassVar[str]
    #: The engine as prose names it (tables, docs).
    engine_label: ClassVar[str] = ""
    #: Fig. 1C draws this engine's robot and body, the one the headline numbers use (read even when
    #: the model is off, if figures are drawn); one registered engine sets it.
    figure_body: ClassVar[bool] = False
    #: The bodies it builds for Fig. 1C: robot (a key of ROBOT_BODIES) -> import path
    #: ``module:attribute`` of its :class:`morphlearn.physics.body.FigureBody` (builder, caption
    #: words, label offsets), imported only when a figure draws it. An engine without a renderer's
    #: build of a robot names none: Fig. 1C then draws the robot as the first registered engine
    #: that names one builds it (:func:`morphlearn.models.figure_body_path`).
    figure_bodies: ClassVar[Mapping[str, str]] = MappingProxyType({})
    #: The engine the paper's physics ran in (ODE): drawn and answered first where enabled.
    paper_engine: ClassVar[bool] = False
    #: Why its answer to a paper claim differs, where no claim-specific reason says more (the
    #: reproduction table's reason and its docs/results.md anchor); None: :meth:`differs_reason`'s
    #: generic sentence.
    differs_because: ClassVar[tuple[str, str] | None] = None
    #: Its ``evaluate_design`` takes ``partial=`` (a design resumes inside itself, see
    #: :mod:`morphlearn.physics.partial`): :meth:`evaluate` then keeps each running design's
    #: episodes where ``partial`` says (the run's design cache).
    resumes_inside_design: ClassVar[bool] = False
    cli_options = ("morphology", "robot")
    path_keys = ("morphology", "results_from")
    schema_like = "empirical"  # the physics section's keys (config_schema.yaml)
    #: The robots this engine builds (keys of ROBOT_BODIES); the first is the default.
    robots: ClassVar[tuple[str, ...]] = ("project",)
    #: Its ``evaluate_design`` takes ``screen=`` (cells its adaptive grid's first wave also
    #: simulates, from ``adaptive_screen``: :mod:`morphlearn.physics.screen`).
    takes_screen: ClassVar[bool] = False
    #: Where the measured miss rate of its adaptive weight grid is documented (captions).
    levers_doc: ClassVar[str] = "docs/empirical_levers.md"

    # -- what its results are ------------------------------------------------------------------------
    def robot_of(self, science: Mapping[str, Any]) -> str:
        """The robot results made with ``science`` modelled (a key of ROBOT_BODIES; a record names
        it only when not the engine's default)."""
        return str(science.get("robot") or self.robots[0])

    def robot_label(self, science: Mapping[str, Any]) -> str:
        """The robot results made with ``science`` modelled, as prose names it."""
        robot = self.robot_of(science)
        return ROBOT_LABELS.get(robot, robot)

    def not_the_paper(self, science: Mapping[str, Any]) -> str:
        """The paper's physics is the authors' robot in its engine (ODE, ``paper_engine``): results of
        another robot or engine answer other questions than its claims."""
        robot = self.robot_of(science)
        if self.paper_engine and robot == "authors":
            return ""
        what = [] if self.paper_engine else ["another engine"]
        what += [] if robot == "authors" else ["another robot"]
        return (
            f"{self.engine_label or self.engine} with {self.robot_label(science)}: {' and '.join(what)} than "
            "the paper's (the authors' robot in the paper's engine), so not a verdict on its claim"
        )

    def differs_reason(self) -> tuple[str, str]:
        """(sentence, docs/results.md anchor) of a paper claim's row this engine answers and that
        differs (the reproduction table's ``reason``, ``anchor``)."""
        if self.differs_because is not None:
            return self.differs_because
        return f"The authors' robot in {self.engine_label or self.engine}, at the designs this run holds.", ""

    # -- settings ----------------------------------------------------------------------------------
    def parse(self, sec: Mapping[str, Any], shared: Shared) -> PhysicsSettings:
        grid = shared.grid
        enabled = bool(sec.get("enabled"))
        g = grid.designs
        results_from = sec.get("results_from")
        bundle_th, weights, from_held = None, sec.get("weights", 11), ()
        if enabled and results_from is not None:
            # the bundle's weights, not the section's: the summary counts its controllers
            bundle_th, weights, from_held = self.check_results_bundle(results_from, grid.positions_per_axis)
        robot = sec.get("robot") or self.robots[0]
        if robot not in self.robots:
            raise ConfigError(f"{self.name}.robot = {robot!r} is invalid; allowed: {list(self.robots)}")
        morphology = sec.get("morphology") or ROBOT_BODIES[robot]
        mismatch = other_robots_body(robot, morphology)
        if mismatch:
            raise ConfigError(
                f"{self.name}.morphology = {morphology!r} {mismatch} but {self.name}.robot = {robot!r}; "
                f"allowed: null (this robot's own, {ROBOT_BODIES[robot]}) or a body file of your own"
            )
        params, body = None, None
        # the body file is read here, once: the sweep's science and Fig. 1C (the body) need it
        if enabled or (self.figure_body and shared.figures.enabled):
            body = self._read_body(morphology)
        overrides = dict(sec.get("params", {}))
        if enabled and results_from is None:  # a bundle's results carry their own parameters
            self._check_params(overrides, body)
        if body is not None:
            params = EmpiricalParams.from_mapping({**body.to_dict(), **overrides})
        simulates = enabled and results_from is None
        held = self._held(sec, g) if simulates else list(from_held)
        mirror_derive = bool(sec.get("mirror_derive", False))
        simulated = sorted({min(d, int(g.mirror(d))) for d in held}) if mirror_derive else list(held)
        if simulates:
            self._check_designs(sec, simulated)
        options = SweepOptions.from_config(sec)
        if simulates and options.screen is not None:
            self._check_screen(options, grid.positions_per_axis, int(sec["weights"]), simulated)
        science = None
        if simulates:
            science = {
                "model": self.name,
                "positions_per_axis": grid.positions_per_axis,
                "weights": sec["weights"],
                "designs": list(held),
                "params": {**body.to_dict(), **overrides},
                # only when not the engine's default robot: the digests of results made before hold
                **({"robot": robot} if robot != self.robots[0] else {}),
                # only when on, so that the digests of results made before the option existed hold
                **({"mirror_derive": True} if mirror_derive else {}),
                **options.science(),
            }
        return PhysicsSettings(
            enabled=enabled,
            robot=robot,
            morphology=morphology,
            params=params,
            weights=weights,
            held=tuple(held),
            simulated=tuple(simulated),
            mirror_derive=mirror_derive,
            results_from=results_from,
            bundle_thresholds=MappingProxyType(bundle_th) if bundle_th else None,
            options=options,
            shards=sec.get("shards", 1),
            optimise=MappingProxyType(dict(sec.get("optimise", {}))),
            science=MappingProxyType(science) if science else None,
        )

    def _read_body(self, path: str) -> EmpiricalParams:
        try:
            return load_params(path)
        except ValueError as e:
            raise ConfigError(
                f"{self.name}.morphology = {path!r}: {e}; allowed: a YAML file of body parameters"
            ) from None

    def _check_params(self, overrides: Mapping[str, Any], body: EmpiricalParams | None) -> None:
        for k in overrides:
            if k not in EmpiricalParams.__dataclass_fields__:
                raise ConfigError(
                    f"unknown key ['{k}'] under '{self.name}.params'; "
                    f"allowed: {sorted(EmpiricalParams.__dataclass_fields__)}"
                )
        try:
            # on the body they override: the light must stay beyond the body's contact distance
            EmpiricalParams.from_mapping({**(body.to_dict() if body else {}), **overrides})
        except ValueError as e:
            raise ConfigError(f"{self.name}.params.{e}") from None

    def _held(self, sec: Mapping[str, Any], g: DesignGrid) -> list[int]:
        """Sorted design indices the results hold: every design, or the listed ones (and with
        ``include_mirrors`` their mirror images)."""
        designs = sec.get("designs", "all")
        if designs == "all":
            return list(range(g.size))
        if isinstance(designs, Mapping):  # {top_of, random}: a screen's best and/or a random check
            parts = [np.zeros(0, dtype=np.int64)]
            if "top_of" in designs:
                parts.append(self._screened(designs["top_of"], g))
            if "random" in designs:
                r = designs["random"]
                if r["n"] > g.size:
                    raise ConfigError(
                        f"{self.name}.designs.random.n = {r['n']} exceeds the grid's {g.size} designs; "
                        f"allowed: 1..{g.size}"
                    )
                parts.append(np.random.default_rng(r["seed"]).choice(g.size, r["n"], replace=False))
            idx = np.concatenate(parts)
            if sec.get("include_mirrors", True):
                idx = np.concatenate([idx, g.mirror(idx)])
            return sorted({int(x) for x in idx})
        idx = []
        for i, (l1, l2) in enumerate(designs):
            try:
                idx.append(g.index_of(tuple(l1), tuple(l2)))
            except ValueError as e:
                raise ConfigError(f"{self.name}.designs.{i}: {e}; {off_grid_hint(designs)}") from None
        d = np.array(idx, dtype=np.int64)
        if sec.get("include_mirrors", True):
            d = np.concatenate([d, g.mirror(d)])
        return sorted({int(x) for x in d})

    def _screened(self, top: Mapping[str, Any], g: DesignGrid) -> np.ndarray:
        """``designs: {top_of: {bundle, model, by, n}}``: the ``n`` best designs by ``by`` (each of a list) of a
        committed survey of the same grid (screen with a cheaper engine, refine with this one;
        its table is checked against the bundle's record; designs with a positive value only, ties
        as :func:`metrics.best_designs`)."""
        import pandas as pd

        from morphlearn import metrics, provenance

        key = f"{self.name}.designs.top_of"
        path = Path(top["bundle"]) / top["model"] / "metrics.csv"
        try:
            provenance.check_derived(path)
            table = pd.read_csv(path, comment="#")
        except (OSError, ValueError) as e:
            raise ConfigError(f"{key}: {path}: {str(e).splitlines()[0]}; allowed: a committed survey bundle") from None
        if len(table) != g.size:
            raise ConfigError(
                f"{key}: {path} holds {len(table)} designs; allowed: a survey of every design of this grid ({g.size})"
            )
        by = [top["by"]] if isinstance(top["by"], str) else list(top["by"])
        best = []
        for b in by:  # a list of metrics: the union of each one's n best
            one = metrics.best_designs(table, b, top["n"])
            if not one:
                raise ConfigError(f"{key}: {path} has no design with {b} > 0; allowed: a survey with one")
            best += [d for d in one if d not in best]
        return np.array(best, dtype=np.int64)

    def _check_screen(self, options: SweepOptions, positions: int, weights: int, simulated: list[int]) -> None:
        from morphlearn.physics.screen import Screen

        key = f"{self.name}.adaptive_screen"
        if not self.takes_screen:
            raise ConfigError(f"{key} is set, but the {self.name} model's sweep takes no screen; allowed: null")
        if not options.adaptive_weights:
            raise ConfigError(
                f"{key} is set with {self.name}.adaptive_weights = false; allowed: null, or the adaptive grid on"
            )
        Screen(*options.screen, key).check(positions, weights, simulated)  # type: ignore[misc]

    def _check_designs(self, sec: Mapping[str, Any], simulated: list[int]) -> None:
        if sec.get("mirror_derive") and sec.get("designs") != "all" and not sec.get("include_mirrors", True):
            raise ConfigError(
                f"{self.name}.mirror_derive = true needs the mirror images in the results; "
                f"allowed: {self.name}.include_mirrors = true or {self.name}.designs = all"
            )
        if sec["shards"] > len(simulated):
            raise ConfigError(
                f"{self.name}.shards = {sec['shards']} exceeds the {len(simulated)} designs "
                f"simulated; allowed: 1..{len(simulated)}"
            )

    def check_results_bundle(
        self, path: str, n: int, key: str | None = None, survey: bool = False
    ) -> tuple[dict[str, float], int, tuple[int, ...]]:
        """A bundle to read the results from: present, on this config's grid (its checksums are
        checked when the results are copied, by the rule <model>_from_bundle). Returns the
        thresholds its metrics were made with, its weights per synapse and the designs its results
        hold (a survey: all; a refine bundle: a few). ``key``: the config key naming it (error
        messages). ``survey``: it must hold every design of its grid, which may be a coarser grid
        whose positions are this one's (the 5-point grid's 625 designs beside a 9-point run: a
        survey of the paper's grid can cost too much in an engine, the sub-grid's is its sample)."""
        from morphlearn import store

        key = key or f"{self.name}.results_from"
        need = [
            Path(path) / "bundle.json",
            Path(path) / self.name / "metrics.csv",
            Path(path) / self.name / "merged.zarr",
        ]
        missing = [str(p) for p in need if not p.exists()]
        if missing:
            raise ConfigError(
                f"{key} = {path!r}: {missing[0]} is missing; allowed: a results bundle "
                f"with {self.name} results (e.g. results/survey), or null"
                + (" to simulate" if key.endswith("results_from") else "")
            )
        try:
            merged = store.open_merged(Path(path) / self.name / "merged.zarr")
            sci = store.science_of(merged)
            positions = self.positions_of(sci)
            weights = int(merged.sizes["w1"])
            held = tuple(int(d) for d in sci["designs"])
            prov = bounded.json_file(Path(path) / self.name / "metrics.provenance.json")
            thresholds = dict(prov["config"]["thresholds"])
        except Exception as e:  # a damaged store: say which and why, in one line
            raise ConfigError(f"{key} = {path!r}: unreadable {self.name} results ({e})") from None
        if positions != n and not (survey and gridmod.is_subgrid(positions, n)):
            sub = " or a survey of a grid whose positions are among its (e.g. 5 in 9)" if survey else ""
            raise ConfigError(
                f"{key} = {path!r} holds results on the {positions}-point grid; "
                f"allowed: a bundle on grid.positions_per_axis = {n}{sub}"
            )
        if survey and len(held) != gridmod.DesignGrid(positions).size:
            raise ConfigError(
                f"{key} = {path!r}: its {self.name} results hold {len(held)} of the "
                f"{gridmod.DesignGrid(positions).size} designs of its {positions}-point grid; allowed: a survey "
                "of every design (e.g. results/survey9-mujoco)"
            )
        return thresholds, weights, held

    def results_from(self, s: Settings) -> str | None:
        return self.settings(s).results_from

    # -- the sweep ---------------------------------------------------------------------------------
    def inputs(self, s: Settings) -> dict[str, str]:
        return {"morphology": self.settings(s).morphology}

    def designs(self, s: Settings) -> np.ndarray:
        return np.array(self.settings(s).simulated, dtype=np.int64)

    def mirror_derived(self, s: Settings) -> bool:
        """Physics mirror images are simulated unless ``mirror_derive`` (an engine is symmetric
        only to solver tolerance)."""
        return self.settings(s).mirror_derive

    def thresholds(self, s: Settings) -> Thresholds:
        from morphlearn.metrics import Thresholds

        e = self.settings(s)
        if e.bundle_thresholds is not None:  # the bundle's own, as its metrics were made
            return Thresholds(**e.bundle_thresholds)
        p = e.params  # success = touching the light within the episode (the authors' test for theirs)
        r = success_radius(p) if e.robot == "authors" else p.contact_distance
        return Thresholds(p.horizon, r, p.horizon, r)

    @staticmethod
    def design_evaluator() -> Callable[..., DesignResult]:
        """The engine's ``evaluate_design(l1, l2, weights, params, progress=, options=)`` of its
        first robot."""
        raise NotImplementedError

    def centre_paths(
        self, params: EmpiricalParams, l1: tuple[float, float], l2: tuple[float, float], w: tuple[float, float]
    ) -> tuple[list[float], list[np.ndarray]]:
        """One controller's four episodes of its first robot, each to contact or horizon (no early
        stop), with the centre path recorded: (closest approach per environment, centre path per
        environment, float64 (steps + 1, 2)). The engine comparison's disagreement figure draws them;
        an engine in that comparison (``models.COMPARED``) implements it."""
        raise NotImplementedError(f"{self.name}: no recorded centre paths")

    def robot_evaluator(self, robot: str) -> Callable[..., DesignResult]:
        """The ``evaluate_design`` of ``robot`` (an engine with several robots overrides it)."""
        if robot != self.robots[0]:
            raise ValueError(f"{self.name}: robot {robot!r} is not built; allowed: {list(self.robots)}")
        return self.design_evaluator()

    def section_evaluator(self, e: PhysicsSettings) -> Callable[..., DesignResult]:
        """The ``evaluate_design`` a run of section ``e`` calls (a model with a kernel choice in its
        section, the reduced model's backend, overrides it)."""
        return self.robot_evaluator(e.robot)

    def evaluate(
        self, s: Settings, designs: np.ndarray, done: Done | None = None, partial: PartialPath | None = None
    ) -> list[DesignResult]:
        from tqdm import tqdm

        e = self.settings(s)
        evaluate_design = self.section_evaluator(e)
        w = self.weights(s)
        partial = partial if self.resumes_inside_design else None
        out = []
        screen = self._screen(e.options)
        shard = DesignsProgress(len(designs))
        for i, d in enumerate(tqdm(designs, unit="design", mininterval=1.0)):
            label = f"design {i + 1}/{len(designs)} (index {int(d)})"
            print(f"{label}: started", flush=True)  # the shard log is never silent for a whole design
            log = EpisodeProgress(label, at_most=e.options.adaptive_weights)
            kw: dict[str, Any] = {"partial": partial(int(d))} if partial else {}
            if screen is not None:
                kw["screen"] = screen(int(d), e.params)
            out.append(evaluate_design(*self.sensors(s, int(d)), w, e.params, progress=log, options=e.options, **kw))
            if done:
                done(i, out[-1])  # stores the design (design_cache.save, which removes its partial file)
            shard(i + 1)  # the shard's time left: the adaptive grid's episode counts give only a bound
        return out

    def _screen(self, options: SweepOptions) -> Callable[[int, EmpiricalParams], np.ndarray] | None:
        """``(design, params) -> cells`` of ``options.screen`` (None: no screen)."""
        if options.screen is None:
            return None
        from morphlearn.physics.screen import Screen

        sc = Screen(*options.screen, f"{self.name}.adaptive_screen")
        return lambda d, p: sc.cells(d, p.contact_distance, options.near)

    @staticmethod
    def sensors(s: Settings, design: int) -> tuple[tuple[float, float], tuple[float, float]]:
        """The design's sensor points l1, l2 as :meth:`evaluate` passes them (grid floats: a
        partial file's identity holds their reprs)."""
        c = s.grid.designs.coords(np.array([int(design)]))[0]
        return (c[0], c[1]), (c[2], c[3])

    def partial_identity(self, s: Settings, design: int) -> str:
        """The identity a partial file of ``design`` must name for :meth:`evaluate` to resume it."""
        from morphlearn.physics import partial

        e = self.settings(s)
        return partial.identity(*self.sensors(s, design), self.weights(s), e.params, e.options)

    def resimulate(self, science: Mapping[str, Any], designs: np.ndarray) -> list[DesignResult]:
        from morphlearn import store

        g = gridmod.DesignGrid(self.positions_of(science))
        w = gridmod.weights(science["weights"])
        params = EmpiricalParams.from_mapping(science["params"])
        options = SweepOptions.from_science(science)  # early stop, adaptive grid: as the run had them
        evaluate_design = self.robot_evaluator(science.get("robot", self.robots[0]))
        out, made = [], {}
        screen = self._screen(options)
        for d in (int(x) for x in designs):
            # mirror_derive: the run simulated one of each mirror pair (the lower index) and derived
            # the other from it (store.merge_shards); an engine is symmetric only to tolerance
            src = min(d, int(g.mirror(d))) if science.get("mirror_derive") else d
            if src not in made:
                c = g.coords(np.array([src]))[0]
                kw = {} if screen is None else {"screen": screen(src, params)}
                made[src] = evaluate_design((c[0], c[1]), (c[2], c[3]), w, params, options=options, **kw)
            r = made[src]
            if src != d:
                r = DesignResult(**store.mirror_arrays({v: getattr(r, v) for v in store.VARS}))
            out.append(r)
        return out

    def backend(self, s: Settings) -> dict[str, str]:
        return {"backend": self.engine, "device": f"cpu ({platform.machine()})"}

    def resources(self, s: Settings) -> Resources:
        return Resources(threads=1, runtime=240, mem_mb=2000)

    # -- records -----------------------------------------------------------------------------------
    def positions_of(self, science: Mapping[str, Any]) -> int:
        return int(science["positions_per_axis"])

    def how_made(self, science: Mapping[str, Any]) -> str:
        """How a record's designs were simulated (mirror derivation, adaptive grid), for :meth:`describe`."""
        how = "one of each mirror pair simulated, the other derived" if science.get("mirror_derive") else "simulated"
        if ad := science.get("adaptive_weights"):
            how += (
                f", weight grid refined adaptively around successes and near misses (within "
                f"{ad.get('near')} contact distances; cells not simulated count as failures; "
                f"measured miss rate in {self.levers_doc})"
            )
        return how

    def describe(self, science: Mapping[str, Any], n_designs: int, m: int) -> str:
        pr = science.get("params", {})
        how = self.how_made(science)
        return (
            f"{n_designs} designs {how} on the {science.get('positions_per_axis')}-point grid, "
            f"{m} weights per synapse; light distance {pr.get('light_distance', float('nan')):.4g}, "
            f"{pr.get('steps')} steps of dt = {pr.get('dt')}, success = touching the light; "
            + (
                "the paper authors' robot as this engine builds it (docs/authors_robot.md)"
                if science.get("robot") == "authors"
                else f"body from the committed morphology (wheel radius {pr.get('wheel_radius', float('nan')):.4g})"
            )
        )

    def evaluate_one(
        self, l1: tuple[float, float], l2: tuple[float, float], w: np.ndarray, a: argparse.Namespace
    ) -> DesignResult:
        robot = self.cli_robot(a)
        path = a.morphology or ROBOT_BODIES[robot]
        mismatch = other_robots_body(robot, path)
        if mismatch:  # the config's refusal (parse), at the command line too
            raise UsageError(
                f"--morphology {path} {mismatch} but the {self.name} model builds the {robot} robot "
                f"(--robot {robot}); allowed: its own body file {ROBOT_BODIES[robot]} or one of your own"
            )
        if not os.path.exists(path):  # a device or a FIFO exists: the bounded reader says what it is
            raise UsageError(f"--morphology {path}: no such file (a YAML of body parameters)")
        try:
            params = load_params(path)
        except ValueError as e:
            raise UsageError(f"--morphology {path}: {e}") from None
        # progress on stderr with the time left (half an hour for an ODE design at 121 x 121 once
        # passed in silence); stdout keeps the result (--json: one line)
        log = EpisodeProgress(f"design l1={l1} l2={l2}", every_s=10.0, stream=sys.stderr)
        with c_stdout_to_stderr():  # pybullet's banner
            return self.robot_evaluator(robot)(l1, l2, w, params, progress=log)

    def cli_robot(self, a: argparse.Namespace) -> str:
        """``--robot``, checked against the robots this engine builds (default: its first)."""
        robot = a.robot or self.robots[0]
        if robot not in self.robots:
            raise UsageError(f"--robot {robot}: the {self.name} model builds {', '.join(self.robots)}")
        return robot
