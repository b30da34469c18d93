"""The authors' robot reduced to the motions that decide an episode: the constants of its step.

Derived from the ODE set-up (docs/ode.md, :mod:`morphlearn.physics.authors`, the body file), not
fitted to any outcome. The robot is one rigid planar assembly (the chassis box, the two sphere
wheels, the castor sphere and the two sensor spheres, at their ODE positions and masses) with
three spinning parts (the wheels about their axle, the castor about its free hinge), on a floor
it touches at the three spheres' lowest points. What ODE does and what this keeps:

- Contacts: mu = infinity with force-dependent slip 0.01 in both tangential directions, i.e. each
  contact point's tangential velocity after the step is -0.01 x the tangential force: a linear
  damper of 1 / 0.01 = 100 N s/m, implicit in the step exactly as ODE's constraint-force mixing
  makes it. Normal forces never limit friction (mu is infinite), so they do not enter.
- Motors: a velocity target max_speed tanh(w s) on the wheel's rate relative to the chassis,
  torque capped at max_torque, with ODE's default constraint-force mixing (1e-5) on the motor row;
  solved exactly with the dampers, as dWorldStep's LCP solves them.
- Masses and inertias: ODE's (dMassSetBoxTotal, dMassSetSphereTotal): the box's yaw inertia
  m (1 + 1) / 12, each sphere 2/5 m r^2 about any axis; the assembly's yaw inertia about the
  chassis centre and its first moment (the centre of mass is off the chassis centre: wheels set
  back, sensors where the design puts them) from them.
- Step: semi-implicit Euler with dt as dWorldStep (new velocities, then positions with them; the
  heading turned as ODE turns a quaternion).

Approximations (named; each is measured against ODE cell by cell, docs/reduced.md):

1. Planar: the chassis neither pitches, rolls nor sinks (ODE's normal contacts and joints hold it
   level to ~1e-3 under its weight; the sensors' height above the light is taken as built).
2. Rigid joints: the axles and the sensors' welds are exact (ODE's joints give way by about
   1e-5 x their force and are pulled back by ERP = 0.2 each step).
3. The light is never touched before success (contact starts at the success radius or beyond:
   success is the contact distance plus 2^-10), so it is not a body here.
4. Gyroscopic terms vanish (every spinning part is a sphere; the box turns about z only).
"""

# ruff: noqa: N803, N806 (M, S, J, A, G, K: the matrices by their names in the step equations)
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from morphlearn.physics import authors
from morphlearn.physics.params import EmpiricalParams

#: ODE's default constraint-force mixing (dWorldSetCFM), on the motor rows.
ODE_CFM = 1e-5


@dataclass(frozen=True)
class Body:
    """The constant matrices of one design's step (row-major, float64; kernel.py reads them)."""

    g: np.ndarray  # (36,) G = A^-1 M: momentum to velocities with the dampers implicit
    hm: np.ndarray  # (12,) dt A^-1 J_m^T: velocities per unit motor torque (left, right)
    #: (8,) K = dt J_m A^-1 J_m^T + cfm I (k00, k01, k11), K^-1 (i00, i01, i11), 1 / k00, 1 / k11
    kk: np.ndarray
    cen: np.ndarray  # (6,) dt A^-1 (S_x, S_y, 0...): velocities per unit om^2 (centripetal)
    dz2: float  # squared height of the sensors' centres above the light's


def masses(
    p: EmpiricalParams, l1: tuple[float, float], l2: tuple[float, float]
) -> list[tuple[float, float, float, float]]:
    """Every part of the assembly as (mass, x, y, own yaw inertia), project frame, about its centre."""
    r = p.wheel_radius
    sphere = 2.0 / 5.0
    return [
        (p.body_mass, 0.0, 0.0, p.body_mass * (1.0 + 1.0) / 12.0),
        (p.wheel_mass, -p.wheel_setback, authors.WHEEL_Y, sphere * p.wheel_mass * r * r),
        (p.wheel_mass, -p.wheel_setback, -authors.WHEEL_Y, sphere * p.wheel_mass * r * r),
        (p.castor_mass, authors.CASTOR_X, 0.0, sphere * p.castor_mass * r * r),
        (authors.SENSOR_MASS, l1[0], l1[1], sphere * authors.SENSOR_MASS * authors.SENSOR_RADIUS**2),
        (authors.SENSOR_MASS, l2[0], l2[1], sphere * authors.SENSOR_MASS * authors.SENSOR_RADIUS**2),
    ]


def mass_matrix(p: EmpiricalParams, l1: tuple[float, float], l2: tuple[float, float]) -> tuple[np.ndarray, np.ndarray]:
    """M over q = (u, v, om, spin_left, spin_right, spin_castor) (u, v: the chassis centre's velocity
    in the body frame) and the first moment S = sum m (x, y) about the chassis centre."""
    parts = masses(p, l1, l2)
    m = sum(pt[0] for pt in parts)
    sx = sum(pt[0] * pt[1] for pt in parts)
    sy = sum(pt[0] * pt[2] for pt in parts)
    inertia = sum(pt[3] + pt[0] * (pt[1] ** 2 + pt[2] ** 2) for pt in parts)
    r = p.wheel_radius
    M = np.zeros((6, 6))
    M[0, 0] = M[1, 1] = m
    M[0, 2] = M[2, 0] = -sy
    M[1, 2] = M[2, 1] = sx
    M[2, 2] = inertia
    # a sphere spinning about a horizontal axle while the body yaws: no cross term (isotropic)
    M[3, 3] = M[4, 4] = 2.0 / 5.0 * p.wheel_mass * r * r
    M[5, 5] = 2.0 / 5.0 * p.castor_mass * r * r
    return M, np.array([sx, sy])


def contact_jacobian(p: EmpiricalParams) -> np.ndarray:
    """(6, 6): the tangential velocities (x, y) of the three floor contacts (left wheel, right wheel,
    castor) from q. A spin about the axle (+y, the wheels' hinge axis) moves the lowest point by
    -r spin along x."""
    r = p.wheel_radius
    contacts = [
        (-p.wheel_setback, authors.WHEEL_Y, 3),
        (-p.wheel_setback, -authors.WHEEL_Y, 4),
        (authors.CASTOR_X, 0.0, 5),
    ]
    J = np.zeros((6, 6))
    for k, (x, y, spin) in enumerate(contacts):
        J[2 * k, 0], J[2 * k, 2], J[2 * k, spin] = 1.0, -y, -r
        J[2 * k + 1, 1], J[2 * k + 1, 2] = 1.0, x
    return J


def body(p: EmpiricalParams, l1: tuple[float, float], l2: tuple[float, float]) -> Body:
    """The step's constants for sensors at ``l1``, ``l2`` (project frame)."""
    M, S = mass_matrix(p, l1, l2)
    J = contact_jacobian(p)
    # M (q_new - q) = dt (J^T f + centripetal + J_m^T lam), f = -(1/slip) J q_new: the dampers implicit
    damping = p.dt / authors.SLIP * J.T @ J
    return constants(p.dt, M, S, damping, authors.sensor_height(p) - authors.LIGHT_Z)


def constants(dt: float, M: np.ndarray, S: np.ndarray, damping: np.ndarray, dz: float) -> Body:
    """The step's constants from the mass matrix ``M``, the first moment ``S``, the dampers' implicit
    term ``damping`` (dt J^T C J) and the sensors' height above the light ``dz``: one derivation for
    the model (:func:`body`) and for variants of it (benchmarks/ablate_reduced.py)."""
    Ainv = np.linalg.inv(M + damping)
    G = Ainv @ M
    Hm = dt * Ainv[:, 3:5]
    K = dt * Ainv[3:5, 3:5] + ODE_CFM * np.eye(2)
    cen = dt * Ainv[:, 0:2] @ S
    k3 = (K[0, 0], 0.5 * (K[0, 1] + K[1, 0]), K[1, 1])
    inverse = np.linalg.inv(np.array([[k3[0], k3[1]], [k3[1], k3[2]]]))
    return Body(
        g=np.ascontiguousarray(G.ravel()),
        hm=np.ascontiguousarray(Hm.ravel()),
        kk=np.array([*k3, *(inverse[0, 0], inverse[0, 1], inverse[1, 1]), 1.0 / k3[0], 1.0 / k3[2]]),
        cen=np.ascontiguousarray(cen),
        dz2=float(dz * dz),
    )
