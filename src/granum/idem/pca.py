"""Surface normals of a particle cloud from the covariance of neighbouring surface particles.

Article appendix "法線ベクトルを粒子群から求める方法" (``shared/reference/idem.md`` §3): the
tangent plane at particle i minimises sum_j ((x_j - x_i) . n)^2 over |n| = 1, an eigenproblem
of the 3 x 3 scatter matrix; the normal is the eigenvector of the smallest eigenvalue, found
with the Jacobi method. Choices where the article is silent:

* [A2] neighbours: the other *surface* particles of the same body within ``radius`` (default
  1.2 x the particle spacing, i.e. the nearest lattice neighbours only, so that on a face the
  particles next to an edge get the exact face normal); when fewer than 3 are found, the 3
  nearest surface particles instead (a plane needs the particle and 3 others).
* [A3] scatter matrix: S = sum_j d_j d_j^T (3 x 3; the article's "M^T M" has the wrong
  dimensions for its M), taken about the centroid of the neighbourhood (particle included)
  rather than about x_i. On a flat patch both give the same normal; at an edge or a corner the
  centred form gives the bisector, while S about x_i is degenerate there (equal eigenvalues).
* [A4] orientation: outward, i.e. pointing away from the centroid of *all* particles (surface
  and interior) within ``radius``; when that offset vanishes (a body given by its surface
  only), away from the body's centre of mass.

Besides the normal each particle gets its *surface variation* sigma = l0 / (l0 + l1 + l2) in
[0, 1/3] (0 on a flat patch, larger at edges and corners); the contact search uses it to
prefer the normal of the flatter particle of a pair (see :mod:`granum.idem.broadphase`).
"""

from __future__ import annotations

import math

import numpy as np

from granum._jit import jit
from granum.kernels.copy import copy_to_row


@jit
def jacobi_eigh3(S):
    """Eigen-decomposition of a symmetric (3, 3) matrix by cyclic Jacobi rotations.

    Returns ``(w, V)``: eigenvalues (3,) in increasing order and the matching unit
    eigenvectors as the columns of V (3, 3). Sweeps stop when the off-diagonal part is
    below 1e-30 of the squared Frobenius norm (or after 50 sweeps).
    """
    A = S.copy()
    V = np.eye(3)
    scale2 = 0.0
    for i in range(3):
        for j in range(3):
            scale2 += A[i, j] * A[i, j]
    for _sweep in range(50):
        off = A[0, 1] ** 2 + A[0, 2] ** 2 + A[1, 2] ** 2
        if off <= 1e-30 * scale2 or off == 0.0:
            break
        for p in range(2):
            for q in range(p + 1, 3):
                apq = A[p, q]
                if apq == 0.0:
                    continue
                # rotation angle that zeroes A[p, q] (Golub & Van Loan, Algorithm 8.4.1)
                theta = (A[q, q] - A[p, p]) / (2.0 * apq)
                t = math.copysign(1.0, theta) / (abs(theta) + math.sqrt(theta * theta + 1.0))
                c = 1.0 / math.sqrt(t * t + 1.0)
                s = t * c
                for k in range(3):
                    akp = A[k, p]
                    akq = A[k, q]
                    A[k, p] = c * akp - s * akq
                    A[k, q] = s * akp + c * akq
                for k in range(3):
                    apk = A[p, k]
                    aqk = A[q, k]
                    A[p, k] = c * apk - s * aqk
                    A[q, k] = s * apk + c * aqk
                for k in range(3):
                    vkp = V[k, p]
                    vkq = V[k, q]
                    V[k, p] = c * vkp - s * vkq
                    V[k, q] = s * vkp + c * vkq
    w = np.array([A[0, 0], A[1, 1], A[2, 2]])
    order = np.argsort(w)
    return w[order], V[:, order]


@jit
def pca_normal(points):
    """Unit normal (3,) of the best-fit plane through ``points`` (k, 3) and its surface variation.

    The normal is the eigenvector of the smallest eigenvalue of the centred scatter matrix
    S = sum (p - c)(p - c)^T, c the centroid; sigma = l0 / (l0 + l1 + l2). Sign arbitrary.
    """
    k = points.shape[0]
    c = np.zeros(3)
    for i in range(k):
        for a in range(3):
            c[a] += points[i, a]
    c /= k
    S = np.zeros((3, 3))
    for i in range(k):
        for a in range(3):
            for b in range(3):
                S[a, b] += (points[i, a] - c[a]) * (points[i, b] - c[b])
    w, V = jacobi_eigh3(S)
    tr = w[0] + w[1] + w[2]
    sigma = max(w[0], 0.0) / tr if tr > 0.0 else 1.0 / 3.0
    return V[:, 0].copy(), sigma


@jit
def surface_normals(points, surface, radius, com, normals, sigma):
    """Outward unit normals (np, 3) and surface variation (np,) of the surface particles of one body.

    ``points`` (np, 3) [m]; ``surface`` (np,) bool; ``radius`` [m] the neighbourhood radius;
    ``com`` (3,) the body's centre of mass (orientation fallback). Interior particles get a zero
    normal and sigma = 1/3. See the module docstring for the choices [A2]-[A4].
    """
    n = points.shape[0]
    sidx = np.nonzero(surface)[0]
    ns = sidx.shape[0]
    r2 = radius * radius
    d2 = np.empty(ns)
    for i in range(n):
        if not surface[i]:
            for a in range(3):
                normals[i, a] = 0.0
            sigma[i] = 1.0 / 3.0
            continue
        for t in range(ns):
            j = sidx[t]
            d2[t] = 0.0
            for a in range(3):
                d2[t] += (points[j, a] - points[i, a]) ** 2
        count = 0
        for t in range(ns):
            if sidx[t] != i and d2[t] <= r2:
                count += 1
        if count >= 3:
            nb = np.empty((count + 1, 3))
            m = 1
            for t in range(ns):
                if sidx[t] != i and d2[t] <= r2:
                    copy_to_row(nb, m, points[sidx[t]])
                    m += 1
        else:  # too sparse: the 3 nearest surface particles (ties broken by index)
            order = np.argsort(d2, kind="mergesort")
            nb = np.empty((4, 3))
            m = 1
            for t in order:
                if sidx[t] != i:
                    copy_to_row(nb, m, points[sidx[t]])
                    m += 1
                    if m == 4:
                        break
        copy_to_row(nb, 0, points[i])
        nv, s = pca_normal(nb)
        # outward: away from the centroid of every particle (interior ones too) around i
        off = np.zeros(3)
        cnt = 0
        for j in range(n):
            if j == i:
                continue
            dd = 0.0
            for a in range(3):
                dd += (points[j, a] - points[i, a]) ** 2
            if dd <= r2:
                cnt += 1
                for a in range(3):
                    off[a] += points[j, a]
        side = 0.0
        if cnt > 0:
            for a in range(3):
                side += (points[i, a] - off[a] / cnt) * nv[a]
        if abs(side) <= 1e-9 * radius:  # flat neighbourhood (a shell): use the centre of mass
            side = 0.0
            for a in range(3):
                side += (points[i, a] - com[a]) * nv[a]
        if side < 0.0:
            nv = -nv
        for a in range(3):
            normals[i, a] = nv[a]
        sigma[i] = s


@jit
def nearest_distances(points):
    """Distance (np,) from each point to its nearest other point [m] (brute force, O(np^2))."""
    n = points.shape[0]
    out = np.full(n, np.inf)
    for i in range(n):
        for j in range(n):
            if i != j:
                d = 0.0
                for a in range(3):
                    d += (points[j, a] - points[i, a]) ** 2
                if d < out[i]:
                    out[i] = d
    return np.sqrt(out)


@jit
def detect_surface(points, radius):
    """Surface mask (np,) of a volume-filling cloud: a particle is on the surface when it has fewer
    neighbours within ``radius`` than the best-surrounded particle of the body, or when the
    centroid of its neighbours is off by more than 10 % of ``radius`` (one-sided neighbourhood)."""
    n = points.shape[0]
    count = np.zeros(n, np.int64)
    shift = np.zeros(n)
    r2 = radius * radius
    for i in range(n):
        c = np.zeros(3)
        for j in range(n):
            if i == j:
                continue
            d = 0.0
            for a in range(3):
                d += (points[j, a] - points[i, a]) ** 2
            if d <= r2:
                count[i] += 1
                for a in range(3):
                    c[a] += points[j, a] - points[i, a]
        if count[i] > 0:
            shift[i] = math.sqrt(c[0] ** 2 + c[1] ** 2 + c[2] ** 2) / count[i]
    full = count.max()
    return (count < full) | (shift > 0.1 * radius)
