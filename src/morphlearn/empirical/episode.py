"""Episodes of the empirical model and the per-design sweep over (env, w1, w2).

Controller (Braitenberg, contralateral): ``s_i = 1 / d_i^2`` with ``d_i`` the horizontal
distance of sensor ``i`` to the light centre; sensor 1 drives the RIGHT wheel with ``w1``,
sensor 2 the LEFT wheel with ``w2``; ``motor = tanh(w * s)``; wheel target velocity
``motor * max_speed`` under velocity control with force ``max_torque``.
Success: the body centre comes within ``0.5 + wheel_radius + light_radius`` (horizontal) of
the light centre, i.e. the robot touches it; the first such step ``k`` gives time ``k * dt``.

One pybullet client is reused for all episodes; each episode empties and rebuilds its world
(``resetSimulation``, ~3.5 ms) because ``restoreState`` keeps the previous episode's contact
manifolds and so is not repeatable bit for bit (see :func:`robot.rebuild`). Episodes are
bit-for-bit identical to ones in a fresh client (tested).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pybullet as pb

from morphlearn.empirical.robot import LEFT_WHEEL, RIGHT_WHEEL, World, build_world, rebuild
from morphlearn.grid import light_positions
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import EmpiricalParams
from morphlearn.physics.reach import CHECK_EVERY, ReachBound, sensor_reach
from morphlearn.physics.sweep import sweep
from morphlearn.results import DesignResult

Point = tuple[float, float]


@dataclass(frozen=True)
class Episode:
    """Outcome of one episode."""

    first_time: float  # s, first contact with the light (NaN if none)
    min_dist: float  # min horizontal centre-to-light distance (up to contact or horizon)
    steps: int  # physics steps simulated
    max_tilt: float  # rad, largest angle between body up-axis and world z
    max_lift: float  # m, largest |z - wheel_radius| of the body centre (0 = resting)
    finite: bool  # False if the state became NaN/inf (episode stopped there)
    #: First checked step at which the reach bound said the light is out of reach (-1: never or
    #: not checked). With ``stop_hopeless`` the episode stopped there (``steps`` equals it).
    hopeless_step: int = -1

    @property
    def success(self) -> bool:
        return not math.isnan(self.first_time)


class EpisodeRunner:
    """Runs episodes in one reusable DIRECT-mode client. Use as a context manager.

    ``reuse=False`` connects a new client per episode (the reference for determinism tests).
    """

    def __init__(self, params: EmpiricalParams | None = None, *, reuse: bool = True) -> None:
        self.params = params or EmpiricalParams()
        self.reuse = reuse
        self.lights = light_positions(self.params.light_distance)
        self._world: World | None = None
        self._bounds: dict[tuple[float, float, float], ReachBound] = {}

    def _ready(self, env: int) -> World:
        light = (float(self.lights[env][0]), float(self.lights[env][1]))
        if self._world is not None and self.reuse:
            self._world = rebuild(self._world, light)
        else:
            self.close()
            self._world = build_world(self.params, light)
        return self._world

    def close(self) -> None:
        if self._world is not None:
            self._world.close()
            self._world = None

    def __enter__(self) -> EpisodeRunner:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def bound(self, l1: Point, l2: Point, w1: float, w2: float, margin: float) -> ReachBound:
        """The reach bound of an episode (tables cached per weight magnitude and design)."""
        key = (max(abs(float(w1)), abs(float(w2))), sensor_reach(l1, l2), margin)
        b = self._bounds.get(key)
        if b is None:
            b = self._bounds[key] = ReachBound(self.params, *key)
        return b

    def run(
        self,
        l1: Point,
        l2: Point,
        w1: float,
        w2: float,
        env: int,
        *,
        stop_at_contact: bool = True,
        bound: ReachBound | None = None,
        stop_hopeless: bool = True,
        path: list[tuple[float, float]] | None = None,
    ) -> Episode:
        """One episode of design ``(l1, l2)`` with weights ``(w1, w2)`` in environment ``env``.

        With ``bound``, every ``CHECK_EVERY`` steps the episode asks it whether the light is still
        reachable in the time left; ``stop_hopeless`` stops it at the first "no" (else the step is
        only recorded, to validate the bound against full episodes). With ``path`` (a list), the
        body centre (x, y) observed at every step ``0..steps`` is appended to it (for drawing;
        the episode is unchanged).
        """
        p = self.params
        world = self._ready(env)
        c, robot = world.client, world.robot
        lx, ly = float(self.lights[env][0]), float(self.lights[env][1])
        x1, y1 = float(l1[0]), float(l1[1])
        x2, y2 = float(l2[0]), float(l2[1])
        w1, w2 = float(w1), float(w2)
        z0, vmax, tau = p.wheel_radius, p.max_speed, p.max_torque
        contact2 = p.contact_distance**2
        forces = [tau, tau]
        joints = [RIGHT_WHEEL, LEFT_WHEEL]
        get_pose, step = pb.getBasePositionAndOrientation, pb.stepSimulation
        control, vel = pb.setJointMotorControlArray, pb.VELOCITY_CONTROL

        min_d2 = math.inf
        first = math.nan
        max_tilt_c = 1.0  # cos of the largest tilt, from the quaternion: 1 - 2 (qx^2 + qy^2)
        max_lift = 0.0
        finite = True
        hopeless = -1
        every = CHECK_EVERY if bound is not None else 0
        get_vel = pb.getBaseVelocity
        k = 0
        while True:
            (px, py, pz), (qx, qy, qz, qw) = get_pose(robot, physicsClientId=c)
            if not math.isfinite(px + py + pz + qx + qy + qz + qw):
                finite = False
                break
            if path is not None:
                path.append((px, py))
            dx, dy = px - lx, py - ly
            d2 = dx * dx + dy * dy
            min_d2 = min(min_d2, d2)
            max_tilt_c = min(max_tilt_c, 1.0 - 2.0 * (qx * qx + qy * qy))
            max_lift = max(max_lift, abs(pz - z0))
            if d2 <= contact2 and math.isnan(first):
                first = k * p.dt
                if stop_at_contact:
                    break
            if k == p.steps:
                break
            if every and k % every == 0 and hopeless < 0:
                (vx, vy, _), _ = get_vel(robot, physicsClientId=c)
                if bound.hopeless(math.sqrt(d2), math.hypot(vx, vy), (p.steps - k) * p.dt):
                    hopeless = k
                    if stop_hopeless:
                        break
            # Body x and y axes on the floor: rotation-matrix columns from the quaternion.
            ax, ay = 1.0 - 2.0 * (qy * qy + qz * qz), 2.0 * (qx * qy + qz * qw)
            bx, by = 2.0 * (qx * qy - qz * qw), 1.0 - 2.0 * (qx * qx + qz * qz)
            e1x, e1y = dx + ax * x1 + bx * y1, dy + ay * x1 + by * y1
            e2x, e2y = dx + ax * x2 + bx * y2, dy + ay * x2 + by * y2
            s1 = 1.0 / (e1x * e1x + e1y * e1y)
            s2 = 1.0 / (e2x * e2x + e2y * e2y)
            control(
                robot,
                joints,
                vel,
                targetVelocities=[math.tanh(w1 * s1) * vmax, math.tanh(w2 * s2) * vmax],
                forces=forces,
                physicsClientId=c,
            )
            step(physicsClientId=c)
            k += 1
        return Episode(
            first_time=first,
            min_dist=math.sqrt(min_d2),
            steps=k,
            max_tilt=math.acos(max(-1.0, min(1.0, max_tilt_c))),
            max_lift=max_lift,
            finite=finite,
            hopeless_step=hopeless,
        )


def evaluate_design(
    l1: Point,
    l2: Point,
    weights: np.ndarray,
    params: EmpiricalParams | None = None,
    progress: Callable[[int, int], None] | None = None,
    options: SweepOptions | None = None,
    partial: Path | None = None,
) -> DesignResult:
    """All (env, w1, w2) episodes of one design; arrays (4, m, m) indexed [env, i_w1, i_w2]: the
    physics layer's sweep (:func:`morphlearn.physics.sweep.sweep`: adaptive grid, resume from
    ``partial``, progress) over this runner's episodes, one per batch call (``progress`` and the
    partial file's checkpoints after each episode, as an episode is ~0.1-1 s of one core)."""
    options = options or SweepOptions()
    with EpisodeRunner(params) as runner:

        def batch(w: np.ndarray, env: np.ndarray) -> SimpleNamespace:
            eps = []
            for (w1, w2), e in zip(w.tolist(), env.tolist(), strict=True):
                b = runner.bound(l1, l2, w1, w2, options.margin) if options.early_stop else None
                eps.append(runner.run(l1, l2, w1, w2, e, bound=b))
            return SimpleNamespace(
                first_time=np.array([ep.first_time for ep in eps]),
                min_dist=np.array([ep.min_dist for ep in eps]),
                finite=np.array([ep.finite for ep in eps], bool),
            )

        return sweep(batch, l1, l2, weights, runner.params, options, progress, partial, chunk=1)
