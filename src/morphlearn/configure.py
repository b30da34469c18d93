"""The whole config parsed into :class:`~morphlearn.settings.Settings`, once, at the edge: the shared
sections (:mod:`morphlearn.settings`), each model's own section by its plug-in (the registry,
:mod:`morphlearn.models`), and the bundles the config reads results from (checked here: present, on
this grid, readable).

Above the model registry: the Snakefile (``workflow/rules/common.smk``), each rule script's entry
(``workflow/scripts/_entry.py``), the CLI and the scenario runner call :func:`parse` or :func:`load`.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from types import MappingProxyType
from typing import Any

from morphlearn import config as cfgmod
from morphlearn import models
from morphlearn import settings as st
from morphlearn.physics.model import Physics


def _parse_survey(sec: Mapping[str, Any], grid: st.GridSettings) -> st.SurveySettings:
    """The survey bundle: a physics model's results holding every design of this grid or of a
    coarser one whose positions are this grid's (checked by the model)."""
    bundle, name = sec["bundle"], sec["model"]  # the schema fills both
    physics = models.physics()
    if name not in physics:
        raise cfgmod.ConfigError(f"survey_from.model = {name!r} is not a physics model; allowed: {physics}")
    if bundle is None:
        return st.SurveySettings(None, name, None)
    model = models.get(name)
    assert isinstance(model, Physics)
    th, _, _ = model.check_results_bundle(bundle, grid.positions_per_axis, key="survey_from.bundle", survey=True)
    return st.SurveySettings(bundle, name, MappingProxyType(th))


def _parse_screen(sec: Mapping[str, Any], grid: st.GridSettings) -> st.Screen:
    """The screen (every design of this grid, a physics model's) and its refinement (the paper's
    engine at some designs of the same grid and weights), each checked by its model."""
    if sec["bundle"] is None and sec["refinement"] is None:
        return None
    if sec["bundle"] is None or sec["refinement"] is None:
        given, other = ("bundle", "refinement") if sec["refinement"] is None else ("refinement", "bundle")
        raise cfgmod.ConfigError(f"screen_from.{given} is set without screen_from.{other}; allowed: both, or neither")
    physics = models.physics()
    if sec["model"] not in physics:
        raise cfgmod.ConfigError(f"screen_from.model = {sec['model']!r} is not a physics model; allowed: {physics}")
    screen, paper = models.get(sec["model"]), models.get(models.paper_engine())
    assert isinstance(screen, Physics) and isinstance(paper, Physics)
    n = grid.positions_per_axis
    th, w, held = screen.check_results_bundle(sec["bundle"], n, key="screen_from.bundle", survey=True)
    if len(held) != grid.designs.size:  # a survey of a coarser grid rules out none of this grid's other designs
        raise cfgmod.ConfigError(
            f"screen_from.bundle = {sec['bundle']!r} holds {len(held)} designs; allowed: every design of "
            f"grid.positions_per_axis = {n} ({grid.designs.size})"
        )
    th_r, w_r, _ = paper.check_results_bundle(sec["refinement"], n, key="screen_from.refinement")
    if w_r != w:
        raise cfgmod.ConfigError(
            f"screen_from.refinement = {sec['refinement']!r} holds {w_r} x {w_r} weights, the screen {w} x {w}; "
            "allowed: the same weights"
        )
    return (
        st.SurveySettings(sec["bundle"], sec["model"], MappingProxyType(th)),
        st.SurveySettings(sec["refinement"], paper.name, MappingProxyType(th_r)),
    )


def _parse_text_sweep(path: str | None, grid: st.GridSettings) -> str | None:
    """The second theory sweep's bundle: present, and holding every design of this grid."""
    if path is None:
        return None
    from morphlearn import store

    key = "text_sweep_from"
    merged = Path(path) / "theory" / "merged.zarr"
    for need in (Path(path) / "bundle.json", merged):
        if not need.exists():
            raise cfgmod.ConfigError(
                f"{key} = {path!r}: {need} is missing; allowed: a theory bundle of every design, or null"
            )
    try:
        ds = store.open_merged(merged)
        n = int(store.science_of(ds)["grid"]["positions_per_axis"])
        held = int(ds.sizes["design"])
    except Exception as e:  # a damaged store: say which and why, in one line
        raise cfgmod.ConfigError(f"{key} = {path!r}: unreadable theory results ({e})") from None
    if n != grid.positions_per_axis or held != grid.designs.size:
        raise cfgmod.ConfigError(
            f"{key} = {path!r} holds {held} designs of the {n}-point grid; allowed: every design of "
            f"grid.positions_per_axis = {grid.positions_per_axis} ({grid.designs.size})"
        )
    return str(path)


def parse(cfg: Mapping[str, Any]) -> st.Settings:
    """Validate ``cfg`` (defaults filled, cross-checks) and parse it into :class:`~morphlearn.settings.Settings`.
    Raises :class:`morphlearn.config.ConfigError` with a one-line message."""
    v = cfgmod.validate(dict(cfg), models.path_keys(), models.schema_sections())
    st.check_theory(v["theory"], lambda k: f"theory.{k}")
    grid = st.section(st.GridSettings, v["grid"])
    sweep = st.section(st.SweepSettings, v["sweep"])
    figures = st.section(st.FigureSettings, v["figures"])
    learners = st.section(st.LearnerSettings, v["learners"])
    if learners.enabled:
        g = grid.designs
        n_run = min(len(g.representatives()), learners.max_designs or g.size)
        if learners.shards > n_run:
            raise cfgmod.ConfigError(
                f"learners.shards = {learners.shards} exceeds the {n_run} designs the learners run; allowed: 1..{n_run}"
            )
    coopt = st.coopt_section(v["coopt"])
    st.check_coopt(coopt)
    return st.Settings(
        source=MappingProxyType(v),
        results_dir=v["results_dir"],
        design_cache=bool(v["design_cache"]),
        grid=grid,
        sweep=sweep,
        analysis=st.section(st.AnalysisSettings, v["analysis"]),
        figures=figures,
        learners=learners,
        coopt=coopt,
        engines=st.section(st.EnginesSettings, v["engines"]),
        agreement=st.agreement_section(v["agreement"]),
        # each model parses its own section (schema defaults filled: {} when absent)
        models=MappingProxyType(
            {name: m.parse(v.get(name, {}), st.Shared(grid, sweep, figures)) for name, m in models.MODELS.items()}
        ),
        bundle_dir=v["bundle_dir"],
        bundle_designs=v["bundle_designs"],
        survey=_parse_survey(v["survey_from"], grid),
        screen=_parse_screen(v["screen_from"], grid),
        text_sweep=_parse_text_sweep(v["text_sweep_from"], grid),
        scenarios=v["scenarios"],
        scenario_file=v["scenario_file"],
        render_only=bool(v["render_only"]),
    )


def load(path: str | Path, overrides: list[str | Path] = ()) -> st.Settings:
    """Read a YAML config (deep-merging override files, as ``--configfile`` does) and parse it."""
    return parse(cfgmod.read(path, overrides))
