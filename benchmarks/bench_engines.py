"""Episodes per core-second, pybullet vs MuJoCo vs ODE, on the same designs, weights and environments.

Both engines run every (design, env, w1, w2) cell of ``--designs`` designs of the
5-positions-per-axis grid (the canonical design first, then a fixed random sample) at
``--m`` x ``--m`` weights, the committed body, one process (one core: MuJoCo's batch on one
thread), episodes stopping at contact; once with full-length failures and once with the early
stop (exact). Rate = episodes / CPU seconds of this process. Then a profile of the MuJoCo run:
the share inside ``Batch.step`` (C) against the numpy controller, and MuJoCo's own stage timers
over one episode (what inside ``mj_step`` costs). ODE (:mod:`morphlearn.ode`) runs the same cells
with its own body, the authors' (``config/authors_body.yaml``; it has no reach bound: every
episode stops at success), and says how close an episode is to the cost of ``dWorldStep`` alone
(the C core's own timers, CPU time). Usage::

    python benchmarks/bench_engines.py [--designs 3] [--m 5] [--seed 0]
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
import time
from pathlib import Path

import numpy as np

from morphlearn.empirical import EpisodeRunner
from morphlearn.grid import DesignGrid, canonical_design, weights
from morphlearn.mujoco.episode import BatchRunner
from morphlearn.mujoco.model import LEFT, RIGHT
from morphlearn.physics.params import load_params

ROOT = Path(__file__).resolve().parents[1]


def cells(n_designs: int, m: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    g = DesignGrid(5)
    canon = g.index_of(*canonical_design())
    rng = np.random.default_rng(seed)
    others = rng.choice(np.setdiff1d(np.arange(g.size), [canon]), n_designs - 1, replace=False)
    designs = np.concatenate([[canon], others]).astype(int)
    w = weights(m)
    d, e, i, j = np.meshgrid(designs, np.arange(4), np.arange(m), np.arange(m), indexing="ij")
    c = g.coords(d.ravel())
    return c[:, :2], c[:, 2:], np.stack([w[i.ravel()], w[j.ravel()]], 1), e.ravel()


def bench_pybullet(params, l1, l2, w, env, margin):  # type: ignore[no-untyped-def]
    first = np.full(len(w), np.nan)
    t = time.process_time()
    with EpisodeRunner(params) as r:
        for k in range(len(w)):
            b = r.bound(tuple(l1[k]), tuple(l2[k]), w[k, 0], w[k, 1], margin) if margin else None
            first[k] = r.run(tuple(l1[k]), tuple(l2[k]), w[k, 0], w[k, 1], int(env[k]), bound=b).first_time
    return time.process_time() - t, first


def bench_mujoco(params, l1, l2, w, env, margin):  # type: ignore[no-untyped-def]
    runner = BatchRunner(params, nthread=1)
    t = time.process_time()
    ep = runner.run(l1, l2, w, env, margin=margin)
    return time.process_time() - t, ep.first_time, ep.steps


def bench_ode(l1, l2, w, env):  # type: ignore[no-untyped-def]
    from morphlearn.ode import core

    body = load_params(ROOT / "config/authors_body.yaml")
    t = time.process_time()
    ep, _ = core.run(body, l1, l2, w, env)
    spent = time.process_time() - t
    timing: dict[str, float] = {}
    core.run(body, l1, l2, w, env, timing=timing)  # again, timed inside C (clock reads add a little)
    return spent, ep, timing


def stage_timers(params) -> dict[str, float]:  # type: ignore[no-untyped-def]
    """MuJoCo's stage timers over one full-length canonical episode at w = (0.6, 0.2), env 45 deg."""
    import mujoco

    m = BatchRunner(params).model
    d = mujoco.MjData(m)
    light = np.array([4.0, 4.0])
    (x1, y1), (x2, y2) = canonical_design()
    for _ in range(params.steps):
        q = d.qpos
        xm = d.xmat[1].reshape(3, 3)
        dx, dy = q[0] - light[0], q[1] - light[1]
        e1 = (dx + xm[0, 0] * x1 + xm[0, 1] * y1, dy + xm[1, 0] * x1 + xm[1, 1] * y1)
        e2 = (dx + xm[0, 0] * x2 + xm[0, 1] * y2, dy + xm[1, 0] * x2 + xm[1, 1] * y2)
        d.ctrl[RIGHT] = np.tanh(0.6 / (e1[0] ** 2 + e1[1] ** 2)) * params.max_speed
        d.ctrl[LEFT] = np.tanh(0.2 / (e2[0] ** 2 + e2[1] ** 2)) * params.max_speed
        mujoco.mj_step(m, d)
    timer = mujoco.mjtTimer
    step = d.timer[timer.mjTIMER_STEP].duration
    out = {"us_per_mj_step": 1e6 * step / d.timer[timer.mjTIMER_STEP].number}
    for n in ["POSITION", "POS_COLLISION", "VELOCITY", "ACTUATION", "CONSTRAINT", "ADVANCE"]:
        out[n.lower()] = d.timer[getattr(timer, "mjTIMER_" + n)].duration / step
    # the acceleration stage (mass-matrix solve) and the step's checks have no timer of their own
    out["other"] = 1.0 - sum(v for k, v in out.items() if k not in ("us_per_mj_step", "pos_collision"))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, default=3)
    ap.add_argument("--m", type=int, default=5)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--params", type=Path, default=ROOT / "config/empirical_morphology.yaml")
    a = ap.parse_args()
    params = load_params(a.params)
    l1, l2, w, env = cells(a.designs, a.m, a.seed)
    n = len(w)
    print(f"{a.designs} designs x 4 envs x {a.m}x{a.m} weights = {n} episodes per engine per way; one core")
    for label, margin in (("to contact or horizon", None), ("early stop (margin 2)", 2.0)):
        t_pb, f_pb = bench_pybullet(params, l1, l2, w, env, margin)
        t_mj, f_mj, steps = bench_mujoco(params, l1, l2, w, env, margin)
        r_pb, r_mj = n / t_pb, n / t_mj
        agree = int((np.isnan(f_pb) == np.isnan(f_mj)).sum())
        print(
            f"{label}: pybullet {r_pb:.2f} episodes/core-s ({t_pb:.1f} s), MuJoCo {r_mj:.1f} episodes/core-s "
            f"({t_mj:.2f} s, {1e6 * t_mj / steps.sum():.2f} us per robot-step), ratio {r_mj / r_pb:.1f}x; "
            f"successes pybullet {int((~np.isnan(f_pb)).sum())}, MuJoCo {int((~np.isnan(f_mj)).sum())}, "
            f"same outcome in {agree}/{n} episodes"
        )
    t_ode, ep, timing = bench_ode(l1, l2, w, env)
    print(
        f"ODE (authors' body, to success or horizon): {n / t_ode:.1f} episodes/core-s ({t_ode:.1f} s, "
        f"{1e6 * t_ode / ep.steps.sum():.2f} us per step, {int(ep.steps.sum())} steps, {int(ep.success.sum())} "
        f"successes); dWorldStep alone {n / timing['world_step']:.1f} episodes/core-s "
        f"({100 * timing['world_step'] / t_ode:.0f} % of the run), "
        f"dSpaceCollide {100 * timing['collide'] / t_ode:.0f} %"
    )
    # Where the MuJoCo time goes.
    prof = cProfile.Profile()
    runner = BatchRunner(params, nthread=1)
    prof.enable()
    runner.run(l1, l2, w, env, margin=None)
    prof.disable()
    st = pstats.Stats(prof)
    total = sum(v[2] for v in st.stats.values())  # type: ignore[attr-defined]
    step = sum(v[2] for k, v in st.stats.items() if "_batch.step" in k[2] or k[2].endswith("step}"))  # type: ignore[attr-defined]
    print(
        f"MuJoCo profile: {100 * step / total:.0f} % of the run inside Batch.step (C: load state row, mj_step, "
        f"save row), {100 * (1 - step / total):.0f} % numpy controller and bookkeeping"
    )
    timers = stage_timers(params)
    parts = ", ".join(f"{k} {100 * v:.0f} %" for k, v in timers.items() if k != "us_per_mj_step")
    print(f"mj_step alone (one MjData, one robot, timers on): {timers['us_per_mj_step']:.2f} us; stages: {parts}")


if __name__ == "__main__":
    main()
