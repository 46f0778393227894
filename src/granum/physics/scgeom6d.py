"""ScGeom6D: ScGeom plus the relative rotation of the two bodies since the contact began (twist, bending).

A contact with 6 degrees of freedom (normal, two shear, twist, two bending) keeps the orientations q1_0, q2_0
of its bodies at its creation (``initialOrientation1/2``, YADE's ``initRotations``). At every step the
relative rotation since then is

.. math::
    \\Delta q = \\frac{(q_1 q_{1,0}^{*})(q_{2,0} q_2^{*})}{|\\ldots|},\\qquad
    \\theta = \\text{rotation vector of } \\Delta q \\text{ (angle in } [0, \\pi]),\\qquad
    \\text{twist} = \\theta \\cdot n,\\qquad \\text{bending} = \\theta - \\text{twist}\\; n

with n the current normal: for body 2 turning by an angle a about u with body 1 still, theta = -a u (the
rotation of body 1 relative to body 2), so that a moment k theta on body 2 resists the rotation.
The geometry functors are those of ScGeom (sphere-sphere, facet-sphere, box-sphere) followed by
:func:`scgeom6d_update`; YADE 2023.02a has no ``Ig2_Wall_Sphere_ScGeom6D``.

References:
    YADE class reference: ScGeom6D, Ig2_Sphere_Sphere_ScGeom6D, Ig2_Facet_Sphere_ScGeom6D,
    Ig2_Box_Sphere_ScGeom6D; F. Bourrier, F. Kneib, B. Chareyre, T. Fourcaud (2013), Discrete modeling of
    granular soils reinforcement by plant roots, *Ecological Engineering* 61:646-657 (the twist/bending
    decomposition). Checked against YADE 2023.02a: tests/reference/yade/cohfrict.py.
"""

from __future__ import annotations

import dataclasses
import math

from granum._jit import jit
from granum.core.contacts import F_NORMAL, FLAG_NEW, I_FLAGS, register_history
from granum.physics import registry
from granum.physics.box import geom_box_sphere
from granum.physics.facet import geom_facet_sphere
from granum.physics.registry import Functor, Param
from granum.physics.sphere import geom_sphere_sphere
from granum.physics.vec import load4, quat_mul

#: orientation of body 1 when the contact began (w, x, y, z) [-]
# after the groups of the laws that may run on it (every ScGeom law: the moment, Hertz-Mindlin's, the
# visco-elastic ones; the cohesion's lies among them), so that those laws' own pools stay narrow; it shares its
# columns with L3Geom's (no contact has both geometries; checked per plan). physics/__init__ imports it last.
G6_ORI1 = register_history("scgeom6d", 12, after=("moment", "mindlin", "viscel_shear_elastic"))
#: orientation of body 2 when the contact began (w, x, y, z) [-]
G6_ORI2 = G6_ORI1 + 4
#: twist: relative rotation about the normal [rad]
G6_TWIST = G6_ORI1 + 8
#: bending: relative rotation about axes in the tangent plane, as a rotation vector [rad]
G6_BENDING = G6_ORI1 + 9
#: the history group of every ScGeom6D functor
HISTORY = ("scgeom6d",)

registry.register_geom_type("ScGeom6D", "ScGeom", {
    "initialOrientation1": (G6_ORI1, 4), "initialOrientation2": (G6_ORI2, 4), "twist": (G6_TWIST, 1),
    "bending": (G6_BENDING, 3)})


@jit
def scgeom6d_init(c, id1, id2, S, C):
    """Start the relative rotation of contact ``c`` from now (YADE's ``initRotations``): the bodies' current
    orientations become the initial ones, twist and bending zero."""
    f = C.con_f
    for k in range(4):
        f[c, G6_ORI1 + k] = S.ori[id1, k]
        f[c, G6_ORI2 + k] = S.ori[id2, k]
    for k in range(4):
        f[c, G6_TWIST + k] = 0.0


@jit
def rotation_vector(q):
    """Rotation vector angle * axis [rad] of the unit quaternion ``q`` (w, x, y, z), the angle in [0, pi]:
    2 atan2(|v|, |w|) about v/|v|, turned over when w < 0 (q and -q are the same rotation); zero for the
    identity."""
    s = math.sqrt(q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    if s == 0.0:
        return (0.0, 0.0, 0.0)
    angle = 2.0 * math.atan2(s, abs(q[0]))
    k = angle / s if q[0] >= 0.0 else -angle / s
    return (q[1] * k, q[2] * k, q[3] * k)


@jit
def scgeom6d_rotations(c, id1, id2, S, C):
    """Twist and bending of contact ``c`` from the orientations now and at its beginning (module docstring)."""
    f = C.con_f
    q10 = (f[c, G6_ORI1], -f[c, G6_ORI1 + 1], -f[c, G6_ORI1 + 2], -f[c, G6_ORI1 + 3])   # conjugate
    q20 = (f[c, G6_ORI2], f[c, G6_ORI2 + 1], f[c, G6_ORI2 + 2], f[c, G6_ORI2 + 3])
    q1 = load4(S.ori, id1)
    q2 = load4(S.ori, id2)
    q2c = (q2[0], -q2[1], -q2[2], -q2[3])
    d = quat_mul(quat_mul(q1, q10), quat_mul(q20, q2c))
    dn = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + d[3] * d[3])
    theta = rotation_vector((d[0] / dn, d[1] / dn, d[2] / dn, d[3] / dn))
    n = (f[c, F_NORMAL], f[c, F_NORMAL + 1], f[c, F_NORMAL + 2])
    twist = theta[0] * n[0] + theta[1] * n[1] + theta[2] * n[2]
    f[c, G6_TWIST] = twist
    for k in range(3):
        f[c, G6_BENDING + k] = theta[k] - twist * n[k]


@jit
def scgeom6d_update(c, id1, id2, S, C, rotations):
    """After the ScGeom of contact ``c`` is written: a new contact starts its rotations
    (:func:`scgeom6d_init`); an existing one updates twist and bending if ``rotations`` (YADE's
    ``updateRotations``)."""
    if C.con_i[c, I_FLAGS] & FLAG_NEW:
        scgeom6d_init(c, id1, id2, S, C)
    elif rotations:
        scgeom6d_rotations(c, id1, id2, S, C)


_SS = registry.FUNCTORS["Ig2_Sphere_Sphere_ScGeom"]
_FS = registry.FUNCTORS["Ig2_Facet_Sphere_ScGeom"]
_BS = registry.FUNCTORS["Ig2_Box_Sphere_ScGeom"]
#: the parameters every ScGeom6D functor adds to those of its ScGeom functor (whose slots come first)
_ROTATION_PARAMS = (
    Param("updateRotations", True, "Compute twist and bending at every step (else they keep their values) [-]"),
    Param("creep", False, "Subtract the rotational creep ScGeom6D.twistCreep (not implemented yet: only False)",
          supported=False),
)
SS6D = Functor("Ig2_Sphere_Sphere_ScGeom6D", "geom", _SS.types, "ScGeom6D", f"{__name__}:geom_sphere_sphere_6d",
               _SS.params + _ROTATION_PARAMS, "", HISTORY)
# YADE's facet and box functors have no updateRotations: they always update
FS6D = Functor("Ig2_Facet_Sphere_ScGeom6D", "geom", _FS.types, "ScGeom6D", f"{__name__}:geom_facet_sphere_6d",
               _FS.params, "", HISTORY)
BS6D = Functor("Ig2_Box_Sphere_ScGeom6D", "geom", _BS.types, "ScGeom6D", f"{__name__}:geom_box_sphere_6d",
               _BS.params, "", HISTORY)
SS6D_ROTATIONS = SS6D.slot("updateRotations")


@jit
def geom_sphere_sphere_6d(c, id1, id2, shift, S, C, prm):
    """Sphere-sphere ScGeom6D: the ScGeom of :func:`granum.physics.sphere.geom_sphere_sphere` (its parameters
    first, same slots), then :func:`scgeom6d_update`."""
    sep = geom_sphere_sphere(c, id1, id2, shift, S, C, prm)
    if c >= 0:
        scgeom6d_update(c, id1, id2, S, C, prm[SS6D_ROTATIONS] != 0.0)
    return sep


@jit
def geom_facet_sphere_6d(c, id1, id2, shift, S, C, prm):
    """Facet-sphere ScGeom6D: the ScGeom of :func:`granum.physics.facet.geom_facet_sphere`, then
    :func:`scgeom6d_update` (the facet's orientation is body 1's)."""
    sep = geom_facet_sphere(c, id1, id2, shift, S, C, prm)
    if c >= 0:
        scgeom6d_update(c, id1, id2, S, C, True)
    return sep


@jit
def geom_box_sphere_6d(c, id1, id2, shift, S, C, prm):
    """Box-sphere ScGeom6D: the ScGeom of :func:`granum.physics.box.geom_box_sphere`, then
    :func:`scgeom6d_update`."""
    sep = geom_box_sphere(c, id1, id2, shift, S, C, prm)
    if c >= 0:
        scgeom6d_update(c, id1, id2, S, C, True)
    return sep


for _spec, _base in ((SS6D, _SS), (FS6D, _FS), (BS6D, _BS)):
    registry.register_functor(dataclasses.replace(
        _spec, doc=f"{_base.doc}\n\nThen twist and bending (ScGeom6D): {scgeom6d_rotations.py_func.__doc__}"))
