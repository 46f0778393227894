"""One iDEM time step, compiled, and a loop of steps (article §8, outer loop).

Order within a step ([A9]): gravity first, V <- V + g dt (the impulses then remove the
gravity-induced approach of resting and sliding contacts; the article allows this order:
"場合によっては、エネルギー保存型力積法を行う前に重力による速度の更新を行う"), then the contact
search on the current positions, the impulse resolution with frozen positions, and last the
positions and orientations with the new velocities (velocities before positions).
"""

from __future__ import annotations

import numpy as np

from granum._jit import PARALLEL_THRESHOLD, jit
from granum.idem.broadphase import find_contacts
from granum.idem.impulse import ST_SIZE, resolve
from granum.idem.rigid import advance_bodies, update_particles, update_particles_par


@jit
def step(dt, gravity, e, mu, alpha0, tol, tie, mode, max_rounds, max_iter, cutoff,
         fixed, pos, vel, ang_vel, ori, inv_mass, inertia0, inv_inertia0, inv_inertia,
         pbody, surf, r0, n0, pspacing, sigma, x, nw, stats):
    """Advance the bodies by one step ``dt`` [s] under ``gravity`` (3,) [m/s^2].

    Body arrays (nb, ...) and particle arrays (np, ...) as in :class:`~granum.idem.solver.IDEMSolver`;
    ``x``/``nw`` must hold the world positions/normals of the current configuration and
    ``inv_inertia`` the current world inverse inertia; all are updated. ``stats`` (ST_SIZE,)
    receives the step's counters (see :mod:`granum.idem.impulse`).
    """
    for k in range(ST_SIZE):
        stats[k] = 0.0
    for b in range(pos.shape[0]):
        if not fixed[b]:
            for k in range(3):
                vel[b, k] += gravity[k] * dt
    pa, pb, ba, bb, nrm, ra, rb, cp = find_contacts(surf, pbody, pspacing, x, nw, sigma, fixed, pos, cutoff)
    resolve(e, mu, alpha0, tol, tie, mode, max_rounds, max_iter, ba, bb, ra, rb, nrm, fixed, inv_mass, inv_inertia,
            vel, ang_vel, stats)
    advance_bodies(dt, fixed, pos, vel, ang_vel, ori, inertia0, inv_inertia0, inv_inertia)
    if pbody.shape[0] >= PARALLEL_THRESHOLD:
        update_particles_par(pbody, pos, ori, r0, n0, x, nw)
    else:
        update_particles(pbody, pos, ori, r0, n0, x, nw)


@jit
def run_steps(nsteps, dt, gravity, e, mu, alpha0, tol, tie, mode, max_rounds, max_iter, cutoff,
              fixed, pos, vel, ang_vel, ori, inv_mass, inertia0, inv_inertia0, inv_inertia,
              pbody, surf, r0, n0, pspacing, sigma, x, nw):
    """``nsteps`` steps of :func:`step`; returns the per-step statistics (nsteps, ST_SIZE)."""
    out = np.zeros((nsteps, ST_SIZE))
    for s in range(nsteps):
        step(dt, gravity, e, mu, alpha0, tol, tie, mode, max_rounds, max_iter, cutoff,
             fixed, pos, vel, ang_vel, ori, inv_mass, inertia0, inv_inertia0, inv_inertia,
             pbody, surf, r0, n0, pspacing, sigma, x, nw, out[s])
    return out
