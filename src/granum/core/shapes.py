"""Per-kind shape tables.

A body's ``shape_kind`` selects one of these tables and ``shape_row`` its row, in the
manner of MuJoCo's ``geom_type``/``geom_dataid``. Geometry is stored in the body's
local frame; the global position and orientation come from the body table.

To add a shape kind: add a member to :class:`granum.core.bodies.ShapeKind`, declare
its table here, register its bound and contact-geometry functions in
:mod:`granum.physics` and expose its YADE class in :mod:`granum.yade.shapes`.
"""

from __future__ import annotations

from granum.core.bodies import ShapeKind
from granum.core.table import Column, Table

SHAPE_COLUMNS = {
    ShapeKind.SPHERE: (
        Column("radius", (), "f8", float("nan"), "Sphere radius [m], (S,)."),
    ),
    ShapeKind.FACET: (
        Column("vertices", (3, 3), "f8", 0.0,
               "Triangle vertices relative to the body position, local frame [m], (F, 3, 3)."),
        Column("normal", (3,), "f8", 0.0, "Unit normal (v1-v0)x(v2-v0)/|..| in the local frame [-], (F, 3)."),
    ),
    ShapeKind.WALL: (
        Column("axis", (), "i1", 0, "Axis (0, 1, 2) normal to the infinite plane, (W,)."),
        Column("sense", (), "i1", 0, "Side that interacts: -1 negative, +1 positive, 0 both, (W,)."),
    ),
    ShapeKind.BOX: (
        Column("extents", (3,), "f8", 0.0, "Half-sizes along the local axes [m], (B, 3)."),
    ),
    ShapeKind.CLUMP: (
        Column("member_first", (), "i4", 0, "First entry of the clump's members in the clump member table, (K,)."),
        Column("member_count", (), "i4", 0, "Number of members, (K,)."),
    ),
}

#: Member ids of all clumps, each clump's members contiguous (see the CLUMP shape table).
CLUMP_MEMBER_COLUMNS = (Column("id", (), "i4", -1, "Body id of a clump member, (M,)."),)


def new_shape_tables(capacity: int = 8) -> dict[ShapeKind, Table]:
    """One empty table per shape kind, keyed by :class:`ShapeKind`."""
    return {kind: Table(cols, capacity) for kind, cols in SHAPE_COLUMNS.items()}
