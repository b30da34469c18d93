"""A second empirical model: the same robot in MuJoCo, batched (``mujoco`` package, CPU).

- :mod:`.model`: the MJCF, generated from :class:`~morphlearn.physics.params.EmpiricalParams`
  (the pybullet model's parameters, ``config/empirical_morphology.yaml``) plus
  :class:`~.model.MujocoSettings` for what exists only in MuJoCo;
- :mod:`.episode`: batched episodes (:class:`~.episode.BatchRunner`) and
  :func:`~.episode.evaluate_design`, a drop-in for :func:`morphlearn.empirical.episode.evaluate_design`;
- :mod:`.mjwarp` (optional, ``mujoco.backend: warp``): the same episodes on MuJoCo Warp, one world
  per episode on a GPU (:class:`~.mjwarp.WarpBatchRunner`); imported only when asked for.

The same as the pybullet model (:mod:`morphlearn.empirical.robot`, :mod:`morphlearn.empirical.episode`):
body 1 x 1 x wheel_radius/2 at z = wheel_radius, masses, sphere wheels at the sides set back
``wheel_setback``, frictionless castor sphere, wheel radius, gravity, dt, 2500 steps, the lights at
r = 4*sqrt(2) at 45/135/225/315 deg, sensors 1/d^2 at the sensor points, motor = tanh(w s) with
the same wiring, wheel target = motor * max_speed with the torque limit max_torque, success =
centre-to-light distance <= ``params.contact_distance``, the early-stop reach bound
(:mod:`morphlearn.physics.reach`) and the adaptive weight grid (:mod:`morphlearn.physics.refine`).

Where the engines cannot be the same, and what this model chose:

- **Velocity motor.** pybullet: a hard constraint row driving the joint to the target velocity,
  its impulse limited by max_torque * dt, solved with the contacts. MuJoCo has no such row: a
  ``velocity`` actuator gives ``kv (target - qvel)`` clamped to +-max_torque (forcerange; ctrlrange
  +-max_speed), integrated implicitly (``implicitfast``) while unclamped. ``kv`` = 100 (a time
  constant of about one step); stiffer gains make the wheels chatter between the torque limits at
  dt = 0.05 (measured: mirror-image episodes then differ), softer ones lag the target.
- **Contact softness.** pybullet's contacts are (nearly) rigid, the body rests at z = wheel_radius
  (max lift 1e-4 m with the committed body). MuJoCo's are soft: default solref/solimp, and
  ``refsafe`` raises the time constant to 2 * dt = 0.1 s, so the body rests ~5 mm into the floor
  and sinks ~2.5 cm on the first step from its start at z = wheel_radius.
- **Solver and friction.** pybullet: sequential impulses, 100 iterations, friction as two
  independent directions each limited by mu N (a square). MuJoCo: Newton, up to 100 iterations,
  tolerance 1e-8, pyramidal cone (MuJoCo's default). Friction coefficients are pybullet's products
  (wheel_friction * floor 1.0; box 0.5 * 1.0); the castor contact has condim 1 (frictionless). No
  rolling or torsional friction in either. ``params.solver_iterations`` is pybullet's and unused here.
- **The light is not a body.** In pybullet it is a static sphere the robot could bump into; every
  episode ends at centre distance contact_distance = 0.5 + wheel_radius + light_radius, before any
  part of the body can reach the light except a wheel rim approaching exactly sideways (by < 1 mm).
  Here each episode has its own simulation and the light is a point in numpy.
- **Batching.** One simulation per episode (``mujoco.batch.Batch``, bit-identical to a loop over
  one MjData each), not many robots in one world: MuJoCo's constraint solver couples all the
  constraints of a world (one iteration count, one line search), so in a shared world an episode
  could depend on its neighbours. Results do not depend on the batch size or composition (tested).
"""

from __future__ import annotations

from morphlearn.mujoco.model import MujocoSettings, build_model, mjcf

__all__ = ["BatchRunner", "Episodes", "MujocoSettings", "build_model", "evaluate_design", "mjcf"]


def __getattr__(name: str) -> object:
    if name in {"BatchRunner", "Episodes", "evaluate_design"}:
        from morphlearn.mujoco import episode

        return getattr(episode, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
