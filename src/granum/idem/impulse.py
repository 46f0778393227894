"""The energy-conserving iterative impulse method (article §6-§8, ``shared/reference/idem.md``).

Within a time step positions are frozen; the contacts (C_p <= 0) receive impulses until no
pair approaches (C_v > 0 or |C_v| within tolerance). One *round* is a compression phase
followed by a release phase; rounds repeat while some pair approaches.

Compression (§6): the contact with the smallest (most negative) relative normal velocity v_n
gets the normal velocity change dv_n = -v_n / (alpha0 N_comp); its impulse follows the static /
sliding Coulomb rule with the projections of K_AB; the normal work
dW = -1/2 (v_n^(k) + v_n^(k+1)) J_n is stored per pair. Release (§7): Stronge's hypothesis
W_rel = e^2 W_comp per pair; the pair with the largest remaining W_rel gets
dv_n = dvbar / alpha0 with dvbar = -v_n + sqrt(v_n^2 + 2 W_rel n.K.n), and W_rel decreases by
the work 1/2 (v_n^(l) + v_n^(l+1)) J_n of that impulse.

Choices where the article is ambiguous:

* [A6] N_comp, ties: all pairs whose v_n is within ``tie`` (relative) of the minimum form the
  group of the iteration and receive their impulses *together*: every impulse is computed from
  the velocities at the start of the iteration, then all are applied (a face resting on a face
  stays symmetric: no spurious rotation from the order of application). The release phase
  groups ties of W_rel the same way, with the article's factor alpha0 (no N). In a group of N
  pairs the static friction impulse of each pair cancels 1/N of its tangential velocity, so that
  the group cancels it together as one pair does alone (N pairs of one body each cancelling all
  of it at once would overshoot N-fold and amplify round-off into spurious sliding).
* Work bookkeeping: 1/2 (v_n^(k) + v_n^(k+1)) J_n uses the normal velocity *after* the whole
  group (the article's first, trapezoidal form). For one pair this is the article's
  1/2 (2 v_n + dv_n) J_n; for a group it makes the sum of the works equal the change of kinetic
  energy exactly (the impulses ramp together), so no energy is created by the grouping.
* [A7] termination: v_n decays geometrically (dv_n is a fraction of the *current* v_n, as the
  article writes v_n^(k)), so compression stops when every pair has v_n >= -tol v_ref (v_ref the
  fastest approach at the start of the step) and release when every W_rel <= tol W_max (the
  largest at the start of the phase); the unreleased remainder counts as dissipated.
* Which pairs a compression phase works on ("impact" mode):
  ``sequential`` (default): the pairs approaching at the start of the round. A pair that starts
  to approach because of the impulses of the round waits for the next round of the same step,
  after the release. A chain of touching bodies then resolves as a sequence of binary impacts
  (Newton's cradle: the striker stops and the last body leaves with its velocity).
  ``simultaneous``: every contact of the step can join the compression as soon as it approaches
  (one multi-contact compression, then the release of all stored energies).
* [A8] friction: static if mu J_n >= J_t with J_t = v_t / (t.K.t) cancelling the whole tangential
  velocity (1/N of it in a group of N, see [A6]), the impulse J_n n - J_t t; otherwise sliding, J = J_n (n - mu t) with
  J_n = dv_n / (n.K.(n - mu t)): the tangential impulse always opposes the tangential velocity.
  Near jamming (n.K.(n - mu t) < n.K.n / 10, possible for large mu and strong rotational
  coupling) the normal impulse stays dv_n / (n.K.n) and the tangential one is limited to mu J_n.
* [A11] the stored energies restart at zero every round (hence every step); e and mu are global.
* [A12] the projections n.K.n, t.K.t and n.K.(n - mu t) use the full K_AB (rotational coupling
  included); the off-diagonal coupling of a static impulse is not corrected, as in the article.
* Safeguards: after ``max_rounds`` rounds a final fully inelastic compression over all contacts
  ends the step; ``max_iter`` bounds the iterations of any one phase. Both are reported.
"""

from __future__ import annotations

import math

import numpy as np

from granum._jit import jit
from granum.idem import heap as hp
from granum.idem.rigid import k_apply
from granum.kernels.copy import copy_items
from granum.physics.vec import add, cross, dot, load3, matvec, norm, scale, sub

# slots of the per-step statistics array
ST_CONTACTS = 0      # contacts of the step (C_p <= 0)
ST_ROUNDS = 1        # compression/release rounds
ST_COMP_ITERS = 2    # iterations of the compression phases
ST_REL_ITERS = 3     # iterations of the release phases
ST_IMPULSES = 4      # impulses applied (sum of the group sizes)
ST_W_COMP = 5        # normal compression work stored [J]
ST_W_REL = 6         # normal work released [J]
ST_RESIDUAL = 7      # e^2 W_comp left unreleased at the tolerance [J]
ST_FRICTION = 8      # tangential work of the impulses [J] (<= 0: dissipated by friction)
ST_OVERSHOOT = 9     # energy released beyond e^2 W_comp by a group (clamped; should stay 0) [J]
ST_CAPPED = 10       # bit flags: 1 max_rounds was reached, 2 max_iter was reached
ST_SIZE = 11

SEQUENTIAL = 0
SIMULTANEOUS = 1


@jit
def contact_velocity(c, ba, bb, ra, rb, vel, omg):
    """Relative velocity v_iA - v_jB of the particle pair of contact c [m/s] (article §4, C_v)."""
    a = ba[c]
    b = bb[c]
    va = add(load3(vel, a), cross(load3(omg, a), load3(ra, c)))
    vb = add(load3(vel, b), cross(load3(omg, b), load3(rb, c)))
    return sub(va, vb)


@jit
def normal_stiffness(c, ba, bb, ra, rb, nrm, invm, invI):
    """kappa_n = n.K_AB.n [1/kg] of contact c."""
    a = ba[c]
    b = bb[c]
    n = load3(nrm, c)
    return dot(n, k_apply(invm[a], invI[a], load3(ra, c), invm[b], invI[b], load3(rb, c), n))


@jit
def trial_impulse(c, v, dvn, mu, share, ba, bb, ra, rb, nrm, invm, invI, kappa):
    """Impulse on A (on B: its opposite) giving the normal velocity change ``dvn`` (article §6.3-6.4).

    ``v`` the current relative velocity of the pair, ``kappa`` (nc,) the n.K.n of the contacts
    (constant within a step: positions are frozen). Returns ``(J, J_n)``: the impulse (3-tuple)
    [N s] and its normal component. Static friction cancels the fraction ``share`` (1/N in a
    group of N pairs, see [A6]) of the tangential velocity, J_t = share v_t / (t.K.t), when
    mu J_n >= J_t; otherwise the sliding impulse J_n (n - mu t).
    """
    a = ba[c]
    b = bb[c]
    n = load3(nrm, c)
    r_a = load3(ra, c)
    r_b = load3(rb, c)
    kn = kappa[c]
    jn = dvn / kn
    if mu == 0.0:  # frictionless: the normal impulse only
        return scale(n, jn), jn
    vn = dot(v, n)
    vt_vec = sub(v, scale(n, vn))
    vt = norm(vt_vec)
    if vt == 0.0:
        return scale(n, jn), jn
    t = scale(vt_vec, 1.0 / vt)
    Kt = k_apply(invm[a], invI[a], r_a, invm[b], invI[b], r_b, t)
    jt = share * vt / dot(t, Kt)
    if mu * jn >= jt:  # static: cancel the tangential velocity of the pair
        return sub(scale(n, jn), scale(t, jt)), jn
    ks = kn - mu * dot(n, Kt)  # n.K.(n - mu t), K symmetric
    if ks < 0.1 * kn:  # near jamming: keep the normal target, limit friction to mu J_n
        return sub(scale(n, jn), scale(t, mu * jn)), jn
    jn = dvn / ks
    return scale(sub(n, scale(t, mu)), jn), jn


@jit
def apply_impulse(c, J, ba, bb, ra, rb, invm, invI, vel, omg):
    """V_A += J/M_A, w_A += I_A^-1 (r_A x J); V_B -= J/M_B, w_B -= I_B^-1 (r_B x J) (article §6.5)."""
    a = ba[c]
    b = bb[c]
    da = matvec(invI[a], cross(load3(ra, c), J))
    db = matvec(invI[b], cross(load3(rb, c), J))
    for k in range(3):
        vel[a, k] += J[k] * invm[a]
        omg[a, k] += da[k]
        vel[b, k] -= J[k] * invm[b]
        omg[b, k] -= db[k]


@jit
def _group_step(ng, group, dvn_mode, alpha0, mu, Wstore, sign, ba, bb, ra, rb, nrm, invm, invI, kappa, vel, omg,
                v0, Jg, jng, stats):
    """Compute the impulses of a group from the velocities at the start of the iteration, apply
    them together, and book the normal work of each pair into ``Wstore`` (``sign`` -1: compression
    stores -work; +1: release removes work). ``dvn_mode`` 0: dv_n = -v_n / (alpha0 N) (compression);
    1: dv_n = dvbar / alpha0 from the pair's remaining energy (release)."""
    for g in range(ng):
        c = group[g]
        v = contact_velocity(c, ba, bb, ra, rb, vel, omg)
        for k in range(3):
            v0[g, k] = v[k]
        n = load3(nrm, c)
        vn = dot(v, n)
        if dvn_mode == 0:
            dvn = -vn / (alpha0 * ng)
        else:
            w2 = 2.0 * Wstore[c] * kappa[c]
            root = math.sqrt(vn * vn + w2)
            # dvbar = -v_n + sqrt(v_n^2 + 2 W kappa), in the form without cancellation for v_n > 0
            dvbar = w2 / (vn + root) if vn > 0.0 else root - vn
            dvn = dvbar / alpha0
        J, jn = trial_impulse(c, v, dvn, mu, 1.0 / ng, ba, bb, ra, rb, nrm, invm, invI, kappa)
        for k in range(3):
            Jg[g, k] = J[k]
        jng[g] = jn
    for g in range(ng):
        apply_impulse(group[g], (Jg[g, 0], Jg[g, 1], Jg[g, 2]), ba, bb, ra, rb, invm, invI, vel, omg)
    for g in range(ng):
        c = group[g]
        v1 = contact_velocity(c, ba, bb, ra, rb, vel, omg)
        n = load3(nrm, c)
        vb = (v0[g, 0], v0[g, 1], v0[g, 2])
        wn = 0.5 * (dot(vb, n) + dot(v1, n)) * jng[g]
        wt = 0.5 * dot((Jg[g, 0], Jg[g, 1], Jg[g, 2]), add(vb, v1))
        stats[ST_FRICTION] += wt - wn
        # compression: W_comp += -work (work < 0 while approaching); release: W_rel -= work
        Wstore[c] -= wn
        if sign < 0.0:
            stats[ST_W_COMP] -= wn
        else:
            stats[ST_W_REL] += wn
            if Wstore[c] < 0.0:
                stats[ST_OVERSHOOT] -= Wstore[c]
                Wstore[c] = 0.0
    stats[ST_IMPULSES] += ng


@jit
def _compress(members, nm, tol_v, alpha0, tie, mu, max_iter, ba, bb, ra, rb, nrm, fixed, invm, invI, kappa, vel,
              omg, cstart, clist, keys, heap, where, Wc, group, stack, v0, Jg, jng, cstamp, bstamp, stamp, stats):
    """Compression phase over the contacts ``members[:nm]`` (article §6); returns the stamp counter."""
    size = 0
    for m in range(nm):
        c = members[m]
        keys[c] = dot(contact_velocity(c, ba, bb, ra, rb, vel, omg), load3(nrm, c))
        size = hp.push(keys, heap, where, size, c)
    iters = 0
    while size > 0:
        vmin = keys[heap[0]]
        if vmin >= -tol_v:
            break
        if iters >= max_iter:
            stats[ST_CAPPED] = float(int(stats[ST_CAPPED]) | 2)
            break
        ng = hp.collect(keys, heap, size, vmin + tie * abs(vmin), group, stack)
        _group_step(ng, group, 0, alpha0, mu, Wc, -1.0, ba, bb, ra, rb, nrm, invm, invI, kappa, vel, omg, v0, Jg,
                    jng, stats)
        # the impulses changed the velocity of every contact of the free bodies involved
        stamp += 1
        for g in range(ng):
            c = group[g]
            for body in (ba[c], bb[c]):
                if fixed[body] or bstamp[body] == stamp:
                    continue
                bstamp[body] = stamp
                for u in range(cstart[body], cstart[body + 1]):
                    c2 = clist[u]
                    if where[c2] >= 0 and cstamp[c2] != stamp:
                        cstamp[c2] = stamp
                        vn = dot(contact_velocity(c2, ba, bb, ra, rb, vel, omg), load3(nrm, c2))
                        hp.update(keys, heap, where, size, c2, vn)
        iters += 1
    hp.clear(heap, where, size)
    stats[ST_COMP_ITERS] += iters
    return stamp


@jit
def _release(members, nm, e, tol, alpha0, tie, mu, max_iter, ba, bb, ra, rb, nrm, invm, invI, kappa, vel, omg,
             keys, heap, where, Wc, Wr, group, stack, v0, Jg, jng, stats):
    """Release phase (article §7): W_rel = e^2 W_comp per pair, largest first."""
    size = 0
    wmax = 0.0
    for m in range(nm):
        c = members[m]
        Wr[c] = e * e * Wc[c]
        if Wr[c] > 0.0:
            keys[c] = -Wr[c]
            size = hp.push(keys, heap, where, size, c)
            wmax = max(wmax, Wr[c])
    tol_w = tol * wmax
    iters = 0
    while size > 0:
        w = -keys[heap[0]]
        if w <= tol_w:
            break
        if iters >= max_iter:
            stats[ST_CAPPED] = float(int(stats[ST_CAPPED]) | 2)
            break
        ng = hp.collect(keys, heap, size, -w + tie * w, group, stack)
        _group_step(ng, group, 1, alpha0, mu, Wr, 1.0, ba, bb, ra, rb, nrm, invm, invI, kappa, vel, omg, v0, Jg,
                    jng, stats)
        for g in range(ng):
            hp.update(keys, heap, where, size, group[g], -Wr[group[g]])
        iters += 1
    hp.clear(heap, where, size)
    for m in range(nm):
        stats[ST_RESIDUAL] += Wr[members[m]]
        Wr[members[m]] = 0.0
    stats[ST_REL_ITERS] += iters


@jit
def contact_csr(nb, ba, bb, fixed):
    """Contacts of each free body: ``(start (nb+1,), list)``, in increasing contact index."""
    count = np.zeros(nb + 1, np.int64)
    for c in range(ba.shape[0]):
        if not fixed[ba[c]]:
            count[ba[c] + 1] += 1
        if not fixed[bb[c]] and bb[c] != ba[c]:
            count[bb[c] + 1] += 1
    for b in range(nb):
        count[b + 1] += count[b]
    out = np.empty(count[nb], np.int64)
    fill = count[:nb].copy()
    for c in range(ba.shape[0]):
        if not fixed[ba[c]]:
            out[fill[ba[c]]] = c
            fill[ba[c]] += 1
        if not fixed[bb[c]] and bb[c] != ba[c]:
            out[fill[bb[c]]] = c
            fill[bb[c]] += 1
    return count, out


@jit
def resolve(e, mu, alpha0, tol, tie, mode, max_rounds, max_iter, ba, bb, ra, rb, nrm, fixed, invm, invI, vel, omg,
            stats):
    """Resolve the contacts of one time step by rounds of compression and release.

    Parameters: restitution ``e`` in [0, 1], friction ``mu`` >= 0, iteration parameter
    ``alpha0`` > 0, relative tolerance ``tol``, relative tie tolerance ``tie``, ``mode``
    (SEQUENTIAL or SIMULTANEOUS), the safeguards ``max_rounds``/``max_iter``; contacts
    ``ba``/``bb`` (nc,) bodies A and B, ``ra``/``rb`` (nc, 3) lever arms [m], ``nrm`` (nc, 3)
    unit normals out of B; bodies ``fixed`` (nb,), ``invm`` (nb,) [1/kg], ``invI`` (nb, 3, 3)
    world inverse inertia [1/(kg m^2)], ``vel``/``omg`` (nb, 3) [m/s, rad/s] updated in place.
    ``stats`` (ST_SIZE,) receives the step's counters and energies (see the ST_* slots).
    """
    nc = ba.shape[0]
    nb = vel.shape[0]
    stats[ST_CONTACTS] = nc
    if nc == 0:
        return
    cstart, clist = contact_csr(nb, ba, bb, fixed)
    kappa = np.empty(nc)
    for c in range(nc):
        kappa[c] = normal_stiffness(c, ba, bb, ra, rb, nrm, invm, invI)
    # velocity scale: the fastest approach now, with a floor at round-off of the body speeds
    vref = 0.0
    for c in range(nc):
        vref = max(vref, -dot(contact_velocity(c, ba, bb, ra, rb, vel, omg), load3(nrm, c)))
    vbody = 0.0
    for b in range(nb):
        vbody = max(vbody, norm(load3(vel, b)))
    tol_v = max(tol * vref, 1e-12 * vbody, 1e-300)
    if vref <= tol_v:
        return
    keys = np.zeros(nc)
    heap = np.empty(nc, np.int64)
    where = np.full(nc, -1, np.int64)
    Wc = np.zeros(nc)
    Wr = np.zeros(nc)
    group = np.empty(nc, np.int64)
    stack = np.empty(nc, np.int64)
    v0 = np.empty((nc, 3))
    Jg = np.empty((nc, 3))
    jng = np.empty(nc)
    cstamp = np.zeros(nc, np.int64)
    bstamp = np.zeros(nb, np.int64)
    members = np.empty(nc, np.int64)
    everything = np.arange(nc)
    stamp = 0
    rounds = 0
    while True:
        nm = 0
        for c in range(nc):
            if dot(contact_velocity(c, ba, bb, ra, rb, vel, omg), load3(nrm, c)) < -tol_v:
                members[nm] = c
                nm += 1
        if nm == 0:
            break
        if rounds >= max_rounds:  # safeguard: end with a fully inelastic compression of everything
            stats[ST_CAPPED] = float(int(stats[ST_CAPPED]) | 1)
            stamp = _compress(everything, nc, tol_v, alpha0, tie, mu, max_iter, ba, bb, ra, rb, nrm, fixed, invm,
                              invI, kappa, vel, omg, cstart, clist, keys, heap, where, Wc, group, stack, v0, Jg, jng,
                              cstamp, bstamp, stamp, stats)
            break
        if mode == SIMULTANEOUS:
            nm = nc
            copy_items(members, everything, nc)
        for m in range(nm):
            Wc[members[m]] = 0.0
        stamp = _compress(members, nm, tol_v, alpha0, tie, mu, max_iter, ba, bb, ra, rb, nrm, fixed, invm, invI,
                          kappa, vel, omg, cstart, clist, keys, heap, where, Wc, group, stack, v0, Jg, jng, cstamp,
                          bstamp, stamp, stats)
        _release(members, nm, e, tol, alpha0, tie, mu, max_iter, ba, bb, ra, rb, nrm, invm, invI, kappa, vel, omg, keys,
                 heap, where, Wc, Wr, group, stack, v0, Jg, jng, stats)
        rounds += 1
    stats[ST_ROUNDS] = rounds
