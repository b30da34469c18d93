"""pybullet's rows for the resumable one-design runner (:mod:`morphlearn.physics.rows`)."""

from __future__ import annotations

from typing import Any

import numpy as np

from morphlearn import provenance
from morphlearn.physics.params import EmpiricalParams
from morphlearn.physics.rows import CHUNK_VARS, Engine, RowJob
from morphlearn.results import STATUS_NONFINITE, STATUS_OK


def _row(runner: Any, job: RowJob, row: int) -> dict[str, np.ndarray]:
    """The row's 4 x m episodes one by one, as ``evaluate_design`` calls them."""
    w, m, opt = job.weights, job.m, job.options
    out = {
        k: np.zeros((4, m), dtype=np.float64 if k in ("first_time", "min_dist") else dt) for k, dt in CHUNK_VARS.items()
    }
    for env in range(4):
        for j in range(m):
            b = runner.bound(job.l1, job.l2, w[row], w[j], opt.margin) if opt.early_stop else None
            ep = runner.run(job.l1, job.l2, w[row], w[j], env, bound=b)
            out["first_time"][env, j] = ep.first_time
            out["min_dist"][env, j] = ep.min_dist
            out["status"][env, j] = STATUS_OK if ep.finite else STATUS_NONFINITE
            out["steps"][env, j] = ep.steps
    return {k: out[k].astype(dt) for k, dt in CHUNK_VARS.items()}  # the stored dtypes, as DesignResult


def _identity() -> dict[str, Any]:
    # pybullet's entry is what it was before MuJoCo existed, so its folders keep their run keys
    return {"pybullet": provenance.library_versions(["pybullet"]).get("pybullet", "unknown")}


def _runner(params: EmpiricalParams) -> Any:
    from morphlearn.empirical.episode import EpisodeRunner  # loads pybullet

    return EpisodeRunner(params)


ENGINE = Engine(_identity, _runner, _row)
