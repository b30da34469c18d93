"""Which figures a config draws, and each figure's notebook parameters from the settings.

Light imports only: the Snakefile imports this module at parse time.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from morphlearn import models
from morphlearn.figures.registry import FIGURES as FIGURE_SPECS
from morphlearn.figures.registry import PHYSICS, REFERENCE_PHYSICS
from morphlearn.settings import Settings, Source

#: The paper's figures, drawn by every run; :func:`figures` adds those of enabled extra stages.
PAPER_FIGURES = tuple(f for f, spec in FIGURE_SPECS.items() if spec.needs is None)


def physics_survey(s: Settings) -> bool:
    """A physics survey of every design of the grid: the run's (simulated, or read from a bundle
    that holds them all) or the bundle of ``survey_from`` (which the survey figure then draws)."""
    e = s.models[models.reference_physics()]
    return s.survey.bundle is not None or (e.enabled and len(e.held) == s.grid.designs.size)


def physics_only(s: Settings) -> bool:
    """A run of physics models without the theory (the maps figure: each design's map)."""
    return not models.MODELS[models.REFERENCE].enabled(s) and bool(_physics_on(s))


#: Figure conditions besides "a config section is enabled" (registry ``needs``).
FIGURE_CONDITIONS: dict[str, Callable[[Settings], bool]] = {
    "physics_survey": physics_survey,
    "physics_only": physics_only,
}
#: Config sections with an ``enabled`` switch that a figure may need.
STAGES: dict[str, Callable[[Settings], bool]] = {
    "learners": lambda s: s.learners.enabled,
    "coopt": lambda s: s.coopt.enabled,
    "engines": lambda s: s.engines.enabled,
    "agreement": lambda s: s.agreement.enabled,
}


def figures(s: Settings) -> list[str]:
    """The figures this config draws (none without figures.enabled): the paper's and those whose
    ``needs`` is met; without the reference model (the theory) only those that read none of its
    results (Fig. 1, the maps of a physics-only run's designs), where once it drew none, silently."""
    if not s.figures.enabled:
        return []
    with_theory = models.MODELS[models.REFERENCE].enabled(s)

    def met(needs: str | None) -> bool:
        if needs is None:
            return True
        return {**FIGURE_CONDITIONS, **STAGES}[needs](s)

    def drawable(spec: Any) -> bool:
        return with_theory or not ({models.REFERENCE, REFERENCE_PHYSICS} & set(spec.reads))

    return [f for f, spec in FIGURE_SPECS.items() if met(spec.needs) and drawable(spec)]


def figure_robot(s: Settings | None = None) -> dict[str, Any]:
    """What Fig. 1C draws: the registry's ``figure_body`` model's engine, robot, body parameters and
    the body it builds for the figure (``figure_body``: import path of its
    :class:`morphlearn.physics.body.FigureBody`). Without settings (the notebook run on its own):
    the reference physics engine's default robot with default parameters and no body file."""
    if s is None:
        name = models.reference_physics()
        model = models.get(name)
        robot, params, morphology = model.robots[0], None, None  # type: ignore[attr-defined]
    else:
        name = models.figure_body()
        model, sec = models.get(name), s.models[name]
        robot, params, morphology = sec.robot, sec.params.to_dict(), sec.morphology
    return {
        "engine": getattr(model, "engine_label", "") or getattr(model, "engine", name),
        "robot": robot,
        "robot_label": model.robot_label({"robot": robot}),  # type: ignore[attr-defined]
        "body": params,
        "morphology": morphology,
        "figure_body": models.figure_body_path(name, robot),
    }


#: Figure options that name a module its notebook imports by name (``module:attribute`` under this
#: key): Fig. 1C's body, which its engine supplies. That module's code is the figure's input too.
IMPORTED_OPTIONS: dict[str, str] = {"figure_robot": "figure_body"}


def imported_modules(opts: dict[str, Any]) -> list[str]:
    """The modules a figure with notebook parameters ``opts`` imports by name (figures.registry.named_modules)."""
    return [opts[o][key].split(":")[0] for o, key in IMPORTED_OPTIONS.items() if opts.get(o)]


def trajectory_settings(s: Settings) -> dict[str, float]:
    """What a reference trajectory for a figure needs (figures.data.TheorySettings fields)."""
    p = s.models[models.REFERENCE].params
    return {"r": p.r, "horizon": p.horizon, "radius": p.success_radius, "tol": p.rtol}


#: Figure options computed from the settings rather than read from its ``figures`` section.
DERIVED_FIGURE_OPTIONS: dict[str, Callable[[Settings], Any]] = {
    # the reference engine's body (the disagreement figure: the body both engines simulated); None
    # when it is off (its body not read; that figure is then not drawn)
    "morphology": lambda s: None if (p := s.models[models.reference_physics()].params) is None else p.to_dict(),
    "figure_robot": figure_robot,  # Fig. 1C
    "trajectory_settings": trajectory_settings,
    "top": lambda s: s.analysis.top,  # the survey figure's sensor maps: the summary's top designs
    "coopt_sigma": lambda s: s.coopt.sigmas[0],  # the coopt figure's evolution strategies: the first step
}


def survey_option(s: Settings) -> dict[str, Any] | None:
    """The physics survey read from a bundle (``survey_from``): its model and the thresholds its
    metrics were made with, or None when the config sets none."""
    if not s.survey.bundle:
        return None
    return {"model": s.survey.model, "thresholds": dict(s.survey.thresholds or {})}


def screen_option(s: Settings) -> dict[str, Any] | None:
    """The screen and its refinement (``screen_from``): where each bundle is, its model and the
    thresholds its metrics were made with, or None when the config sets none."""
    if s.screen is None:
        return None
    return {
        part: {"bundle": b.bundle, "model": b.model, "thresholds": dict(b.thresholds or {})}
        for part, b in zip(("screen", "refinement"), s.screen, strict=True)
    }


def screen_files(s: Settings) -> list[str]:
    """What the screen rows read: each bundle's metrics table and manifest (empty: no screen)."""
    return [f for b in s.screen or () for f in Source(str(b.bundle), b.model).files()]


def text_sweep_files(s: Settings) -> list[str]:
    """What the second-sweep rows read: the bundle's manifest, metrics table and outcome store
    (empty: none set)."""
    if s.text_sweep is None:
        return []
    return [f"{s.text_sweep}/bundle.json", f"{s.text_sweep}/theory/metrics.csv", f"{s.text_sweep}/theory/merged.zarr"]


def figure_options(s: Settings, fig: str) -> dict[str, Any]:
    """Notebook parameters of figure ``fig`` (registry: what it reads and takes).

    Only what that figure uses, so that changing a figure parameter re-renders only the figures
    that depend on it: ``<model>_thresholds`` of the models it reads (a model other than the
    reference only when enabled, with ``<model>_enabled``), then its options from
    DERIVED_FIGURE_OPTIONS or ``figures.<name>``.
    """
    spec = FIGURE_SPECS[fig]
    opts: dict[str, Any] = {}
    for name in map(_model, spec.reads):
        if name == PHYSICS:  # every enabled physics model, in registry order; the notebook loops
            opts["physics"] = {n: models.get(n).thresholds(s).__dict__ for n in _physics_on(s)}
            opts["physics_registered"] = models.physics()
            continue
        m = models.get(name)
        on = m.enabled(s)
        if name != models.REFERENCE:
            opts[f"{name}_enabled"] = on
        if on or name == models.REFERENCE:
            opts[f"{name}_thresholds"] = m.thresholds(s).__dict__
    for name in spec.options:
        opts[name] = DERIVED_FIGURE_OPTIONS[name](s) if name in DERIVED_FIGURE_OPTIONS else s.figures.option(name)
    if spec.survey and s.survey.bundle:  # only when set: figures without a survey keep their parameters
        opts["survey"] = survey_option(s)
    return opts


def data_models(s: Settings, fig: str) -> list[str]:
    """The models whose results a figure reads (registry), those off left out."""
    out: list[str] = []
    for name in map(_model, FIGURE_SPECS[fig].reads):
        out += _physics_on(s) if name == PHYSICS else [name] if models.get(name).enabled(s) else []
    return out


def _model(token: str) -> str:
    """A ``reads`` token's model name (:data:`PHYSICS` stays a token)."""
    return models.reference_physics() if token == REFERENCE_PHYSICS else token


def _physics_on(s: Settings) -> list[str]:
    return [n for n in models.physics() if models.get(n).enabled(s)]
