"""Interaction storage: a light list of potential pairs and a pool of real contacts.

YADE distinguishes *potential* interactions (the bounds of two bodies overlap) from
*real* ones (the contact geometry exists and a law acts). In a dense packing most
potential pairs are never real, so granum keeps them apart:

``pair_ids``  (P, 2) int32
    Potential pairs found by the collider, sorted by (min id, max id). Rebuilt only
    when the collider runs.
``pair_cell``  (P, 3) int32
    Periodic image of the second body of the pair: its position is taken as
    ``pos + hSize @ pair_cell`` (YADE's ``cellDist``). Aperiodic scenes store none
    (0 rows) once the collider has run.
``pair_con``  (P,) int32
    Index of the pair's real contact in the pool, or -1.
``pair_gap``  (P,) float32
    Motion budget of a pair without contact [m]: while the relative motion of its two
    bodies since the budget was set (from ``pair_ref``) stays below it, they cannot touch and the
    geometry is not evaluated (see :func:`granum.kernels.interaction.detect_block`).
    -inf: evaluate at the next step (new pairs, ended contacts); +inf: never (the pair has
    a contact, or its shapes do not interact). A pair with a contact always has +inf: the detection
    passes over it on that alone.
``pair_ref``  (P, 3) int16
    Relative displacement d_a - d_b of the pair's bodies since the collider ran (less the detection's shift,
    ``detect_shift``, which :func:`granum.kernels.motion.reorigin` moves), taken when its budget was
    set, in units of ``scal[S_PAIR_REF_UNIT]`` (rounded; the rounding is taken from the budget): the motion
    the budget is compared with is measured from there (see :func:`granum.kernels.interaction.detect_block`).
``pair_hit``  (P,) uint8
    Outcome of this step's detection for the pair (``HIT_*`` of the interaction loop), set for the pairs
    found touching and zeroed again as they become contacts: zero outside the interaction loop.
``con_i``, ``con_f``  (K, NI_CORE or NI) int32 and (K, NF) float64
    The pool of real contacts, one row per contact (all columns of a contact are
    adjacent in memory, which suits the per-contact loop). Column offsets are the
    ``I_*`` and ``F_*`` constants below; laws may declare extra history columns,
    appended after the core ones (see :func:`contact_width`); the periodic image columns
    of ``con_i`` exist in periodic scenes only.
``csr_start``, ``csr_con``  (N+1,) and (2K,) int32
    For each body, the indices of its live contacts in increasing order. Forces are
    gathered per body through this index, so the summation order is fixed and
    results do not depend on the number of threads.
``ctr``  (NCTR,) int64
    Counters and status flags (``C_*`` constants). ``ctr[C_REPLACED]`` changes whenever compiled code replaces
    one of these arrays (each place that does counts it): Python takes the arrays back from the kernels' record
    only then (:meth:`granum.core.scene.Scene.take_contacts`). Checkpoints of versions with fewer counters load
    with the missing ones zero.
``ended``  (NF,) float64
    Per ``con_f`` column, the sums over the contacts that ended of the columns that are running totals
    outliving their contact (:func:`register_totals`: YADE's law accumulators such as Hertz-Mindlin's
    ``frictionDissipation``); 0 in the other columns.
``scratch``  (W,) float64
    The stages' work area for a step's temporaries (:mod:`granum.kernels.scratch`); not state, so not
    saved in checkpoints.

Contacts are appended in the order their pairs became real (pair order within a
step) and removed by stable compaction, so the pool order is deterministic.
"""

from __future__ import annotations

import numpy as np

from granum.core.records import RecordSpec

# ---- integer columns of con_i -------------------------------------------------
I_ID1 = 0        # body id 1 (in the order the geometry functor expects, e.g. facet first)
I_ID2 = 1        # body id 2
I_PAIR = 2       # index of the potential pair in pair_ids, -1 if none
I_FLAGS = 3      # FLAG_* bits
I_GEOM = 4       # code of the geometry functor
I_PHYS = 5       # code of the physics functor
I_LAW = 6        # code of the law functor
I_BORN = 7       # step at which the contact became real
NI_CORE = 8      # width of con_i in an aperiodic scene
I_CELL = 8       # 8, 9, 10: periodic image of body 2 (YADE cellDist); periodic scenes only
NI = 11          # width of con_i in a periodic scene

# ---- float columns of con_f -------------------------------------------------------
F_NORMAL = 0       # 0..2  unit normal from body 1 to body 2 [-]
F_PREV_NORMAL = 3  # 3..5  normal at the previous step [-]
F_PEN = 6          # penetration depth, > 0 when overlapping [m]
F_POINT = 7        # 7..9  contact point [m]
F_R1 = 10          # reference radius of body 1 (ScGeom radius1) [m]
F_R2 = 11          # reference radius of body 2 (ScGeom radius2) [m]
F_KN = 12          # normal stiffness [N/m]
F_KS = 13          # shear stiffness [N/m]
F_TANPHI = 14      # tangent of the friction angle [-]
F_FN = 15          # 15..17 normal force on body 2 [N]
F_FS = 18          # 18..20 shear force on body 2 [N]
NF_CORE = 21

#: Optional float column groups after the core ones, name -> (offset, width), in offset order.
#: The pool is only as wide as the last group its plan uses (the energies when O.trackEnergy,
#: the history the laws of its InteractionLoop declare): a Cundall-Strack packing stores 21
#: floats per contact, not 28.
HISTORY_COLUMNS: dict[str, tuple[int, int]] = {}


def register_history(name: str, width: int, after: tuple[str, ...] = ()) -> int:
    """Declare a group of per-contact float columns (a law's history); return its offset in ``con_f``.

    Functors that use the group name it in :attr:`granum.physics.registry.Functor.history`. Groups are
    appended, so a group declared later (a user's law, :mod:`granum.yade.userlaws`) moves no other
    one; declaring a group again with the same width returns its offset (a script run twice).

    With ``after`` (groups declared before), the group starts where the last of them ends instead, sharing
    its columns with the groups declared in between: the pools of the laws using it stay narrow. That is
    for groups that no contact uses together with those (another contact law, another geometry): each
    contact uses the groups of its own functors only, its row starts zeroed, and the interaction loop
    refuses a plan in which one contact's functors would use two groups sharing a column
    (:func:`shared_columns`).
    """
    if name in HISTORY_COLUMNS:
        offset, old_width = HISTORY_COLUMNS[name]
        if old_width != width:
            raise ValueError(f"contact history column group {name!r} is already declared with width {old_width}")
        return offset
    offset = max(sum(HISTORY_COLUMNS[g]) for g in after) if after else nf()
    HISTORY_COLUMNS[name] = (offset, width)
    return offset


#: Columns of history groups that are running totals a law keeps after a contact ends, group -> (first, count)
TOTALS: dict[str, tuple[int, int]] = {}


def register_totals(group: str, first: int, count: int) -> None:
    """Declare the columns ``first .. first + count - 1`` of the history group ``group`` running totals that
    outlive their contact: when a contact whose law uses the group ends (in a step or erased from Python), they
    are added to ``ended`` (module docstring), so that the law's accumulator, the live contacts' sum plus
    ``ended``, keeps the share of ended contacts (YADE's)."""
    offset, width = HISTORY_COLUMNS[group]
    if not (offset <= first and first + count <= offset + width):
        raise ValueError(f"totals {first}..{first + count - 1} lie outside the group {group!r}")
    TOTALS[group] = (first, count)


def retire_totals(C, c: int, groups) -> None:
    """Add the running totals of contact ``c`` (its law's history ``groups``) to ``ended``, in Python (an
    interaction or body erased by a script); compiled code does the same for contacts a law ends."""
    for g in groups:
        if g in TOTALS:
            first, count = TOTALS[g]
            C.ended[first:first + count] += C.con_f[c, first:first + count]


def shared_columns(groups) -> tuple[str, str] | None:
    """Two of the history groups ``groups`` that share a column (see :func:`register_history`), or None."""
    spans = sorted((HISTORY_COLUMNS[g][0], HISTORY_COLUMNS[g][0] + HISTORY_COLUMNS[g][1], g) for g in set(groups))
    for (_, end, a), (start, _, b) in zip(spans, spans[1:], strict=False):
        if start < end:
            return a, b
    return None


def nf() -> int:
    """Number of float columns of a contact when every group is in use: where the last group ends."""
    return max([NF_CORE] + [offset + width for offset, width in HISTORY_COLUMNS.values()])


def contact_width(groups) -> int:
    """Width of ``con_f`` that holds the core columns and the history groups named in ``groups``."""
    return max([NF_CORE] + [HISTORY_COLUMNS[g][0] + HISTORY_COLUMNS[g][1] for g in groups])


F_E_ELAST = register_history("energy", 2)  # elastic energy stored in the contact [J] (O.trackEnergy)
F_E_DISSIP = F_E_ELAST + 1                  # energy dissipated by friction during this step [J]
#: moment on body 2 that is not arm x force (bending, twisting, rolling resistance) [N m]; body 1 gets the
#: opposite. Written by the laws that name the group "moment" in their history; the force gather adds it to
#: both bodies' torques only in plans whose laws do (granum.kernels.interaction.gather_body).
F_MOMENT = register_history("moment", 3)

FLAG_ALIVE = 1     # the row holds a live contact
FLAG_NEW = 2       # physics constants not computed yet
FLAG_RATCHET = 4   # shear laws use the anti-ratcheting relative velocity (ScGeom)
FLAG_RADIAL_ARMS = 16  # torques use the lever arms (R_i - delta/2) n instead of C - x_i (YADE sphericalBodies)
FLAG_PHYS_AGAIN = 32   # run the physics functor of this existing contact at the next step (e.g. setCohesionNow)

# ---- counters in ctr ---------------------------------------------------------------
C_PAIRS = 0        # number of potential pairs
C_CONTACTS = 1     # rows used in the pool (live and dead)
C_DEAD = 2         # dead rows awaiting compaction
C_CSR_DIRTY = 3    # contact set changed since the CSR index was built
C_COLLIDE = 4      # the collider must run at the next step (set by Python on scene edits): COLLIDE_*
C_STATUS = 5       # STATUS_* of the last step
C_ERR_A = 6        # first value describing the error (body id or code)
C_ERR_B = 7        # second value describing the error
C_COLLIDER_RUNS = 8
C_REPLACED = 9     # times compiled code replaced one of the storage's arrays (pair list, grown pool or work area)
C_MOTIONS_STAGE = 10  # the stage (its C_STAGE) whose check left the bodies' motions at the start of the work area, for
                      # the interaction loop if it is the next stage (granum.kernels.motion.take_motions); 0: none
C_STAGE = 11       # stages called since the step loop was entered (granum.kernels.steploop counts them)
NCTR = 12

#: ``ctr[C_COLLIDE]``: 0 the collider runs when a body left its bound; COLLIDE_FULL at the next step, every body
#: bounded again and the pair list rebuilt (a scene edit); COLLIDE_APPENDED at the next step, and bodies were only
#: appended since it last ran (a factory's): it may bound and pair only them
#: (:mod:`granum.kernels.collider_append`).
COLLIDE_FULL = 1
COLLIDE_APPENDED = 2

STATUS_OK = 0
STATUS_NO_PHYS = 1      # no IPhys functor for a material pair (ERR_A, ERR_B: body ids)
STATUS_NO_LAW = 2       # no law functor for a geometry/physics pair (ERR_A, ERR_B: body ids)
STATUS_NONFINITE = 3    # NaN/inf or exploding velocity (ERR_A: body id)
STATUS_NO_GEOM = 4      # bounds of two bodies overlap, a geometry functor exists but is not listed
STATUS_TOO_LARGE = 5    # a body is wider than half the periodic cell (ERR_A: body id, ERR_B: cell axis)
STATUS_NO_PAIR_VALUE = 6  # an Ip2 functor has no value for the materials of a new contact (ERR_A, ERR_B: body ids)

#: Record of the interaction storage passed to kernels (see the module docstring).
CONTACTS = RecordSpec("ContactArrays", [
    ("pair_ids", "i4", 2), ("pair_cell", "i4", 2), ("pair_con", "i4", 1), ("pair_gap", "f4", 1),
    ("pair_ref", "i2", 2), ("pair_hit", "u1", 1),
    ("con_i", "i4", 2),
    ("con_f", "f8", 2), ("csr_start", "i4", 1), ("csr_con", "i4", 1), ("ctr", "i8", 1), ("ended", "f8", 1),
    ("scratch", "f8", 1)], transient=("scratch",), counted=False)
ContactArrays = CONTACTS.tuple


def new_contact_arrays(n_bodies: int, pair_capacity: int = 64, contact_capacity: int = 64,
                       periodic: bool = False) -> ContactArrays:
    """Empty interaction storage for ``n_bodies`` bodies (with the image columns when ``periodic``)."""
    con_i = np.zeros((contact_capacity, NI if periodic else NI_CORE), np.int32)
    con_i[:, I_PAIR] = -1
    ctr = np.zeros(NCTR, np.int64)
    ctr[C_COLLIDE] = COLLIDE_FULL
    return ContactArrays(
        pair_ids=np.zeros((pair_capacity, 2), np.int32),
        pair_cell=np.zeros((pair_capacity, 3), np.int32),
        pair_con=np.full(pair_capacity, -1, np.int32),
        pair_gap=np.full(pair_capacity, -np.inf, np.float32),
        pair_ref=np.zeros((pair_capacity, 3), np.int16),
        pair_hit=np.zeros(pair_capacity, np.uint8),
        con_i=con_i,
        con_f=np.zeros((contact_capacity, NF_CORE), np.float64),
        csr_start=np.zeros(n_bodies + 1, np.int32),
        csr_con=np.zeros(2 * contact_capacity, np.int32),
        ctr=ctr,
        ended=np.zeros(NF_CORE),
        scratch=np.zeros(0),
    )


def with_images(C: ContactArrays) -> ContactArrays:
    """Storage with the periodic image columns ``I_CELL`` (zero for the contacts so far)."""
    if C.con_i.shape[1] >= NI:
        return C
    con_i = np.zeros((C.con_i.shape[0], NI), np.int32)
    con_i[:, :C.con_i.shape[1]] = C.con_i
    return C._replace(con_i=con_i)


def resize_for_bodies(C: ContactArrays, n_bodies: int) -> ContactArrays:
    """Storage whose per-body index fits ``n_bodies`` bodies (the CSR is marked for rebuild)."""
    if C.csr_start.shape[0] == n_bodies + 1:
        return C
    C.ctr[C_CSR_DIRTY] = 1
    return C._replace(csr_start=np.zeros(n_bodies + 1, np.int32))


def end_contact(C: ContactArrays, c: int, groups=()) -> None:
    """End live contact ``c`` from Python (body erased, interaction erased by the user).

    The row is unlinked from its pair and left for compaction, exactly as when a law
    ends a contact inside a step; its running totals (its law's history ``groups``) go to ``ended``.
    """
    retire_totals(C, c, groups)
    C.con_i[c, I_FLAGS] &= ~FLAG_ALIVE
    p = C.con_i[c, I_PAIR]
    if p >= 0:
        C.pair_con[p] = -1
        C.pair_gap[p] = -np.inf
    C.con_i[c, I_ID1] = -1
    C.con_i[c, I_PAIR] = -1
    C.ctr[C_DEAD] += 1
    C.ctr[C_CSR_DIRTY] = 1
