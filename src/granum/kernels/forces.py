"""Stages that set forces or impose motion: ForceResetter, GravityEngine, ForceEngine and the kinematic
engines (TranslationEngine, RotationEngine, HelixEngine, their combinations).

Each writes only the rows of its own bodies, in parallel over blocks of bodies.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from granum._jit import BLOCK, PARALLEL_THRESHOLD, jit, kernel, prange
from granum.core.arrays import E_GRAV_WORK, S_DT, SI_NBODIES, SI_TRACK_ENERGY
from granum.core.records import raw
from granum.kernels.schedule import block_queue, next_block, queue_workers
from granum.physics.vec import load3, quat_from_rotvec, quat_rotate, scale, sub


@jit
def reset_block(b, S, nb):
    """Forces and torques of the bodies of block ``b`` back to the permanent ones (``perm_force`` and
    ``perm_torque`` are lazy columns: 0 rows until a script sets one). The columns are read into locals
    once: ``S`` is a raw view, and a store could otherwise make the loop reload them from the record."""
    force, torque, perm_force, perm_torque = S.force, S.torque, S.perm_force, S.perm_torque
    perm_f = perm_force.shape[0] > 0
    perm_t = perm_torque.shape[0] > 0
    for i in range(b * BLOCK, min(nb, (b + 1) * BLOCK)):
        for k in range(3):
            force[i, k] = perm_force[i, k] if perm_f else 0.0
            torque[i, k] = perm_torque[i, k] if perm_t else 0.0


def _reset(S, nb):
    queue = block_queue((nb + BLOCK - 1) // BLOCK)
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            reset_block(b, S, nb)
            b = next_block(queue, w, b)


reset, reset_par = kernel(_reset)


@jit
def reset_stage(S, C, P):
    """ForceResetter: forces and torques back to their permanent values."""
    nb = S.iscal[SI_NBODIES]
    if nb < PARALLEL_THRESHOLD:  # through a raw view: no reference counting per body (granum.core.records)
        reset(raw(S), nb)
    else:
        reset_par(raw(S), nb)


class GravityParams(NamedTuple):
    """Parameters of :func:`gravity_stage` (GravityEngine)."""

    gravity: np.ndarray  #: gravitational acceleration [m/s^2], (3,) float64
    mask: int            #: only bodies sharing a bit with this mask (0: all)


@jit
def gravity_stage(S, C, P):
    """GravityEngine: F += m g on bodies whose mask matches; ``P``: :class:`GravityParams`."""
    gravity, mask = P.gravity, P.mask
    nb = S.iscal[SI_NBODIES]
    dt = S.scal[S_DT]
    # columns read once: a field read from the record counts a reference, and a store would reload it
    alive, body_mask, mass, vel, force = S.alive, S.mask, S.mass, S.vel, S.force
    work = 0.0
    for i in range(nb):
        if alive[i] and (mask == 0 or body_mask[i] & mask) and mass[i] > 0.0:
            for k in range(3):
                force[i, k] += mass[i] * gravity[k]
                work -= mass[i] * gravity[k] * vel[i, k] * dt
    if S.iscal[SI_TRACK_ENERGY]:
        S.energy[E_GRAV_WORK] += work
        S.energy_set[E_GRAV_WORK] = 1


class ForceParams(NamedTuple):
    """Parameters of :func:`force_stage` (ForceEngine)."""

    ids: np.ndarray    #: the bodies, (n,) int64
    force: np.ndarray  #: force added to each [N], (3,) float64


@jit
def force_stage(S, C, P):
    """ForceEngine: F += force on the listed bodies; ``P``: :class:`ForceParams`."""
    force = P.force
    for i in P.ids:
        for k in range(3):
            S.force[i, k] += force[k]


#: columns of a part row of :func:`kinematic_stage`: velocity (3) [m/s], unit axis (3), angular speed [rad/s],
#: point of the axis (3) [m], 1.0 if the bodies orbit the axis
K_VEL, K_AXIS, K_SPEED, K_ZERO, K_ORBIT, K_COLS = 0, 3, 6, 7, 10, 11


class KinematicParams(NamedTuple):
    """Parameters of :func:`kinematic_stage`."""

    ids: np.ndarray     #: the bodies, (n,) int64
    parts: np.ndarray   #: one row per part, in order, (K, K_COLS) float64
    turned: np.ndarray  #: angle each part turned so far [rad], (K,) float64; the stage adds to it


@jit
def kinematic_stage(S, C, P):
    """Kinematic engines (YADE's KinematicEngine: TranslationEngine, RotationEngine, HelixEngine and their
    combinations): the velocity and angular velocity of the listed bodies are reset, then each part adds its
    own motion, in order.

    ``P``: :class:`KinematicParams`. Part k adds to every listed body
    vel += velocity_k, angVel += speed_k axis_k and, if it orbits, the chord of the circle about the axis
    through zero_k, vel += (R(speed_k dt, axis_k)(x - zero_k) + zero_k - x) / dt, which puts the body on
    the circle after the step; turned[k] += speed_k dt [rad] (HelixEngine.angleTurned).
    """
    ids, parts, turned = P.ids, P.parts, P.turned
    dt = S.scal[S_DT]
    vel, ang_vel, pos = S.vel, S.ang_vel, S.pos  # read once: a store could make the loop reload them
    for i in ids:
        for j in range(3):
            vel[i, j] = 0.0
            ang_vel[i, j] = 0.0
    for k in range(parts.shape[0]):
        speed = parts[k, K_SPEED]
        axis = (parts[k, K_AXIS], parts[k, K_AXIS + 1], parts[k, K_AXIS + 2])
        zero = (parts[k, K_ZERO], parts[k, K_ZERO + 1], parts[k, K_ZERO + 2])
        q = quat_from_rotvec(scale(axis, speed * dt))
        orbit = parts[k, K_ORBIT] != 0.0
        for i in ids:
            for j in range(3):
                vel[i, j] += parts[k, K_VEL + j]
                ang_vel[i, j] += speed * axis[j]
            if orbit:
                r = sub(load3(pos, i), zero)
                chord = sub(quat_rotate(q, r), r)
                for j in range(3):
                    vel[i, j] += chord[j] / dt
        turned[k] += speed * dt
