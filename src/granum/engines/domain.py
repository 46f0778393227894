"""DomainLimiter: erase the bodies that left an axis-aligned box (YADE ``DomainLimiter``).

Rules of YADE 2023.02a used as a black box (``tests/reference/yade/domain_limiter.json``): when due (its
periods are :class:`~granum.engines.base.PeriodicEngine`'s), every body with ``mask & groupMask != 0`` whose
position is outside ``[lo, hi]`` (a position on a face is inside) is erased, fixed ones too. A clump is
judged by its own position and erased with its members; members are not judged on their own. Only spheres and
clumps are judged: YADE keeps a facet outside the box (and crashes on a box outside it).
``nDeleted`` counts the bodies erased (a clump once), ``mDeleted`` adds their masses [kg] and ``vDeleted``
the volumes of the spheres among them [m^3] (a clump adds none). It runs from Python between compiled
chunks, as erasing bodies is an edit of the scene.
"""

from __future__ import annotations

import math

import numpy as np

from granum.core.attrs import Attr, to_float, to_int
from granum.core.shapes import ShapeKind
from granum.engines.base import PeriodicEngine
from granum.engines.pipeline import to_vec3
from granum.mathtypes import Vector3


class DomainLimiter(PeriodicEngine):
    """Delete particles that are out of the axis-aligned box given by ``lo`` and ``hi`` [m]."""

    _attrs = {
        "lo": Attr(Vector3(0, 0, 0), "Lower corner of the domain [m]", to_vec3),
        "hi": Attr(Vector3(0, 0, 0), "Upper corner of the domain [m]", to_vec3),
        "nDeleted": Attr(0, "Number of bodies deleted so far (a clump counts once)", to_int("nDeleted")),
        "mDeleted": Attr(0.0, "Mass of the bodies deleted so far [kg]", to_float("mDeleted")),
        "vDeleted": Attr(0.0, "Volume of the spheres deleted so far [m^3]", to_float("vDeleted")),
        "mask": Attr(-1, "Only bodies with mask & groupMask != 0 are deleted", to_int("mask")),
    }

    def run_python(self, omega) -> None:
        scene = omega._scene
        b = scene.bodies
        n = scene.body_count
        lo, hi = np.asarray(self.lo, dtype=np.float64), np.asarray(self.hi, dtype=np.float64)
        kind = b.shape_kind[:n]
        judged = (b.alive[:n] & ((b.clump_id[:n] < 0) | (b.clump_id[:n] == np.arange(n)))
                  & ((kind == ShapeKind.SPHERE) | (kind == ShapeKind.CLUMP)))
        if self.mask != -1:
            judged &= (b.mask[:n] & self.mask) != 0
        outside = ((b.pos[:n] < lo) | (b.pos[:n] > hi)).any(axis=1)
        ids = np.flatnonzero(judged & outside)
        if not len(ids):
            return
        sphere = b.shape_kind[ids] == ShapeKind.SPHERE
        r = scene.shapes[ShapeKind.SPHERE].radius[b.shape_row[ids[sphere]]]
        self.nDeleted += len(ids)
        self.mDeleted += float(b.mass[ids].sum())
        self.vDeleted += float((4.0 / 3.0 * math.pi * r ** 3).sum())
        for i in ids:
            omega.bodies.erase(int(i), bool(b.shape_kind[i] == ShapeKind.CLUMP))
