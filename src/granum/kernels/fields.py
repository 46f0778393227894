"""Stages of the force fields and body-wise engines: InterpolatingDirectedForceEngine, StepDisplacer, DragEngine
and LinearDragEngine, AxialGravityEngine, CentralConstantAccelerationEngine.

Each loops serially over its bodies in id order (the listed ones, or all those its mask selects), so that
results do not depend on the number of threads. Formulas and the facts measured on YADE 2023.02a
(tests/reference/yade/engines_extra.py) are in each stage's docstring.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from granum._jit import jit
from granum.core.arrays import S_DT, S_TIME, SI_NBODIES
from granum.core.shapes import ShapeKind
from granum.kernels.kinematic import interpolate
from granum.physics.vec import load4, quat_angle, quat_mul, quat_normalized

_SPHERE = int(ShapeKind.SPHERE)


class InterpolatedForceParams(NamedTuple):
    """Parameters of :func:`interpolated_force_stage`."""

    ids: np.ndarray        #: the bodies, (n,) int64
    table: np.ndarray      #: rows (time [s], force magnitude [N]), (T, 2) float64
    direction: np.ndarray  #: unit direction of the force, (3,) float64
    wrap: bool             #: the time goes round the table
    force: np.ndarray      #: the force of the last step [N], (3,) float64; written by the stage (engine.force)


@jit
def interpolated_force_stage(S, C, P):
    """InterpolatingDirectedForceEngine: force = direction * magnitude(t), the magnitude interpolated linearly
    in the table at the time t of the start of the step (the first before the first time, the last after the
    last; with ``wrap`` t goes round by whole periods tn - t0); F += force on the listed bodies."""
    mag = interpolate(P.table, 0, P.table.shape[0], S.scal[S_TIME], P.wrap)
    force = S.force
    for k in range(3):
        P.force[k] = mag * P.direction[k]
    for i in P.ids:
        for k in range(3):
            force[i, k] += P.force[k]


class StepDisplacerParams(NamedTuple):
    """Parameters of :func:`step_displacer_stage`."""

    ids: np.ndarray         #: the bodies, (n,) int64
    move: np.ndarray        #: displacement per step [m], (3,) float64
    rotation: np.ndarray    #: unit rotation quaternion per step (w, x, y, z), (4,) float64
    set_velocities: bool    #: impose the velocities that make these steps instead of moving the bodies


@jit
def step_displacer_stage(S, C, P):
    """StepDisplacer: each step pos += mov and ori = rot * ori (normalised); with ``setVelocities``, instead
    vel = mov / dt and angVel = (angle axis of rot) / dt, which NewtonIntegrator turns into the same step
    (YADE 2023.02a; velocities are left alone otherwise)."""
    dt = S.scal[S_DT]
    move, rot = P.move, (P.rotation[0], P.rotation[1], P.rotation[2], P.rotation[3])
    pos, ori, vel, ang_vel = S.pos, S.ori, S.vel, S.ang_vel
    # the rotation vector (angle in [0, pi] times the axis) of rot, whose w may be negative
    sin_half = math.sqrt(max(0.0, 1.0 - rot[0] * rot[0]))
    per_sin = (quat_angle(rot) / sin_half if sin_half > 0.0 else 0.0) * (1.0 if rot[0] >= 0.0 else -1.0)
    for i in P.ids:
        if P.set_velocities:
            for k in range(3):
                vel[i, k] = move[k] / dt
                ang_vel[i, k] = rot[k + 1] * per_sin / dt
        else:
            q = quat_normalized(quat_mul(rot, load4(ori, i)))
            for k in range(3):
                pos[i, k] += move[k]
            for k in range(4):
                ori[i, k] = q[k]


class DragParams(NamedTuple):
    """Parameters of :func:`drag_stage`."""

    ids: np.ndarray    #: the bodies, (n,) int64
    quadratic: float   #: rho Cd / 2 [kg/m^3] (DragEngine; 0 for LinearDragEngine)
    linear: float      #: 6 pi nu [Pa s] (LinearDragEngine; 0 for DragEngine)


@jit
def drag_stage(S, C, P):
    """DragEngine and LinearDragEngine on the listed spheres (other shapes are skipped, as in YADE):
    F -= (rho Cd / 2 |v| pi r^2 + 6 pi nu r) v, v the velocity at the start of the step, r the radius
    (the quadratic drag of a disc's projected area, and Stokes' drag with the Stokes radius r)."""
    vel, force, kind, row, radius = S.vel, S.force, S.shape_kind, S.shape_row, S.sphere_radius
    for i in P.ids:
        if kind[i] != _SPHERE:
            continue
        r = radius[row[i]]
        speed = math.sqrt(vel[i, 0] ** 2 + vel[i, 1] ** 2 + vel[i, 2] ** 2)
        b = P.quadratic * speed * math.pi * r * r + P.linear * r
        for k in range(3):
            force[i, k] -= b * vel[i, k]


class AxialGravityParams(NamedTuple):
    """Parameters of :func:`axial_gravity_stage`."""

    point: np.ndarray   #: a point of the axis [m], (3,) float64
    axis: np.ndarray    #: unit direction of the axis, (3,) float64
    acceleration: float  #: magnitude of the acceleration towards the axis [m/s^2]
    mask: int           #: only bodies sharing a bit with this mask (0: all)


@jit
def axial_gravity_stage(S, C, P):
    """AxialGravityEngine: F += m a (towards the axis) on every body the mask selects: -a m d/|d|, d the
    body's offset from the axis perpendicular to it; nothing on a body on the axis."""
    nb = S.iscal[SI_NBODIES]
    alive, body_mask, mass, pos, force = S.alive, S.mask, S.mass, S.pos, S.force
    for i in range(nb):
        if not alive[i] or not (P.mask == 0 or body_mask[i] & P.mask):
            continue
        d = np.zeros(3)
        along = 0.0
        for k in range(3):
            d[k] = pos[i, k] - P.point[k]
            along += d[k] * P.axis[k]
        dist = 0.0
        for k in range(3):
            d[k] -= along * P.axis[k]
            dist += d[k] * d[k]
        dist = math.sqrt(dist)
        if dist == 0.0:
            continue
        for k in range(3):
            force[i, k] -= P.acceleration * mass[i] * d[k] / dist


class CentralAccelerationParams(NamedTuple):
    """Parameters of :func:`central_acceleration_stage`."""

    central: int        #: id of the central body
    accel: float        #: magnitude of the acceleration towards it [m/s^2]
    reciprocal: bool    #: the central body gets the opposite forces
    mask: int           #: only bodies sharing a bit with this mask (0: all)


@jit
def central_acceleration_stage(S, C, P):
    """CentralConstantAccelerationEngine: F += m accel u on every other body the mask selects, u the unit
    vector from it to the central body (whatever the distance); with ``reciprocal`` the central body gets
    -m accel u of each of them (YADE 2023.02a: each body's own mass, so the forces balance)."""
    nb = S.iscal[SI_NBODIES]
    c = P.central
    alive, body_mask, mass, pos, force = S.alive, S.mask, S.mass, S.pos, S.force
    for i in range(nb):
        if i == c or not alive[i] or not (P.mask == 0 or body_mask[i] & P.mask):
            continue
        dist = math.sqrt((pos[c, 0] - pos[i, 0]) ** 2 + (pos[c, 1] - pos[i, 1]) ** 2 + (pos[c, 2] - pos[i, 2]) ** 2)
        if dist == 0.0:
            continue
        for k in range(3):
            f = mass[i] * P.accel * (pos[c, k] - pos[i, k]) / dist
            force[i, k] += f
            if P.reciprocal:
                force[c, k] -= f
