"""The per-trajectory outcome arrays that both models return and the store keeps."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Trajectory status codes (int8 in storage).
STATUS_OK = 0
STATUS_STEP_UNDERFLOW = 1  # adaptive step fell below its floor (singular designs)
STATUS_STEP_CAP = 2  # step-count cap reached before the horizon
STATUS_NONFINITE = 3  # state became NaN/inf
#: Not simulated: the adaptive weight grid (empirical.adaptive_weights) took it as a failure.
STATUS_INFERRED = 4
STATUS_NAMES = {0: "ok", 1: "step_underflow", 2: "step_cap", 3: "nonfinite", 4: "inferred"}
#: Codes of trajectories that stopped abnormally (the metrics tables' ``flagged`` count).
STATUS_FLAGGED = (STATUS_STEP_UNDERFLOW, STATUS_STEP_CAP, STATUS_NONFINITE)


@dataclass
class DesignResult:
    """Outcomes of one design over the (env, w1, w2) grid, each array of shape (4, m, m).

    ``first_time``: model time of first success (NaN if none within the simulated horizon);
    ``min_dist``: minimum centre-to-light distance (up to success or the horizon; for an
    empirical episode stopped early by the reach bound, up to that stop; NaN if inferred);
    ``status``: one of the ``STATUS_*`` codes.
    """

    first_time: np.ndarray
    min_dist: np.ndarray
    status: np.ndarray

    def __post_init__(self) -> None:
        self.first_time = np.asarray(self.first_time, dtype=np.float32)
        self.min_dist = np.asarray(self.min_dist, dtype=np.float32)
        self.status = np.asarray(self.status, dtype=np.int8)
        shapes = {self.first_time.shape, self.min_dist.shape, self.status.shape}
        if len(shapes) != 1 or self.first_time.ndim != 3 or self.first_time.shape[0] != 4:
            raise ValueError(f"DesignResult arrays must share shape (4, m, m), got {shapes}")
