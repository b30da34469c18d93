"""The paper authors' robot in pybullet (docs/authors_robot.md).

The robot of :mod:`morphlearn.ode` (docs/ode.md), built as closely as pybullet allows, to the
spec of the MuJoCo build (``morphlearn.mujoco.authors``); shared facts in
:mod:`morphlearn.physics.authors`, body parameters from the body file
(``config/authors_body.yaml``). Project frame: the robot starts at the origin facing +x, +y left.

- bodies as ODE's, one ``createMultiBody`` (no URDF, no files): the base is the chassis box
  ``1 x 1 x WR/2`` at ``z = WR``; links, in ODE's creation order: the left and right wheels
  (spheres of radius ``WR``) at ``(-setback, +-0.5, WR)`` on revolute joints about +y (a positive
  rate rolls the robot forward), the two sensor spheres (radius 0.05, mass 1) on fixed joints at
  ``(x_i, y_i, 2 WR + 0.05)`` (so the body is built per design), and the castor, a sphere as large
  as a wheel at ``(0.5, 0, WR)`` on a revolute joint about y whose default velocity motor is
  switched off (force 0): it rolls freely, as ODE's motorless hinge. Inertias are pybullet's from
  the shapes (box ``m (b^2 + c^2) / 12``, sphere ``2/5 m r^2``: ODE's ``dMassSet*Total``). The
  multibody is reduced-coordinate (Featherstone), so its joints are exact where ODE's are
  constraint rows; its links do not collide with each other (ODE: jointed bodies never collide).
  Linear, angular and joint damping are set to 0 (btMultiBody's default damping is not 0; ODE has
  none); sleeping is off;
- engine: DIRECT client, gravity ``-gravity``, ``fixedTimeStep = dt``, no substeps, ``steps``
  steps; ``numSolverIterations`` is the body file's ``solver_iterations`` (100, the value that
  made the project's pybullet episodes converged and mirror-symmetric; ODE's ``dWorldStep`` solves
  exactly, pybullet's sequential-impulse solver iterates); ``deterministicOverlappingPairs`` on;
  contact ERP, split impulse and restitution at pybullet's defaults (as ODE's ERP/CFM are ODE's);
- the wheel motors: ODE's hinge motor (target rate ``max_speed tanh(w s)``, force limit
  ``max_torque``) is pybullet's ``VELOCITY_CONTROL`` (``targetVelocity``, ``force = max_torque``),
  a velocity constraint row with impulse bounded by ``max_torque dt``: the same law as ODE's, but
  solved by iteration beside the contacts instead of in one LCP (pybullet's velocity gain is 1:
  an unbounded motor reaches its target in one step, checked in the tests);
- contacts: ODE's have mu = infinity and force-dependent slip 0.01 (the tangential slip velocity
  is 0.01 m/s per N), a viscous law pybullet lacks (its friction is Coulomb). So every floor
  contact is frictionless (lateral, rolling and spinning friction 0 on the floor and every link;
  pybullet multiplies the two frictions, so the floor's 0 alone would do) and the slip law is
  applied as external forces each step, from the state before the step: ``F = -v_t / SLIP`` at
  each wheel's lowest point (``v_t``: that point's horizontal velocity, the wheel centre's velocity
  plus ``omega x (0, 0, -WR)``) and, at the castor's lowest point, only along its axle projected
  on the floor (its rolling direction carries ~no force in ODE: spinning the 7 g castor up takes
  ~1e-4 N); each only while the sphere touches the floor, ``centre z - WR <= 0``, ODE's test for
  a sphere-plane contact (pybullet rests the spheres ~1e-5 into the floor, so a resting wheel
  counts; ``getContactPoints`` would also count pybullet's speculative contacts up to its
  margin above the floor, which ODE does not have). The forces go to ``applyExternalForce`` in
  ``WORLD_FRAME`` at the contact point (pybullet clears them after each step, so they are set
  every step). Explicit, where ODE's is implicit: stable here, the slip's rate ``dt / (SLIP m)``
  is at most ~0.1 for the lightest mass it moves (a wheel's rim, ~47 kg). The box's and the
  sensors' floor contacts (only if the robot tips) are frictionless with no slip force, as
  MuJoCo's;
- the light is not a body: every part of the robot that collides with it reaches at most
  :func:`~morphlearn.physics.authors.reach` from the chassis centre, so touching it comes after
  the success test (within ``success_radius`` of its centre), where the episode stops;
- sensors read ``1 / |p_sensor - p_light|^2`` in 3D from the sphere centres (the light's centre at
  ``(light xy, LIGHT_Z)``); sensor 1 drives the right wheel with ``w1``, sensor 2 the left with
  ``w2``; success and ``min_dist`` as ODE's (2D, chassis centre read before each step ``0 ..
  steps - 1``, success at the first step within ``success_radius``: contact distance + 2^-10).

Each episode empties the runner's one client (``resetSimulation``) and builds its world again, as
ODE builds a world per episode: resetting bodies in place would keep the previous episode's
contact manifolds and their warm-start impulses, so an outcome would depend on the episode before
it (:func:`morphlearn.empirical.robot.rebuild`). Outcomes do not depend on the batch or its order
(tested). The link states are read with ``computeForwardKinematics``: without it pybullet returns
its cached link transforms, which lag the state after a step (measured ~1e-7 m; it moved first
times by up to ~1 s).

Against ODE at 11 x 11 weights, all four environments (2026-11-26; no constant tuned): the
canonical design ``(0.5, 0.5), (0.5, -0.5)`` has the same outcome in 484 of 484 cells (32
successes each, first times within 1.25 s, median 0.05 s), the paper's best design ``(-0.5,
0.125), (0.5, -0.375)`` 484 of 484 (14 each, within 0.15 s). Cost: ~29 us of CPU per step, 0.07 s
per episode on the canonical 11 x 11 (most run all 2500 steps), one core of the project's 2-core
VM; the step loop is Python calling pybullet (pybullet's ``stepSimulation`` alone is ~19 us).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pybullet as pb

from morphlearn.grid import light_positions
from morphlearn.physics import authors as robot
from morphlearn.physics.options import SweepOptions
from morphlearn.physics.params import BODY_SIZE, EmpiricalParams
from morphlearn.physics.sweep import sweep, without_reach_bound
from morphlearn.results import DesignResult

Point = tuple[float, float]
#: Link indices, in ODE's creation order (the base, -1, is the chassis).
LEFT, RIGHT, SENSOR1, SENSOR2, CASTOR = 0, 1, 2, 3, 4
#: Episodes per batch call of :func:`evaluate_design` (progress between calls; results do not depend on it).
CHUNK = 64


@dataclass(frozen=True)
class AuthorsEpisodes:
    """Outcomes of a batch, arrays of shape (n,): what :func:`morphlearn.physics.sweep.sweep`'s
    batch function returns."""

    first_time: np.ndarray  # s, first success (NaN: none)
    min_dist: np.ndarray  # closest 2D chassis-to-light distance up to success (or the horizon)
    steps: np.ndarray  # steps simulated
    finite: np.ndarray  # False where the state became NaN/inf (stopped there)

    @property
    def success(self) -> np.ndarray:
        return ~np.isnan(self.first_time)


def _point(name: str, v: Any) -> Point:
    a = np.asarray(v, dtype=np.float64)
    if a.shape != (2,) or not np.isfinite(a).all() or np.abs(a).max() > 0.5 * BODY_SIZE:
        raise ValueError(f"{name} = {np.asarray(v).tolist()!r} is off the body; allowed: finite x, y in [-0.5, 0.5]")
    return float(a[0]), float(a[1])


def check_batch(w: Any, env: Any) -> tuple[np.ndarray, np.ndarray]:
    """Weights (n, 2) finite in [-1, 1] and environments (n,) in 0..3, or a one-line ValueError."""
    w = np.atleast_2d(np.asarray(w, dtype=np.float64))
    n = len(w)
    if w.ndim != 2 or w.shape != (n, 2):
        raise ValueError(f"weights must have shape (n, 2); got {w.shape}")
    if not np.isfinite(w).all() or np.abs(w).max(initial=0.0) > 1.0:
        bad = w[~(np.isfinite(w) & (np.abs(w) <= 1.0))][0]
        raise ValueError(f"weight {float(bad)!r} is invalid; allowed: finite values in [-1, 1]")
    e = np.asarray(env)
    if e.ndim > 1 or (e.ndim == 1 and len(e) != n):
        raise ValueError(f"env must be one value or have shape ({n},); got {e.shape}")
    if e.size and not np.issubdtype(e.dtype, np.integer):
        raise ValueError(f"env must be integers 0..3; got dtype {e.dtype}")
    e = np.broadcast_to(e.astype(np.int64), (n,))
    if np.any((e < 0) | (e > 3)):
        raise ValueError(f"env {sorted(set(e.tolist()) - {0, 1, 2, 3})} invalid; allowed: 0..3")
    return w, e


class AuthorsEpisodeRunner:
    """Episodes of the authors' robot in one DIRECT pybullet client (use as a context manager or
    call :meth:`close`); each episode builds its world afresh in it."""

    def __init__(self, params: EmpiricalParams) -> None:
        self.params = params
        self.lights = light_positions(params.light_distance)
        self._client: int | None = None

    @property
    def client(self) -> int:
        if self._client is None or not pb.isConnected(self._client):
            self._client = pb.connect(pb.DIRECT)
        return self._client

    def close(self) -> None:
        if self._client is not None and pb.isConnected(self._client):
            pb.disconnect(self._client)
        self._client = None

    def __enter__(self) -> AuthorsEpisodeRunner:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __del__(self) -> None:  # pragma: no cover - best effort at interpreter exit
        try:
            self.close()
        except Exception:
            pass

    def build(self, l1: Point, l2: Point) -> int:
        """Empty the client and build the world of design ``(l1, l2)``: floor and robot. Returns
        the robot's body id."""
        c, p = self.client, self.params
        r = p.wheel_radius
        pb.resetSimulation(physicsClientId=c)
        pb.setGravity(0, 0, -p.gravity, physicsClientId=c)
        pb.setPhysicsEngineParameter(
            fixedTimeStep=p.dt,
            numSolverIterations=p.solver_iterations,
            numSubSteps=0,
            deterministicOverlappingPairs=1,
            physicsClientId=c,
        )
        floor = pb.createMultiBody(0, pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=c), physicsClientId=c)
        half = 0.5 * BODY_SIZE
        box = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[half, half, r / 4], physicsClientId=c)
        wheel = pb.createCollisionShape(pb.GEOM_SPHERE, radius=r, physicsClientId=c)
        sensor = pb.createCollisionShape(pb.GEOM_SPHERE, radius=robot.SENSOR_RADIUS, physicsClientId=c)
        zs = robot.sensor_height(p) - r  # sensor centres relative to the chassis centre
        y, x = robot.WHEEL_Y, -p.wheel_setback
        body = pb.createMultiBody(
            baseMass=p.body_mass,
            baseCollisionShapeIndex=box,
            basePosition=[0.0, 0.0, r],
            linkMasses=[p.wheel_mass, p.wheel_mass, robot.SENSOR_MASS, robot.SENSOR_MASS, p.castor_mass],
            linkCollisionShapeIndices=[wheel, wheel, sensor, sensor, wheel],
            linkVisualShapeIndices=[-1] * 5,
            linkPositions=[
                [x, y, 0.0],
                [x, -y, 0.0],
                [l1[0], l1[1], zs],
                [l2[0], l2[1], zs],
                [robot.CASTOR_X, 0.0, 0.0],
            ],
            linkOrientations=[[0, 0, 0, 1]] * 5,
            linkInertialFramePositions=[[0, 0, 0]] * 5,
            linkInertialFrameOrientations=[[0, 0, 0, 1]] * 5,
            linkParentIndices=[0] * 5,
            linkJointTypes=[pb.JOINT_REVOLUTE, pb.JOINT_REVOLUTE, pb.JOINT_FIXED, pb.JOINT_FIXED, pb.JOINT_REVOLUTE],
            linkJointAxis=[[0, 1, 0]] * 5,
            physicsClientId=c,
        )
        none = {"lateralFriction": 0.0, "rollingFriction": 0.0, "spinningFriction": 0.0, "restitution": 0.0}
        pb.changeDynamics(floor, -1, **none, physicsClientId=c)
        pb.changeDynamics(
            body,
            -1,
            **none,
            linearDamping=0.0,
            angularDamping=0.0,
            activationState=pb.ACTIVATION_STATE_DISABLE_SLEEPING,
            physicsClientId=c,
        )
        for link in range(5):
            pb.changeDynamics(body, link, **none, jointDamping=0.0, physicsClientId=c)
        # the castor rolls freely: pybullet's default velocity motor off
        pb.setJointMotorControl2(body, CASTOR, pb.VELOCITY_CONTROL, targetVelocity=0.0, force=0.0, physicsClientId=c)
        return body

    def run(self, l1: Any, l2: Any, w: Any, env: Any) -> AuthorsEpisodes:
        """Episodes of one design (``l1``, ``l2``: points, project frame), weights ``w`` (n, 2) in
        [-1, 1], environments ``env`` (n,) in 0..3, in that order."""
        p1, p2 = _point("l1", l1), _point("l2", l2)
        w, env = check_batch(w, env)
        n = len(w)
        first = np.full(n, np.nan)
        dmin = np.full(n, np.inf)
        steps = np.zeros(n, np.int64)
        finite = np.ones(n, bool)
        for i in range(n):
            first[i], dmin[i], steps[i], finite[i] = self.episode(p1, p2, float(w[i, 0]), float(w[i, 1]), int(env[i]))
        return AuthorsEpisodes(first, dmin, steps, finite)

    def episode(self, l1: Point, l2: Point, w1: float, w2: float, env: int) -> tuple[float, float, int, bool]:
        """One episode: (first success time or NaN, min_dist, steps simulated, finite)."""
        p = self.params
        body = self.build(l1, l2)
        c = self.client
        lx, ly = float(self.lights[env][0]), float(self.lights[env][1])
        lz = robot.LIGHT_Z
        r, vmax, tau, dt, radius = p.wheel_radius, p.max_speed, p.max_torque, p.dt, robot.success_radius(p)
        k_slip = 1.0 / robot.SLIP
        zs = robot.sensor_height(p) - r
        (x1, y1), (x2, y2) = l1, l2
        get_pose, get_links, step = pb.getBasePositionAndOrientation, pb.getLinkStates, pb.stepSimulation
        control, push, vel, world = (
            pb.setJointMotorControlArray,
            pb.applyExternalForce,
            pb.VELOCITY_CONTROL,
            pb.WORLD_FRAME,
        )
        motors, forces, links = [RIGHT, LEFT], [tau, tau], [LEFT, RIGHT, CASTOR]
        best, first, ok, k = math.inf, math.nan, True, 0
        for k in range(p.steps):
            (px, py, pz), (qx, qy, qz, qw) = get_pose(body, physicsClientId=c)
            if not math.isfinite(px + py + pz + qx + qy + qz + qw):
                ok = False
                break
            dx, dy = px - lx, py - ly
            d = math.sqrt(dx * dx + dy * dy)
            best = min(best, d)
            if d <= radius:
                first = k * dt
                break
            # rotation matrix columns: body x (a), y (b), z (e) in the world
            ax, ay, az = 1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy + qz * qw), 2 * (qx * qz - qy * qw)
            bx, by, bz = 2 * (qx * qy - qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz + qx * qw)
            ex, ey, ez = 2 * (qx * qz + qy * qw), 2 * (qy * qz - qx * qw), 1 - 2 * (qx * qx + qy * qy)
            # sensors: 3D from the sphere centres (chassis frame (x_i, y_i, zs)) to the light's centre
            dz, hx, hy, hz = pz - lz, ex * zs, ey * zs, ez * zs
            sx, sy, sz = dx + ax * x1 + bx * y1 + hx, dy + ay * x1 + by * y1 + hy, dz + az * x1 + bz * y1 + hz
            s1 = 1.0 / (sx * sx + sy * sy + sz * sz)
            sx, sy, sz = dx + ax * x2 + bx * y2 + hx, dy + ay * x2 + by * y2 + hy, dz + az * x2 + bz * y2 + hz
            s2 = 1.0 / (sx * sx + sy * sy + sz * sz)
            control(
                body,
                motors,
                vel,
                targetVelocities=[vmax * math.tanh(w1 * s1), vmax * math.tanh(w2 * s2)],
                forces=forces,
                physicsClientId=c,
            )
            # the slip law at the wheels' and the castor's floor contacts (module docstring)
            # computeForwardKinematics: without it the link poses (and the velocities' lever arms)
            # lag the state by pybullet's cached transforms (measured: ~1e-7 m, outcomes change)
            states = get_links(body, links, computeLinkVelocity=1, computeForwardKinematics=1, physicsClientId=c)
            for link, state in zip(links, states, strict=True):
                (cx, cy, cz), (vx, vy, _), (wx, wy, _) = state[0], state[6], state[7]
                if cz - r > 0.0:
                    continue
                tx, ty = vx - r * wy, vy + r * wx  # v + omega x (0, 0, -r), horizontal
                if link == CASTOR:  # along its axle (body y) on the floor only
                    h = math.hypot(bx, by)
                    ux, uy = bx / h, by / h
                    t = tx * ux + ty * uy
                    tx, ty = t * ux, t * uy
                push(body, link, (-k_slip * tx, -k_slip * ty, 0.0), (cx, cy, cz - r), world, physicsClientId=c)
            step(physicsClientId=c)
        else:
            k = p.steps
        return first, best, k, ok


def evaluate_design(
    l1: Point,
    l2: Point,
    weights: np.ndarray,
    params: EmpiricalParams,
    progress: Callable[[int, int], None] | None = None,
    options: SweepOptions | None = None,
    partial: Path | None = None,
) -> DesignResult:
    """All (env, w1, w2) episodes of one design; arrays (4, m, m) [env, i_w1, i_w2]: the physics
    layer's sweep (:func:`morphlearn.physics.sweep.sweep`: adaptive grid, resume from ``partial``)
    over this runner's batches."""
    options = without_reach_bound(options, "for the authors' robot")
    p1, p2 = _point("l1", l1), _point("l2", l2)
    with AuthorsEpisodeRunner(params) as runner:
        return sweep(
            lambda w, env: runner.run(p1, p2, w, env), p1, p2, weights, params, options, progress, partial, chunk=CHUNK
        )
