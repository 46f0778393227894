"""Clumps as text: ``export.textClumps`` (YADE's ``x_y_z_r_clumpId`` format; ``ymport.textClumps`` reads it).

The file, as YADE 2023.02a writes it: a line ``#format x_y_z_r_clumpId``, the comment (if any) after
``# ``, then one tab-separated line per spherical member, ``x y z r clumpId``, clumps by increasing id and
members by increasing id, numbers printed with C's ``%g`` (six significant digits: YADE's format, so the
positions read back are rounded).
"""

from __future__ import annotations

import numpy as np

from granum.core.shapes import ShapeKind
from granum.io.atomic import write_text
from granum.yade.clumps import clump_members

__all__ = ["write"]

FORMAT = "x_y_z_r_clumpId"


def write(filename, format=FORMAT, comment="", mask=-1):  # noqa: A002 (YADE's argument name)
    """``export.textClumps``: write the spherical clump members with ``mask & groupMask != 0`` (all
    with -1); return ``(number of clumps, number of spheres)`` written."""
    from granum.yade.omega import O  # lazy: the omega module imports the scene code

    if format != FORMAT:
        raise ValueError(f"export.textClumps: format {format!r} is not supported; only {FORMAT!r}")
    scene = O._scene
    b = scene.bodies
    n = scene.body_count
    radius = scene.shapes[ShapeKind.SPHERE].radius
    lines = [f"#format {format}"]
    if comment:
        lines.append(f"# {comment}")
    clumps = spheres = 0
    for c in np.flatnonzero(b.alive[:n] & (b.shape_kind[:n] == ShapeKind.CLUMP)):
        rows = [m for m in sorted(clump_members(scene, int(c)))
                if b.shape_kind[m] == ShapeKind.SPHERE and (mask == -1 or b.mask[m] & int(mask))]
        for m in rows:
            x, y, z = b.pos[m]
            lines.append(f"{x:g}\t{y:g}\t{z:g}\t{radius[b.shape_row[m]]:g}\t{c:d}")
        clumps += bool(rows)
        spheres += len(rows)
    write_text(filename, "\n".join(lines) + "\n")
    return clumps, spheres
