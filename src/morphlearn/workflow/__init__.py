"""What the workflow's rules do: the Snakefile and the rule scripts (``workflow/``) parse the
settings and call these.

- :mod:`.rules`: the simulate / merge / metrics rules and the render-only start checks;
- :mod:`.results_check`: the start-up check for results another config made;
- :mod:`.blas_kernel`: one OpenBLAS kernel for every process the workflow starts.

Nothing is imported here (the Snakefile imports these at parse time): import the submodules.
"""
