"""``SpherePack.makeClumpCloud``: a loose random cloud of rigid clumps of spheres.

What the method does, as observed on YADE 2023.02a used as a black box (the compiled
insertion loop is :func:`granum.yade._packing.clump_fill`):

* ``clumps`` is a list of template ``SpherePack`` objects; each new clump takes one of them
  at random (equal chances, drawn once per clump) and gets at most 200 placement attempts
  (YADE's warning says "Exceeded 200 attempts to place non-overlapping clump").
* An attempt puts the template's reference point (the centre of its bounding box) at a
  uniformly random point of the box and turns the template by a random rotation. It fails
  when a member overlaps any sphere already in the pack, old spheres included; members of
  one clump may overlap each other. Without ``periodic`` every member must lie inside the
  box; with ``periodic`` members may stick out and overlaps count across the faces
  (minimum image).
* Generation stops after ``num`` clumps, or at the first clump whose attempts all fail
  (with ``num`` given this warns). The return value is the number of clumps added.
* New spheres are appended after the existing ones, clump after clump.
* ``periodic=True`` sets ``cellSize`` to the box size but leaves ``isPeriodic`` as it was,
  so ``toSimulation`` does not set up the cell (YADE's tutorial 06 runs like that: its
  scene keeps the default unit cell).

Deliberate differences from YADE (both are YADE defects, reported in the project notes):

* orientations are uniform over all rotations; YADE normalises a quaternion with four
  uniform [0, 1) components, which favours one octant of rotations;
* YADE rotates each member's offset *plus* the reference point (not minus), so templates
  whose reference point is off the origin end up far from the drawn point (or never fit
  in a closed box); granum rotates about the reference point. For templates centred on
  the origin both agree;
* YADE numbers the new clumps from 0 even when the pack already holds clumps (merging
  unrelated clumps); granum continues after the largest clump id present.
"""

from __future__ import annotations

import secrets
import warnings

import numpy as np

from granum._jit import call
from granum.yade import _packing

__all__ = ["MAX_CLUMP_TRY", "clump_cloud", "template_arrays"]

#: Placement attempts for one clump before generation stops (YADE's value, from its warning).
MAX_CLUMP_TRY = 200


def template_arrays(clumps):
    """Concatenate template packs into the arrays :func:`_packing.clump_fill` takes.

    ``clumps``: sequence of objects with ``centers`` (K, 3) and ``radii`` (K,) arrays
    (SpherePacks), each with at least one sphere. Returns ``(start (T+1,) int64,
    rel (M, 3), rad (M,))``: template ``t`` is rows ``start[t]:start[t+1]``; member centres
    are relative to the centre of the template's bounding box (radii included), the point
    that is placed uniformly in the box and about which the template turns.
    """
    clumps = list(clumps)
    if not clumps:
        raise ValueError("makeClumpCloud: give at least one template SpherePack in `clumps`")
    rels, rads, start = [], [], [0]
    for t in clumps:
        if not (hasattr(t, "centers") and hasattr(t, "radii")):
            raise TypeError(f"makeClumpCloud: clump templates must be SpherePacks, got {t!r}")
        c = np.asarray(t.centers, dtype=np.float64).reshape(-1, 3)
        r = np.asarray(t.radii, dtype=np.float64).reshape(-1)
        if len(r) == 0:
            raise ValueError("makeClumpCloud: a clump template holds no sphere")
        if np.any(r <= 0):
            raise ValueError("makeClumpCloud: template radii must be positive")
        ref = 0.5 * ((c - r[:, None]).min(axis=0) + (c + r[:, None]).max(axis=0))
        rels.append(c - ref)
        rads.append(r)
        start.append(start[-1] + len(r))
    return (np.array(start, dtype=np.int64), np.ascontiguousarray(np.concatenate(rels)),
            np.ascontiguousarray(np.concatenate(rads)))


def clump_cloud(centers, radii, clump_ids, minCorner, maxCorner, clumps, periodic=False, num=-1, seed=-1):
    """Add a random cloud of clumps to a packing given as arrays; see the module docstring.

    ``centers`` (N, 3), ``radii`` (N,), ``clump_ids`` (N,) int (-1: standalone) describe the
    spheres already present; ``minCorner``/``maxCorner`` (3,) the box [m]; ``seed < 0``
    draws a fresh seed. Returns ``(centers (N', 3), radii (N',), clump_ids (N',), added)``
    with the old spheres first; new clumps get ids from ``max(clump_ids) + 1`` on.
    """
    lo = np.asarray(minCorner, dtype=np.float64).reshape(3)
    length = np.asarray(maxCorner, dtype=np.float64).reshape(3) - lo
    if np.any(length < 0):
        raise ValueError("makeClumpCloud: maxCorner must not be below minCorner")
    start, rel, rad = template_arrays(clumps)
    num = int(num)
    if seed is None or seed < 0:
        seed = secrets.randbits(32)
    pos, r, n, tpl_of, k = call(
        _packing.clump_fill, np.ascontiguousarray(centers, dtype=np.float64).reshape(-1, 3),
        np.ascontiguousarray(radii, dtype=np.float64), lo, length, bool(periodic), start, rel, rad,
        num, MAX_CLUMP_TRY, int(seed) % (1 << 32))
    if 0 < num and k < num:
        warnings.warn(f"makeClumpCloud: exceeded {MAX_CLUMP_TRY} attempts to place a non-overlapping clump; "
                      f"only {k} of {num} clumps were added", stacklevel=3)
    old = np.asarray(clump_ids, dtype=np.int64)
    first = int(old.max()) + 1 if len(old) and old.max() >= 0 else 0
    sizes = np.diff(start)[tpl_of[:k]]
    new = np.repeat(np.arange(first, first + k, dtype=np.int64), sizes)
    return pos[:n].copy(), r[:n].copy(), np.concatenate([old, new]), int(k)
