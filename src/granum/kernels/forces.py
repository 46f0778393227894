"""Stages that set forces or impose motion: ForceResetter, GravityEngine, ForceEngine,
TranslationEngine and RotationEngine.

Each writes only the rows of its own bodies, in parallel over blocks of bodies.
"""

from __future__ import annotations

from granum._jit import BLOCK, PARALLEL_THRESHOLD, jit, kernel, prange
from granum.core.arrays import E_GRAV_WORK, I_NBODIES, I_TRACK_ENERGY, S_DT
from granum.core.records import raw
from granum.kernels.schedule import block_queue, next_block, queue_workers
from granum.physics.vec import cross, load3, sub


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
    nb = S.iscal[I_NBODIES]
    if nb < PARALLEL_THRESHOLD:  # through a raw view: no reference counting per body (granum.core.records)
        reset(raw(S), nb)
    else:
        reset_par(raw(S), nb)


@jit
def gravity_stage(S, C, P):
    """GravityEngine: F += m g on bodies whose mask matches; P = (gravity (3,), mask)."""
    gravity, mask = P
    nb = S.iscal[I_NBODIES]
    dt = S.scal[S_DT]
    # columns read once: a field read from the record counts a reference, and a store would reload it
    alive, body_mask, mass, vel, force = S.alive, S.mask, S.mass, S.vel, S.force
    work = 0.0
    for i in range(nb):
        if alive[i] and (mask == 0 or body_mask[i] & mask) and mass[i] > 0.0:
            for k in range(3):
                force[i, k] += mass[i] * gravity[k]
                work -= mass[i] * gravity[k] * vel[i, k] * dt
    if S.iscal[I_TRACK_ENERGY]:
        S.energy[E_GRAV_WORK] += work
        S.energy_set[E_GRAV_WORK] = 1


@jit
def force_stage(S, C, P):
    """ForceEngine: F += force on the listed bodies; P = (ids, force (3,))."""
    ids, force = P
    for i in ids:
        for k in range(3):
            S.force[i, k] += force[k]


@jit
def translation_stage(S, C, P):
    """TranslationEngine: v = velocity * axis on the listed bodies; P = (ids, velocity (3,))."""
    ids, velocity = P
    for i in ids:
        for k in range(3):
            S.vel[i, k] = velocity[k]


@jit
def rotation_stage(S, C, P):
    """RotationEngine: spin about an axis, optionally about a point.

    P = (ids, angular velocity vector (3,), rotate_around_zero, zero point (3,)):
    omega = angularVelocity * axis; with ``rotateAroundZero`` also
    v = omega x (x - zeroPoint), so the bodies orbit the axis through zeroPoint.
    """
    ids, omega, around, zero = P
    w = (omega[0], omega[1], omega[2])
    z = (zero[0], zero[1], zero[2])
    for i in ids:
        for k in range(3):
            S.ang_vel[i, k] = w[k]
        if around:
            v = cross(w, sub(load3(S.pos, i), z))
            for k in range(3):
                S.vel[i, k] = v[k]
