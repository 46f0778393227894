"""Stages that set forces: ForceResetter, GravityEngine, ForceEngine and TorqueEngine (the kinematic engines'
stage is in :mod:`granum.kernels.kinematic`, the other force fields' in :mod:`granum.kernels.fields`).

ForceResetter writes only the rows of its own bodies, in parallel over blocks of bodies.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from granum._jit import BLOCK, PARALLEL_THRESHOLD, VECTOR_MIN_ITEMS, jit, kernel, prange
from granum.core.arrays import E_GRAV_WORK, S_DT, SI_NBODIES, SI_TRACK_ENERGY
from granum.core.records import raw
from granum.kernels.schedule import block_queue, next_block, queue_workers


@jit
def reset_block(b, S, nb):
    """Forces and torques of the bodies of block ``b`` back to the permanent ones (``perm_force`` and
    ``perm_torque`` are lazy columns: 0 rows until a script sets one). The columns are read into locals
    once: ``S`` is a raw view, and a store could otherwise make the loop reload them from the record. Each column
    is one loop over a flat view from 0, which LLVM vectorizes (a copy or a fill); a block of fewer than
    VECTOR_MIN_ITEMS bodies is written row by row (a flat view is a call into Numba's run time, about 50 ns)."""
    lo, hi = b * BLOCK, min(nb, (b + 1) * BLOCK)
    if hi - lo < VECTOR_MIN_ITEMS:
        force, torque, perm_force, perm_torque = S.force, S.torque, S.perm_force, S.perm_torque
        perm_f, perm_t = perm_force.shape[0] > 0, perm_torque.shape[0] > 0
        for i in range(lo, hi):
            for k in range(3):
                force[i, k] = perm_force[i, k] if perm_f else 0.0
                torque[i, k] = perm_torque[i, k] if perm_t else 0.0
        return
    for column, permanent in ((S.force, S.perm_force), (S.torque, S.perm_torque)):
        out = column[lo:hi].reshape(3 * (hi - lo))
        if permanent.shape[0] > 0:
            values = permanent[lo:hi].reshape(3 * (hi - lo))
            for j in range(out.size):
                out[j] = values[j]
        else:
            for j in range(out.size):
                out[j] = 0.0


def _reset(S, nb):
    queue = block_queue((nb + BLOCK - 1) // BLOCK)
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            reset_block(b, S, nb)
            b = next_block(queue, w, b)


reset, reset_par = kernel(_reset, over="bodies")


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
    """Parameters of :func:`force_stage` (ForceEngine, TorqueEngine)."""

    ids: np.ndarray     #: the bodies, (n,) int64
    force: np.ndarray   #: force added to each [N], (3,) float64
    torque: np.ndarray  #: torque added to each [N m], (3,) float64


@jit
def force_stage(S, C, P):
    """ForceEngine and TorqueEngine: F += force and T += torque on the listed bodies; ``P``: :class:`ForceParams`."""
    force, torque = P.force, P.torque
    body_force, body_torque = S.force, S.torque  # read once: a store could make the loop reload them
    for i in P.ids:
        for k in range(3):
            body_force[i, k] += force[k]
            body_torque[i, k] += torque[k]
