"""MuJoCo's rows for the resumable one-design runner (:mod:`morphlearn.physics.rows`), with its
default ``MujocoSettings``."""

from __future__ import annotations

from contextlib import nullcontext
from dataclasses import asdict
from typing import Any

import numpy as np

from morphlearn.mujoco.episode import BatchRunner
from morphlearn.mujoco.model import MujocoSettings
from morphlearn.physics.params import EmpiricalParams
from morphlearn.physics.rows import CHUNK_VARS, Engine, RowJob
from morphlearn.results import STATUS_NONFINITE, STATUS_OK


def _row(runner: Any, job: RowJob, row: int) -> dict[str, np.ndarray]:
    """The row's 4 x m episodes in one MuJoCo batch (outcomes do not depend on the batch)."""
    w, m, opt = job.weights, job.m, job.options
    env, j = np.repeat(np.arange(4), m), np.tile(np.arange(m), 4)
    ep = runner.run(
        job.l1, job.l2, np.stack([np.full(4 * m, w[row]), w[j]], 1), env, margin=opt.margin if opt.early_stop else None
    )
    out = {
        "first_time": ep.first_time,
        "min_dist": ep.min_dist,
        "status": np.where(ep.finite, STATUS_OK, STATUS_NONFINITE),
        "steps": ep.steps,
    }
    return {k: np.asarray(out[k]).reshape(4, m).astype(dt) for k, dt in CHUNK_VARS.items()}


def _identity() -> dict[str, Any]:
    import mujoco

    return {"engine": "mujoco", "mujoco": mujoco.__version__, "mujoco_settings": asdict(MujocoSettings())}


def _runner(params: EmpiricalParams) -> Any:
    return nullcontext(BatchRunner(params))


ENGINE = Engine(_identity, _runner, _row)
