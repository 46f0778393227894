"""Contact search between the particles of different rigid bodies (article §4, [A5]).

The article's position condition C_p = (x_iA - x_jB) . n_jB <= 0 says nothing about which
particle pairs to test: any particle behind the tangent plane of j satisfies it. Choices:

* Candidates: surface particles of *different* bodies (not both fixed) closer than a cut-off
  ``cutoff * (s_i + s_j) / 2``, s the particle spacing (default factor 0.8: a particle resting
  on a face of a lattice with the same spacing is at most s / sqrt(2) from the nearest particle
  of that face, and particles one spacing away along a neighbouring coplanar face stay out).
* For every surface particle and every other body within reach, only the *nearest* particle of
  that body is kept: it carries the local tangent plane of that body. Pairs found from both
  sides are merged, so each pair appears once; the list is sorted by particle index.
* The normal of a pair: the article always uses the normal of the particle of "B". We take the
  normal of the *flatter* particle (smaller surface variation sigma, see :mod:`granum.idem.pca`),
  a fixed body's particle winning ties against a free body (floors and slopes carry exact given
  normals). When neither particle is clearly flatter (sigma within a factor 2, e.g. face on
  face, edge on edge of equal boxes) the two normals are averaged, n = (n_j - n_i) / |n_j - n_i|,
  which for coplanar faces is the face normal even at their edges and corners.
* The pair is a contact when C_p <= 1e-9 x the spacing (touching within round-off counts, so
  bodies placed exactly in contact are detected).

The search has two levels, like granum's collider but over particles (the core collider works
on whole bodies through the scene record, so iDEM has its own small grid): bodies whose
bounding boxes, grown by the cut-off, overlap another's (sort and sweep); then a uniform grid
(cells of twice the largest cut-off, hashed) over the surface particles of those bodies, each
particle scanning the 2 x 2 x 2 cells on its side. The output is deterministic and independent
of the thread count.
"""

from __future__ import annotations

import math

import numpy as np

from granum._jit import PARALLEL_THRESHOLD, jit, kernel, prange

#: A particle is "clearly flatter" than its partner when its surface variation is below this
#: fraction of the partner's.
FLATTER = 0.5
#: Contact when C_p <= TOUCH x spacing (bodies placed exactly touching count as in contact).
TOUCH = 1e-9


@jit
def build_grid(xs, h):
    """Bin points ``xs`` (ns, 3) into cubic cells of size ``h`` [m], with a hash table of the cells.

    Returns ``(lo, h, dims, cell, order, table)``: the grid origin (3,) and the cell size actually
    used (``h`` grows if an axis would need more than 2**20 cells), cells per axis (3,), cell of
    each point (ns, 3), point indices sorted by cell key, and an open-addressing hash table
    (size, 3) (size a power of two) of rows (cell key, first, last): the points of that cell are
    ``order[first:last]`` (key -1: empty slot).
    """
    ns = xs.shape[0]
    lo = np.empty(3)
    hi = np.empty(3)
    for k in range(3):
        lo[k] = xs[0, k] if ns > 0 else 0.0
        hi[k] = lo[k]
    for i in range(ns):
        for k in range(3):
            lo[k] = min(lo[k], xs[i, k])
            hi[k] = max(hi[k], xs[i, k])
    for k in range(3):  # keys must fit in int64: at most 2**20 cells per axis
        h = max(h, (hi[k] - lo[k]) / (1 << 20))
    dims = np.ones(3, np.int64)
    for k in range(3):
        dims[k] = int((hi[k] - lo[k]) / h) + 1
    cell = np.empty((ns, 3), np.int64)
    keys = np.empty(ns, np.int64)
    for i in range(ns):
        for k in range(3):
            cell[i, k] = min(int((xs[i, k] - lo[k]) / h), dims[k] - 1)
        keys[i] = (cell[i, 0] * dims[1] + cell[i, 1]) * dims[2] + cell[i, 2]
    order = np.argsort(keys, kind="mergesort")
    size = 16
    while size < 2 * ns:
        size *= 2
    table = np.full((size, 3), -1, np.int64)  # key, first, last: one cache line per probe
    u = 0
    while u < ns:
        key = keys[order[u]]
        v = u + 1
        while v < ns and keys[order[v]] == key:
            v += 1
        slot = hash_slot(key, size)
        while table[slot, 0] >= 0:
            slot = (slot + 1) & (size - 1)
        table[slot, 0] = key
        table[slot, 1] = u
        table[slot, 2] = v
        u = v
    return lo, h, dims, cell, order, table


@jit
def hash_slot(key, size):
    """Home slot of a cell key in a table of ``size`` (a power of two) slots: the key modulo size.

    Neighbouring cells (consecutive keys) land in neighbouring slots, so the queries, made in cell
    order, read the table almost sequentially; scrambling the keys was 2x slower (cache misses).
    """
    return key & (size - 1)


@jit
def cell_range(key, table):
    """Range [a, b) of ``order`` holding the points of cell ``key`` (empty if the cell is)."""
    size = table.shape[0]
    slot = hash_slot(key, size)
    while table[slot, 0] >= 0:
        if table[slot, 0] == key:
            return table[slot, 1], table[slot, 2]
        slot = (slot + 1) & (size - 1)
    return 0, 0


@jit
def near_bodies(x, surf, pbody, pspacing, fixed, nb, factor):
    """Bodies (nb,) bool whose bounding box, grown by the cut-off, overlaps another's (not both fixed).

    Sort and sweep along x over the boxes of the surface particles ``surf`` (positions ``x``,
    bodies ``pbody``); only the particles of these bodies can be in contact, the others skip the
    particle search.
    """
    lo = np.full((nb, 3), np.inf)
    hi = np.full((nb, 3), -np.inf)
    reach = np.zeros(nb)
    for u in range(surf.shape[0]):
        i = surf[u]
        b = pbody[i]
        reach[b] = max(reach[b], factor * pspacing[i])
        for k in range(3):
            lo[b, k] = min(lo[b, k], x[i, k])
            hi[b, k] = max(hi[b, k], x[i, k])
    for b in range(nb):
        for k in range(3):
            lo[b, k] -= reach[b]
            hi[b, k] += reach[b]
    order = np.argsort(lo[:, 0], kind="mergesort")
    near = np.zeros(nb, np.bool_)
    for u in range(nb):
        i = order[u]
        if not lo[i, 0] <= hi[i, 0]:
            continue  # no surface particle
        for w in range(u + 1, nb):
            j = order[w]
            if lo[j, 0] > hi[i, 0]:
                break
            if fixed[i] and fixed[j]:
                continue
            if lo[j, 1] <= hi[i, 1] and lo[i, 1] <= hi[j, 1] and lo[j, 2] <= hi[i, 2] and lo[i, 2] <= hi[j, 2]:
                near[i] = True
                near[j] = True
    return near


def _within(xs, sb, sd, fixed, factor, dims, cell, order, table, count, part, dist):
    """For each point s: the points of other bodies (not both fixed) within the pair cut-off, reduced
    to the nearest point of each such body (ties: the smaller index), written into row s of
    ``part``/``dist`` (ns, cap) with their number in ``count[s]`` (which may exceed cap: then the
    caller repeats with a larger cap). Cells are at least twice the cut-off, so the 2 x 2 x 2
    cells on the side of the point's half-cell hold every point within reach."""
    cap = part.shape[1]
    for v in prange(xs.shape[0]):
        s = order[v]  # in cell order: consecutive queries read the same cells (cache locality)
        a = sb[s]
        n = 0
        c0 = cell[s, 0] - 1 + cell[s, 3]
        c1 = cell[s, 1] - 1 + cell[s, 4]
        c2 = cell[s, 2] - 1 + cell[s, 5]
        for cx in range(c0, c0 + 2):
            if cx < 0 or cx >= dims[0]:
                continue
            for cy in range(c1, c1 + 2):
                if cy < 0 or cy >= dims[1]:
                    continue
                for cz in range(c2, c2 + 2):
                    if cz < 0 or cz >= dims[2]:
                        continue
                    lo, hi = cell_range((cx * dims[1] + cy) * dims[2] + cz, table)
                    for u in range(lo, hi):
                        t = order[u]
                        b = sb[t]
                        if b == a or (fixed[a] and fixed[b]):
                            continue
                        d2 = 0.0
                        for k in range(3):
                            d2 += (xs[t, k] - xs[s, k]) ** 2
                        cut = factor * 0.5 * (sd[s] + sd[t])
                        if d2 > cut * cut:
                            continue
                        # keep only the nearest point of body b
                        m = 0
                        while m < min(n, cap) and sb[part[s, m]] != b:
                            m += 1
                        if m < min(n, cap):
                            t0 = part[s, m]
                            if d2 < dist[s, m] or (d2 == dist[s, m] and t < t0):
                                part[s, m] = t
                                dist[s, m] = d2
                        else:
                            if n < cap:
                                part[s, n] = t
                                dist[s, n] = d2
                            n += 1
        count[s] = n


within_pairs, within_pairs_par = kernel(_within, over="particles")


@jit
def candidate_pairs(surf, x, pbody, pspacing, fixed, factor):
    """Unique candidate pairs (m, 2) of particle indices, i < j, sorted (see the module docstring).

    ``surf`` (ns,) indices of the surface particles, ``x`` (np, 3) world positions [m],
    ``pbody`` (np,) bodies, ``pspacing`` (np,) spacings [m], ``fixed`` (nb,) bool, ``factor`` the
    cut-off factor. For each particle and each other body within reach, the pair with that body's
    nearest particle.
    """
    ns_all = surf.shape[0]
    if ns_all == 0:
        return np.zeros((0, 2), np.int64)
    near = near_bodies(x, surf, pbody, pspacing, fixed, fixed.shape[0], factor)
    ns = 0
    for u in range(ns_all):
        if near[pbody[surf[u]]]:
            ns += 1
    if ns == 0:
        return np.zeros((0, 2), np.int64)
    sel = np.empty(ns, np.int64)
    xq = np.empty((ns, 3))
    bq = np.empty(ns, np.int64)
    dq = np.empty(ns)
    h = 0.0
    m = 0
    for u in range(ns_all):
        i = surf[u]
        if near[pbody[i]]:
            sel[m] = i
            for k in range(3):
                xq[m, k] = x[i, k]
            bq[m] = pbody[i]
            dq[m] = pspacing[i]
            h = max(h, 2.0 * factor * dq[m])
            m += 1
    lo, h, dims, cell3, order, table = build_grid(xq, h)
    # store the points in cell order (the neighbours read in a cell are then contiguous in memory:
    # random access made the search 3x slower), with each point's cell and half-cell: the
    # 2 x 2 x 2 block to scan starts one cell lower on the axes where the point lies in the lower
    # half of its cell
    cell = np.empty((ns, 6), np.int64)
    xo = np.empty((ns, 3))
    bo = np.empty(ns, np.int64)
    do = np.empty(ns)
    so = np.empty(ns, np.int64)
    for v in range(ns):
        u = order[v]
        so[v] = sel[u]
        bo[v] = bq[u]
        do[v] = dq[u]
        for k in range(3):
            xo[v, k] = xq[u, k]
            cell[v, k] = cell3[u, k]
            cell[v, 3 + k] = 0 if (xq[u, k] - lo[k]) - cell3[u, k] * h < 0.5 * h else 1
    xq = xo
    bq = bo
    dq = do
    sel = so
    order = np.arange(ns)
    count = np.zeros(ns, np.int64)
    cap = 4
    par = ns >= PARALLEL_THRESHOLD
    while True:
        part = np.empty((ns, cap), np.int64)
        dist = np.empty((ns, cap))
        if par:
            within_pairs_par(xq, bq, dq, fixed, factor, dims, cell, order, table, count, part, dist)
        else:
            within_pairs(xq, bq, dq, fixed, factor, dims, cell, order, table, count, part, dist)
        most = count.max()
        if most <= cap:
            break
        cap = most
    keys = np.empty(count.sum(), np.int64)
    nk = 0
    for u in range(ns):
        for m in range(count[u]):
            t = part[u, m]
            keys[nk] = min(sel[u], sel[t]) * x.shape[0] + max(sel[u], sel[t])
            nk += 1
    keys = np.unique(keys)
    pairs = np.empty((keys.shape[0], 2), np.int64)
    for m in range(keys.shape[0]):
        pairs[m, 0] = keys[m] // x.shape[0]
        pairs[m, 1] = keys[m] % x.shape[0]
    return pairs


@jit
def find_contacts(surf, pbody, pspacing, x, nw, sigma, fixed, pos, factor):
    """Contacts of the current configuration (C_p <= 0), in the article's A/B roles.

    ``surf`` (ns,) indices of the surface particles; ``pbody``/``pspacing``/``sigma`` (np,)
    per particle; ``x``/``nw`` (np, 3) world positions and normals; ``fixed`` (nb,);
    ``pos`` (nb, 3) centres of mass. Returns ``(pa, pb, ba, bb, nrm, ra, rb, cp)``: particle
    and body of A and of B (B owns the normal), the unit normal (m, 3) pointing out of B, the
    lever arms x - X (m, 3) [m] and the gap C_p (m,) [m] (<= 0 for the contacts returned).
    """
    pairs = candidate_pairs(surf, x, pbody, pspacing, fixed, factor)
    m = pairs.shape[0]
    pa = np.empty(m, np.int64)
    pb = np.empty(m, np.int64)
    nrm = np.empty((m, 3))
    cp = np.empty(m)
    keep = np.zeros(m, np.bool_)
    for c in range(m):
        p = pairs[c, 0]
        q = pairs[c, 1]
        P = pbody[p]
        Q = pbody[q]
        owner = -1
        if fixed[P] != fixed[Q]:
            f = p if fixed[P] else q
            o = q if fixed[P] else p
            if sigma[f] <= sigma[o]:
                owner = f
        if owner < 0:
            if sigma[p] < FLATTER * sigma[q]:
                owner = p
            elif sigma[q] < FLATTER * sigma[p]:
                owner = q
        if owner >= 0:
            a = q if owner == p else p
            b = owner
            n = (nw[b, 0], nw[b, 1], nw[b, 2])
        else:  # comparable flatness: average the two outward normals (B = q)
            a = p
            b = q
            d = (nw[q, 0] - nw[p, 0], nw[q, 1] - nw[p, 1], nw[q, 2] - nw[p, 2])
            dn = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            if dn > 1e-6:
                n = (d[0] / dn, d[1] / dn, d[2] / dn)
            else:  # normals pointing the same way: not facing each other, keep B's own
                n = (nw[q, 0], nw[q, 1], nw[q, 2])
        gap = (x[a, 0] - x[b, 0]) * n[0] + (x[a, 1] - x[b, 1]) * n[1] + (x[a, 2] - x[b, 2]) * n[2]
        pa[c] = a
        pb[c] = b
        for k in range(3):
            nrm[c, k] = n[k]
        cp[c] = gap
        keep[c] = gap <= TOUCH * 0.5 * (pspacing[a] + pspacing[b])
    idx = np.nonzero(keep)[0]
    k = idx.shape[0]
    ba = np.empty(k, np.int64)
    bb = np.empty(k, np.int64)
    ra = np.empty((k, 3))
    rb = np.empty((k, 3))
    for t in range(k):
        c = idx[t]
        ba[t] = pbody[pa[c]]
        bb[t] = pbody[pb[c]]
        for j in range(3):
            ra[t, j] = x[pa[c], j] - pos[ba[t], j]
            rb[t, j] = x[pb[c], j] - pos[bb[t], j]
    return pa[idx], pb[idx], ba, bb, nrm[idx], ra, rb, cp[idx]
