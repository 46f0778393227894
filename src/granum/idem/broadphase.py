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

The broad phase is a uniform grid of cell size equal to the largest cut-off (granum's
collider grid works on whole bodies through the scene record, so iDEM has its own small grid
over particles; same idea: bin, scan the 27 neighbouring cells, deterministic output).
"""

from __future__ import annotations

import math

import numpy as np

from granum._jit import PARALLEL_THRESHOLD, jit, kernel, prange

#: Other bodies tracked per particle during the search (a particle near more distinct bodies
#: than this keeps the first ones found; 16 is far above what packed convex bodies produce).
MAX_NEIGHBOUR_BODIES = 16
#: A particle is "clearly flatter" than its partner when its surface variation is below this
#: fraction of the partner's.
FLATTER = 0.5
#: Contact when C_p <= TOUCH x spacing (bodies placed exactly touching count as in contact).
TOUCH = 1e-9


@jit
def build_grid(xs, h):
    """Bin points ``xs`` (ns, 3) into cubic cells of size ``h``.

    Returns ``(lo, dims, cell, order, keys_sorted, dense_start)``: lower corner (3,), cells per
    axis (3,), cell of each point (ns, 3), point indices sorted by cell key, the sorted keys, and
    a dense per-key offset table (empty when the grid is too sparse: binary search instead).
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
    keys_sorted = keys[order]
    ncells = dims[0] * dims[1] * dims[2]
    if ncells <= 4 * ns + 1024:
        dense_start = np.zeros(ncells + 1, np.int64)
        for key in keys_sorted:
            dense_start[key + 1] += 1
        for k in range(ncells):
            dense_start[k + 1] += dense_start[k]
    else:
        dense_start = np.zeros(0, np.int64)
    return lo, dims, cell, order, keys_sorted, dense_start


@jit
def cell_range(key, keys_sorted, dense_start):
    """Range [a, b) of the sorted points in cell ``key``."""
    if dense_start.shape[0] > 0:
        if key < 0 or key >= dense_start.shape[0] - 1:
            return 0, 0
        return dense_start[key], dense_start[key + 1]
    return np.searchsorted(keys_sorted, key, side="left"), np.searchsorted(keys_sorted, key, side="right")


def _nearest(xs, sb, sd, fixed, factor, dims, cell, order, keys_sorted, dense_start, count, start, out):
    """Pass 1 (``out`` empty): count, for each point, the other bodies within reach; pass 2: write
    the pairs (point, nearest point of that body) in order of first discovery."""
    fill = out.shape[0] > 0
    for s in prange(xs.shape[0]):
        bodies = np.full(MAX_NEIGHBOUR_BODIES, -1, np.int64)
        best = np.full(MAX_NEIGHBOUR_BODIES, -1, np.int64)
        bestd = np.full(MAX_NEIGHBOUR_BODIES, np.inf)
        nfound = 0
        a = sb[s]
        for dx in range(-1, 2):
            cx = cell[s, 0] + dx
            if cx < 0 or cx >= dims[0]:
                continue
            for dy in range(-1, 2):
                cy = cell[s, 1] + dy
                if cy < 0 or cy >= dims[1]:
                    continue
                for dz in range(-1, 2):
                    cz = cell[s, 2] + dz
                    if cz < 0 or cz >= dims[2]:
                        continue
                    lo, hi = cell_range((cx * dims[1] + cy) * dims[2] + cz, keys_sorted, dense_start)
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
                        slot = -1
                        for m in range(nfound):
                            if bodies[m] == b:
                                slot = m
                                break
                        if slot < 0:
                            if nfound == MAX_NEIGHBOUR_BODIES:
                                continue
                            slot = nfound
                            bodies[slot] = b
                            nfound += 1
                        # nearest, ties broken by the smaller index (independent of scan order)
                        if d2 < bestd[slot] or (d2 == bestd[slot] and t < best[slot]):
                            bestd[slot] = d2
                            best[slot] = t
        if fill:
            for m in range(nfound):
                out[start[s] + m, 0] = s
                out[start[s] + m, 1] = best[m]
        else:
            count[s] = nfound


nearest_pairs, nearest_pairs_par = kernel(_nearest)


@jit
def candidate_pairs(xs, sb, sd, fixed, factor):
    """Unique candidate pairs (m, 2) of point indices, i < j, sorted (see the module docstring).

    ``xs`` (ns, 3) world positions of the surface particles [m], ``sb`` (ns,) their bodies,
    ``sd`` (ns,) their spacings [m], ``fixed`` (nb,) bool, ``factor`` the cut-off factor.
    """
    ns = xs.shape[0]
    if ns == 0:
        return np.zeros((0, 2), np.int64)
    h = 0.0
    for s in range(ns):
        h = max(h, factor * sd[s])
    lo, dims, cell, order, keys_sorted, dense_start = build_grid(xs, h)
    count = np.zeros(ns, np.int64)
    start = np.zeros(ns + 1, np.int64)
    none = np.zeros((0, 2), np.int64)
    par = ns >= PARALLEL_THRESHOLD
    if par:
        nearest_pairs_par(xs, sb, sd, fixed, factor, dims, cell, order, keys_sorted, dense_start, count, start, none)
    else:
        nearest_pairs(xs, sb, sd, fixed, factor, dims, cell, order, keys_sorted, dense_start, count, start, none)
    for s in range(ns):
        start[s + 1] = start[s] + count[s]
    raw = np.empty((start[ns], 2), np.int64)
    if par:
        nearest_pairs_par(xs, sb, sd, fixed, factor, dims, cell, order, keys_sorted, dense_start, count, start, raw)
    else:
        nearest_pairs(xs, sb, sd, fixed, factor, dims, cell, order, keys_sorted, dense_start, count, start, raw)
    keys = np.empty(raw.shape[0], np.int64)
    for m in range(raw.shape[0]):
        i = min(raw[m, 0], raw[m, 1])
        j = max(raw[m, 0], raw[m, 1])
        keys[m] = i * ns + j
    keys = np.unique(keys)
    pairs = np.empty((keys.shape[0], 2), np.int64)
    for m in range(keys.shape[0]):
        pairs[m, 0] = keys[m] // ns
        pairs[m, 1] = keys[m] % ns
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
    ns = surf.shape[0]
    xs = np.empty((ns, 3))
    sb = np.empty(ns, np.int64)
    sd = np.empty(ns)
    for s in range(ns):
        i = surf[s]
        xs[s, :] = x[i]
        sb[s] = pbody[i]
        sd[s] = pspacing[i]
    pairs = candidate_pairs(xs, sb, sd, fixed, factor)
    m = pairs.shape[0]
    pa = np.empty(m, np.int64)
    pb = np.empty(m, np.int64)
    nrm = np.empty((m, 3))
    cp = np.empty(m)
    keep = np.zeros(m, np.bool_)
    for c in range(m):
        p = surf[pairs[c, 0]]
        q = surf[pairs[c, 1]]
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
