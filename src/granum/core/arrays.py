"""The bundle of scene arrays handed to compiled kernels.

Kernels never see Python objects: the scene packs its tables into one record
(:data:`SCENE`, see :mod:`granum.core.records`) before each run.
Scalars that kernels update (time, step) live in small arrays so that compiled code
can write them in place.

Constants are named by the array they index: ``S_*`` slots of ``scal``, ``SI_*`` slots of
``iscal``, ``E_*`` slots of ``energy``; the contact pool's columns are ``I_*`` (``con_i``) and
``F_*`` (``con_f``), its counters ``C_*`` (:mod:`granum.core.contacts`).
"""

from __future__ import annotations

from granum.core.bodies import BODY_COLUMNS
from granum.core.records import RecordSpec
from granum.core.shapes import SHAPES

# ---- float scalars: scal ---------------------------------------------------------
S_DT = 0           # time step [s]
S_TIME = 1         # simulated time [s]
S_VERLET = 2       # Verlet distance of the current bounds [m]
S_PAIR_REF_UNIT = 3  # length unit of the pairs' reference motions ``pair_ref``, set by the collider [m]
S_TURN_ALLOWANCE = 4  # rotation allowance in the budgets of pairs with a turning body, fixed by the collider [m]
S_TURN_SEEN = 5     # greatest rotation term 2 max w seen since the collider ran [m]
NSCAL = 6

# ---- integer scalars: iscal ------------------------------------------------------
SI_ITER = 0         # step counter
SI_TRACK_ENERGY = 1  # 1 when O.trackEnergy
SI_NBODIES = 2      # number of body ids in use (len(O.bodies))
SI_PERIODIC = 3     # 1 when the scene is periodic
SI_HOMO_DEFORM = 4  # YADE's Cell.homoDeform: 0 none, 1 velocity jumps, 2 also the convective term
SI_HOOK = 5         # set by a compiled engine that needs its Python hook run after this step (engine index + 1)
NSISCAL = 6

# ---- energy slots: energy[E_*], energy_set[E_*] -------------------------------------
ENERGY_NAMES = ("kinetic", "gravWork", "nonviscDamp", "elastPotential", "plastDissip")
E_KINETIC, E_GRAV_WORK, E_NONVISC_DAMP, E_ELAST_POT, E_PLAST_DISSIP = range(5)
# instantaneous terms are recomputed every step; the others accumulate
ENERGY_RESET = (True, False, False, True, False)
NENERGY = len(ENERGY_NAMES)

# ---- the material table: mat_kind (M,), mat (M, ncol) ---------------------------------
#: Names of the material kinds in code order (``mat_kind`` holds the index) and of the columns of ``mat``.
#: Core stores the table and physics says what is in it: each material kind the physics registry
#: registers is declared here (:func:`declare_material`), and the scene fills the table from these.
MATERIAL_KINDS: list[str] = []
MATERIAL_COLUMNS: list[str] = []


def declare_material(kind: str, columns) -> None:
    """Give the material kind ``kind`` the next code (unless it has one) and the table the ``columns``
    (names) it lacks, at the end."""
    if kind not in MATERIAL_KINDS:
        MATERIAL_KINDS.append(kind)
    for c in columns:
        if c not in MATERIAL_COLUMNS:
            MATERIAL_COLUMNS.append(c)

def _scene_fields() -> list[tuple[str, str, int]]:
    fields = [(c.name, c.dtype, 1 + len(c.tail)) for c in BODY_COLUMNS]
    for shape in SHAPES:
        fields += [(shape.record_field(c.name), c.dtype, 1 + len(c.tail)) for c in shape.columns]
    fields += [
        ("mat_kind", "i4", 1),      # material class code of each material row, (M,)
        ("mat", "f8", 2),           # material parameters, columns named by the registry, (M, ncol)
        ("cell_hsize", "f8", 2),    # periodic cell base vectors as columns [m], (3, 3)
        ("cell_velgrad", "f8", 2),  # velocity gradient of the cell [1/s], (3, 3)
        ("cell_prev_velgrad", "f8", 2),  # velocity gradient of the previous step [1/s], (3, 3)
        ("cell_trsf", "f8", 2),     # accumulated deformation gradient F [-], (3, 3)
        ("cell_bound_hsize", "f8", 2),  # hSize when the collider last ran [m], (3, 3)
        ("cell_prev_hsize", "f8", 2),   # hSize before the current step's deformation (YADE prevHSize) [m], (3, 3)
        ("clump_members", "i4", 1),  # member ids of all clumps (see the shape table clump_member_first/count), (M,)
        ("scal", "f8", 1),          # float scalars S_*, (NSCAL,)
        ("iscal", "i8", 1),         # integer scalars I_*, (NSISCAL,)
        ("energy", "f8", 1),        # energy terms E_* [J], (NENERGY,)
        ("energy_set", "u1", 1),    # 1 once a term has been computed, (NENERGY,)
    ]
    return fields


#: The record of all scene arrays passed to kernels: body columns (see
#: :data:`granum.core.bodies.BODY_COLUMNS`), shape tables as ``<kind>_<column>``,
#: materials, cell, scalars and energies.
SCENE = RecordSpec("SceneArrays", _scene_fields(), counted=False)
