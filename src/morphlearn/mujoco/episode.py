"""Batched episodes of the MuJoCo model and the per-design sweep over (env, w1, w2).

Each episode is its own simulation of the one-robot model (:func:`.model.build_model`), and a
``mujoco.batch.Batch`` steps all of them in C (MuJoCo guarantees results bit-identical to a
loop over one ``MjData`` per simulation). So an episode cannot depend on which others share its
batch: there is no shared world, contact solver or broadphase (a many-robots-in-one-world model
would couple the robots through the constraint solver's common iteration count and line search).
The controller of every live episode is computed at once with numpy per step; Python does no
work per robot per step.

Controller, success and bookkeeping are those of :class:`morphlearn.empirical.episode.EpisodeRunner`,
in the same order per step: observe the pose at step ``k``; record the closest approach; the
first ``k`` with centre-to-light distance ``<= params.contact_distance`` gives the contact time
``k * dt`` (the episode stops there); stop at ``k == steps``; every ``CHECK_EVERY`` steps ask the
reach bound whether the light is still reachable; set the wheel targets
``tanh(w * s) * max_speed`` (sensor 1 -> right wheel with ``w1``, sensor 2 -> left wheel with
``w2``, ``s = 1 / d^2`` of the sensor point's horizontal distance to the light); step.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from morphlearn.grid import light_positions
from morphlearn.mujoco.model import LEFT, RIGHT, MujocoSettings, build_model
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import EmpiricalParams
from morphlearn.physics.reach import CHECK_EVERY, ReachBound, sensor_reach
from morphlearn.physics.sweep import sweep
from morphlearn.results import DesignResult

Point = tuple[float, float]
#: Episodes per ``Batch``: bounds the memory of a 121 x 121 sweep; results do not depend on it.
CHUNK = 4096


@dataclass(frozen=True)
class Episodes:
    """Outcomes of a batch of episodes, arrays of shape (n,), as :class:`empirical.episode.Episode`."""

    first_time: np.ndarray  # s, first contact (NaN if none)
    min_dist: np.ndarray  # closest centre-to-light distance up to contact, stop or horizon
    steps: np.ndarray  # physics steps simulated
    finite: np.ndarray  # False where the state became NaN/inf (stopped there)
    hopeless_step: np.ndarray  # first checked step the reach bound said "out of reach" (-1: never)
    max_tilt: np.ndarray  # rad
    max_lift: np.ndarray  # m, largest |z - wheel_radius| of the body centre

    @property
    def success(self) -> np.ndarray:
        return ~np.isnan(self.first_time)

    @classmethod
    def joined(cls, parts: list[Episodes]) -> Episodes:
        """The outcomes of consecutive batches as one."""
        if len(parts) == 1:
            return parts[0]
        return cls(*(np.concatenate([getattr(q, f) for q in parts]) for f in cls.__dataclass_fields__))


def lower_times(b: ReachBound, d: np.ndarray, u: np.ndarray) -> np.ndarray:
    """:meth:`ReachBound.lower_time` for arrays of distances ``d`` and speeds ``u`` (same floats:
    the same operations in the same order; tests/test_mujoco.py compares them)."""
    n = len(b.speed)
    mu = b.margin * np.abs(u)
    far = d > b.c
    i = np.where(far, (d - b.c) / b.STEP, 0.0).astype(np.int64)
    beyond = i >= n
    below = _below(b, np.minimum(i, n - 1), mu)
    last = b.c + b.STEP * (n - 1)
    ext = (d - last) / np.maximum(np.maximum(mu, float(b.speed[-1])), 1e-300)
    return np.where(far, np.where(beyond, below + ext, below), 0.0)


def _below(b: ReachBound, i: np.ndarray, mu: np.ndarray) -> np.ndarray:
    t_i = b.time[i]
    with np.errstate(divide="ignore", invalid="ignore"):
        fast = i * b.STEP / mu
        # first index with speed < mu, in the prefix [0, i] (speed is non-increasing)
        j = np.minimum(np.searchsorted(-b.speed, -mu, side="right"), i + 1)
        mid = b.time[np.minimum(j, len(b.time) - 1)] + (i - j) * b.STEP / mu
    return np.where(mu <= 0.0, t_i, np.where(mu >= b.speed[0], fast, np.where(j > i, t_i, mid)))


def batch_inputs(w: Any, env: Any, path: list[np.ndarray] | None) -> tuple[np.ndarray, np.ndarray]:
    """A batch's weights (n, 2) and environments (n,), checked (both robots' runners)."""
    w = np.atleast_2d(np.asarray(w, dtype=np.float64))
    n = len(w)
    env = np.broadcast_to(np.asarray(env, dtype=np.int64), (n,))
    if w.shape != (n, 2) or np.any((env < 0) | (env > 3)):
        raise ValueError(f"weights must be (n, 2) and env in 0..3; got {w.shape}, env {np.unique(env)}")
    if path is not None and n > CHUNK:
        raise ValueError(f"path records at most CHUNK = {CHUNK} episodes at once; got {n}")
    return w, env


class BatchRunner:
    """Runs batches of episodes of one body (params + settings) on ``nthread`` threads."""

    def __init__(
        self, params: EmpiricalParams | None = None, settings: MujocoSettings | None = None, nthread: int = 1
    ) -> None:
        self.params = params or EmpiricalParams()
        self.settings = settings or MujocoSettings()
        self.nthread = int(nthread)
        self.model = build_model(self.params, self.settings)
        self.lights = light_positions(self.params.light_distance)
        self._bounds: dict[tuple[float, float, float], ReachBound] = {}

    def bound(self, w_max: float, rho: float, margin: float) -> ReachBound:
        key = (float(w_max), float(rho), float(margin))
        b = self._bounds.get(key)
        if b is None:
            b = self._bounds[key] = ReachBound(self.params, *key)
        return b

    def run(
        self,
        l1: Any,
        l2: Any,
        w: Any,
        env: Any,
        *,
        margin: float | None = None,
        stop_at_contact: bool = True,
        stop_hopeless: bool = True,
        path: list[np.ndarray] | None = None,
    ) -> Episodes:
        """Episodes of designs ``l1``, ``l2`` ((n, 2) or one (2,) point for all), weights ``w``
        (n, 2) and environments ``env`` (n,). With ``margin`` the reach bound is checked every
        ``CHECK_EVERY`` steps (``stop_hopeless``: stop at the first "out of reach"). With ``path``
        (a list; at most ``CHUNK`` episodes), an (n, 2) array of the body centres (x, y) observed
        at each step is appended to it per step, NaN for episodes already stopped (for drawing;
        the episodes are unchanged)."""
        w, env = batch_inputs(w, env, path)
        n = len(w)
        l1 = np.broadcast_to(np.asarray(l1, dtype=np.float64), (n, 2))
        l2 = np.broadcast_to(np.asarray(l2, dtype=np.float64), (n, 2))
        parts = [
            self._run(
                l1[a : a + CHUNK],
                l2[a : a + CHUNK],
                w[a : a + CHUNK],
                env[a : a + CHUNK],
                margin,
                stop_at_contact,
                stop_hopeless,
                path,
            )
            for a in range(0, n, CHUNK)
        ]
        return Episodes.joined(parts)

    def _run(
        self,
        l1: np.ndarray,
        l2: np.ndarray,
        w: np.ndarray,
        env: np.ndarray,
        margin: float | None,
        stop_at_contact: bool,
        stop_hopeless: bool,
        path: list[np.ndarray] | None = None,
    ) -> Episodes:
        from mujoco import batch as mjbatch

        p = self.params
        n = len(w)
        first = np.full(n, np.nan)
        min_d2 = np.full(n, np.inf)
        steps = np.zeros(n, np.int64)
        finite = np.ones(n, bool)
        hopeless = np.full(n, -1, np.int64)
        tilt_c = np.ones(n)
        lift = np.zeros(n)
        if n == 0:
            return Episodes(first, np.sqrt(min_d2), steps, finite, hopeless, tilt_c, lift)
        b = mjbatch.Batch(self.model, n, self.nthread)
        b.reset()
        qpos, qvel, ctrl = b.bind("qpos"), b.bind("qvel"), b.bind("ctrl")
        lx, ly = self.lights[env, 0], self.lights[env, 1]
        x1, y1, x2, y2 = l1[:, 0], l1[:, 1], l2[:, 0], l2[:, 1]
        w1, w2 = w[:, 0], w[:, 1]
        c2, z0, vmax, dt = p.contact_distance**2, p.wheel_radius, p.max_speed, p.dt
        group = np.zeros(n, np.int64)
        bounds: list[ReachBound] = []
        if margin is not None:
            rho = [sensor_reach(tuple(a), tuple(c)) for a, c in zip(l1, l2, strict=True)]
            keys = np.stack([np.maximum(np.abs(w1), np.abs(w2)), np.array(rho)], 1)
            uniq, group = np.unique(keys, axis=0, return_inverse=True)
            group = group.reshape(-1)
            bounds = [self.bound(wm, rho, margin) for wm, rho in uniq]
        act = np.arange(n)
        k = 0
        while act.size:
            q = qpos[act]
            ok = np.isfinite(q).all(axis=1)
            if not ok.all():
                finite[act[~ok]] = False
                steps[act[~ok]] = k
                act, q = act[ok], q[ok]
            if path is not None:
                xy = np.full((n, 2), np.nan)
                xy[act] = q[:, :2]
                path.append(xy)
            px, py, pz = q[:, 0], q[:, 1], q[:, 2]
            qw, qx, qy, qz = q[:, 3], q[:, 4], q[:, 5], q[:, 6]
            dx, dy = px - lx[act], py - ly[act]
            d2 = dx * dx + dy * dy
            min_d2[act] = np.minimum(min_d2[act], d2)
            tilt_c[act] = np.minimum(tilt_c[act], 1.0 - 2.0 * (qx * qx + qy * qy))
            lift[act] = np.maximum(lift[act], np.abs(pz - z0))
            hit = (d2 <= c2) & np.isnan(first[act])
            first[act[hit]] = k * dt
            keep = ~hit if stop_at_contact else np.ones(act.size, bool)
            if k == p.steps:
                steps[act] = k
                break
            if bounds and k % CHECK_EVERY == 0:
                ask = keep & (hopeless[act] < 0)
                if ask.any():
                    d = np.sqrt(d2)
                    u = np.hypot(qvel[act, 0], qvel[act, 1])
                    g = group[act]
                    gone = np.zeros(act.size, bool)
                    for gi in np.unique(g[ask]):
                        sel = ask & (g == gi)
                        gone[sel] = lower_times(bounds[gi], d[sel], u[sel]) > (p.steps - k) * dt
                    hopeless[act[gone]] = k
                    if stop_hopeless:
                        keep &= ~gone
            if not keep.all():
                steps[act[~keep]] = k
                act = act[keep]
                dx, dy, qw, qx, qy, qz = dx[keep], dy[keep], qw[keep], qx[keep], qy[keep], qz[keep]
                if not act.size:
                    break
            # Body x and y axes on the floor: rotation-matrix columns from the quaternion.
            ax, ay = 1.0 - 2.0 * (qy * qy + qz * qz), 2.0 * (qx * qy + qz * qw)
            bx, by = 2.0 * (qx * qy - qz * qw), 1.0 - 2.0 * (qx * qx + qz * qz)
            a1, b1, a2, b2 = x1[act], y1[act], x2[act], y2[act]
            e1x, e1y = dx + ax * a1 + bx * b1, dy + ay * a1 + by * b1
            e2x, e2y = dx + ax * a2 + bx * b2, dy + ay * a2 + by * b2
            s1 = 1.0 / (e1x * e1x + e1y * e1y)
            s2 = 1.0 / (e2x * e2x + e2y * e2y)
            ctrl[act, RIGHT] = np.tanh(w1[act] * s1) * vmax
            ctrl[act, LEFT] = np.tanh(w2[act] * s2) * vmax
            b.step(act)
            k += 1
        max_tilt = np.arccos(np.clip(tilt_c, -1.0, 1.0))
        return Episodes(first, np.sqrt(min_d2), steps, finite, hopeless, max_tilt, lift)


def evaluate_design(
    l1: Point,
    l2: Point,
    weights: np.ndarray,
    params: EmpiricalParams | None = None,
    progress: Callable[[int, int], None] | None = None,
    options: SweepOptions | None = None,
    *,
    settings: MujocoSettings | None = None,
    runner: BatchRunner | None = None,
) -> DesignResult:
    """All (env, w1, w2) episodes of one design in MuJoCo; arrays (4, m, m) [env, i_w1, i_w2].

    The signature and result of :func:`morphlearn.empirical.episode.evaluate_design`, with the
    same levers: ``options.early_stop`` (the reach bound, margin ``options.margin``) and
    ``options.adaptive_weights`` (the physics layer's sweep, :mod:`morphlearn.physics.sweep`; unsimulated
    cells get ``STATUS_INFERRED`` and NaN). ``progress(done, total)`` is called per batch.
    """
    options = options or SweepOptions()
    runner = runner or BatchRunner(params, settings)
    if params is not None and runner.params != params:
        raise ValueError("runner was built for other params than the ones passed")
    margin = options.margin if options.early_stop else None

    def batch(w: np.ndarray, env: np.ndarray) -> Episodes:
        return runner.run(l1, l2, w, env, margin=margin)

    # a whole wave per batch (one call per wave; outcomes do not depend on the batch)
    return sweep(batch, l1, l2, weights, runner.params, options, progress)
