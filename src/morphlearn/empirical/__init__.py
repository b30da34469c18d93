"""The empirical model: a pybullet simulation of the two-wheeled light-seeking robot.

- :mod:`.params`: physical parameters and solver settings (:class:`EmpiricalParams`);
- :mod:`.robot`: builds the world (floor, robot, light) with ``createMultiBody``;
- :mod:`.episode`: one episode (:class:`EpisodeRunner`) and a design's sweep
  (:func:`evaluate_design`);
- :mod:`.optimise`: the base-morphology optimisation (NSGA-II) that picks the body.

Only :mod:`.params` is imported eagerly: the config, the Snakefile and the theory/analysis rules
read the parameters, and their environments (envs/theory.yaml, envs/analysis.yaml) hold no
pybullet. The simulation names load pybullet on first use.
"""

from __future__ import annotations

from typing import Any

from morphlearn.empirical.params import EmpiricalParams, load_params

__all__ = ["EmpiricalParams", "Episode", "EpisodeRunner", "evaluate_design", "load_params"]
_LAZY = {"Episode", "EpisodeRunner", "evaluate_design"}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        from morphlearn.empirical import episode

        return getattr(episode, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
