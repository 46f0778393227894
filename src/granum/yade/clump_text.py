"""Clumps as text: ``export.textClumps`` and ``ymport.textClumps`` (YADE's ``x_y_z_r_clumpId`` format).

The file, as YADE 2023.02a writes it: a line ``#format x_y_z_r_clumpId``, the comment (if any) after
``# ``, then one tab-separated line per spherical member, ``x y z r clumpId``, clumps by increasing id and
members by increasing id, numbers printed with C's ``%g`` (six significant digits: YADE's format, so the
positions read back are rounded). Reading groups the lines by their last column in order of first
appearance and appends each group with ``O.bodies.appendClumped``, each sphere placed at
``orientation * (scale * x) + shift`` with radius ``scale * r``; lines starting with ``#`` are skipped.
"""

from __future__ import annotations

import numpy as np

from granum.core.shapes import ShapeKind
from granum.io.atomic import write_text
from granum.mathtypes import Quaternion, Vector3, as_quat_wxyz, as_vec3
from granum.yade.clumps import clump_members, rotation

__all__ = ["read", "write"]

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


def read(fileName, shift=Vector3(0, 0, 0), discretization=0, orientation=Quaternion(1, 0, 0, 0),  # noqa: B008, N803
         scale=1.0, **kw):
    """``ymport.textClumps``: append the clumps of a ``x_y_z_r_clumpId`` file; return
    ``[(clumpId, [memberIds]), ...]``. ``kw`` goes to ``utils.sphere``."""
    from granum.yade import utils  # lazy: utils imports the scene code
    from granum.yade.omega import O

    groups: dict[str, list] = {}
    with open(fileName) as f:
        for k, line in enumerate(f, 1):
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            cols = line.split()
            if len(cols) != 5:
                raise ValueError(f"ymport.textClumps: {fileName}:{k}: expected 5 columns x y z r clumpId, got "
                                 f"{len(cols)}")
            try:
                values = [float(v) for v in cols[:4]]
            except ValueError:
                raise ValueError(f"ymport.textClumps: {fileName}:{k}: not a number in {line.strip()!r}") from None
            groups.setdefault(cols[4], []).append(values)
    R = rotation(as_quat_wxyz(orientation))
    t = as_vec3(shift)
    s = float(scale)
    spheres = [[utils.sphere(Vector3(*(R @ (s * np.array(v[:3])) + t)), s * v[3], **kw) for v in rows]
               for rows in groups.values()]
    return [O.bodies.appendClumped(group, discretization) for group in spheres]
