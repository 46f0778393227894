"""YADE's ``yade.geom``: bodies made of facets."""

from __future__ import annotations

import numpy as np

from granum.mathtypes import Quaternion, as_quat_wxyz, as_vec3
from granum.yade import utils

# Corners of a box by signs (x, y, z); each face is two triangles whose normals point
# into the box, in YADE's face order -x, +x, -y, +y, -z, +z (bit k of wallMask).
_FACES = (
    (((-1, -1, -1), (-1, 1, -1), (-1, 1, 1)), ((-1, -1, -1), (-1, 1, 1), (-1, -1, 1))),
    (((1, -1, -1), (1, -1, 1), (1, 1, 1)), ((1, -1, -1), (1, 1, 1), (1, 1, -1))),
    (((-1, -1, -1), (-1, -1, 1), (1, -1, 1)), ((-1, -1, -1), (1, -1, 1), (1, -1, -1))),
    (((-1, 1, -1), (1, 1, -1), (1, 1, 1)), ((-1, 1, -1), (1, 1, 1), (-1, 1, 1))),
    (((-1, -1, -1), (1, -1, -1), (1, 1, -1)), ((-1, -1, -1), (1, 1, -1), (-1, 1, -1))),
    (((-1, -1, 1), (-1, 1, 1), (1, 1, 1)), ((-1, -1, 1), (1, 1, 1), (1, -1, 1))),
)


def facetBox(center, extents, orientation=None, wallMask=63, **kw):
    """Facets of the box ``center`` +- ``extents`` (half-sizes), two per face, normals inwards.

    ``wallMask`` selects the faces: bit 0 -x, 1 +x, 2 -y, 3 +y, 4 -z, 5 +z (31: open top).
    ``orientation`` rotates the box about its centre; other keywords go to ``utils.facet``.
    A flat box (one extent 0) is one rectangle, whatever ``wallMask``: the two facets of its -x, -y or -z
    face, normal along +x, +y or +z (YADE 2023.02a); two zero extents are refused.
    """
    if not 0 <= int(wallMask) <= 63:
        raise ValueError(f"facetBox: wallMask must be in 0..63, got {wallMask!r}")
    c = as_vec3(center)
    e = as_vec3(extents)
    flat = [k for k in range(3) if e[k] == 0]
    if len(flat) > 1:
        raise ValueError(f"facetBox: at least two extents must be nonzero, got extents={tuple(e.tolist())}")
    faces = (1 << 2 * flat[0]) if flat else int(wallMask)
    q = Quaternion(*as_quat_wxyz(orientation)) if orientation is not None else Quaternion(1, 0, 0, 0)
    rot = np.asarray(q.toRotationMatrix()._a)
    out = []
    for k, face in enumerate(_FACES):
        if faces >> k & 1:
            for tri in face:
                out.append(utils.facet([tuple(c + rot @ (e * np.array(s, float))) for s in tri], **kw))
    return out
