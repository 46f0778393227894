"""NewtonIntegrator stage: leapfrog integration of translation and rotation.

Velocities live at mid-steps and positions at full steps (YADE section 3.5,
(3.5,1)-(3.5,7)). Per degree of freedom w that is not blocked:

.. math::
    a_w = F_w / m + g_w, \\qquad
    a_w \\leftarrow a_w\\,\\big(1 - \\lambda_d\\,\\mathrm{sgn}(a_w (v_w + a_w \\Delta t/2))\\big),
    \\qquad v_w \\mathrel{+}= a_w \\Delta t, \\qquad x_w \\mathrel{+}= v_w \\Delta t

with YADE's non-viscous damping lambda_d (3.5,24), which acts on the whole
acceleration including gravity. Blocked DOFs keep their velocity (imposed motion).
Spherical rotation: omega += T/I dt, orientation turned by omega dt (3.5,8)-(3.5,11).
Aspherical bodies without blocked rotations integrate the angular momentum with
Fincham's leapfrog (3.5,20)-(3.5,21).

Bodies are processed in fixed blocks; per-block energy sums and error flags are
combined serially, so results do not depend on the number of threads.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from granum._jit import BLOCK, PARALLEL_THRESHOLD, jit, kernel, prange
from granum.core.arrays import (
    E_GRAV_WORK,
    E_KINETIC,
    E_NONVISC_DAMP,
    S_DT,
    SI_HOMO_DEFORM,
    SI_NBODIES,
    SI_PERIODIC,
    SI_TRACK_ENERGY,
)
from granum.core.contacts import C_ERR_A, C_STATUS, STATUS_NONFINITE
from granum.core.records import raw
from granum.core.shapes import ShapeKind
from granum.kernels.schedule import block_queue, next_block, queue_workers
from granum.kernels.scratch import area, rows_of, take_f8, take_i8
from granum.physics.vec import (
    add,
    cross,
    load3,
    load4,
    matvec,
    quat_from_rotvec,
    quat_mul,
    quat_normalized,
    quat_renormalized,
    quat_rotate,
    quat_rotate_inv,
    scale,
    sub,
)

#: A body faster than this is taken as a numerical explosion [m/s].
EXPLODING_SPEED = 1e8


@jit
def damp(a, v, damping):
    """YADE's non-viscous damping of one acceleration component (3.5,24): a (1 - damping sgn(a v)).

    The factor is selected, not branched on: the sign of a v is as good as random in a dense packing, and
    mispredicted branches cost a quarter of NewtonIntegrator's time at 1e5 spheres. 1 - damping and
    1 + damping are the bits of 1 - damping * (+-1); selecting them avoids converting the sign to a float
    and multiplying (10,648 spinning spheres, damping 0.2, one thread: 377 -> 317 us a step)."""
    s = a * v
    f = 1.0 - damping if s > 0.0 else 1.0
    f = 1.0 + damping if s < 0.0 else f
    return a * f


@jit
def quat_dot(q, w_local):
    """Time derivative of the orientation, q' = q (0, w_local) / 2."""
    d = quat_mul(q, (0.0, w_local[0], w_local[1], w_local[2]))
    return (0.5 * d[0], 0.5 * d[1], 0.5 * d[2], 0.5 * d[3])


@jit
def integrate_aspherical(i, S, torque, dt):
    """Fincham's leapfrog for the rotation of an aspherical body (3.5,20)-(3.5,21).

    References:
        D. Fincham (1992), Leapfrog rotational algorithms, *Molecular Simulation* 8:165-178.
    """
    q = load4(S.ori, i)
    inertia = (S.inertia[i, 0], S.inertia[i, 1], S.inertia[i, 2])
    mom = (S.ang_mom[i, 0], S.ang_mom[i, 1], S.ang_mom[i, 2])
    mom_on = (mom[0] + 0.5 * dt * torque[0], mom[1] + 0.5 * dt * torque[1], mom[2] + 0.5 * dt * torque[2])
    mom_mid = (mom[0] + dt * torque[0], mom[1] + dt * torque[1], mom[2] + dt * torque[2])
    l_on = quat_rotate_inv(q, mom_on)
    w_on = (l_on[0] / inertia[0], l_on[1] / inertia[1], l_on[2] / inertia[2])
    dq = quat_dot(q, w_on)
    q_half = (q[0] + 0.5 * dt * dq[0], q[1] + 0.5 * dt * dq[1], q[2] + 0.5 * dt * dq[2], q[3] + 0.5 * dt * dq[3])
    # the mid-step momentum is taken to the body frame with the mid-step orientation (Fincham
    # 1992); YADE uses the start-of-step one, which makes the scheme only first order
    l_mid = quat_rotate_inv(quat_normalized(q_half), mom_mid)
    w_mid = (l_mid[0] / inertia[0], l_mid[1] / inertia[1], l_mid[2] / inertia[2])
    dq = quat_dot(q_half, w_mid)
    q_new = quat_normalized((q[0] + dt * dq[0], q[1] + dt * dq[1], q[2] + dt * dq[2], q[3] + dt * dq[3]))
    w = quat_rotate(q_new, w_mid)
    for k in range(3):
        S.ang_mom[i, k] = mom_mid[k]
        S.ang_vel[i, k] = w[k]
    for k in range(4):
        S.ori[i, k] = q_new[k]


@jit
def clump_gather(i, S):
    """Add the forces and torques of clump ``i``'s members to the clump (3.5,22).

    F_c = sum F_m, T_c = sum (T_m + (x_m - x_c) x F_m).
    """
    row = S.shape_row[i]
    xc = load3(S.pos, i)
    for t in range(S.clump_member_first[row], S.clump_member_first[row] + S.clump_member_count[row]):
        m = S.clump_members[t]
        f = load3(S.force, m)
        arm_t = cross(sub(load3(S.pos, m), xc), f)
        for k in range(3):
            S.force[i, k] += f[k]
            S.torque[i, k] += S.torque[m, k] + arm_t[k]


@jit
def counted_force(i, S):
    """Resultant force on body ``i`` [N] as YADE's unbalanced force counts it: a clump's is the sum of its
    members' forces whether or not this step's gathering (:func:`clump_gather`) has run (YADE 2023.02a, measured:
    the same value before and after NewtonIntegrator); any other body's is its own."""
    if S.shape_kind[i] != ShapeKind.CLUMP:
        return load3(S.force, i)
    row = S.shape_row[i]
    fx = fy = fz = 0.0
    for t in range(S.clump_member_first[row], S.clump_member_first[row] + S.clump_member_count[row]):
        m = S.clump_members[t]
        fx += S.force[m, 0]
        fy += S.force[m, 1]
        fz += S.force[m, 2]
    return (fx, fy, fz)


@jit
def clump_place(i, S):
    """Move clump ``i``'s members rigidly with the clump: position, orientation, velocities."""
    row = S.shape_row[i]
    q = load4(S.ori, i)
    xc = load3(S.pos, i)
    v = load3(S.vel, i)
    w = load3(S.ang_vel, i)
    for t in range(S.clump_member_first[row], S.clump_member_first[row] + S.clump_member_count[row]):
        m = S.clump_members[t]
        arm = quat_rotate(q, load3(S.clump_rel_pos, m))
        vm = add(v, cross(w, arm))
        qm = quat_mul(q, load4(S.clump_rel_ori, m))
        for k in range(3):
            S.pos[m, k] = xc[k] + arm[k]
            S.vel[m, k] = vm[k]
            S.ang_vel[m, k] = w[k]
        for k in range(4):
            S.ori[m, k] = qm[k]


@jit(inline="always")  # inlined with constant arguments, the branches of the cases not taken vanish
def translate(i, pos, vel, force, m, gravity, dt, blocked, damping, damp_gravity, flow, jump, conv, track, sums):
    """Leapfrog step of body ``i``'s centre (3.5,1)-(3.5,7) with YADE's damping (0 for none): the velocity of each
    DOF not blocked, then the position. ``flow``: the homogeneous flow's velocity at the body (periodic cell),
    ``jump``/``conv`` the velocity's jump and convective change there (zero outside a periodic cell). ``sums``:
    (kinetic energy, damping's work, gravity's work) so far, returned with this body's part added when ``track``
    (energies use the velocity of the previous mid-step, as YADE does)."""
    kinetic, damp_work, grav_work = sums
    for k in range(3):
        v = vel[i, k]
        vf = v - flow[k]
        if track:
            kinetic += 0.5 * m * vf * vf
        if not blocked >> k & 1:
            g = gravity[k]
            a = force[i, k] / m + g
            if track:
                grav_work -= m * g * vf * dt
            if damping != 0.0:
                if damp_gravity:
                    ad = damp(a, vf + 0.5 * dt * a, damping)
                else:
                    ad = damp(a - g, vf + 0.5 * dt * a, damping) + g
                if track:
                    damp_work += abs(m * (a - ad) * vf) * dt
                a = ad
            v += a * dt + jump[k] + conv[k]
            vel[i, k] = v
        pos[i, k] += v * dt
    return kinetic, damp_work, grav_work


@jit(inline="always")
def spin(i, ori, ang_vel, t, inertia, dt, blocked, damping, track, damp_work, exact_norm):
    """Spherical rotation of body ``i`` (3.5,8)-(3.5,11): omega += T/I dt for each rotational DOF not blocked
    (YADE's damping applied), the orientation turned by omega dt. ``t``: the torque [N m]. Returns the damping's
    work so far, with this body's added when ``track``. ``exact_norm``: the orientation normalized with a square
    root (an aspherical body with blocked rotations, a wall turned by an engine, keeps YADE's normalization,
    whose bits the kinematic tests compare); else with the series (:func:`quat_renormalized`)."""
    for k in range(3):
        w = ang_vel[i, k]
        if not blocked >> (3 + k) & 1:
            aa = t[k] / inertia[i, k]
            if damping != 0.0:
                aad = damp(aa, w + 0.5 * dt * aa, damping)
                if track:
                    damp_work += abs(inertia[i, k] * (aa - aad) * w) * dt
                aa = aad
            w += aa * dt
            ang_vel[i, k] = w
    rv = (ang_vel[i, 0] * dt, ang_vel[i, 1] * dt, ang_vel[i, 2] * dt)
    if rv[0] != 0.0 or rv[1] != 0.0 or rv[2] != 0.0:
        q = quat_mul(quat_from_rotvec(rv), load4(ori, i))
        q = quat_normalized(q) if exact_norm else quat_renormalized(q)
        for k in range(4):
            ori[i, k] = q[k]
    return damp_work


@jit(inline="always")
def sane(i, pos, vel, ang_vel):
    """Whether body ``i`` is finite and not exploding. One test for all six: one inf or NaN makes the sum NaN
    (x - x != 0); finite values whose sum overflows (beyond 1e307) are reported too, as exploding."""
    speed2 = vel[i, 0] ** 2 + vel[i, 1] ** 2 + vel[i, 2] ** 2
    sum6 = pos[i, 0] + pos[i, 1] + pos[i, 2] + ang_vel[i, 0] + ang_vel[i, 1] + ang_vel[i, 2]
    return (speed2 < EXPLODING_SPEED ** 2) & (sum6 - sum6 == 0.0)


@jit
def newton_block(b, S, nb, gravity, damping, damp_gravity, mask, sums, bad):
    """Leapfrog step of the bodies of block ``b``; their energy sums into ``sums[b]`` (when energies are
    tracked), the first non-finite or exploding body into ``bad[b]``. With ``mask`` > 0, a body sharing no bit
    with it is left alone: neither its velocity nor its position changes (YADE 2023.02a, measured).

    The per-body columns are read into local arrays once (``S`` is a raw view: they are borrowed),
    so that the loop does not reload them from the record after every store. A body without blocked DOFs
    whose rotation is spherical (a sphere), outside a periodic cell and without energies, takes the same
    steps with those cases' values as constants, which the compiler folds: a fifth to a quarter faster (4,416
    spheres, one thread: 17.7 -> 13.4-13.8 ns a body at rest; spinning and damped: 47.5 -> 38-44).
    """
    dt = S.scal[S_DT]
    periodic = S.iscal[SI_PERIODIC] != 0
    homo = S.iscal[SI_HOMO_DEFORM]
    track = S.iscal[SI_TRACK_ENERGY] != 0
    pos, vel, ori, ang_vel, force, torque = S.pos, S.vel, S.ori, S.ang_vel, S.force, S.torque
    mass, inertia, blocked_dofs, is_damped = S.mass, S.inertia, S.blocked, S.is_damped
    alive, clump_id, shape_kind, aspherical, body_mask = S.alive, S.clump_id, S.shape_kind, S.aspherical, S.mask
    plain = not periodic and not track
    still = (0.0, 0.0, 0.0)
    energy = (0.0, 0.0, 0.0)   # kinetic energy, damping's work, gravity's work
    for i in range(b * BLOCK, min(nb, (b + 1) * BLOCK)):
        if not alive[i] or clump_id[i] >= 0 and clump_id[i] != i or mask > 0 and body_mask[i] & mask == 0:
            continue
        damp_i = damping if is_damped[i] else 0.0
        if plain and blocked_dofs[i] == 0 and not aspherical[i] and shape_kind[i] != ShapeKind.CLUMP:
            translate(i, pos, vel, force, mass[i], gravity, dt, 0, damp_i, damp_gravity, still, still, still, False,
                      still)
            spin(i, ori, ang_vel, (torque[i, 0], torque[i, 1], torque[i, 2]), inertia, dt, 0, damp_i, False, 0.0,
                 False)
            if not sane(i, pos, vel, ang_vel) and bad[b] < 0:
                bad[b] = i
            continue
        clump = shape_kind[i] == ShapeKind.CLUMP
        if clump:
            clump_gather(i, S)
        blocked = blocked_dofs[i]
        # periodic cell: bodies follow the homogeneous flow L x (YADE's homoDeform); damping
        # and energies see only the fluctuation v - Lp x
        flow = still
        jump = still
        conv = still
        if periodic:
            x = load3(pos, i)
            flow = matvec(S.cell_prev_velgrad, x)
            if homo >= 1:  # the flow changed: v jumps by (L - Lp) x
                jump = sub(matvec(S.cell_velgrad, x), flow)
            if homo == 2:  # convective acceleration Lp v
                conv = scale(matvec(S.cell_prev_velgrad, load3(vel, i)), dt)
        energy = translate(i, pos, vel, force, mass[i], gravity, dt, blocked, damp_i, damp_gravity, flow, jump,
                           conv, track, energy)
        kinetic, damp_work, grav_work = energy
        # rotation
        t = (torque[i, 0], torque[i, 1], torque[i, 2])
        if track:
            wl = quat_rotate_inv(load4(ori, i), (ang_vel[i, 0], ang_vel[i, 1], ang_vel[i, 2]))
            for k in range(3):
                kinetic += 0.5 * inertia[i, k] * wl[k] * wl[k]
        if aspherical[i] and blocked >> 3 == 0:
            if damp_i != 0.0:
                t = (damp(t[0], ang_vel[i, 0], damping), damp(t[1], ang_vel[i, 1], damping),
                     damp(t[2], ang_vel[i, 2], damping))
            integrate_aspherical(i, S, t, dt)
        else:
            damp_work = spin(i, ori, ang_vel, t, inertia, dt, blocked, damp_i, track, damp_work, aspherical[i])
        energy = (kinetic, damp_work, grav_work)
        if clump:
            clump_place(i, S)
        if not sane(i, pos, vel, ang_vel) and bad[b] < 0:
            bad[b] = i
    sums[b, 0] = energy[0]
    sums[b, 1] = energy[1]
    sums[b, 2] = energy[2]


def _newton_blocks(S, nb, gravity, damping, damp_gravity, mask, sums, bad):
    queue = block_queue(sums.shape[0])
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            newton_block(b, S, nb, gravity, damping, damp_gravity, mask, sums, bad)
            b = next_block(queue, w, b)


newton_blocks, newton_blocks_par = kernel(_newton_blocks, over="bodies")


class NewtonParams(NamedTuple):
    """Parameters of :func:`newton_stage` (NewtonIntegrator)."""

    gravity: np.ndarray  #: gravitational acceleration [m/s^2], (3,) float64
    damping: float       #: Cundall's non-viscous damping [-]
    damp_gravity: bool   #: damping acts on the whole acceleration, gravity included
    mask: int            #: > 0: only bodies sharing a bit with it move; <= 0: all


@jit
def newton_stage(S, C, P):
    """Engine stage of NewtonIntegrator; ``P``: :class:`NewtonParams`."""
    gravity, damping, damp_gravity, mask = P.gravity, P.damping, P.damp_gravity, P.mask
    nb = S.iscal[SI_NBODIES]
    nblocks = (nb + BLOCK - 1) // BLOCK
    w = area(C, nblocks * 4)  # the temporaries from the work area (granum.kernels.scratch)
    sums, at = take_f8(w, 0, nblocks * 3)
    sums = rows_of(sums, 3)
    bad, at = take_i8(w, at, nblocks)
    bad[:] = -1
    if nb < PARALLEL_THRESHOLD:  # through a raw view: no reference counting per body (granum.core.records)
        newton_blocks(raw(S), nb, gravity, damping, damp_gravity, mask, sums, bad)
    else:
        newton_blocks_par(raw(S), nb, gravity, damping, damp_gravity, mask, sums, bad)
    for b in range(nblocks):
        if bad[b] >= 0:
            C.ctr[C_STATUS] = STATUS_NONFINITE
            C.ctr[C_ERR_A] = bad[b]
            break
    if S.iscal[SI_TRACK_ENERGY]:
        kinetic = damp_work = grav_work = 0.0
        for b in range(nblocks):   # fixed order: deterministic sums
            kinetic += sums[b, 0]
            damp_work += sums[b, 1]
            grav_work += sums[b, 2]
        S.energy[E_KINETIC] = kinetic
        S.energy_set[E_KINETIC] = 1
        if damping != 0.0:
            S.energy[E_NONVISC_DAMP] += damp_work
            S.energy_set[E_NONVISC_DAMP] = 1
        S.energy[E_GRAV_WORK] += grav_work  # YADE lists gravWork even without gravity
        S.energy_set[E_GRAV_WORK] = 1


@jit
def first_massless_free_body(S):
    """The first live body with a free translational DOF whose mass is not positive, or -1 (the leapfrog divides
    by the mass: the runner refuses such a body before a run). A clump member is left out: it moves with its
    clump."""
    blocked, clump_id, mass = S.blocked, S.clump_id, S.mass
    for i in range(S.iscal[SI_NBODIES]):
        if S.alive[i] and blocked[i] & 7 != 7 and (clump_id[i] < 0 or clump_id[i] == i) and not mass[i] > 0.0:
            return i
    return -1
