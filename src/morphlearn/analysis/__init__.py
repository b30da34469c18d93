"""The analysis stages that are one module each (the larger ones are packages beside this one:
:mod:`morphlearn.figures`, :mod:`morphlearn.learners`, :mod:`morphlearn.coopt`, :mod:`morphlearn.scenarios`).

- :mod:`.compare`: theory against physics, design by design;
- :mod:`.agreement`: each engine and robot against ODE with the authors' robot;
- :mod:`.engines`: the two physics engines compared design by design;
- :mod:`.summary`: the run's summary (canonical and best designs);
- :mod:`.candidates`: which designs to refine at the paper's weights.

Nothing is imported here: import the submodules.
"""
