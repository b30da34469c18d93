"""The physics layer: what every rigid-body engine model shares.

- :mod:`.model`: the model base :class:`~.model.Physics` (config section, success rule, record,
  per-design evaluation) on which an engine is data plus its batch-of-episodes function;
- :mod:`.sweep`: the one sweep of designs over (env, w1, w2) every engine's batch runs on
  (pybullet, MuJoCo, MuJoCo Warp, ODE, the reduced model), with the levers (adaptive weight grid,
  reach bound, resume inside a design, checkpoints) in one place; :mod:`.batch`: a batch of the
  authors' robot's episodes; :mod:`.design_cache`: finished designs kept across shards and kills;
  :mod:`.progress`: progress lines;
- :mod:`.params`: the body and world parameters (:class:`~.params.EmpiricalParams`);
  :mod:`.authors`: the paper authors' robot and world, which several engines build;
- :mod:`.body`: a body as Fig. 1C draws it (:class:`~.body.FigureBody`), what an engine supplies for the figure;
- :mod:`.options`: the sweep's levers (early stop, adaptive weight grid);
- :mod:`.reach`: the reach bound behind the early stop; :mod:`.refine`: the adaptive weight grid;
  :mod:`.screen`: its screen, a cheaper model's outcomes of the same designs;
- :mod:`.partial`: a running design's finished episodes (resume inside a design);
- (the committed refine folders, one design row by row, are history read by
  :mod:`morphlearn.refine.folder`; :mod:`morphlearn.refine.seed` seeds a design's partial file from them.)

The engines are packages beside each other on this layer: :mod:`morphlearn.empirical` (pybullet),
:mod:`morphlearn.mujoco`, :mod:`morphlearn.ode`, :mod:`morphlearn.reduced`. Nothing here imports
an engine or anything above the model interface (import-linter contracts in pyproject.toml).
"""
