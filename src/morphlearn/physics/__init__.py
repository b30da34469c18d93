"""The physics layer: what every rigid-body engine model shares.

- :mod:`.model`: the model base :class:`~.model.Physics` (config section, success rule, record,
  per-design evaluation) on which an engine is data plus its episode function;
- :mod:`.sweep`: a design's sweep over (env, w1, w2) for an engine's batch of episodes, with the
  levers (adaptive weight grid, resume inside a design) in one place (MuJoCo and ODE run on it;
  pybullet still runs its own per-episode sweep, environment by environment: not moved yet);
- :mod:`.params`: the body and world parameters (:class:`~.params.EmpiricalParams`);
- :mod:`.body`: a body as Fig. 1C draws it (:class:`~.body.FigureBody`), what an engine supplies for the figure;
- :mod:`.options`: the sweep's levers (early stop, adaptive weight grid);
- :mod:`.reach`: the reach bound behind the early stop; :mod:`.refine`: the adaptive weight grid;
- :mod:`.partial`: a running design's finished episodes (resume inside a design);
- (the committed refine folders, one design row by row, are history read by
  :mod:`morphlearn.refine.folder`; :mod:`morphlearn.refine.seed` seeds a design's partial file from them.)

The engines are packages beside each other on this layer: :mod:`morphlearn.empirical` (pybullet),
:mod:`morphlearn.mujoco`, :mod:`morphlearn.ode`. Nothing here imports an engine or anything above
the model interface (import-linter contracts in pyproject.toml).
"""
