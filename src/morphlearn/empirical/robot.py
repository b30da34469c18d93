"""Build the pybullet world: floor, the two-wheeled square robot, and one light.

Frame: +x forward, +y left, z up; the robot starts at the origin facing +x (as in
:mod:`morphlearn.grid`). The robot is one ``createMultiBody`` (no URDF, no data files):

- base: box ``1 x 1 x wheel_radius/2`` centred at ``z = wheel_radius``;
- links 0/1: left/right sphere wheels of radius ``wheel_radius`` on hinges about +y, centred
  midway along the sides (``y = +-0.5``, so the track is 1 as in the theory model) and set back
  ``wheel_setback`` from the body centre (exactly at the centre the motor reaction tips the
  body back ~24 deg); a positive joint velocity rolls the robot forward;
- link 2: a frictionless castor sphere of radius ``wheel_radius/2`` fixed at the front centre,
  touching the floor.

Links of one multibody do not collide with each other (pybullet's default), so the wheel
spheres may overlap the box. Sensors are points on the body and are not simulated.
The light is a static sphere; only one is in the world, moved per environment, because a
robot must not bump into the other environments' lights.
"""

from __future__ import annotations

from dataclasses import dataclass

import pybullet as pb

from morphlearn.physics.params import BODY_SIZE, EmpiricalParams

LEFT_WHEEL, RIGHT_WHEEL, CASTOR = 0, 1, 2


@dataclass
class World:
    """Handles of one DIRECT-mode pybullet client holding a floor, a robot and a light."""

    client: int
    robot: int
    light: int
    params: EmpiricalParams

    def close(self) -> None:
        if pb.isConnected(self.client):
            pb.disconnect(self.client)


def configure(client: int, params: EmpiricalParams) -> None:
    """Engine settings measured to make episodes deterministic and mirror-symmetric."""
    pb.setGravity(0, 0, -params.gravity, physicsClientId=client)
    pb.setPhysicsEngineParameter(
        fixedTimeStep=params.dt,
        numSolverIterations=params.solver_iterations,
        # Sorted overlapping pairs: without it, results depend on what else is in the world.
        deterministicOverlappingPairs=1,
        numSubSteps=0,
        physicsClientId=client,
    )


def add_floor(client: int, params: EmpiricalParams) -> int:
    shape = pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=client)
    floor = pb.createMultiBody(0, shape, physicsClientId=client)
    pb.changeDynamics(floor, -1, lateralFriction=1.0, physicsClientId=client)
    return floor


def add_robot(client: int, params: EmpiricalParams, origin: tuple[float, float] = (0.0, 0.0)) -> int:
    """Create the robot at ``origin`` (x, y) facing +x; returns its body id."""
    c = client
    r = params.wheel_radius
    half = 0.5 * BODY_SIZE
    body = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[half, half, r / 4], physicsClientId=c)
    wheel = pb.createCollisionShape(pb.GEOM_SPHERE, radius=r, physicsClientId=c)
    castor = pb.createCollisionShape(pb.GEOM_SPHERE, radius=r / 2, physicsClientId=c)
    sb = params.wheel_setback
    robot = pb.createMultiBody(
        baseMass=params.body_mass,
        baseCollisionShapeIndex=body,
        basePosition=[origin[0], origin[1], r],
        linkMasses=[params.wheel_mass, params.wheel_mass, params.castor_mass],
        linkCollisionShapeIndices=[wheel, wheel, castor],
        linkVisualShapeIndices=[-1, -1, -1],
        linkPositions=[[-sb, half, 0.0], [-sb, -half, 0.0], [half, 0.0, -r / 2]],
        linkOrientations=[[0, 0, 0, 1]] * 3,
        linkInertialFramePositions=[[0, 0, 0]] * 3,
        linkInertialFrameOrientations=[[0, 0, 0, 1]] * 3,
        linkParentIndices=[0, 0, 0],
        linkJointTypes=[pb.JOINT_REVOLUTE, pb.JOINT_REVOLUTE, pb.JOINT_FIXED],
        linkJointAxis=[[0, 1, 0], [0, 1, 0], [0, 0, 1]],
        physicsClientId=c,
    )
    pb.changeDynamics(robot, -1, activationState=pb.ACTIVATION_STATE_DISABLE_SLEEPING, physicsClientId=c)
    for link in (LEFT_WHEEL, RIGHT_WHEEL):
        pb.changeDynamics(robot, link, lateralFriction=params.wheel_friction, physicsClientId=c)
        # Start with the motors holding still (pybullet's default motor force is not ours).
        pb.setJointMotorControl2(
            robot,
            link,
            pb.VELOCITY_CONTROL,
            targetVelocity=0.0,
            force=params.max_torque,
            physicsClientId=c,
        )
    pb.changeDynamics(
        robot,
        CASTOR,
        lateralFriction=0.0,
        rollingFriction=0.0,
        spinningFriction=0.0,
        physicsClientId=c,
    )
    return robot


def add_light(client: int, params: EmpiricalParams, xy: tuple[float, float]) -> int:
    """A static sphere resting on the floor at ``xy``."""
    shape = pb.createCollisionShape(pb.GEOM_SPHERE, radius=params.light_radius, physicsClientId=client)
    return pb.createMultiBody(0, shape, basePosition=[xy[0], xy[1], params.light_radius], physicsClientId=client)


def populate(client: int, params: EmpiricalParams, light_xy: tuple[float, float]) -> World:
    """Configure an empty client and add floor, robot (at the origin) and light."""
    configure(client, params)
    add_floor(client, params)
    robot = add_robot(client, params)
    light = add_light(client, params, light_xy)
    return World(client, robot, light, params)


def build_world(params: EmpiricalParams, light_xy: tuple[float, float]) -> World:
    """A fresh DIRECT client with floor, robot at the origin and the light at ``light_xy``."""
    return populate(pb.connect(pb.DIRECT), params, light_xy)


def rebuild(world: World, light_xy: tuple[float, float]) -> World:
    """Empty ``world``'s client (``resetSimulation``) and populate it again: same ids.

    ``restoreState`` of a snapshot is not enough for bit-for-bit repeatability: it restores
    bodies but keeps the contact manifolds (with their warm-start impulses) of the previous
    episode, so an episode that ended near the start point changed the next one's outcome
    (measured: contact at 122.60 s instead of 118.45 s). Rebuilding costs ~3.5 ms.
    """
    pb.resetSimulation(physicsClientId=world.client)
    new = populate(world.client, world.params, light_xy)
    if (new.robot, new.light) != (world.robot, world.light):  # pragma: no cover - pybullet
        raise RuntimeError("pybullet gave new body ids after resetSimulation")
    return new
