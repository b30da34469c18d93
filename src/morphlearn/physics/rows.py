"""How an engine computes one w1 row of a design, episode by episode: what the resumable one-design
runner (:mod:`morphlearn.resumable`) needs of an engine. An engine declares its
:class:`Engine` (:meth:`morphlearn.physics.model.Physics.row_engine`); the runner's table of
engines is derived from the model registry.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import EmpiricalParams

#: The chunk arrays, their dtypes (those of DesignResult, plus the physics steps for the cost).
CHUNK_VARS: dict[str, np.dtype] = {
    "first_time": np.dtype(np.float32),
    "min_dist": np.dtype(np.float32),
    "status": np.dtype(np.int8),
    "steps": np.dtype(np.int16),
}

Point = tuple[float, float]


class RowJob(Protocol):
    """What a row function reads of the runner's job (:class:`morphlearn.resumable.Job`)."""

    l1: Point
    l2: Point
    m: int
    options: SweepOptions

    @property
    def weights(self) -> np.ndarray: ...


@dataclass(frozen=True)
class Engine:
    """How a folder's rows are computed in one physics engine."""

    #: What the run key records about the engine (its version and settings).
    identity: Callable[[], dict[str, Any]]
    #: The episode runner for a body (a context manager).
    runner: Callable[[EmpiricalParams], Any]
    #: One w1 row's 4 x m episodes.
    row: Callable[[Any, RowJob, int], dict[str, np.ndarray]]
