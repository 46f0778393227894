"""YADE's ``yade.utils``: body factories and global measures of the scene.

The factories (:func:`sphere`, :func:`facet`, :func:`wall`, :func:`box`) return a
detached :class:`~granum.yade.bodies.Body` to be appended to ``O.bodies``. The
measures are vectorised NumPy reductions over the storage (no per-body Python).
"""

from __future__ import annotations

import math
import random
import warnings

import numpy as np

from granum._jit import call
from granum.core import validate
from granum.core.attrs import as_flag, as_integer, as_number
from granum.core.bodies import DOF_ALL
from granum.core.contacts import (
    C_CONTACTS,
    C_STATUS,
    CONTACTS,
    F_FN,
    F_FS,
    F_NORMAL,
    F_R1,
    F_R2,
    F_TANPHI,
    FLAG_ALIVE,
    I_CELL,
    I_FLAGS,
    I_ID1,
    I_ID2,
)
from granum.core.shapes import ShapeKind, shape_type
from granum.engines import interrupts
from granum.mathtypes import Matrix3, Quaternion, Vector3, as_quat_wxyz, as_vec3
from granum.yade.batch import readParamsFromTable
from granum.yade.bodies import Body, Box, Facet, Sphere, State, Wall
from granum.yade.cell import det3
from granum.yade.clump_tools import clumpTemplate
from granum.yade.materials import Material, default_material
from granum.yade.omega import O
from granum.yade.video import makeVideo

__all__ = [
    "clumpTemplate",
    "sphere", "facet", "wall", "box", "aabbWalls", "defaultMaterial", "randomColor", "PWaveTimeStep",
    "unbalancedForce", "kineticEnergy", "sumForces", "getSpheresVolume", "getSpheresMass", "aabbExtrema",
    "avgNumInteractions", "porosity", "createInteraction", "scalarOnColorScale", "setContactFriction",
    "getStress", "normalShearStressTensors", "fabricTensor", "makeVideo", "readParamsFromTable",
]

_rng = random.Random()


def _random_rgb() -> tuple[float, float, float]:
    """Three components uniform in [0, 1), drawn in order."""
    return _rng.random(), _rng.random(), _rng.random()


def randomColor():
    """A random colour, RGB components uniform in [0, 1)."""
    return Vector3(*_random_rgb())


def defaultMaterial():
    """YADE's default material: FrictMat(density=1e3, young=1e7, poisson=.3, frictionAngle=.5)."""
    return default_material()


def _material(material):
    """Resolve YADE's ways of naming a material: -1 (last defined), id, label, object, callable."""
    if isinstance(material, Material):
        return material
    if callable(material):
        return _material(material())
    if isinstance(material, str):
        return O.materials[material]
    if isinstance(material, int | np.integer):
        return O.default_material() if material < 0 else O.materials[int(material)]
    raise TypeError(f"material must be a Material, a material id, a label or a callable, got {material!r}")


def _flags(factory: str, **flags) -> dict:
    """The bool arguments ``flags`` of body factory ``factory`` as bools (None stays None: not given);
    TypeError naming the argument for anything else, such as ``fixed='no'``."""
    return {k: v if v is None else as_flag(v, f"{factory}: {k}") for k, v in flags.items()}


def _vec3(value, what: str) -> np.ndarray:
    """``value`` as a 3-vector [m]; the TypeError/ValueError of a wrong one names ``what`` ("sphere: center")."""
    try:
        return as_vec3(value)
    except (TypeError, ValueError) as e:
        raise type(e)(f"{what}: {e}") from None


def _shaped(shape_class, color, **values) -> Body:
    """A new detached body of shape ``shape_class`` (:meth:`Shape.new_body`) coloured ``color``, or at random
    (:func:`_random_rgb`, randomColor's draw) when it is None."""
    b = shape_class.new_body(color=color, **values)
    if color is None:
        b._store.bodies.color[b._row] = _random_rgb()
    return b


def _body(factory, b, center, material, fixed, dynamic, mask, orientation=None):
    """The body of a factory, ``b`` (a new detached body with its shape, :meth:`Shape.new_body`), completed:
    ``fixed`` (or ``dynamic=False``) blocks its six DOFs; ``mask`` is an integer; the mass and inertia of a
    uniform body of the material's density, for a shape kind that declares them
    (:attr:`granum.core.shapes.ShapeType.mass`; massless otherwise)."""
    fixed, dynamic = _flags(factory, fixed=fixed, dynamic=dynamic).values()
    center = _vec3(center, f"{factory}: center")
    b.material = mat = _material(material)
    b.mask = as_integer(mask, f"{factory}: mask")
    if mat.state_class() is not State:   # the material needs its own state class (CpmMat: CpmState)
        b.state = mat.newAssocState()
    st = b.state
    shape = b.shape
    mass = shape_type(shape.kind).mass
    if mass is not None:
        st.mass, st.inertia = mass(mat.density, *shape._table())
    validate.FINITE_VECTOR.check(center, lambda: f"{st._owner()}.pos")   # what st.pos = center checks
    rows = b._store.bodies
    rows.pos[b._row] = rows.ref_pos[b._row] = center
    if orientation is not None:
        st.ori = orientation
        st.refOri = orientation
    if dynamic is not None:
        fixed = not dynamic
    if fixed:
        st.blockedDOFs = "xyzXYZ"
    return b


def sphere(center, radius, dynamic=None, fixed=False, wire=False, color=None, highlight=False,
           material=-1, mask=1):
    """A sphere body: mass rho 4/3 pi r^3, inertia 2/5 m r^2 on all axes.

    ``fixed`` (or ``dynamic=False``) blocks all six degrees of freedom; ``color``
    None picks a random colour; ``material`` is a Material, an id or a label in
    O.materials, a callable returning a Material, or -1 for the last defined one.
    """
    wire, highlight = _flags("sphere", wire=wire, highlight=highlight).values()
    b = _shaped(Sphere, color, radius=as_number(radius, "sphere: radius"), wire=wire, highlight=highlight)
    return _body("sphere", b, center, material, fixed, dynamic, mask)


def facet(vertices, dynamic=None, fixed=True, wire=True, color=None, highlight=False, noBound=False,
          material=-1, mask=1, chain=-1):
    """A triangular facet; the body sits at the centre of the inscribed circle (massless, fixed).

    ``noBound=True`` (a facet the collider never sees) and ``chain`` (YADE's chained cylinders) are not
    implemented yet and refused by name rather than ignored."""
    if noBound is not False:
        raise NotImplementedError(f"facet: noBound={noBound!r} (a facet without bound) is not implemented in granum "
                                  f"yet (only the default False)")
    if chain != -1:
        raise NotImplementedError(f"facet: chain={chain!r} (chained cylinders) is not implemented in granum yet "
                                  f"(only the default -1)")
    v = np.array([_vec3(x, "facet: vertex") for x in vertices]) if len(vertices) == 3 else None
    if v is None:
        raise ValueError("facet: give exactly three vertices")
    edges = np.array([np.linalg.norm(v[1] - v[2]), np.linalg.norm(v[2] - v[0]), np.linalg.norm(v[0] - v[1])])
    if not edges.sum() > 0:
        raise ValueError("facet: the three vertices coincide")
    center = (edges[:, None] * v).sum(axis=0) / edges.sum()
    wire, highlight = _flags("facet", wire=wire, highlight=highlight).values()
    b = _shaped(Facet, color, vertices=list(v - center), wire=wire, highlight=highlight)
    return _body("facet", b, center, material, fixed, dynamic, mask)


def wall(position, axis, sense=0, color=None, material=-1, mask=1):
    """An infinite plane normal to ``axis`` through ``position`` (a coordinate or a point); fixed."""
    if axis not in (0, 1, 2):
        raise ValueError(f"wall: axis must be 0, 1 or 2, got {axis!r}")
    if isinstance(position, int | float | np.floating | np.integer):
        center = np.zeros(3)
        center[axis] = float(position)
    else:
        center = _vec3(position, "wall: position")
    b = _shaped(Wall, color, axis=axis, sense=sense)
    return _body("wall", b, center, material, True, None, mask)


def box(center, extents, orientation=None, dynamic=None, fixed=False, wire=False, color=None, highlight=False,
        material=-1, mask=1):
    """A box with half-sizes ``extents``: mass 8 rho e0 e1 e2, inertia m/3 (e1^2+e2^2, ...); aspherical."""
    wire, highlight = _flags("box", wire=wire, highlight=highlight).values()
    b = _shaped(Box, color, extents=extents, wire=wire, highlight=highlight)
    ori = Quaternion(1, 0, 0, 0) if orientation is None else Quaternion(*_wxyz(orientation))
    return _body("box", b, center, material, fixed, dynamic, mask, ori)


def _wxyz(q):
    return tuple(as_quat_wxyz(q))


def aabbWalls(extrema=None, thickness=0.0, oversizeFactor=1.5, **kw):
    """Six fixed wire boxes enclosing ``extrema`` (default: the spheres' bounding box).

    Returned in the order -x, +x, -y, +y, -z, +z; each is ``thickness`` thick, outside
    the box, and ``oversizeFactor`` times as wide as the box in the other directions.
    """
    lo, hi = (np.asarray(as_vec3(x)) for x in (extrema or aabbExtrema()))
    center = 0.5 * (lo + hi)
    half = 0.5 * (hi - lo)
    kw.setdefault("fixed", True)
    kw.setdefault("wire", True)
    walls = []
    for axis in range(3):
        for side, face in ((-1, lo[axis]), (1, hi[axis])):
            c = center.copy()
            c[axis] = face + side * 0.5 * thickness
            e = oversizeFactor * half
            e[axis] = 0.5 * thickness
            walls.append(box(tuple(c), tuple(e), **kw))
    return walls


# ---- global measures ------------------------------------------------------------------

def _scene():
    return O._scene


def _spheres(mask: int = -1):
    """Ids and radii of the live spheres whose mask shares a bit with ``mask``."""
    s = _scene()
    b = s.bodies
    n = b.count
    sel = b.alive[:n] & (b.shape_kind[:n] == ShapeKind.SPHERE)
    if mask != -1:
        sel &= (b.mask[:n] & mask) != 0
    ids = np.nonzero(sel)[0]
    return ids, s.shapes[ShapeKind.SPHERE].radius[b.shape_row[ids]]


def PWaveTimeStep():
    """Critical time step of the P-wave: min over spheres of r / sqrt(E / rho) [s] (YADE (3.5,34))."""
    s = _scene()
    ids, r = _spheres()
    if ids.size == 0:
        warnings.warn("PWaveTimeStep: no spheres in the simulation", stacklevel=2)
        return math.inf
    kind, mat = s.material_arrays()
    from granum.physics.materials import M_DENSITY, M_YOUNG

    rows = s.bodies.material[ids]
    young = mat[rows, M_YOUNG]
    vol = 4.0 / 3.0 * math.pi * r ** 3
    mass = s.bodies.mass[ids]
    rho = np.where(mass > 0, mass / vol, mat[rows, M_DENSITY])
    ok = young > 0
    return float(np.min(r[ok] / np.sqrt(young[ok] / rho[ok])))  # YADE's order of operations: the same bits


def _live_contacts():
    C = _scene().contacts
    n = int(C.ctr[C_CONTACTS])
    return C, np.nonzero(C.con_i[:n, I_FLAGS] & FLAG_ALIVE)[0]


def _gravity():
    from granum.engines.pipeline import NewtonIntegrator

    for e in _scene().engines:
        if isinstance(e, NewtonIntegrator) and not e.dead:
            return np.asarray(e.gravity._a)
    return np.zeros(3)


def _not_member(b, n):
    """Bodies that move on their own: standalone bodies and clumps, not clump members."""
    ids = np.arange(n)
    return (b.clump_id[:n] < 0) | (b.clump_id[:n] == ids)


def unbalancedForce(useMaxForce=False):
    """Mean (or maximum) resultant force on dynamic bodies over the mean contact force.

    The resultant includes gravity from NewtonIntegrator; clumps count with the sum of
    their members' forces (also before NewtonIntegrator has gathered them), members do not count on their
    own. Tends to 0 at equilibrium.
    NaN when there is no contact.
    """
    s = _scene()
    b = s.bodies
    n = b.count
    dyn = np.nonzero(b.alive[:n] & (b.blocked[:n] != DOF_ALL) & _not_member(b, n))[0]
    C, rows = _live_contacts()
    if rows.size == 0 or dyn.size == 0:
        return math.nan
    force = b.force[:n].copy()
    ids = np.arange(n)
    members = np.nonzero(b.alive[:n] & (b.clump_id[:n] >= 0) & (b.clump_id[:n] != ids))[0]
    force[b.clump_id[members]] = 0.0  # a clump counts its members' forces, gathered this step or not (YADE's)
    np.add.at(force, b.clump_id[members], b.force[members])
    res = np.linalg.norm(force[dyn] + b.mass[dyn, None] * _gravity()[None, :], axis=1)
    num = res.max() if useMaxForce else res.mean()
    f = C.con_f[rows, F_FN:F_FN + 3] + C.con_f[rows, F_FS:F_FS + 3]
    return float(num / np.linalg.norm(f, axis=1).mean())


def kineticEnergy(findMaxId=False):
    """Sum of 1/2 m v^2 + 1/2 w.Iw over dynamic bodies [J] (with findMaxId: (E, id of largest)).

    In a periodic cell v is the fluctuation v - L x around the cell's homogeneous flow.
    """
    s = _scene()
    b = s.bodies
    n = b.count
    sel = np.nonzero(b.alive[:n] & (b.blocked[:n] != DOF_ALL) & _not_member(b, n))[0]
    if sel.size == 0:
        return (0.0, -1) if findMaxId else 0.0
    v = b.vel[sel]
    if s.periodic:  # the fluctuation around the homogeneous flow of the cell
        v = v - b.pos[sel] @ s.cell_velgrad.T
    e = 0.5 * b.mass[sel] * (v ** 2).sum(axis=1)
    w = b.ang_vel[sel]
    q = b.ori[sel]
    # angular velocity in the principal (local) frame: rotate by the conjugate of ori
    u = -q[:, 1:]
    t = 2.0 * np.cross(u, w)
    wl = w + q[:, :1] * t + np.cross(u, t)
    e += 0.5 * (b.inertia[sel] * wl ** 2).sum(axis=1)
    if findMaxId:
        return float(e.sum()), int(sel[np.argmax(e)])
    return float(e.sum())


def sumForces(ids, direction):
    """Sum of the forces on bodies ``ids`` projected on ``direction`` [N]."""
    d = as_vec3(direction)
    ids = np.asarray(list(ids), dtype=np.int64)
    return float((_scene().bodies.force[ids] @ d).sum())


def getSpheresVolume(mask=-1):
    """Total volume of the spheres [m^3]."""
    _, r = _spheres(mask)
    return float((4.0 / 3.0 * math.pi * r ** 3).sum())


def getSpheresMass(mask=-1):
    """Total mass of the spheres [kg]."""
    ids, _ = _spheres(mask)
    return float(_scene().bodies.mass[ids].sum())


def aabbExtrema(cutoff=0.0, centers=False):
    """Corners ``(min, max)`` of the box around all spheres (or their centres) [m]."""
    ids, r = _spheres()
    if ids.size == 0:
        return Vector3(math.inf, math.inf, math.inf), Vector3(-math.inf, -math.inf, -math.inf)
    p = _scene().bodies.pos[ids]
    rr = 0.0 if centers else r[:, None]
    lo, hi = (p - rr).min(axis=0), (p + rr).max(axis=0)
    d = hi - lo
    lo, hi = lo + 0.5 * cutoff * d, hi - 0.5 * cutoff * d  # YADE cuts cutoff*d in all, half per side
    return Vector3(*lo), Vector3(*hi)


def avgNumInteractions(cutoff=0.0, skipFree=False, considerClumps=False):
    """Coordination number Z = 2C/N; with ``skipFree`` (2C - N1)/(N - N0 - N1) (Thornton 2000)."""
    s = _scene()
    b = s.bodies
    n = b.count
    C, rows = _live_contacts()
    alive = np.nonzero(b.alive[:n])[0]
    if not skipFree:
        return 2.0 * rows.size / max(alive.size, 1)
    count = np.bincount(np.concatenate([C.con_i[rows, I_ID1], C.con_i[rows, I_ID2]]), minlength=n)[alive]
    n0, n1 = np.count_nonzero(count == 0), np.count_nonzero(count == 1)
    return (2.0 * rows.size - n1) / (alive.size - n0 - n1)


def porosity(volume=-1):
    """(V - V_spheres)/V, with V the cell (periodic) or the spheres' bounding box unless given [-]."""
    volume = _volume(volume)
    return (volume - getSpheresVolume()) / volume


def _contact_vectors():
    """Live contacts: forces on body 2 ``f``, normals ``n``, branches ``l = x1 - x2 - H k`` and radii sums."""
    s = _scene()
    C, rows = _live_contacts()
    f = C.con_f[rows, F_FN:F_FN + 3] + C.con_f[rows, F_FS:F_FS + 3]
    id1, id2 = C.con_i[rows, I_ID1], C.con_i[rows, I_ID2]
    shift = C.con_i[rows, I_CELL:I_CELL + 3] @ s.cell_hsize.T if s.periodic else 0.0
    l = s.bodies.pos[id1] - (s.bodies.pos[id2] + shift)
    return C, rows, f, C.con_f[rows, F_NORMAL:F_NORMAL + 3], l, C.con_f[rows, F_R1] + C.con_f[rows, F_R2]


def _volume(volume):
    if volume > 0:
        return float(volume)
    s = _scene()
    if s.periodic:
        return det3(s.cell_hsize)
    lo, hi = aabbExtrema()
    return float(np.prod(np.asarray(hi._a) - np.asarray(lo._a)))


def getStress(volume=0):
    """Love-Weber stress (1/V) sum_c f_c (x) l_c [Pa]: f the force on body 2, l = x1 - x2 - H k.

    Compression is negative. V is the cell volume (periodic) or the spheres' bounding
    box, unless given.
    """
    _, _, f, _, l, _ = _contact_vectors()
    return Matrix3(*(np.einsum("ci,cj->ij", f, l) / _volume(volume)).ravel())


def normalShearStressTensors(compressionPositive=False, splitNormalTensor=False, thresholdForce=math.nan):
    """Normal and shear parts of the contact stress, (1/V) sum (r1 + r2) n (x) F_N and n (x) F_T [Pa].

    Periodic scenes only. As in YADE, compression is positive unless
    ``compressionPositive`` (sic) is True.
    """
    s = _scene()
    if not s.periodic:
        raise RuntimeError("normalShearStressTensors: only for periodic scenes (O.periodic)")
    if splitNormalTensor:
        raise NotImplementedError("normalShearStressTensors(splitNormalTensor=True) is not implemented yet")
    C, rows, _, n, _, rsum = _contact_vectors()
    v = det3(s.cell_hsize)
    sign = -1.0 if compressionPositive else 1.0
    fn = C.con_f[rows, F_FN:F_FN + 3]
    fs = C.con_f[rows, F_FS:F_FS + 3]
    sn = sign * np.einsum("c,ci,cj->ij", rsum, n, fn) / v + 0.0  # + 0.0: no negative zeros
    st = sign * np.einsum("c,ci,cj->ij", rsum, n, fs) / v + 0.0
    return Matrix3(*sn.ravel()), Matrix3(*st.ravel())


def fabricTensor(cutoff=0.0, splitTensor=False, thresholdForce=math.nan):
    """Fabric tensor (1/N_c) sum n (x) n of the contact normals [-]."""
    if splitTensor:
        raise NotImplementedError("fabricTensor(splitTensor=True) is not implemented yet")
    _, rows, _, n, _, _ = _contact_vectors()
    if rows.size == 0:
        return Matrix3(0, 0, 0, 0, 0, 0, 0, 0, 0)
    return Matrix3(*(np.einsum("ci,cj->ij", n, n) / rows.size).ravel())


def scalarOnColorScale(x, xmin=0.0, xmax=1.0):
    """Colour of ``x`` on a blue-green-red scale between ``xmin`` and ``xmax``."""
    t = 0.0 if xmax == xmin else min(max((x - xmin) / (xmax - xmin), 0.0), 1.0)
    return Vector3(min(max(2 * t - 0.5, 0), 1) if t > 0.25 else 0.0, 1.0 - abs(2 * t - 1.0), max(1.0 - 2 * t, 0.0))


def setContactFriction(angleRad):
    """Set the friction angle [rad] of the materials of the dynamic bodies, and of the existing contacts
    tan(min(phi1, phi2)) from their bodies' materials (YADE 2023.02a: the materials only fixed bodies use,
    such as walls, keep theirs, and so do their contacts with a lower friction)."""
    s = _scene()
    b = s.bodies
    n = b.count
    used = set(np.unique(b.material[:n][b.alive[:n] & (b.blocked[:n] != DOF_ALL)]).tolist())
    for k, m in enumerate(s.materials):
        if k in used and hasattr(m, "frictionAngle"):
            m.frictionAngle = angleRad
    C, rows = _live_contacts()
    phi = np.array([getattr(m, "frictionAngle", math.inf) for m in s.materials] or [math.inf])
    phi1 = phi[b.material[C.con_i[rows, I_ID1]]]
    phi2 = phi[b.material[C.con_i[rows, I_ID2]]]
    low = np.minimum(phi1, phi2)
    rows, low = rows[np.isfinite(low)], low[np.isfinite(low)]  # contacts of materials without friction: kept
    C.con_f[rows, F_TANPHI] = np.tan(low)


def createInteraction(id1, id2):
    """Make the interaction of two bodies real now, whatever their distance (YADE semantics).

    The geometry and physics come from the functors of the InteractionLoop in O.engines; the loop needs no
    law functor for them, as in YADE (a step that reaches such a contact without one stops, naming it). An
    interaction that is real already is refused (RuntimeError, as in YADE).
    """
    from granum.engines.pipeline import InteractionLoop
    from granum.kernels.interaction import create_contact_now
    from granum.yade.interactions import Interaction

    loops = [e for e in O.engines if isinstance(e, InteractionLoop)]
    if not loops:
        raise RuntimeError("createInteraction: no InteractionLoop in O.engines")
    s = _scene()
    for i in (id1, id2):
        if not (0 <= i < s.body_count and s.bodies.alive[i]):
            raise IndexError(f"createInteraction: no body with id {i}")
    if Interaction(s, id1, id2).isReal:
        raise RuntimeError(f"createInteraction: the interaction ({id1}, {id2}) is real already")
    P = loops[0].params(s, O.engines)
    with interrupts.shielded():   # the contacts go back to the scene whatever Ctrl-C does meanwhile
        S = s.arrays()
        C = CONTACTS.to_record(s.contacts)
        call(create_contact_now, S, C, int(id1), int(id2), P)
        s.contacts = CONTACTS.from_record(C)
    if s.contacts.ctr[C_STATUS]:
        O._runner.raise_status()
    return Interaction(s, id1, id2)


# the rest of yade.utils, by theme; imported last because those modules call the helpers above
from granum.yade.utils_extra import *  # noqa: E402, F403
from granum.yade.utils_extra import __all__ as _extra  # noqa: E402

__all__ += _extra
