"""The shape kinds: one declaration per kind, and the per-kind shape tables.

A body's ``shape_kind`` selects one of the shape tables and ``shape_row`` its row, in the
manner of MuJoCo's ``geom_type``/``geom_dataid``. Geometry is stored in the body's
local frame; the global position and orientation come from the body table.

Each kind is declared once, as a :class:`ShapeType` in :data:`SHAPES`; :class:`ShapeKind`
(its code, the value of ``shape_kind``) and the tables are made from those declarations, and
everything that depends on the kind reads them: the kernel record's fields
(``<kind>_<column>``), the lazy columns a scene allocates, the checks of ``O.load`` and of the
views' setters (``rules``), the YADE class name, the mass of a body made by a factory and the
polygons drawn and written to VTK (``faces``). The layers above register their part keyed by
the kind, in their own layer (:data:`ShapeKind` members are what they key on):

* ``physics/<shape>.py``: the bound and contact-geometry functors (``Functor.types``) and the
  shape's *reach*, the collider's rotation allowance (``registry.register_reach``);
* ``yade/bodies.py``: the view class, whose class name is :attr:`ShapeType.name`, with the
  VTK file it goes to (``vtk``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from enum import IntEnum

import numpy as np

from granum.core import validate
from granum.core.table import Column, Table


@dataclass(frozen=True)
class ShapeType:
    """Declaration of a shape kind.

    Attributes:
        name: YADE class name (``"Sphere"``); the :class:`ShapeKind` member is its upper case, the
            kernel record's fields are ``<name lower case>_<column>``.
        columns: the columns of the kind's shape table (one row per body of the kind).
        rules: the :class:`~granum.core.validate.Rule` each column obeys, checked by the view's
            setter and by ``O.load``, by column name.
        aspherical: bodies of the kind are integrated with the full inertia tensor (Euler's
            equations); a scene holding one allocates the angular momentum.
        mass: ``mass(density, table, row) -> (mass [kg], principal inertia (3,) [kg m^2])`` of a
            body of uniform ``density`` [kg/m^3] whose shape is row ``row`` of ``table``; None for
            a shape whose factory makes massless bodies.
        faces: ``faces(table, rows) -> (M, F, V, 3)`` the surface of the shapes ``rows`` (M,) as F
            polygons of V vertices each, in the local frame [m]; what pictures draw and VTK
            writes. None for a shape without a polygonal surface (drawn, if at all, by its own code).
    """

    name: str
    columns: tuple[Column, ...]
    rules: dict = field(default_factory=dict)
    aspherical: bool = False
    mass: Callable | None = None
    faces: Callable | None = None

    def record_field(self, column: str) -> str:
        """Name of the kernel record's field holding ``column`` of this kind's table (``sphere_radius``)."""
        return f"{self.name.lower()}_{column}"


def _sphere_mass(density: float, table: Table, row: int) -> tuple[float, tuple]:
    """Solid sphere: m = rho 4/3 pi r^3, I = 2/5 m r^2 on all axes."""
    r = float(table.radius[row])
    m = density * 4.0 / 3.0 * math.pi * r ** 3
    return m, (0.4 * m * r * r,) * 3


def _box_mass(density: float, table: Table, row: int) -> tuple[float, tuple]:
    """Solid cuboid of half-sizes e: m = 8 rho e0 e1 e2, I = m/3 (e1^2 + e2^2, e0^2 + e2^2, e0^2 + e1^2)."""
    e = table.extents[row]
    m = density * 8.0 * e.prod()
    e2 = e * e
    return m, (m / 3 * (e2[1] + e2[2]), m / 3 * (e2[0] + e2[2]), m / 3 * (e2[0] + e2[1]))


def _facet_faces(table: Table, rows: np.ndarray) -> np.ndarray:
    """One triangle per facet: (M, 1, 3, 3)."""
    return table.vertices[rows][:, None]


# Corner signs of the six faces of a box, four corners each, in the order YADE's VTK recorder
# writes them: z-, z+, x-, x+, y+, y-.
BOX_FACE_SIGNS = np.array([
    [(-1, -1, -1), (-1, 1, -1), (1, 1, -1), (1, -1, -1)],
    [(-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)],
    [(-1, -1, -1), (-1, -1, 1), (-1, 1, 1), (-1, 1, -1)],
    [(1, 1, 1), (1, -1, 1), (1, -1, -1), (1, 1, -1)],
    [(-1, 1, 1), (1, 1, 1), (1, 1, -1), (-1, 1, -1)],
    [(1, -1, -1), (1, -1, 1), (-1, -1, 1), (-1, -1, -1)],
], dtype=float)


def _box_faces(table: Table, rows: np.ndarray) -> np.ndarray:
    """Six quadrilaterals per box, in :data:`BOX_FACE_SIGNS` order: (M, 6, 4, 3)."""
    return BOX_FACE_SIGNS[None] * table.extents[rows][:, None, None, :]


#: The shape kinds, in code order (kind ``k`` is ``SHAPES[k - 1]``; 0 is "no shape"). Checkpoints
#: record the codes: a new kind goes at the end.
SHAPES: tuple[ShapeType, ...] = (
    ShapeType("Sphere", (
        Column("radius", (), "f8", float("nan"), "Sphere radius [m], (S,)."),
    ), {"radius": validate.POSITIVE_FINITE}, mass=_sphere_mass),
    ShapeType("Facet", (
        Column("vertices", (3, 3), "f8", 0.0,
               "Triangle vertices relative to the body position, local frame [m], (F, 3, 3)."),
        Column("normal", (3,), "f8", 0.0, "Unit normal (v1-v0)x(v2-v0)/|..| in the local frame [-], (F, 3)."),
    ), {"vertices": validate.TRIANGLE}, faces=_facet_faces),
    ShapeType("Wall", (
        Column("axis", (), "i1", 0, "Axis (0, 1, 2) normal to the infinite plane, (W,)."),
        Column("sense", (), "i1", 0, "Side that interacts: -1 negative, +1 positive, 0 both, (W,)."),
    ), {"axis": validate.WALL_AXIS, "sense": validate.WALL_SENSE}),
    ShapeType("Box", (
        Column("extents", (3,), "f8", 0.0, "Half-sizes along the local axes [m], (B, 3)."),
    ), {"extents": validate.EXTENTS}, aspherical=True, mass=_box_mass, faces=_box_faces),
    ShapeType("Clump", (
        Column("member_first", (), "i4", 0, "First entry of the clump's members in the clump member table, (K,)."),
        Column("member_count", (), "i4", 0, "Number of members, (K,)."),
    ), aspherical=True),
)

#: Kind of a body's shape (the ``shape_kind`` column): ``NONE`` (0), then one member per
#: declaration of :data:`SHAPES`, named by its YADE class name in upper case (``ShapeKind.SPHERE``).
ShapeKind = IntEnum("ShapeKind", [("NONE", 0)] + [(s.name.upper(), k) for k, s in enumerate(SHAPES, 1)],
                    module=__name__)
#: The kinds whose bodies rotate as aspherical ones (their angular momentum is integrated).
ASPHERICAL_KINDS: tuple[ShapeKind, ...] = tuple(ShapeKind(k) for k, s in enumerate(SHAPES, 1) if s.aspherical)


def shape_type(kind: int) -> ShapeType:
    """The declaration of shape kind ``kind`` (not ``NONE``)."""
    return SHAPES[int(kind) - 1]


#: Member ids of all clumps, each clump's members contiguous (see the CLUMP shape table).
CLUMP_MEMBER_COLUMNS = (Column("id", (), "i4", -1, "Body id of a clump member, (M,)."),)


def new_shape_tables(capacity: int = 8) -> dict[ShapeKind, Table]:
    """One empty table per shape kind, keyed by :class:`ShapeKind`."""
    return {ShapeKind(k): Table(s.columns, capacity) for k, s in enumerate(SHAPES, 1)}
