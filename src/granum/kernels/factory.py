"""SpheresFactory's compiled parts (CircularFactory, BoxFactory): the stage that meters the mass flow, and the
placement of the new spheres.

Rules of YADE 2023.02a, measured as a black box (``tests/reference/yade/factory.py``):

- each step the goal grows by ``massFlowRate * dt`` (``goalMass``); while the mass produced (``totalMass``) is
  below it, and neither ``maxParticles`` nor ``maxMass`` is reached, one more sphere is made;
- its radius is uniform in ``[rMin, rMax]``, or taken from the PSD: the first size class whose share (of the
  mass produced, or of the count with ``PSDcalculateMass=False``) is below its share of ``PSDcum`` (the
  first class when none is), of diameter ``PSDsizes[k]`` (``exactDiam``) or uniform between ``PSDsizes[k]``
  and ``PSDsizes[k+1]``;
- its centre is drawn uniformly in the box ``center +- extents``, or in a disk of radius ``radius - r`` about
  ``center`` normal to ``normal`` (uniform in the angle and in the distance from the axis, so denser near the
  axis, as YADE's), thickened to ``length`` along the normal; the
  centre is drawn again (up to ``maxAttempt`` times) while the sphere overlaps a sphere of the scene or one
  made before it in the same step (centre distance < r1 + r2), or its box ``c +- r`` overlaps the bound of
  a body of another shape (a facet's box, not the facet itself);
- when no place is found the step's production ends (the caller reports it; with ``stopIfFailed``,
  ``massFlowRate`` becomes 0 and ``goalMass`` the mass made, and no sphere is made any more).

The random numbers come from SplitMix64 (Steele, Lea and Flood, "Fast splittable pseudorandom number
generators", OOPSLA 2014) over one 64-bit state word the engine keeps (and checkpoints).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from granum._jit import jit
from granum.core.arrays import S_DT, S_VERLET, SI_HOOK, SI_NBODIES
from granum.core.shapes import ShapeKind

#: region kinds
KIND_CIRCLE = 0
KIND_BOX = 1

#: slots of the engine's state array the stage writes: ``goalMass`` [kg], and 1 when spheres are due (the hook
#: clears it)
ST_GOAL = 0
ST_DUE = 1
ST_SIZE = 2

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)


class FactoryParams(NamedTuple):
    """Parameters of :func:`factory_stage`."""

    state: np.ndarray     #: the engine's state, (ST_SIZE,) float64: ``goalMass`` [kg], due flag
    rate: float           #: massFlowRate [kg/s]
    total_mass: float     #: totalMass when the chunk began [kg]
    num: int              #: numParticles when the chunk began
    max_particles: int    #: maxParticles (negative: no limit)
    max_mass: float       #: maxMass [kg] (negative: no limit)
    hook_id: int          #: what the stage writes to ``iscal[SI_HOOK]`` when spheres are due


@jit
def may_produce(total_mass, goal, num, max_particles, max_mass):
    """Whether one more sphere is due: mass below the goal, and neither limit reached."""
    return (total_mass < goal and (max_particles < 0 or num < max_particles)
            and (max_mass < 0.0 or total_mass < max_mass))


@jit
def factory_stage(S, C, P):
    """The goal mass grows by ``massFlowRate * dt``; when a sphere is due (and the flow was not stopped:
    massFlowRate 0) the engine's hook makes them after the step (the scene's storage grows in Python)."""
    P.state[ST_GOAL] += P.rate * S.scal[S_DT]
    if P.rate > 0.0 and may_produce(P.total_mass, P.state[ST_GOAL], P.num, P.max_particles, P.max_mass):
        P.state[ST_DUE] = 1.0
        S.iscal[SI_HOOK] = P.hook_id


@jit
def uniform(rng):
    """A double uniform in [0, 1) from the SplitMix64 state ``rng`` ((1,) uint64, advanced)."""
    rng[0] += _GOLDEN
    z = rng[0]
    z = (z ^ (z >> np.uint64(30))) * _MIX1
    z = (z ^ (z >> np.uint64(27))) * _MIX2
    z = z ^ (z >> np.uint64(31))
    return float(z >> np.uint64(11)) * (1.0 / 9007199254740992.0)


@jit
def sphere_mass(density, r):
    """rho 4/3 pi r^3 [kg], as a sphere body's mass is computed (granum.core.shapes)."""
    return density * 4.0 / 3.0 * math.pi * r ** 3


@jit
def pick_radius(rng, r_min, r_max, psd_sizes, psd_cum, psd_done, exact):
    """A radius [m] and its PSD class (-1 without a PSD). ``psd_done`` (K,): mass or count made per class."""
    n = psd_cum.shape[0]
    if n == 0:
        return r_min + uniform(rng) * (r_max - r_min), -1
    total = 0.0
    for k in range(n):
        total += psd_done[k]
    cls = 0
    if total > 0.0:
        for k in range(n):
            share = psd_cum[k] - (psd_cum[k - 1] if k > 0 else 0.0)
            if psd_done[k] / total < share:
                cls = k
                break
    if exact:
        return 0.5 * psd_sizes[cls], cls
    return 0.5 * (psd_sizes[cls] + uniform(rng) * (psd_sizes[cls + 1] - psd_sizes[cls])), cls


@jit
def pick_position(rng, kind, center, frame, size, r, out):
    """A centre [m] in the region: ``frame`` (3, 3) rows: the unit normal and two unit vectors across it;
    ``size``: the box's half extents, or (radius, length, 0) of the circle."""
    if kind == KIND_BOX:
        for k in range(3):
            out[k] = center[k] + (2.0 * uniform(rng) - 1.0) * size[k]
        return
    rho = (size[0] - r) * uniform(rng)    # uniform in the distance from the axis, as YADE's (not in area)
    phi = 2.0 * math.pi * uniform(rng)
    t = (uniform(rng) - 0.5) * size[1]
    a, b = rho * math.cos(phi), rho * math.sin(phi)
    for k in range(3):
        out[k] = center[k] + t * frame[0, k] + a * frame[1, k] + b * frame[2, k]


@jit
def factory_obstacles(S, kind, center, size, r_big):
    """What a new sphere of radius up to ``r_big`` [m] in the region (``kind``, ``center`` (3,) [m], ``size``
    (3,): a box's half sizes, or a circle's radius and length [m]) must not touch: the spheres reaching into the
    region's box (its reach plus ``r_big`` on each side), positions (m, 3) and radii (m,) [m], and the bounds of
    the other bodies reaching into it, less the Verlet distance, lower and upper corners (k, 3) [m]; in id
    order. ``S``: the scene's record."""
    nb = S.iscal[SI_NBODIES]
    verlet = S.scal[S_VERLET]
    lo = np.empty(3)
    hi = np.empty(3)
    for d in range(3):
        reach = size[0] + 0.5 * size[1] if kind == KIND_CIRCLE else size[d]
        lo[d] = center[d] - reach - r_big
        hi[d] = center[d] + reach + r_big
    sphere = np.zeros(nb, np.bool_)
    keep = np.zeros(nb, np.bool_)
    m = 0
    for i in range(nb):
        if not S.alive[i]:
            continue
        sphere[i] = S.shape_kind[i] == ShapeKind.SPHERE
        r = S.sphere_radius[S.shape_row[i]] if sphere[i] else 0.0
        inside = True
        for d in range(3):
            if sphere[i]:
                inside &= S.pos[i, d] + r >= lo[d] and S.pos[i, d] - r <= hi[d]
            else:   # an empty bound (no bound functor, not bounded yet) is kept out by its corners' order
                a = S.bound_min[i, d] + verlet
                b = S.bound_max[i, d] - verlet
                inside &= a <= b and b >= lo[d] and a <= hi[d]
        keep[i] = inside
        m += inside and sphere[i]
    k = int(keep.sum()) - m
    sph_pos = np.empty((m, 3))
    sph_r = np.empty(m)
    box_lo = np.empty((k, 3))
    box_hi = np.empty((k, 3))
    m = 0
    k = 0
    for i in range(nb):
        if not keep[i]:
            continue
        if sphere[i]:
            for d in range(3):
                sph_pos[m, d] = S.pos[i, d]
            sph_r[m] = S.sphere_radius[S.shape_row[i]]
            m += 1
        else:
            for d in range(3):
                box_lo[k, d] = S.bound_min[i, d] + verlet
                box_hi[k, d] = S.bound_max[i, d] - verlet
            k += 1
    return sph_pos, sph_r, box_lo, box_hi


@jit
def is_free(p, r, sph_pos, sph_r, new_pos, new_r, n_new, box_lo, box_hi):
    """Whether a sphere (p, r) touches none of the spheres (m, 3)/(m,), nor the first ``n_new`` new ones, nor
    the boxes (k, 3)/(k, 3) [m]."""
    for j in range(sph_r.shape[0]):
        d2 = 0.0
        for k in range(3):
            d2 += (p[k] - sph_pos[j, k]) ** 2
        if d2 < (r + sph_r[j]) ** 2:
            return False
    for j in range(n_new):
        d2 = 0.0
        for k in range(3):
            d2 += (p[k] - new_pos[j, k]) ** 2
        if d2 < (r + new_r[j]) ** 2:
            return False
    for j in range(box_lo.shape[0]):
        inside = True
        for k in range(3):
            if p[k] + r < box_lo[j, k] or p[k] - r > box_hi[j, k]:
                inside = False
                break
        if inside:
            return False
    return True


@jit
def factory_place(rng, kind, center, frame, size, r_min, r_max, psd_sizes, psd_cum, psd_done, by_mass, exact,
                  density, goal, total_mass, num, max_particles, max_mass, max_attempt,
                  sph_pos, sph_r, box_lo, box_hi, new_pos, new_r):
    """Make the spheres due (see the module's rules), at most ``new_r.shape[0]`` of them, into ``new_pos``
    (n, 3) and ``new_r`` (n,) [m]. Returns ``(count, failed)``: ``failed`` when a sphere found no place in
    ``max_attempt`` draws. ``psd_done`` is updated."""
    p = np.empty(3)
    n = 0
    while n < new_r.shape[0] and may_produce(total_mass, goal, num + n, max_particles, max_mass):
        r, cls = pick_radius(rng, r_min, r_max, psd_sizes, psd_cum, psd_done, exact)
        placed = False
        for _ in range(max_attempt):
            pick_position(rng, kind, center, frame, size, r, p)
            if is_free(p, r, sph_pos, sph_r, new_pos, new_r, n, box_lo, box_hi):
                placed = True
                break
        if not placed:
            return n, True
        for k in range(3):
            new_pos[n, k] = p[k]
        new_r[n] = r
        n += 1
        m = sphere_mass(density, r)
        total_mass += m
        if cls >= 0:
            psd_done[cls] += m if by_mass else 1.0
    return n, False
