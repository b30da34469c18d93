"""The model registry: every model plug-in (:class:`morphlearn.model_interface.Model`), by name.

The workflow's simulate / merge / metrics rules are instantiated per registered model; summary,
compare, bundle, captions, the reproduction table and the CLI ask this registry instead of
comparing names. To add a model: its own package with a ``Model`` subclass, one line in
:data:`PLUGINS`, and its config section in ``config_schema.yaml`` (an engine on the physics base
shares the physics section's keys without one: ``Model.schema_like``).

Light imports only: the Snakefile imports this module at parse time.
"""

from __future__ import annotations

import importlib
from collections.abc import Iterator, MutableMapping
from typing import TYPE_CHECKING

from morphlearn.model_interface import Model
from morphlearn.physics.model import Physics

if TYPE_CHECKING:
    from morphlearn.settings import Settings

#: Every model plug-in, by registry name: ``module:class``. One line per model; the order is the
#: order of tables, summaries and reports, and the first model is the reference.
PLUGINS: dict[str, str] = {
    "theory": "morphlearn.theory.plugin:Theory",
    "empirical": "morphlearn.empirical.plugin:Pybullet",
    "mujoco": "morphlearn.mujoco.plugin:Mujoco",
    "ode": "morphlearn.ode.plugin:Ode",
    "reduced": "morphlearn.reduced.plugin:Reduced",
}


class Registry(MutableMapping[str, Model]):
    """name -> model instance, each plug-in imported on first use (by its import path: this module
    imports no plug-in, so the layers below the registry never depend on a model package)."""

    def __init__(self, plugins: dict[str, str]) -> None:
        self._paths = dict(plugins)
        self._made: dict[str, Model] = {}

    def __getitem__(self, name: str) -> Model:
        if name not in self._made:
            module, cls = self._paths[name].split(":")  # KeyError: not registered
            model = getattr(importlib.import_module(module), cls)()
            if model.name != name:
                raise TypeError(f"{self._paths[name]} is registered as {name!r} but names itself {model.name!r}")
            self._made[name] = model
        return self._made[name]

    def __setitem__(self, name: str, model: Model) -> None:  # a test registers a double
        self._paths.setdefault(name, f"{type(model).__module__}:{type(model).__qualname__}")
        self._made[name] = model

    def __delitem__(self, name: str) -> None:
        del self._paths[name]
        self._made.pop(name, None)

    def __iter__(self) -> Iterator[str]:
        return iter(self._paths)

    def __len__(self) -> int:
        return len(self._paths)


#: The two physics engines the engine comparison (``engines``, config/engines.yaml) sets side by
#: side, by registry name; the ``engines`` section names each one's table by its engine.
COMPARED: tuple[str, str] = ("empirical", "mujoco")

#: name -> model, every registered model.
MODELS: Registry = Registry(PLUGINS)
#: The reference model: figures need it, comparisons are against it.
REFERENCE: str = next(iter(MODELS))


def get(name: str) -> Model:
    try:
        return MODELS[name]
    except KeyError:
        raise ValueError(f"unknown model {name!r}; allowed: {list(MODELS)}") from None


def enabled(s: Settings) -> list[str]:
    """The models this config runs (results simulated or read from a bundle)."""
    return [n for n, m in MODELS.items() if m.enabled(s)]


def simulated(s: Settings) -> list[str]:
    """The models this config simulates."""
    return [n for n, m in MODELS.items() if m.simulates(s)]


def path_keys() -> list[str]:
    """Every model's config keys that name files (``section.key``), checked at start."""
    return [f"{n}.{k}" for n, m in MODELS.items() for k in m.path_keys]


def schema_sections() -> dict[str, str]:
    """Model name -> the config section whose schema its section shares, where it declares one."""
    return {n: m.schema_like for n, m in MODELS.items() if m.schema_like}


def figure_body() -> str:
    """The physics model whose robot and body Fig. 1C draws (``Physics.figure_body``: the one the
    headline numbers use, the authors' robot in ODE); exactly one registered engine sets it."""
    found = [n for n in physics() if getattr(MODELS[n], "figure_body", False)]
    if len(found) != 1:
        raise LookupError(f"Fig. 1C draws one engine's body; Physics.figure_body is set by {found}")
    return found[0]


def figure_body_path(name: str, robot: str) -> str:
    """Import path of the body (:class:`morphlearn.physics.body.FigureBody`) Fig. 1C draws for
    physics model ``name``'s ``robot``: its own (``Physics.figure_bodies``), else that of the first
    engine (:func:`physics` order) that builds the robot for the figure (an engine without a
    renderer's build, ODE's, is drawn as one that has: pybullet's, to the same geometry)."""
    for n in [name, *(n for n in physics() if n != name)]:
        path = getattr(MODELS[n], "figure_bodies", {}).get(robot)
        if path:
            return str(path)
    raise LookupError(f"no registered engine builds the {robot!r} robot for Fig. 1C (Physics.figure_bodies)")


def reference_physics() -> str:
    """The reference physics engine: the first physics model in registry order (pybullet, the
    workflow's ``empirical`` results, with the project's body)."""
    found = set(physics())
    return next(n for n in MODELS if n in found)


def physics() -> list[str]:
    """The registered rigid-body engine models (:class:`morphlearn.physics.model.Physics`): the
    paper's own engine first (figures draw the first enabled one, tables answer with it first),
    then in registry order."""
    found = [n for n, m in MODELS.items() if isinstance(m, Physics)]
    return sorted(found, key=lambda n: not MODELS[n].paper_engine)


def paper_engine() -> str:
    """The physics model of the engine the paper's physics ran in (``Physics.paper_engine``: ODE)."""
    return next(n for n in physics() if MODELS[n].paper_engine)


def compared_engines() -> tuple[str, str]:
    """The engines of the engine comparison's pair (:data:`COMPARED`), as records and its tables'
    columns name them (``Physics.engine``)."""
    a, b = (MODELS[n] for n in COMPARED)
    assert isinstance(a, Physics) and isinstance(b, Physics)
    return a.engine, b.engine


def compared_model(engine: str) -> Physics:
    """The model of one engine of the comparison's pair."""
    found = [m for m in (MODELS[n] for n in COMPARED) if isinstance(m, Physics) and m.engine == engine]
    if not found:
        raise ValueError(f"engine {engine!r} is not in the comparison; allowed: {list(compared_engines())}")
    return found[0]
