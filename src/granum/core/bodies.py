"""Per-body storage: kinematic state, mass properties, flags and force accumulators.

One row per body id; a body keeps its row for its whole life (erased bodies keep a
dead row, so ids never move). ``N`` below is the table's capacity; rows at and past
``count`` are unused.
"""

from __future__ import annotations

import math

from granum.core.table import Column, Table

#: Bits of ``body_blocked`` in YADE's ``blockedDOFs`` letter order ``xyzXYZ``.
DOF_LETTERS = "xyzXYZ"
DOF_ALL = 0b111111


def dofs_from_string(s: str) -> int:
    """Bit mask of the blocked degrees of freedom named in ``s`` (subset of ``'xyzXYZ'``)."""
    bits = 0
    for ch in s:
        k = DOF_LETTERS.find(ch)
        if k < 0:
            raise ValueError(f"blockedDOFs: invalid letter {ch!r} in {s!r}; use letters from 'xyzXYZ'")
        bits |= 1 << k
    return bits


def dofs_to_string(bits: int) -> str:
    """YADE's string form of a blocked-DOF bit mask."""
    return "".join(ch for k, ch in enumerate(DOF_LETTERS) if bits >> k & 1)


#: Slots of the body column ``cpm_state`` (a CpmState's post-processing values, :mod:`granum.yade.cpm`)
CPM_IS_STATE = 0        # 1: the body's state is a CpmState (its material's associated state) [-]
CPM_NORM_DMG = 1        # normDmg: 1 - relative residual strength, averaged with the broken contacts [-]
CPM_NUM_CONTACTS = 2    # numContacts (YADE's CpmStateUpdater leaves it as set) [-]
CPM_EPS_VOLUMETRIC = 3  # epsVolumetric (YADE's leaves it as set) [-]
CPM_STRESS = 4          # 4..12 stress, a Matrix3 row by row [Pa]
CPM_STATE_WIDTH = 13

BODY_COLUMNS = (
    Column("pos", (3,), "f8", 0.0, "Centre of mass (sphere/box centre, facet inscribed-circle centre) [m], (N, 3)."),
    Column("vel", (3,), "f8", 0.0, "Linear velocity at the last mid-step [m/s], (N, 3)."),
    Column("ori", (4,), "f8", (1.0, 0.0, 0.0, 0.0),
           "Orientation quaternion (w, x, y, z), local to global [-], (N, 4)."),
    Column("ang_vel", (3,), "f8", 0.0, "Angular velocity in the global frame [rad/s], (N, 3)."),
    Column("ang_mom", (3,), "f8", 0.0, "Angular momentum in the global frame (aspherical bodies) [kg m^2/s], (N, 3).",
           lazy=True),
    Column("mass", (), "f8", 0.0, "Mass [kg], (N,)."),
    Column("inertia", (3,), "f8", 0.0, "Principal moments of inertia in the local frame [kg m^2], (N, 3)."),
    Column("blocked", (), "u1", 0, "Blocked degrees of freedom, bit k = letter k of 'xyzXYZ', (N,)."),
    Column("is_damped", (), "?", True, "Whether NewtonIntegrator's damping acts on the body, (N,)."),
    Column("aspherical", (), "?", False, "Integrate rotation with the full inertia tensor (Euler's equations), (N,)."),
    Column("ref_pos", (3,), "f8", 0.0, "Reference position for displacement measures [m], (N, 3)."),
    Column("ref_ori", (4,), "f8", (1.0, 0.0, 0.0, 0.0), "Reference orientation (w, x, y, z), (N, 4).", lazy=True),
    Column("alive", (), "?", False, "False for erased ids and unused rows, (N,)."),
    Column("shape_kind", (), "i1", 0, "Kind of the body's shape (granum.core.shapes.ShapeKind), (N,)."),
    Column("shape_row", (), "i4", -1, "Row of the body's shape in the table of its kind, (N,)."),
    Column("material", (), "i4", -1, "Row of the body's material in the scene's material table, (N,)."),
    Column("mask", (), "i8", 1, "Group mask; two bodies interact only if mask1 & mask2 != 0, (N,)."),
    Column("clump_id", (), "i4", -1, "Id of the clump the body belongs to (its own id for a clump), -1 if none, (N,)."),
    Column("clump_rel_pos", (3,), "f8", 0.0, "Member position relative to its clump, clump frame [m], (N, 3).",
           lazy=True),
    Column("clump_rel_ori", (4,), "f8", (1.0, 0.0, 0.0, 0.0), "Member orientation relative to its clump, (N, 4).",
           lazy=True),
    Column("color", (3,), "f8", 1.0, "Display colour, RGB in [0, 1], (N, 3)."),
    Column("wire", (), "?", False, "Display as wire frame, (N,)."),
    Column("highlight", (), "?", False, "Display highlighted, (N,)."),
    Column("force", (3,), "f8", 0.0, "Force accumulated during the current step [N], (N, 3)."),
    Column("torque", (3,), "f8", 0.0, "Torque accumulated during the current step [N m], (N, 3)."),
    Column("perm_force", (3,), "f8", 0.0, "Permanent force, survives ForceResetter [N], (N, 3).", lazy=True),
    Column("perm_torque", (3,), "f8", 0.0, "Permanent torque, survives ForceResetter [N m], (N, 3).", lazy=True),
    Column("cpm_broken", (), "i8", 0, "Contacts of the concrete model that ended (CpmState.numBrokenCohesive), "
           "counted by Law2_ScGeom_CpmPhys_Cpm, (N,).", lazy=True),
    Column("cpm_state", (CPM_STATE_WIDTH,), "f8", 0.0,
           "CpmState of the body: CPM_* slots below (written by CpmStateUpdater), (N, CPM_STATE_WIDTH).", lazy=True),
    Column("bound_min", (3,), "f8", math.nan,
           "Lower corner of the axis-aligned bound incl. Verlet distance [m], (N, 3); NaN until the collider runs."),
    Column("bound_max", (3,), "f8", math.nan,
           "Upper corner of the axis-aligned bound incl. Verlet distance [m], (N, 3); NaN until the collider runs."),
    Column("bound_pos", (3,), "f8", 0.0, "Position when the bound was last computed [m], (N, 3)."),
    Column("bound_ori", (4,), "f8", (1.0, 0.0, 0.0, 0.0), "Orientation when the bound was last computed, (N, 4)."),
    Column("detect_shift", (3,), "f8", 0.0,
           "Displacement since the bound (pos - bound_pos) at the detection's last re-origin "
           "(granum.kernels.motion.reorigin), from which the interaction loop's detection measures motions; "
           "0 when the bound is computed [m], (N, 3)."),
)


#: When each body of a scene was appended (YADE's ``Body.iterBorn``/``timeBorn``); a table of its own,
#: beside the body table, because no kernel reads it (the kernels' record stays as it is).
BORN_COLUMNS = (
    Column("iter", (), "i8", -1, "Step (O.iter) at which the body was appended, -1 if never, (N,)."),
    Column("time", (), "f8", -1.0, "Simulated time (O.time) at which the body was appended [s], -1 if never, (N,)."),
)


def new_body_table(capacity: int = 8) -> Table:
    """An empty body table (see :data:`BODY_COLUMNS` for the columns)."""
    return Table(BODY_COLUMNS, capacity)
