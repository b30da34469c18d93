"""The empirical model: a pybullet simulation of the two-wheeled light-seeking robot.

- :mod:`.params`: physical parameters and solver settings (:class:`EmpiricalParams`);
- :mod:`.robot`: builds the world (floor, robot, light) with ``createMultiBody``;
- :mod:`.episode`: one episode (:class:`EpisodeRunner`) and a design's sweep
  (:func:`evaluate_design`);
- :mod:`.optimise`: the base-morphology optimisation (NSGA-II) that picks the body.
"""

from morphlearn.empirical.episode import Episode, EpisodeRunner, evaluate_design
from morphlearn.empirical.params import EmpiricalParams, load_params

__all__ = ["EmpiricalParams", "Episode", "EpisodeRunner", "evaluate_design", "load_params"]
