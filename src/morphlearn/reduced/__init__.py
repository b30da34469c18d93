"""The reduced model of the paper authors' robot: its planar rigid-body motion with ODE's contacts
(force-dependent slip as implicit dampers) and torque-capped velocity motors, stepped as ODE's
dWorldStep steps it, in a numba kernel (``body``: the physics and its approximations; ``kernel``:
one step source for the CPU and CUDA; ``cpu``, ``core``: batches; ``episode``: a design's sweep;
``plugin``: the registry entry). docs/reduced.md measures it against ODE cell by cell."""
