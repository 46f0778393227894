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
from granum.kernels.static import Static, static_bool, static_switch
from granum.physics.vec import (
    RENORM_SERIES_MAX,
    ROTVEC_SERIES_MAX2,
    add,
    cross,
    load3,
    load4,
    matvec,
    norm_excess,
    quat_from_rotvec,
    quat_mul,
    quat_mul_inlined,
    quat_normalized,
    quat_renormalized,
    quat_rotate,
    quat_rotate_inv,
    renormalized_series,
    rotvec_series,
    scale,
    sub,
)

#: A body faster than this is taken as a numerical explosion [m/s].
EXPLODING_SPEED = 1e8


@jit(inline="always")  # where a loop must vectorize (plain_block): a call stops LLVM's vectorizer
def damp_inlined(a, v, damping):
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
def damp(a, v, damping):
    """:func:`damp_inlined`, called."""
    return damp_inlined(a, v, damping)


@jit(inline="always")  # also in plain_block's loops, which LLVM vectorizes
def damped_acceleration(a, g, v_mid, damping, damp_gravity):
    """YADE's damping (:func:`damp`) of one component ``a`` = F/m + g of a body's acceleration [m/s^2], given its
    velocity estimated at the step ``v_mid`` [m/s]: of the whole acceleration with ``damp_gravity``, else of the
    part from the forces, F/m = a - g."""
    if damp_gravity:
        return damp_inlined(a, v_mid, damping)
    return damp_inlined(a - g, v_mid, damping) + g


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


def clump_gather_if(paths, i, S):
    """:func:`clump_gather` where the scene may hold clumps (``paths``, :attr:`NewtonParams.aspherical`); where it
    holds none, nothing, and neither the clumps' code nor the aspherical bodies' is compiled (:func:`no_clump`,
    :func:`no_aspherical`: the stage of a scene of spheres compiled in 2.8-3.0 s instead of 4.0-4.2 s on one
    process, 2026-12-07)."""
    raise TypeError("clump_gather_if is called from compiled kernels only")


def clump_place_if(paths, i, S):
    """:func:`clump_place`, or nothing, as :func:`clump_gather_if`."""
    raise TypeError("clump_place_if is called from compiled kernels only")


def integrate_aspherical_if(paths, i, S, torque, dt):
    """:func:`integrate_aspherical`, or nothing, as :func:`clump_gather_if`."""
    raise TypeError("integrate_aspherical_if is called from compiled kernels only")


@jit
def no_clump(i, S):
    """:func:`clump_gather_if` and :func:`clump_place_if` in a scene without clumps (never reached)."""


@jit
def no_aspherical(i, S, torque, dt):
    """:func:`integrate_aspherical_if` in a scene without aspherical bodies (never reached)."""


static_switch(clump_gather_if, "aspherical", clump_gather, no_clump)
static_switch(clump_place_if, "aspherical", clump_place, no_clump)
static_switch(integrate_aspherical_if, "aspherical", integrate_aspherical, no_aspherical)


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
                ad = damped_acceleration(a, g, vf + 0.5 * dt * a, damping, damp_gravity)
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
    turn(i, ori, (ang_vel[i, 0] * dt, ang_vel[i, 1] * dt, ang_vel[i, 2] * dt), exact_norm)
    return damp_work


@jit   # called: inlined by Numba, it compiled again in every copy of spin (0.4 s of the stage's first compiling)
def turn(i, ori, rv, exact_norm):
    """Turn the orientation of body ``i`` by the rotation vector ``rv`` = omega dt [rad] (3.5,11), normalized with a
    square root when ``exact_norm``, else with the series (:func:`quat_renormalized`); unchanged for rv = 0."""
    if rv[0] != 0.0 or rv[1] != 0.0 or rv[2] != 0.0:
        q = quat_mul(quat_from_rotvec(rv), load4(ori, i))
        q = quat_normalized(q) if exact_norm else quat_renormalized(q)
        for k in range(4):
            ori[i, k] = q[k]


@jit(inline="always")
def sane_values(p, v, w):
    """Whether a body at ``p`` [m] (3 values), moving at ``v`` [m/s] and turning at ``w`` [rad/s] is finite and not
    exploding. One test for all six: one inf or NaN makes the sum NaN (x - x != 0); finite values whose sum
    overflows (beyond 1e307) are reported too, as exploding."""
    speed2 = v[0] ** 2 + v[1] ** 2 + v[2] ** 2
    sum6 = p[0] + p[1] + p[2] + w[0] + w[1] + w[2]
    return (speed2 < EXPLODING_SPEED ** 2) & (sum6 - sum6 == 0.0)


@jit(inline="always")
def sane(i, pos, vel, ang_vel):
    """:func:`sane_values` of body ``i`` of the (N, 3) positions, velocities and angular velocities."""
    return sane_values((pos[i, 0], pos[i, 1], pos[i, 2]), (vel[i, 0], vel[i, 1], vel[i, 2]),
                       (ang_vel[i, 0], ang_vel[i, 1], ang_vel[i, 2]))


@jit(inline="always")
def sane_flat(i, p, v, w):
    """:func:`sane_values` of body ``i`` of flat (3 n,) positions, velocities and angular velocities (a loop over
    these vectorizes; over (n, 3) views it did not)."""
    return sane_values((p[3 * i], p[3 * i + 1], p[3 * i + 2]), (v[3 * i], v[3 * i + 1], v[3 * i + 2]),
                       (w[3 * i], w[3 * i + 1], w[3 * i + 2]))


@jit(inline="always")
def _plain_move(j, m, g, damping, damp_gravity, pos, vel, force, dt):
    """:func:`translate` of component ``j`` of the flat (3 n,) positions [m], velocities [m/s] and forces [N] of a
    block of plain bodies (no blocked DOF, no periodic cell, no energies; ``damping`` 0 for none): the same
    arithmetic, with the damping selected instead of branched on."""
    v = vel[j]
    a = force[j] / m + g
    ad = damped_acceleration(a, g, v + 0.5 * dt * a, damping, damp_gravity)
    a = ad if damping != 0.0 else a   # undamped, the acceleration is a itself, as in translate
    v += a * dt + 0.0 + 0.0   # translate adds the zero jump and convective change: x + 0.0 is not x for x = -0.0
    vel[j] = v
    pos[j] += v * dt


@jit(inline="always")
def _plain_spin_rate(j, damping, ang_vel, torque, inertia, dt):
    """:func:`spin`'s new angular velocity [rad/s] for component ``j`` of a block's flat (3 n,) angular velocities,
    torques [N m] and inertias [kg m^2]: the same arithmetic, the damping applied even when zero (a factor 1.0:
    the same bits as none)."""
    w = ang_vel[j]
    aa = torque[j] / inertia[j]
    ang_vel[j] = w + damp_inlined(aa, w + 0.5 * dt * aa, damping) * dt


#: Margin under RENORM_SERIES_MAX that :func:`plain_block` keeps |q|^2 - 1 of an orientation before its turn: a turn
#: by an angle within the range of quat_from_rotvec's series changes it by rounding only (about 1e-15).
TURN_NORM_MARGIN = 1e-9


@jit(inline="always")
def is_plain(i, alive, clump_id, body_mask, mask, blocked, aspherical, shape_kind):
    """Whether body ``i`` takes :func:`plain_block`'s steps (outside a periodic cell, without energies): alive, moved
    by the integrator (``mask``), neither a clump nor a clump's member, no DOF blocked, rotation spherical."""
    return (alive[i] & (clump_id[i] < 0) & ((mask <= 0) | (body_mask[i] & mask != 0)) & (blocked[i] == 0)
            & ~aspherical[i] & (shape_kind[i] != ShapeKind.CLUMP))   # no short cut: all_plain's loop vectorizes


@jit
def all_plain(lo, hi, alive, clump_id, body_mask, mask, blocked, aspherical, shape_kind):
    """Whether the bodies lo..hi-1 are all :func:`is_plain`: a count over views from 0, which LLVM vectorizes (no
    early exit), where looking body by body costs about 2 ns a body."""
    n = hi - lo
    alive, clump_id, body_mask = alive[lo:hi], clump_id[lo:hi], body_mask[lo:hi]
    blocked, aspherical, shape_kind = blocked[lo:hi], aspherical[lo:hi], shape_kind[lo:hi]
    count = 0
    for i in range(n):
        count += is_plain(i, alive, clump_id, body_mask, mask, blocked, aspherical, shape_kind)
    return count == n


@jit(inline="always")
def _plain_rates(n, p, v, f, w, t, inert, mass, is_damped, gravity, dt, damping, damp_gravity):
    """:func:`plain_block`'s new velocities and positions (:func:`_plain_move`), then angular velocities
    (:func:`_plain_spin_rate`), of its ``n`` bodies (flat (3 n,) views)."""
    g0, g1, g2 = gravity[0], gravity[1], gravity[2]
    for i in range(n):
        m = mass[i]
        d = damping if is_damped[i] else 0.0
        _plain_move(3 * i, m, g0, d, damp_gravity, p, v, f, dt)
        _plain_move(3 * i + 1, m, g1, d, damp_gravity, p, v, f, dt)
        _plain_move(3 * i + 2, m, g2, d, damp_gravity, p, v, f, dt)
    for i in range(n):
        d = damping if is_damped[i] else 0.0
        _plain_spin_rate(3 * i, d, w, t, inert, dt)
        _plain_spin_rate(3 * i + 1, d, w, t, inert, dt)
        _plain_spin_rate(3 * i + 2, d, w, t, inert, dt)


@jit
def plain_block(lo, hi, pos, vel, ori, ang_vel, force, torque, mass, inertia, is_damped, gravity, dt, damping,
                damp_gravity):
    """The leapfrog step of the bodies lo..hi-1, all plain (:func:`all_plain`) outside a periodic cell and without
    energies: what :func:`translate`, :func:`spin` and :func:`sane` compute body by body, to the bit, in loops that
    LLVM vectorizes. Each loop runs over flat views of the block's rows from index 0 (so the indices are known not
    to be negative), touches few arrays (beyond LLVM's limit of run-time alias checks a loop stays scalar) and has
    no call and no branch. Stand-alone, 8,000 damped spinning spheres, one thread: 38 -> 16 ns a body.

    The orientations turn with the series of :func:`quat_from_rotvec` and :func:`quat_renormalized` when every
    turning body is within their ranges before the turn (rotation angle; |q|^2 - 1 within TURN_NORM_MARGIN of the
    limit), which the turn keeps them in; otherwise body by body, as :func:`spin`. Returns the first body that is
    not :func:`sane`, or -1."""
    n = hi - lo
    pos2, vel2, ang_vel2, ori2 = pos[lo:hi], vel[lo:hi], ang_vel[lo:hi], ori[lo:hi]
    p, v, f = pos2.reshape(3 * n), vel2.reshape(3 * n), force[lo:hi].reshape(3 * n)
    w, t, inert = ang_vel2.reshape(3 * n), torque[lo:hi].reshape(3 * n), inertia[lo:hi].reshape(3 * n)
    o = ori2.reshape(4 * n)
    mass, is_damped = mass[lo:hi], is_damped[lo:hi]
    if damping == 0.0:   # the damping a constant, which LLVM folds away: the same bits (a factor 1.0), fewer
        # operations (stand-alone, 4,428 bodies, one thread: at rest 6.9 -> 5.7 ns a body, spinning 10.9 -> 9.6)
        _plain_rates(n, p, v, f, w, t, inert, mass, is_damped, gravity, dt, 0.0, damp_gravity)
    else:
        _plain_rates(n, p, v, f, w, t, inert, mass, is_damped, gravity, dt, damping, damp_gravity)
    turning = outside = 0
    limit = RENORM_SERIES_MAX - TURN_NORM_MARGIN
    for i in range(n):
        r0, r1, r2 = w[3 * i] * dt, w[3 * i + 1] * dt, w[3 * i + 2] * dt
        moving = (r0 != 0.0) | (r1 != 0.0) | (r2 != 0.0)
        q = (o[4 * i], o[4 * i + 1], o[4 * i + 2], o[4 * i + 3])
        inside = (r0 * r0 + r1 * r1 + r2 * r2 < ROTVEC_SERIES_MAX2) & (abs(norm_excess(q)) < limit)
        turning += moving
        outside += moving & ~inside
    if outside:
        for i in range(n):
            turn(i, ori2, (ang_vel2[i, 0] * dt, ang_vel2[i, 1] * dt, ang_vel2[i, 2] * dt), False)
    elif turning:
        for i in range(n):
            r0, r1, r2 = w[3 * i] * dt, w[3 * i + 1] * dt, w[3 * i + 2] * dt
            c, s = rotvec_series(r0 * r0 + r1 * r1 + r2 * r2)
            q0 = (o[4 * i], o[4 * i + 1], o[4 * i + 2], o[4 * i + 3])
            q = quat_mul_inlined((c, r0 * s, r1 * s, r2 * s), q0)
            q = renormalized_series(q, norm_excess(q))
            moving = (r0 != 0.0) | (r1 != 0.0) | (r2 != 0.0)
            o[4 * i] = q[0] if moving else q0[0]
            o[4 * i + 1] = q[1] if moving else q0[1]
            o[4 * i + 2] = q[2] if moving else q0[2]
            o[4 * i + 3] = q[3] if moving else q0[3]
    insane = 0
    for i in range(n):
        insane += not sane_flat(i, p, v, w)   # a count, which LLVM vectorizes (a running minimum it did not)
    if insane:
        for i in range(n):
            if not sane_flat(i, p, v, w):
                return lo + i
    return -1


def plain_run(vectorized, S, lo, hi, gravity, dt, damping, damp_gravity, mask):
    """The vectorized steps (:func:`plain_block`) of the run of plain bodies (:func:`is_plain`) from body ``lo``,
    one, up to at most ``hi``: ``(end, first)``, the end of the run and its first body not :func:`sane` (-1: none).

    ``vectorized``, a static ``("vectorized", bool)``: without it, nothing is stepped (``(lo, -1)``), and the
    vectorized loops are not compiled (about 1.5 s of a first run's compiling on one process)."""
    raise TypeError("plain_run is called from compiled kernels only")


@jit
def vectorized_run(S, lo, hi, gravity, dt, damping, damp_gravity, mask):
    """:func:`plain_run` in a large scene: the run found (a count over the whole rest of the block first, which
    vectorizes, else body by body) and stepped by :func:`plain_block`."""
    alive, clump_id, body_mask, blocked, aspherical, shape_kind = (S.alive, S.clump_id, S.mask, S.blocked,
                                                                   S.aspherical, S.shape_kind)
    end = hi
    if not all_plain(lo, hi, alive, clump_id, body_mask, mask, blocked, aspherical, shape_kind):
        end = lo + 1
        while end < hi and is_plain(end, alive, clump_id, body_mask, mask, blocked, aspherical, shape_kind):
            end += 1
    return end, plain_block(lo, end, S.pos, S.vel, S.ori, S.ang_vel, S.force, S.torque, S.mass, S.inertia,
                            S.is_damped, gravity, dt, damping, damp_gravity)


@jit
def no_run(S, lo, hi, gravity, dt, damping, damp_gravity, mask):
    """:func:`plain_run` in a small scene: nothing stepped."""
    return lo, -1


static_switch(plain_run, "vectorized", vectorized_run, no_run)


@jit
def newton_block(b, S, nb, P, sums, bad):
    """Leapfrog step of the bodies of block ``b``; their energy sums into ``sums[b]`` (when energies are
    tracked), the first non-finite or exploding body into ``bad[b]``; ``P``: :class:`NewtonParams`. With
    ``P.mask`` > 0, a body sharing no bit with it is left alone: neither its velocity nor its position changes
    (YADE 2023.02a, measured).

    The per-body columns are read into local arrays once (``S`` is a raw view: they are borrowed),
    so that the loop does not reload them from the record after every store. Outside a periodic cell and without
    energies, the plain bodies (:func:`is_plain`: spheres, mostly) take vectorized steps by runs in a large scene
    (:func:`plain_run`), else the same steps as the other bodies with the plain case's values as constants, which
    the compiler folds (4,416 spheres, one thread: 17.7 -> 13.4-13.8 ns a body at rest; spinning and damped: 47.5
    -> 38-44). Both give the same bits.
    """
    gravity, damping, damp_gravity, mask = P.gravity, P.damping, P.damp_gravity, P.mask
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
    hi = min(nb, (b + 1) * BLOCK)
    end = 0   # the end of the last run of plain bodies (plain_run)
    for i in range(b * BLOCK, hi):
        if i < end:
            continue
        if plain and is_plain(i, alive, clump_id, body_mask, mask, blocked_dofs, aspherical, shape_kind):
            end, first = plain_run(P.vectorized, S, i, hi, gravity, dt, damping, damp_gravity, mask)
            if end > i:   # stepped with its run
                if first >= 0 and bad[b] < 0:
                    bad[b] = first
                continue
            damp_i = damping if is_damped[i] else 0.0
            translate(i, pos, vel, force, mass[i], gravity, dt, 0, damp_i, damp_gravity, still, still, still, False,
                      still)
            spin(i, ori, ang_vel, (torque[i, 0], torque[i, 1], torque[i, 2]), inertia, dt, 0, damp_i, False, 0.0,
                 False)
            if not sane(i, pos, vel, ang_vel) and bad[b] < 0:
                bad[b] = i
            continue
        if not alive[i] or clump_id[i] >= 0 and clump_id[i] != i or mask > 0 and body_mask[i] & mask == 0:
            continue
        damp_i = damping if is_damped[i] else 0.0
        clump = shape_kind[i] == ShapeKind.CLUMP
        if clump:
            clump_gather_if(P.aspherical, i, S)
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
        # without the aspherical paths (a body made aspherical from another thread while a run goes on, until the
        # next chunk), as a sphere
        if aspherical[i] and blocked >> 3 == 0 and static_bool(P.aspherical):
            if damp_i != 0.0:
                t = (damp(t[0], ang_vel[i, 0], damping), damp(t[1], ang_vel[i, 1], damping),
                     damp(t[2], ang_vel[i, 2], damping))
            integrate_aspherical_if(P.aspherical, i, S, t, dt)
        else:
            damp_work = spin(i, ori, ang_vel, t, inertia, dt, blocked, damp_i, track, damp_work, aspherical[i])
        energy = (kinetic, damp_work, grav_work)
        if clump:
            clump_place_if(P.aspherical, i, S)
        if not sane(i, pos, vel, ang_vel) and bad[b] < 0:
            bad[b] = i
    sums[b, 0] = energy[0]
    sums[b, 1] = energy[1]
    sums[b, 2] = energy[2]


def _newton_blocks(S, nb, P, sums, bad):
    queue = block_queue(sums.shape[0])
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            newton_block(b, S, nb, P, sums, bad)
            b = next_block(queue, w, b)


newton_blocks, newton_blocks_par = kernel(_newton_blocks, over="bodies")


class NewtonParams(NamedTuple):
    """Parameters of :func:`newton_stage` (NewtonIntegrator)."""

    gravity: np.ndarray  #: gravitational acceleration [m/s^2], (3,) float64
    damping: float       #: Cundall's non-viscous damping [-]
    damp_gravity: bool   #: damping acts on the whole acceleration, gravity included
    mask: int            #: > 0: only bodies sharing a bit with it move; <= 0: all
    #: ``("vectorized", bool)``: plain bodies take :func:`plain_block`'s vectorized steps (:func:`plain_run`);
    #: :func:`vectorized` chooses it
    vectorized: Static
    #: ``("aspherical", bool)``: the integrator's paths for clumps and aspherical bodies (a clump's gather and
    #: placement, Euler's equations) are compiled; :func:`aspherical_paths` chooses it
    aspherical: Static


#: Bodies from which a scene's plain bodies take the vectorized steps. Their loops add about 1.5 s to a first run's
#: compiling (one process) and save about 20 ns a body and step (spinning, damped; 38 -> 16 ns stand-alone): from
#: about 1e8 body-steps on, which a scene of a thousand bodies reaches in 1e5 steps. Smaller scenes compile none.
VECTORIZED_BODIES = 1024


#: the two values of :attr:`NewtonParams.vectorized` and of :attr:`NewtonParams.aspherical`, made once: the runner
#: asks for them before every chunk of steps, and a loop of ``O.step()`` makes a chunk of each step
_VECTORIZED = (Static(("vectorized", False)), Static(("vectorized", True)))
_ASPHERICAL = (Static(("aspherical", False)), Static(("aspherical", True)))


def vectorized(body_count: int) -> Static:
    """:attr:`NewtonParams.vectorized` for a scene of ``body_count`` bodies."""
    return _VECTORIZED[bool(body_count >= VECTORIZED_BODIES)]


def aspherical_paths(clumps: int, aspherical: np.ndarray) -> Static:
    """:attr:`NewtonParams.aspherical` for a scene whose clump table has ``clumps`` rows and whose bodies'
    ``aspherical`` column is ``aspherical``, (N,) bool: True when a clump was ever made or a body (an erased one
    included) is aspherical, which may compile the paths for nothing, never leave them out for a body that needs
    them. Only Python makes a clump or an aspherical body (``O.bodies.clump``, a box, ``b.aspherical = True``): no
    stage does, and the runner builds the parameters anew before every chunk of steps and every compiled segment
    of a step run engine by engine. A body made aspherical from another thread while a run goes on turns as a
    sphere until the next chunk (at most ``CHUNK_SECONDS``)."""
    return _ASPHERICAL[bool(clumps > 0 or np.count_nonzero(aspherical))]   # count_nonzero: no ufunc set-up


@jit
def newton_stage(S, C, P):
    """Engine stage of NewtonIntegrator; ``P``: :class:`NewtonParams`."""
    damping = P.damping
    nb = S.iscal[SI_NBODIES]
    nblocks = (nb + BLOCK - 1) // BLOCK
    w = area(C, nblocks * 4)  # the temporaries from the work area (granum.kernels.scratch)
    sums, at = take_f8(w, 0, nblocks * 3)
    sums = rows_of(sums, 3)
    bad, at = take_i8(w, at, nblocks)
    bad[:] = -1
    if nb < PARALLEL_THRESHOLD:  # through a raw view: no reference counting per body (granum.core.records)
        newton_blocks(raw(S), nb, P, sums, bad)
    else:
        newton_blocks_par(raw(S), nb, P, sums, bad)
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
