"""The paper authors' robot and world in the Open Dynamics Engine (ODE), episodes in C.

- ``_core.c``: the C extension (Debian's libode-dev 0.16, double precision): world, bodies,
  joints, contacts, step order, controller and outcome as the authors' simulator has them;
  one call runs a batch of episodes, each in its own world, with no Python per step;
- :mod:`.core`: the checked Python call (:func:`.core.run`) and the one-line message when the
  extension is missing;
- :mod:`.episode`: a design's sweep (``evaluate_design``), the other physics models' signature;
- :mod:`.plugin`: the registry's ``ode`` model.

docs/ode.md says where each fact comes from and how this model differs from pybullet and MuJoCo.
"""
