"""Compiled kernels behind :mod:`granum.yade.pack`: random sequential insertion of spheres.

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

Radii come either from a given array (deterministic sizes, placed in the given order) or
are drawn one per sphere from a piecewise inverse cumulative distribution (see
:func:`inverse_cdf`). All random numbers come from NumPy's generator *inside* the compiled
code, seeded from the ``seed`` argument, so a seed reproduces a cloud bit for bit.
"""

from __future__ import annotations

import numpy as np

from granum._jit import jit

__all__ = ["inverse_cdf", "inverse_cdf_many", "psd_table", "rsa_fill"]

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
    np.random.seed(seed)
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
    # grid: cells at least one largest diameter wide, total count bounded
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
    head = np.full(nc[0] * nc[1] * nc[2], -1, np.int64)

    cap = max(16, 2 * n0 + (len(radii) if given else 1024))
    pos = np.empty((cap, 3))
    rad = np.empty(cap)
    nxt = np.full(cap, -1, np.int64)
    for i in range(n0):
        pos[i] = pos0[i]
        rad[i] = rad0[i]
        k = _cell_of(pos[i], lo, inv_w, nc, per)
        nxt[i] = head[k]
        head[k] = i
    n = n0
    p = np.empty(3)
    m = 0
    while True:
        if given:
            if m >= len(radii):
                break
            r = radii[m]
        else:
            r = inverse_cdf(np.random.random(), cdf, rtab, mass)
        m += 1
        placed = False
        for _ in range(max_try):
            for d in range(3):
                u = np.random.random()
                if length[d] <= 0.0:
                    p[d] = lo[d]
                elif per:
                    p[d] = lo[d] + u * length[d]
                else:
                    p[d] = lo[d] + r + u * (length[d] - 2.0 * r)
            if not _overlaps(p, r, pos, rad, head, nxt, lo, inv_w, nc, per, length):
                placed = True
                break
        if not placed:
            break
        if n == cap:  # grow storage geometrically (amortised O(1) per sphere)
            cap *= 2
            pos2 = np.empty((cap, 3))
            rad2 = np.empty(cap)
            nxt2 = np.full(cap, -1, np.int64)
            pos2[:n] = pos[:n]
            rad2[:n] = rad[:n]
            nxt2[:n] = nxt[:n]
            pos, rad, nxt = pos2, rad2, nxt2
        pos[n] = p
        rad[n] = r
        k = _cell_of(p, lo, inv_w, nc, per)
        nxt[n] = head[k]
        head[k] = n
        n += 1
    return pos, rad, n
