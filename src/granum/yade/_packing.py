"""Compiled kernels behind :mod:`granum.yade.pack`: random sequential insertion of spheres
(``rsa_fill``, for ``makeCloud``) and of rigid clumps of spheres (``clump_fill``, for
``makeClumpCloud``).

``rsa_fill`` places spheres one after another at uniformly random positions, rejecting a
position when the new sphere would overlap one already placed, and gives up the whole
generation at the first sphere for which ``max_try`` positions all failed (this is what
YADE's ``makeCloud`` does, and it is what makes the cloud "loose": it stops long before
the random-sequential-addition jamming limit).

Overlap tests use a uniform cell grid whose cells are at least one largest diameter wide,
so a new sphere can only touch spheres of its own cell and of the 26 neighbouring ones;
each test is therefore O(1) instead of O(N), and 10^5 spheres take seconds. The grid is a
linked list (``head[cell]`` -> sphere -> ``nxt[sphere]`` -> ...), which needs no resizing
when spheres are added.

``clump_fill`` inserts whole clumps the same way: a clump is a template (member centres
relative to a reference point, and radii) at a random point with a uniformly random
orientation, rejected when one of its members overlaps a sphere already placed. It uses
the same grid; the members of a clump enter it only once the whole clump is accepted.

Radii come either from a given array (deterministic sizes, placed in the given order) or
are drawn one per sphere from a piecewise inverse cumulative distribution (see
:func:`inverse_cdf`). ``rsa_fill``'s random numbers are YADE's (:mod:`granum.yade._stdrandom`: std::mt19937
seeded with ``seed``, drawn in YADE's order: a sphere's radius, then x, y, z per try), so a seed gives YADE's
cloud; ``clump_fill``'s come from NumPy's generator inside the compiled code. Either way a seed reproduces a
cloud bit for bit.
"""

from __future__ import annotations

import numpy as np

from granum._jit import jit
from granum.kernels.copy import copy_items, copy_rows, copy_to_row
from granum.yade._stdrandom import mt_new, mt_uniform

__all__ = ["clump_fill", "inverse_cdf", "inverse_cdf_many", "psd_table", "rsa_fill"]

#: Upper bound on the number of grid cells (memory: 8 bytes each).
_MAX_CELLS = 1 << 22


@jit
def inverse_cdf(u, cdf, rad, mass):
    """Radius whose cumulative *number* fraction is ``u`` (0 <= u <= 1).

    ``cdf`` (K,) non-decreasing knots from 0 to 1 and ``rad`` (K,) the radii at those knots.
    Between knots the radius is linear in ``u`` when ``mass`` is False (number-uniform
    sizes). When ``mass`` is True the *mass* is uniform in size within each segment, so
    the number density goes as r**-3 and ``r**-2`` is linear in ``u`` (``cdf`` must then
    already hold number fractions, converted by the caller).
    """
    k = len(cdf)
    for i in range(k - 1):
        f0 = cdf[i]
        f1 = cdf[i + 1]
        if u <= f1 and f1 > f0:
            t = (u - f0) / (f1 - f0)
            if t < 0.0:
                t = 0.0
            r0 = rad[i]
            r1 = rad[i + 1]
            if mass and r0 > 0.0 and r1 > 0.0 and r1 != r0:
                return 1.0 / np.sqrt(r0 ** -2 + t * (r1 ** -2 - r0 ** -2))
            return r0 + t * (r1 - r0)
    return rad[k - 1]


@jit
def inverse_cdf_many(u, cdf, rad, mass):
    """:func:`inverse_cdf` for each value of the array ``u``; returns an array like ``u``."""
    out = np.empty(len(u))
    for i in range(len(u)):
        out[i] = inverse_cdf(u[i], cdf, rad, mass)
    return out


def psd_table(psdSizes, psdCumm, distributeMass):
    """Knots ``(cdf, radii)`` for :func:`inverse_cdf` from a PSD given as sieve sizes
    (diameters) and cumulative fractions, by number or (``distributeMass``) by mass."""
    d = np.asarray(psdSizes, dtype=np.float64)
    f = np.asarray(psdCumm, dtype=np.float64)
    if d.shape != f.shape or d.ndim != 1 or len(d) < 2:
        raise ValueError("psdSizes and psdCumm must be sequences of the same length >= 2")
    if np.any(np.diff(d) < 0) or np.any(np.diff(f) < 0) or f[-1] <= 0 or d[0] <= 0:
        raise ValueError("psdSizes and psdCumm must be positive and non-decreasing")
    if f[0] > 0:  # a fraction at the smallest size: a vertical step from 0
        d, f = np.concatenate([d[:1], d]), np.concatenate([[0.0], f])
    f = f / f[-1]
    if distributeMass:
        # mass uniform in size within a segment -> number density ~ d^-3; integrate it
        dm, d0, d1 = np.diff(f), d[:-1], d[1:]
        with np.errstate(divide="ignore", invalid="ignore"):
            w = np.where(d1 > d0, dm / (d1 - d0) * 0.5 * (d0 ** -2.0 - d1 ** -2.0), dm / d0 ** 3)
        f = np.concatenate([[0.0], np.cumsum(w)]) / np.sum(w)
    return f, 0.5 * d


@jit
def _grid_dims(length, rmax):
    """Grid over a box of size ``length`` (3,) for spheres of radius at most ``rmax``.

    Cells are at least one largest diameter wide, so a sphere can only touch spheres of
    its own and the 26 neighbouring cells; at most 1024 cells per axis and
    ``_MAX_CELLS`` in all. Returns ``(nc (3,) int64 cell counts, inv_w (3,) cells per
    unit length)``; an axis of zero length has one cell and ``inv_w = 0``.
    """
    width = max(2.0 * rmax, 1e-300)
    nc = np.ones(3, np.int64)
    inv_w = np.zeros(3)
    for d in range(3):
        if length[d] > 0.0:
            nc[d] = max(1, min(int(length[d] / width), 1 << 10))
    while nc[0] * nc[1] * nc[2] > _MAX_CELLS:
        for d in range(3):
            nc[d] = max(1, nc[d] // 2)
    for d in range(3):
        if length[d] > 0.0:
            inv_w[d] = nc[d] / length[d]
    return nc, inv_w


@jit
def _cell_of(p, lo, inv_w, nc, per):
    """Flat grid index of point ``p``: wrapped into the cell if periodic, else clamped."""
    idx = 0
    for d in range(3):
        c = int(np.floor((p[d] - lo[d]) * inv_w[d]))
        if per:
            c %= nc[d]
        elif c < 0:
            c = 0
        elif c >= nc[d]:
            c = nc[d] - 1
        idx = idx * nc[d] + c
    return idx


@jit
def _overlaps(p, r, pos, rad, head, nxt, lo, inv_w, nc, per, length):
    """True if a sphere (``p``, ``r``) overlaps any sphere stored in the grid."""
    ci = np.empty(3, np.int64)
    for d in range(3):
        c = int(np.floor((p[d] - lo[d]) * inv_w[d]))
        if per:
            c %= nc[d]
        elif c < 0:
            c = 0
        elif c >= nc[d]:
            c = nc[d] - 1
        ci[d] = c
    # one cell along an axis: every neighbour offset is that same cell, so scan it once
    s0 = -1 if nc[0] > 1 else 0
    s1 = -1 if nc[1] > 1 else 0
    s2 = -1 if nc[2] > 1 else 0
    for a in range(s0, -s0 + 1):
        x = ci[0] + a
        if per:
            x %= nc[0]
        elif x < 0 or x >= nc[0]:
            continue
        for b in range(s1, -s1 + 1):
            y = ci[1] + b
            if per:
                y %= nc[1]
            elif y < 0 or y >= nc[1]:
                continue
            for c in range(s2, -s2 + 1):
                z = ci[2] + c
                if per:
                    z %= nc[2]
                elif z < 0 or z >= nc[2]:
                    continue
                j = head[(x * nc[1] + y) * nc[2] + z]
                while j >= 0:
                    d2 = 0.0
                    for d in range(3):
                        dx = p[d] - pos[j, d]
                        if per and length[d] > 0.0:
                            dx -= length[d] * np.round(dx / length[d])  # minimum image
                        d2 += dx * dx
                    rr = r + rad[j]
                    if d2 < rr * rr:
                        return True
                    j = nxt[j]
    return False


@jit
def _grid_new(pos0, rad0, cap, lo, inv_w, nc, per):
    """Sphere storage with room for ``cap`` spheres (``cap >= len(rad0)``), holding the
    existing spheres ``pos0`` (N,3), ``rad0`` (N,) in a linked-cell grid of ``nc`` cells.
    Returns ``(pos, rad, nxt, head)``: cell ``c`` holds spheres ``head[c]``, ``nxt[head[c]]``..."""
    head = np.full(nc[0] * nc[1] * nc[2], -1, np.int64)
    pos = np.empty((cap, 3))
    rad = np.empty(cap)
    nxt = np.full(cap, -1, np.int64)
    for i in range(len(rad0)):
        _grid_put(pos, rad, nxt, head, i, pos0[i], rad0[i], lo, inv_w, nc, per)
    return pos, rad, nxt, head


@jit
def _grid_put(pos, rad, nxt, head, i, p, r, lo, inv_w, nc, per):
    """Store sphere ``i`` (centre ``p``, radius ``r``) and link it into its grid cell."""
    copy_to_row(pos, i, p)
    rad[i] = r
    c = _cell_of(pos[i], lo, inv_w, nc, per)
    nxt[i] = head[c]
    head[c] = i


@jit
def _grid_reserve(pos, rad, nxt, n, need):
    """Storage with room for ``need`` spheres, keeping the first ``n``; grows geometrically
    (amortised O(1) per sphere) and returns the arrays unchanged when they are big enough."""
    if need <= len(rad):
        return pos, rad, nxt
    cap = max(need, 2 * len(rad))
    pos2 = np.empty((cap, 3))
    rad2 = np.empty(cap)
    nxt2 = np.full(cap, -1, np.int64)
    copy_rows(pos2, pos, n)
    copy_items(rad2, rad, n)
    copy_items(nxt2, nxt, n)
    return pos2, rad2, nxt2


@jit
def rsa_fill(pos0, rad0, lo, length, per, radii, cdf, rtab, mass, max_try, seed):
    """Append non-overlapping spheres to (``pos0`` (N0,3), ``rad0`` (N0,)) until the first failure.

    Domain: the box ``lo`` .. ``lo + length`` (3,). Non-periodic: centres drawn so that the
    sphere lies inside the box (an axis of zero length is a 2D packing: that coordinate
    stays ``lo``). Periodic (``per``): centres anywhere in ``[lo, lo + length)`` and the
    overlap test uses the minimum image.

    Radii: ``radii`` (M,) if M > 0, placed in that order (at most M spheres); otherwise one
    radius per sphere drawn through :func:`inverse_cdf` with (``cdf``, ``rtab``, ``mass``),
    without limit. Each sphere gets ``max_try`` random positions; when all of them overlap,
    generation stops. Returns ``(pos, rad, n)``: arrays whose first ``n`` rows are the old
    spheres followed by the new ones.
    """
    rng = mt_new(seed)
    n0 = len(rad0)
    given = len(radii) > 0
    rmax = 0.0
    for i in range(n0):
        rmax = max(rmax, rad0[i])
    if given:
        for i in range(len(radii)):
            rmax = max(rmax, radii[i])
    else:
        for i in range(len(rtab)):
            rmax = max(rmax, rtab[i])
    nc, inv_w = _grid_dims(length, rmax)
    cap = max(16, 2 * n0 + (len(radii) if given else 1024))
    pos, rad, nxt, head = _grid_new(pos0, rad0, cap, lo, inv_w, nc, per)
    n = n0
    p = np.empty(3)
    m = 0
    while True:
        if given:
            if m >= len(radii):
                break
            r = radii[m]
        else:
            r = inverse_cdf(mt_uniform(rng), cdf, rtab, mass)
        m += 1
        placed = False
        for _ in range(max_try):
            for d in range(3):
                if length[d] <= 0.0:  # the flat axis of a 2D packing: no number drawn, as in YADE
                    p[d] = lo[d]
                    continue
                u = mt_uniform(rng)
                if per:
                    p[d] = lo[d] + u * length[d]
                else:
                    p[d] = lo[d] + r + u * (length[d] - 2.0 * r)
            if not _overlaps(p, r, pos, rad, head, nxt, lo, inv_w, nc, per, length):
                placed = True
                break
        if not placed:
            break
        pos, rad, nxt = _grid_reserve(pos, rad, nxt, n, n + 1)
        _grid_put(pos, rad, nxt, head, n, p, r, lo, inv_w, nc, per)
        n += 1
    return pos, rad, n


@jit
def _random_rotation(R):
    """Write into ``R`` (3, 3) a rotation drawn uniformly from SO(3) (Haar measure).

    The unit quaternion is a 4D normal vector normalised, which is uniform on the 3-sphere
    because the normal distribution is isotropic; normalising uniform [0, 1) components
    instead would favour rotations close to one octant (YADE 2023.02a does that).
    """
    n2 = 0.0
    while n2 < 1e-12:  # a (near) zero vector has no direction: draw again
        w = np.random.standard_normal()
        x = np.random.standard_normal()
        y = np.random.standard_normal()
        z = np.random.standard_normal()
        n2 = w * w + x * x + y * y + z * z
    s = 2.0 / n2  # 2/|q|^2 normalises q inside the matrix formula
    R[0, 0] = 1.0 - s * (y * y + z * z)
    R[0, 1] = s * (x * y - w * z)
    R[0, 2] = s * (x * z + w * y)
    R[1, 0] = s * (x * y + w * z)
    R[1, 1] = 1.0 - s * (x * x + z * z)
    R[1, 2] = s * (y * z - w * x)
    R[2, 0] = s * (x * z - w * y)
    R[2, 1] = s * (y * z + w * x)
    R[2, 2] = 1.0 - s * (x * x + y * y)


@jit
def clump_fill(pos0, rad0, lo, length, per, tpl_start, tpl_rel, tpl_rad, num, max_try, seed):
    """Append rigid clumps of spheres to (``pos0`` (N0,3), ``rad0`` (N0,)) by random insertion.

    Templates: template ``t`` is the spheres ``tpl_start[t]:tpl_start[t+1]`` of ``tpl_rel``
    (M,3), member centres relative to the template's reference point, and ``tpl_rad`` (M,).
    Each new clump takes a template drawn uniformly, then gets up to ``max_try`` attempts,
    each with a reference point uniform in the box ``lo`` .. ``lo + length`` (3,) and a
    uniformly random orientation. An attempt fails when one member overlaps a sphere
    already placed (members of one clump may overlap each other) or, unless ``per``, lies
    partly outside the box; with ``per`` the overlap test uses the minimum image and
    members may stick out of the box. Generation stops after ``num`` clumps (``num < 0``:
    no limit) or at the first clump whose attempts all failed.

    Returns ``(pos, rad, n, tpl_of, k)``: the first ``n`` rows of ``pos``/``rad`` are the old
    spheres followed by the members of the new clumps, clump after clump in template
    order; ``tpl_of[:k]`` is the template of each of the ``k`` new clumps.
    """
    np.random.seed(seed)
    n0 = len(rad0)
    ntpl = len(tpl_start) - 1
    rmax = 0.0
    for i in range(n0):
        rmax = max(rmax, rad0[i])
    for i in range(len(tpl_rad)):
        rmax = max(rmax, tpl_rad[i])
    nc, inv_w = _grid_dims(length, rmax)

    big = 0  # largest template: room for one candidate clump
    for t in range(ntpl):
        big = max(big, tpl_start[t + 1] - tpl_start[t])
    cap = max(16, 2 * n0 + (num * big if num > 0 else 1024))
    pos, rad, nxt, head = _grid_new(pos0, rad0, cap, lo, inv_w, nc, per)
    tpl_of = np.empty(max(16, num if num > 0 else 1024), np.int64)
    cand = np.empty((big, 3))
    ref = np.empty(3)
    R = np.empty((3, 3))
    n = n0
    k = 0
    while num < 0 or k < num:
        t = min(int(np.random.random() * ntpl), ntpl - 1)
        s0 = tpl_start[t]
        m = tpl_start[t + 1] - s0
        placed = False
        for _ in range(max_try):
            for d in range(3):
                ref[d] = lo[d] + np.random.random() * length[d]
            _random_rotation(R)
            ok = True
            for j in range(m):
                r = tpl_rad[s0 + j]
                for d in range(3):
                    cand[j, d] = ref[d] + (R[d, 0] * tpl_rel[s0 + j, 0] + R[d, 1] * tpl_rel[s0 + j, 1]
                                           + R[d, 2] * tpl_rel[s0 + j, 2])
                    if not per and (cand[j, d] - r < lo[d] or cand[j, d] + r > lo[d] + length[d]):
                        ok = False
                if ok and _overlaps(cand[j], r, pos, rad, head, nxt, lo, inv_w, nc, per, length):
                    ok = False
                if not ok:
                    break
            if ok:
                placed = True
                break
        if not placed:
            break
        pos, rad, nxt = _grid_reserve(pos, rad, nxt, n, n + m)
        if k == len(tpl_of):
            tpl2 = np.empty(2 * k, np.int64)
            copy_items(tpl2, tpl_of, k)
            tpl_of = tpl2
        # members go into the grid only now: they must not be tested against each other
        for j in range(m):
            _grid_put(pos, rad, nxt, head, n, cand[j], tpl_rad[s0 + j], lo, inv_w, nc, per)
            n += 1
        tpl_of[k] = t
        k += 1
    return pos, rad, n, tpl_of, k
