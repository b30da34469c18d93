"""The model registry: every model plug-in (:class:`morphlearn.model_interface.Model`), by name.

The workflow's simulate / merge / metrics rules are instantiated per registered model; summary,
compare, bundle, captions, the reproduction table and the CLI ask this registry instead of
comparing names. To add a model: its own package with a ``Model`` subclass, one line in
:func:`_registry`, and its config section in ``config_schema.yaml``.

Light imports only: the Snakefile imports this module at parse time.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from morphlearn.model_interface import Model

if TYPE_CHECKING:
    from morphlearn.settings import Settings


def _registry() -> dict[str, Model]:
    from morphlearn.empirical.plugin import Pybullet
    from morphlearn.mujoco.plugin import Mujoco
    from morphlearn.ode.plugin import Ode
    from morphlearn.theory.plugin import Theory

    # Order is the order of tables, summaries and reports; the first model is the reference.
    return {m.name: m for m in (Theory(), Pybullet(), Mujoco(), Ode())}


#: name -> model, every registered model.
MODELS: dict[str, Model] = _registry()
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
