"""A design's sweep over (env, w1, w2) in the reduced model: the physics layer's sweep of the
authors' robot's engines (:func:`morphlearn.physics.sweep.authors_robot_design`: adaptive grid,
resume, progress, every episode to its first success) over this model's batches, with the signature
and result of every physics model's ``evaluate_design``."""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from typing import Any

from morphlearn.physics.sweep import authors_robot_design
from morphlearn.reduced.core import run

#: Episodes per kernel call: progress is reported between calls; results do not depend on it.
CHUNK = 8192


def evaluator(backend: str = "cpu") -> Callable[..., Any]:
    """``evaluate_design`` whose batches run on ``backend`` (:data:`morphlearn.reduced.core.BACKENDS`)."""
    kernel = run if backend == "cpu" else partial(run, backend=backend)
    return partial(authors_robot_design, kernel, where="in the reduced model", chunk=CHUNK)


#: ``evaluate_design(l1, l2, weights, params, progress=None, options=None, partial=None)``: all
#: (env, w1, w2) episodes of one design, arrays (4, m, m) [env, i_w1, i_w2], on the scalar kernel.
evaluate_design = evaluator("cpu")
