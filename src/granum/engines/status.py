"""What went wrong in a step, in words: one message per ``STATUS_*`` code a kernel can set.

A kernel that cannot complete a step stores a ``STATUS_*`` code of :mod:`granum.core.contacts`
and up to two values (``C_ERR_A``, ``C_ERR_B``: body ids, or a body and a cell axis) in the contact
counters and returns; the runner turns them into a :class:`~granum.engines.runner.SimulationError` with
:func:`status_message`. :data:`MESSAGES` holds one message builder per code, so each failure names
its own cause and what to change: a missing functor, a body too large for the periodic cell,
coincident centres, an infinite stiffness, or (only when none of those explains it) a time step
too large.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from granum.core.contacts import (
    C_CONTACTS,
    F_FN,
    F_FS,
    F_KN,
    F_KS,
    F_NORMAL,
    FLAG_ALIVE,
    I_FLAGS,
    I_ID1,
    I_ID2,
    STATUS_NO_GEOM,
    STATUS_NO_LAW,
    STATUS_NO_PAIR_VALUE,
    STATUS_NO_PHYS,
    STATUS_NONFINITE,
    STATUS_TOO_LARGE,
)
from granum.core.shapes import shape_type


def _shape(scene, i: int) -> str:
    """YADE class name of body ``i``'s shape (``"Sphere"``)."""
    return shape_type(scene.bodies.shape_kind[i]).name


def _materials(scene, a: int, b: int) -> tuple[str, str]:
    """Class names of the materials of bodies ``a`` and ``b``."""
    return tuple(type(scene.materials[scene.bodies.material[i]]).__name__ for i in (a, b))


def _no_phys(scene, a: int, b: int) -> str:
    ma, mb = _materials(scene, a, b)
    return (f"no IPhys functor in InteractionLoop for the material pair {ma}+{mb} (bodies {a} and {b}); "
            f"add the matching Ip2_ functor")


def _no_law(scene, a: int, b: int) -> str:
    ma, mb = _materials(scene, a, b)
    return (f"no Law2 functor in InteractionLoop for the contact of bodies {a} and {b} (materials {ma}+{mb}); "
            f"add the matching Law2_ functor")


def _no_geom(scene, a: int, b: int) -> str:
    sa, sb = _shape(scene, a), _shape(scene, b)
    return (f"bodies {a} ({sa}) and {b} ({sb}) may collide but no IGeom functor for {sa}+{sb} is listed in "
            f"InteractionLoop; add the matching Ig2_ functor")


def _too_large(scene, a: int, axis: int) -> str:
    """Body ``a`` spans over half the cell along the cell's axis ``axis`` (the collider's rule:
    :mod:`granum.kernels.collider_periodic`)."""
    bd = scene.bodies
    span = np.asarray(bd.bound_max[a]) - np.asarray(bd.bound_min[a])
    cell = np.linalg.norm(np.asarray(scene.cell_hsize), axis=0)
    return (f"body {a} ({_shape(scene, a)}, bound {tuple(span.round(12).tolist())}) spans over half of the "
            f"periodic cell along the cell's axis {axis} (cell sizes {tuple(cell.round(12).tolist())}) and meets "
            f"another body: enlarge O.cell.hSize, make the body smaller, flip a sheared cell (flipCell) or set "
            f"InsertionSortCollider.allowBiggerThanPeriod=True (each pair then meets through its nearest image)")


def _live_contacts_of(scene, a: int) -> list[tuple[int, int]]:
    """``(contact row, other body id)`` of the live contacts of body ``a``."""
    C = scene.contacts
    n = int(C.ctr[C_CONTACTS])
    rows = C.con_i[:n]
    mine = (rows[:, I_FLAGS] & FLAG_ALIVE != 0) & ((rows[:, I_ID1] == a) | (rows[:, I_ID2] == a))
    return [(int(c), int(rows[c, I_ID2] if rows[c, I_ID1] == a else rows[c, I_ID1])) for c in np.nonzero(mine)[0]]


def _nonfinite(scene, a: int, _b: int) -> str:
    """The cause of a non-finite or exploding body state, from the contacts of that body: an undefined
    normal (coincident centres), a non-finite stiffness, a non-finite force; else the time step."""
    bd = scene.bodies
    state = (f"body {a} has a non-finite or exploding state (pos={tuple(bd.pos[a].tolist())}, "
             f"vel={tuple(bd.vel[a].tolist())})")
    f = scene.contacts.con_f
    for c, other in _live_contacts_of(scene, a):
        normal, force = f[c, F_NORMAL:F_NORMAL + 3], f[c, F_FN:F_FS + 3]
        kn, ks = float(f[c, F_KN]), float(f[c, F_KS])
        if not np.isfinite(normal).all():
            return (f"{state}: the contact of bodies {a} and {other} has no defined normal "
                    f"(normal={tuple(normal.tolist())}): their centres coincide, or a shape is degenerate; "
                    f"move one of them")
        if not (np.isfinite(kn) and np.isfinite(ks)):
            ma, mb = _materials(scene, a, other)
            return (f"{state}: the contact of bodies {a} and {other} has a non-finite stiffness (kn={kn}, ks={ks}); "
                    f"check the parameters of their materials ({ma}, {mb}) and of the Ip2_ functor")
        if not np.isfinite(force).all():
            return (f"{state}: the contact of bodies {a} and {other} has a non-finite force "
                    f"(normal force={tuple(force[:3].tolist())}, shear force={tuple(force[3:].tolist())})")
    return f"{state}; is O.dt too large (compare PWaveTimeStep())?"


def _no_pair_value(scene, a: int, b: int) -> str:
    """An Ip2 functor has no value for the materials of bodies ``a`` and ``b``: its Python side says why
    (``explain_pair``: a MatchMaker without a match, materials it cannot combine)."""
    for e in scene.engines:
        for f in getattr(getattr(e, "physDispatcher", None), "functors", ()):
            why = f.explain_pair(scene, a, b)
            if why:
                return why
    ma, mb = _materials(scene, a, b)
    return f"the Ip2 functor has no value for the materials of bodies {a} and {b} ({ma}, {mb})"


#: One message builder per ``STATUS_*`` code: ``builder(scene, err_a, err_b) -> str`` (the cause and what
#: to change; the runner adds the step number).
MESSAGES: dict[int, Callable[[object, int, int], str]] = {
    STATUS_NO_PHYS: _no_phys,
    STATUS_NO_LAW: _no_law,
    STATUS_NONFINITE: _nonfinite,
    STATUS_NO_GEOM: _no_geom,
    STATUS_TOO_LARGE: _too_large,
    STATUS_NO_PAIR_VALUE: _no_pair_value,
}


def status_message(scene, status: int, a: int, b: int) -> str:
    """The message of a failed step: ``status`` (a ``STATUS_*`` code) and its values ``a``, ``b``."""
    build = MESSAGES.get(status)
    detail = build(scene, a, b) if build else f"unknown failure status {status} (values {a}, {b})"
    return f"step {scene.iter}: {detail}. The scene is kept as this step left it."
