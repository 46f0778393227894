"""ScGeom: the sphere-centred contact geometry shared by all sphere contacts.

An ScGeom contact is described by the unit normal n (from body 1 to body 2), the
penetration depth delta (> 0 when the bodies overlap), the contact point C and two
reference radii. Shear laws are incremental; they need the relative velocity at the
contact and the rotation of the tangent plane since the last step.

References:
    YADE documentation, section 3.3 "Contact geometry" and 3.3.2 "Incremental
    shear displacement"; equations (3.3,1)-(3.3,6).
"""

from __future__ import annotations

from granum._jit import jit
from granum.core.arrays import S_DT, SI_PERIODIC
from granum.core.contacts import (
    F_NORMAL,
    F_PEN,
    F_POINT,
    F_PREV_NORMAL,
    F_R1,
    F_R2,
    FLAG_NEW,
    FLAG_RATCHET,
    I_CELL,
    I_FLAGS,
)
from granum.physics import registry
from granum.physics.vec import add, cross, dot, load3, matvec, scale, sub

registry.register_geom_type("IGeom")
registry.register_geom_type("GenericSpheresContact", "IGeom",
                            {"refR1": (F_R1, 1), "refR2": (F_R2, 1), "normal": (F_NORMAL, 3),
                             "contactPoint": (F_POINT, 3)})
registry.register_geom_type("ScGeom", "GenericSpheresContact",
                            {"penetrationDepth": (F_PEN, 1), "radius1": (F_R1, 1), "radius2": (F_R2, 1)})


@jit
def scgeom_write(c, C, normal, pen, point, r1, r2, ratchet):
    """Store the current geometry of contact ``c``, keeping the previous normal.

    For a contact made real in this step the previous normal is the current one, so
    that the tangent plane does not rotate in the first step. ``ratchet`` records
    whether shear laws use the anti-ratcheting relative velocity.
    """
    f = C.con_f
    flags = C.con_i[c, I_FLAGS]
    new_flags = (flags | FLAG_RATCHET) if ratchet else (flags & ~FLAG_RATCHET)
    if new_flags != flags:  # a store would make the row's cache line dirty, written back every step
        C.con_i[c, I_FLAGS] = new_flags
    if flags & FLAG_NEW:
        for k in range(3):
            f[c, F_PREV_NORMAL + k] = normal[k]
    else:
        for k in range(3):
            f[c, F_PREV_NORMAL + k] = f[c, F_NORMAL + k]
    for k in range(3):
        f[c, F_NORMAL + k] = normal[k]
        f[c, F_POINT + k] = point[k]
    f[c, F_PEN] = pen
    f[c, F_R1] = r1
    f[c, F_R2] = r2


@jit(inline="always")  # per contact: no call
def scgeom_shear_rotation(c, id1, id2, S, C):
    """The step's rotation of contact ``c``'s tangent plane, ``(orth, twist)`` for :func:`rotate_tangential`:
    orth = n_prev x n (the normal's turn, (3.3,4)) and twist = dt/2 (n_prev . (w1 + w2)) n_prev (the common
    spin of the two bodies about the normal). A law carrying several tangential vectors computes it once."""
    f = C.con_f
    n = (f[c, F_NORMAL], f[c, F_NORMAL + 1], f[c, F_NORMAL + 2])
    n0 = (f[c, F_PREV_NORMAL], f[c, F_PREV_NORMAL + 1], f[c, F_PREV_NORMAL + 2])
    orth = cross(n0, n)
    w = add(load3(S.ang_vel, id1), load3(S.ang_vel, id2))
    return orth, scale(n0, 0.5 * S.scal[S_DT] * dot(n0, w))


@jit(inline="always")  # per contact: no call
def rotate_tangential(v, rotation):
    """Carry the tangential vector ``v`` of the last step into the current tangent plane:
    v -= v x orth, then v -= v x twist (``rotation`` from :func:`scgeom_shear_rotation`)."""
    orth, twist = rotation
    v = sub(v, cross(v, orth))
    return sub(v, cross(v, twist))


@jit(inline="always")  # per contact: no call
def scgeom_rotate_shear(c, id1, id2, S, C, fs):
    """Carry the shear force ``fs`` of the last step into the current tangent plane.

    Rotation of the contact plane (3.3,4): fs -= fs x (n_prev x n); then the common
    spin of the two bodies about the normal: fs -= fs x (dt/2 (n_prev . (w1 + w2)) n_prev).
    """
    return rotate_tangential(fs, scgeom_shear_rotation(c, id1, id2, S, C))


@jit(inline="always")  # called per contact by the laws and the force gather: no call
def contact_shift(c, S, C):
    """Offset of body 2's periodic image and its velocity, ``(shift [m], shift_vel [m/s])``.

    For a contact across the periodic boundary with cell offset k (YADE ``cellDist``)
    the image of body 2 sits at pos2 + H k and moves with the extra velocity L H k
    (H = ``cell.hSize``, L = ``cell.velGrad``). Zero in aperiodic scenes.
    """
    if S.iscal[SI_PERIODIC] == 0:
        return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    k = (float(C.con_i[c, I_CELL]), float(C.con_i[c, I_CELL + 1]), float(C.con_i[c, I_CELL + 2]))
    shift = matvec(S.cell_hsize, k)
    shift_vel = matvec(S.cell_velgrad, shift)
    return shift, shift_vel


@jit(inline="always")  # per contact: no call
def scgeom_incident_vel(c, id1, id2, S, C, shift, shift_vel, ratchet):
    """Velocity of body 2 relative to body 1 at the contact point [m/s].

    With ``ratchet`` (YADE's ``avoidGranularRatcheting`` of the geometry) the lever arms are
    the reference radii and the centre velocities are scaled by
    alpha = (r1 + r2) / (r1 + r2 - delta), which removes the spurious ratcheting of
    cyclic loading; otherwise the arms are the vectors from the centres to C.
    """
    f = C.con_f
    n = (f[c, F_NORMAL], f[c, F_NORMAL + 1], f[c, F_NORMAL + 2])
    v1 = load3(S.vel, id1)
    v2 = add(load3(S.vel, id2), shift_vel)
    w1 = load3(S.ang_vel, id1)
    w2 = load3(S.ang_vel, id2)
    if ratchet:
        r1 = f[c, F_R1]
        r2 = f[c, F_R2]
        alpha = (r1 + r2) / (r1 + r2 - f[c, F_PEN])
        return sub(add(scale(sub(v2, v1), alpha), cross(w2, scale(n, -r2))), cross(w1, scale(n, r1)))
    p = (f[c, F_POINT], f[c, F_POINT + 1], f[c, F_POINT + 2])
    arm1 = sub(p, load3(S.pos, id1))
    arm2 = sub(p, add(load3(S.pos, id2), shift))
    return sub(add(v2, cross(w2, arm2)), add(v1, cross(w1, arm1)))


@jit(inline="always")  # per contact: no call
def scgeom_ratchet(c, C):
    """Whether the geometry functor of contact ``c`` asked for the anti-ratcheting velocity."""
    return C.con_i[c, I_FLAGS] & FLAG_RATCHET != 0


@jit(inline="always")  # per contact: no call
def tangential(v, n):
    """Component of ``v`` orthogonal to the unit vector ``n``."""
    return sub(v, scale(n, dot(v, n)))
