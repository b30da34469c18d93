"""The pybullet engine (registered as the model ``empirical``): the two-wheeled light-seeking
robot in pybullet, one engine on the physics layer (:mod:`morphlearn.physics`).

- :mod:`.robot`: builds the world (floor, robot, light) with ``createMultiBody``;
- :mod:`.episode`: one episode (:class:`EpisodeRunner`) and a design's sweep
  (:func:`evaluate_design`);
- :mod:`.optimise`: the base-morphology optimisation (NSGA-II) that picks the body;
- :mod:`.figure_body`: both robots' bodies as Fig. 1C draws them (the authors' also for ODE);
- :mod:`.plugin`: the engine as a model plug-in (:class:`~.plugin.Pybullet`).

Nothing is imported eagerly: the Snakefile and the theory/analysis rules import this package's
plug-in, and their environments (envs/theory.yaml, envs/analysis.yaml) hold no pybullet. The
simulation names load pybullet on first use.
"""

from __future__ import annotations

from typing import Any

__all__ = ["Episode", "EpisodeRunner", "evaluate_design"]
_LAZY = set(__all__)


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        from morphlearn.empirical import episode

        return getattr(episode, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
