"""``yade.bf``: breakage functions for replacement-based breakage of spheres and clumps.

The seed documentation (section 6.1) describes the module; the rules below were checked against
YADE 2023.02a's ``yade.bf`` used as a black box (``tests/reference/yade/bf.json``).

**Stress** (:func:`stressTensor`). The Love-Weber stress of a sphere of radius ``r`` and volume
``V = 4/3 pi r^3`` at ``x``, from its contacts ``c`` (force ``f_c`` on the sphere, contact point
``x_c``), compression negative:

.. math::  \\sigma_{ij} = \\frac{1}{V} \\sum_c f_{c,i} (x_c - x)_j
           \\; - \\; \\frac{r}{V} \\frac{F_i F_j}{|F|}

where the second term, the correction (``stress_correction=True``), balances the net force
``F = O.forces.f(id)``: a force ``-F`` acting at ``x + r F/|F|``, the point of the surface
opposite to it. A clump member's contacts with the other members of its clump do not exist
(members do not interact), so its contacts rarely balance; the correction stands for the
members holding it, which makes a member's stress like that of a standalone sphere.

**Failure** (:func:`checkFailure`, Gladkyy and Kuna 2017). With ``s1 >= s3`` the largest and
smallest principal stresses (real parts of the tensor's eigenvalues), tensile strength ``st``
and compressive strength ``sc``, the effort is

* ``s1/st - s3/sc`` when ``s1 > 0 > s3`` (Mohr-Coulomb between tension and compression);
* ``max(|s1|/st, |s3|/sc)`` otherwise (all principal stresses of one sign);

with ``weibull`` multiplied by ``(V / (V0 ln(1/(1 - P))))^(1/m)``, the size effect of a Weibull
distribution of strength (a volume ``V`` fails at the strengths given with probability ``P``
when ``V = V0``). It returns the effort when it exceeds 1, else 0.

**Replacing a sphere** (:func:`replaceSphere`). A sphere of radius ``r``, density ``rho`` becomes
``n = ceil(M / m0)`` spheres of equal size, ``M`` the mass to keep (the sphere's mass or
``subparticles_mass``) and ``m0`` the mass of a sphere of radius ``r / radius_ratio``; their
radius ``r_s`` makes their total mass ``M``. Centres are taken from a hexagonal lattice
(``pack.regularHexa``, radius ``r_s / grow_radius``, gap ``relative_gap * r_s``) filling the ball
of radius ``initial_packing_scale * r`` around the sphere (intersected with
``outer_predicate``), nearest to the centre first, leaving out any that would overlap a
neighbour sphere (``neighbours_ids``, and with ``search_for_neighbours`` every sphere reaching
into that ball). When fewer than ``n`` fit, the scale grows by ``scale_multiplier`` (default
``max_scale / initial_packing_scale``) up to ``max_scale``; beyond it the sphere is not replaced.

**Breaking a clump** (:func:`evalClump`). The member with the largest effort (if any exceeds 1)
breaks: it leaves the clump and is replaced by subparticles whose mass is the clump's mass
less the mass of what remains (the overlap it shared is not counted twice), the remaining
members being their neighbours. The remaining members are grouped by contact (centre distance
below the sum of the radii): a group of one becomes a standalone sphere, a larger one a clump
(``discretization``); the old clump is erased. As in YADE, with more than one member left the
groups are made of new bodies (appended after the subparticles), while a single member left
of a two-member clump keeps its id.

Deliberate differences from YADE (YADE's results are in ``bf.json``):

* momentum is conserved: the groups keep the rigid motion of the old clump at their place and
  the subparticles take the linear and angular momentum left (a rigid motion of their own);
  YADE sets every body made by these functions at rest. :func:`replaceSphere` gives its
  subparticles the sphere's momentum (scaled by the mass ratio when ``subparticles_mass``
  differs from the sphere's mass);
* the total mass is conserved exactly: the subparticles' mass is computed from the groups as
  they are made (YADE computes it from the released clump, and the groups made afterwards may
  weigh slightly differently: 0.02 % in ``clumps-breakage/first_example.py``);
* :func:`stressTensor` returns float64 (YADE: float32) and :func:`checkFailure` a float (YADE
  sometimes a complex number, and it multiplies the stress tensor it got by the Weibull factor
  in place); :func:`replaceSphere` returns the new ids (YADE: None), or None when the sphere
  could not be replaced;
* ``max_grow_radius`` has no effect that could be observed in YADE 2023.02a; granum checks
  ``1 <= grow_radius <= max_grow_radius`` and uses it for nothing else.
"""

from __future__ import annotations

import math

import numpy as np

from granum.core.contacts import C_CONTACTS, F_FN, F_FS, F_POINT, FLAG_ALIVE, I_FLAGS, I_ID1, I_ID2
from granum.core.shapes import ShapeKind
from granum.mathtypes import Vector3
from granum.yade import pack
from granum.yade.clumps import clump_members, mass_properties, member_mass, rotation
from granum.yade.omega import O

__all__ = ["checkFailure", "evalClump", "growParticle", "replaceSphere", "stressTensor"]


# ------------------------------------------------------------------------------------------- stress
def _sphere(b, what: str):
    """``(id, radius [m], centre (3,) [m])`` of sphere body ``b`` (a Body or an id)."""
    i = b if isinstance(b, int | np.integer) else getattr(b, "id", None)
    if i is None:
        raise TypeError(f"{what}: expected a Body or a body id, got {b!r}")
    body = O.bodies[int(i)]
    if body is None:
        raise IndexError(f"{what}: body {i} was erased")
    scene = O._scene
    if scene.bodies.shape_kind[body.id] != ShapeKind.SPHERE:
        raise TypeError(f"{what}: body {body.id} is not a sphere")
    r = float(scene.shapes[ShapeKind.SPHERE].radius[scene.bodies.shape_row[body.id]])
    return body.id, r, scene.bodies.pos[body.id].copy()


def _contact_forces(i: int):
    """``(forces on body i (K, 3) [N], contact points (K, 3) [m])`` of its live contacts."""
    C = O._scene.contacts
    n = int(C.ctr[C_CONTACTS])
    ci = C.con_i[:n]
    alive = (ci[:, I_FLAGS] & FLAG_ALIVE) != 0
    first, second = alive & (ci[:, I_ID1] == i), alive & (ci[:, I_ID2] == i)
    rows = C.con_f[:n]
    on2 = rows[:, F_FN:F_FN + 3] + rows[:, F_FS:F_FS + 3]  # force on body 2
    f = np.concatenate([-on2[first], on2[second]])
    x = np.concatenate([rows[first, F_POINT:F_POINT + 3], rows[second, F_POINT:F_POINT + 3]])
    return f, x


def _stress(i: int, r: float, x, stress_correction: bool) -> np.ndarray:
    f, xc = _contact_forces(i)
    volume = 4.0 / 3.0 * math.pi * r ** 3
    sigma = np.einsum("ki,kj->ij", f, xc - x) / volume
    if stress_correction:
        F = np.asarray(O._scene.bodies.force[i], dtype=np.float64)
        norm = float(np.linalg.norm(F))
        if norm > 0:
            sigma -= r * np.outer(F, F) / (norm * volume)
    return sigma


def stressTensor(b, stress_correction=True) -> np.ndarray:
    """Love-Weber stress tensor (3, 3) [Pa] of sphere ``b`` (a Body), compression negative, with the
    correction for its unbalanced force (module docstring)."""
    i, r, x = _sphere(b, "stressTensor")
    return _stress(i, r, x, bool(stress_correction))


# ------------------------------------------------------------------------------------------ failure
def weibull_factor(volume: float, wei_V0: float, wei_P: float, wei_m: float) -> float:
    """``(V / (V0 ln(1/(1 - P))))^(1/m)``: how much weaker a volume ``V`` [m^3] is than the strength
    given for failure probability ``P`` at volume ``V0`` [m^3], Weibull modulus ``m``."""
    if not (wei_V0 > 0 and 0 < wei_P < 1 and wei_m > 0):
        raise ValueError(f"checkFailure: Weibull parameters need wei_V0 > 0, 0 < wei_P < 1, wei_m > 0; got "
                         f"wei_V0={wei_V0!r}, wei_P={wei_P!r}, wei_m={wei_m!r}")
    return (volume / (wei_V0 * math.log(1.0 / (1.0 - wei_P)))) ** (1.0 / wei_m)


def effort(sigma: np.ndarray, tension_strength: float, compressive_strength: float) -> float:
    """Gladkyy-Kuna effort of stress ``sigma`` (3, 3) [Pa] (module docstring), without size effect."""
    if not (tension_strength > 0 and compressive_strength > 0):
        raise ValueError(f"checkFailure: strengths must be positive, got tension_strength={tension_strength!r}, "
                         f"compressive_strength={compressive_strength!r}")
    principal = np.sort(np.linalg.eigvals(sigma).real)
    s1, s3 = float(principal[2]), float(principal[0])
    if s1 > 0 > s3:
        return s1 / tension_strength - s3 / compressive_strength
    return max(abs(s1) / tension_strength, abs(s3) / compressive_strength)


def checkFailure(b, tension_strength, compressive_strength, wei_V0=0.01, wei_P=0.63, wei_m=3, weibull=True,
                 stress_correction=True) -> float:
    """Effort (equivalent stress / strength) of sphere ``b`` when above 1, else 0 (Gladkyy and Kuna
    2017; strengths [Pa], ``wei_V0`` [m^3]; module docstring)."""
    i, r, x = _sphere(b, "checkFailure")
    e = effort(_stress(i, r, x, bool(stress_correction)), float(tension_strength), float(compressive_strength))
    if weibull:
        e *= weibull_factor(4.0 / 3.0 * math.pi * r ** 3, float(wei_V0), float(wei_P), float(wei_m))
    return e if e > 1.0 else 0.0


# ------------------------------------------------------------------------------------- subparticles
def _density(i: int) -> float:
    scene = O._scene
    return float(scene.materials[scene.bodies.material[i]].density)


def _neighbour_spheres(ids):
    """``(centres (K, 3), radii (K,))`` of the spheres among ``ids``."""
    scene = O._scene
    b = scene.bodies
    ids = [int(i) for i in ids if b.alive[int(i)] and b.shape_kind[int(i)] == ShapeKind.SPHERE]
    return b.pos[ids].copy(), scene.shapes[ShapeKind.SPHERE].radius[b.shape_row[ids]].copy()


def _spheres_reaching(x, reach: float, skip: int):
    """Ids of the spheres other than ``skip`` whose surface comes within ``reach`` of ``x``."""
    scene = O._scene
    b = scene.bodies
    n = scene.body_count
    ids = np.flatnonzero(b.alive[:n] & (b.shape_kind[:n] == ShapeKind.SPHERE))
    ids = ids[ids != skip]
    r = scene.shapes[ShapeKind.SPHERE].radius[b.shape_row[ids]]
    return ids[np.linalg.norm(b.pos[ids] - x, axis=1) - r < reach]


def subparticle_layout(i: int, mass: float, radius_ratio=2, relative_gap=0, neighbours_ids=(),
                       initial_packing_scale=1.5, max_scale=3, scale_multiplier=None, search_for_neighbours=True,
                       outer_predicate=None, grow_radius=1.0, max_grow_radius=2.0):
    """Where the subparticles of sphere ``i`` go: ``(centres (n, 3), radius)``, or None when they do
    not fit within ``max_scale``; nothing in the scene changes (module docstring)."""
    if not radius_ratio > 0:
        raise ValueError(f"replaceSphere: radius_ratio must be positive, got {radius_ratio!r}")
    if not 1.0 <= grow_radius <= max_grow_radius:
        raise ValueError(f"replaceSphere: need 1 <= grow_radius <= max_grow_radius, got grow_radius={grow_radius!r}, "
                         f"max_grow_radius={max_grow_radius!r}")
    if not (0 < initial_packing_scale <= max_scale):
        raise ValueError(f"replaceSphere: need 0 < initial_packing_scale <= max_scale, got "
                         f"initial_packing_scale={initial_packing_scale!r}, max_scale={max_scale!r}")
    multiplier = max_scale / initial_packing_scale if scale_multiplier is None else float(scale_multiplier)
    if not multiplier > 1.0 and initial_packing_scale < max_scale:
        raise ValueError(f"replaceSphere: scale_multiplier must exceed 1, got {scale_multiplier!r}")
    scene = O._scene
    r = float(scene.shapes[ShapeKind.SPHERE].radius[scene.bodies.shape_row[i]])
    x = scene.bodies.pos[i].copy()
    rho = _density(i)
    m0 = rho * 4.0 / 3.0 * math.pi * (r / radius_ratio) ** 3
    n = math.ceil(mass / m0 - 1e-12)  # M = n m0 up to rounding still gives n
    if n < 1:
        return np.zeros((0, 3)), 0.0
    rs = (3.0 * mass / (rho * 4.0 * math.pi * n)) ** (1.0 / 3.0)
    scale = float(initial_packing_scale)
    while scale <= max_scale * (1.0 + 1e-12):
        predicate = pack.inSphere(Vector3(*x), r * scale)
        if outer_predicate is not None:
            predicate = predicate & outer_predicate
        centres = pack.regularHexaCenters(predicate, rs / grow_radius, relative_gap * rs)
        centres = centres[np.argsort(np.linalg.norm(centres - x, axis=1), kind="stable")]
        near = set(int(k) for k in neighbours_ids)
        if search_for_neighbours:
            near |= set(int(k) for k in _spheres_reaching(x, r * scale, i))
        near.discard(i)
        if near and len(centres):
            c, rad = _neighbour_spheres(sorted(near))
            gap = np.linalg.norm(centres[:, None] - c[None], axis=2) - (rs + rad[None])
            centres = centres[(gap >= 0).all(axis=1)]
        if len(centres) >= n:
            return centres[:n], rs
        if multiplier <= 1.0:
            break
        scale *= multiplier
    return None


def _rigid_fit(m, x, inertia, P, L):
    """``(v (3,), w (3,), centre (3,))``: the rigid motion of bodies (masses ``m`` (K,), centres ``x``
    (K, 3), inertia tensors ``inertia`` (K, 3, 3)) with linear momentum ``P`` and angular momentum
    ``L`` about the origin."""
    M = m.sum()
    c = (m[:, None] * x).sum(axis=0) / M
    d = x - c
    tensor = inertia.sum(axis=0) + np.einsum("k,kij->ij", m, (d * d).sum(axis=1)[:, None, None] * np.eye(3)
                                               - d[:, :, None] * d[:, None, :])
    v = P / M
    w = np.linalg.lstsq(tensor, L - np.cross(c, P), rcond=None)[0]
    return v, w, c


def _append_subparticles(material, color, centres, rs: float, P, L) -> list[int]:
    """Append spheres of radius ``rs`` at ``centres`` (``material``, ``color``), moving rigidly with
    momentum ``P``, ``L`` (about the origin); return their ids."""
    from granum.yade import utils  # lazy: utils imports the scene code

    ids = O.bodies.append([utils.sphere(Vector3(*c), rs, material=material, color=color) for c in centres])
    if ids:
        _set_rigid_motion(ids, P, L)
    return ids


def _set_rigid_motion(ids, P, L) -> None:
    """Give standalone spheres ``ids`` the rigid motion with momentum ``P``, ``L`` (about the origin)."""
    scene = O._scene
    b = scene.bodies
    m, inertia = member_mass(scene, ids)
    v, w, c = _rigid_fit(m, b.pos[ids], inertia, P, L)
    b.vel[ids] = v + np.cross(w, b.pos[ids] - c)
    b.ang_vel[ids] = w


def _sphere_momentum(i: int):
    """``(P, L about the origin)`` of standalone sphere ``i``."""
    b = O._scene.bodies
    m = b.mass[i]
    return m * b.vel[i], np.cross(b.pos[i], m * b.vel[i]) + b.inertia[i] * b.ang_vel[i]


def replaceSphere(sphere_id, subparticles_mass=None, radius_ratio=2, relative_gap=0, neighbours_ids=[],  # noqa: B006
                  initial_packing_scale=1.5, max_scale=3, scale_multiplier=None, search_for_neighbours=True,
                  outer_predicate=None, grow_radius=1.0, max_grow_radius=2.0):
    """Replace standalone sphere ``sphere_id`` by ``subparticles_mass`` [kg] (default: its mass) of
    smaller spheres (module docstring); return their ids, or None when they do not fit (the sphere
    then stays)."""
    i, _, _ = _sphere(sphere_id, "replaceSphere")
    b = O._scene.bodies
    if b.clump_id[i] >= 0:
        raise ValueError(f"replaceSphere: body {i} is a member of clump {b.clump_id[i]}; release it first "
                         f"(O.bodies.releaseFromClump) or use evalClump")
    mass = float(b.mass[i]) if subparticles_mass is None else float(subparticles_mass)
    layout = subparticle_layout(i, mass, radius_ratio, relative_gap, neighbours_ids, initial_packing_scale,
                                max_scale, scale_multiplier, search_for_neighbours, outer_predicate, grow_radius,
                                max_grow_radius)
    if layout is None:
        return None
    P, L = _sphere_momentum(i)
    share = mass / float(b.mass[i])
    src = O.bodies[i]
    material, color = src.material, tuple(src.shape.color)
    O.bodies.erase(i)
    return _append_subparticles(material, color, layout[0], layout[1], share * P, share * L)


# ------------------------------------------------------------------------------------------- clumps
def _groups(ids) -> list[list[int]]:
    """``ids`` (spheres) split into groups that touch (centre distance < r1 + r2), by lowest id."""
    x, r = _neighbour_spheres(ids)
    touch = np.linalg.norm(x[:, None] - x[None], axis=2) < r[:, None] + r[None]
    seen, groups = set(), []
    for k in range(len(ids)):
        if k in seen:
            continue
        stack, group = [k], []
        seen.add(k)
        while stack:
            a = stack.pop()
            group.append(ids[a])
            for c in np.flatnonzero(touch[a]):
                if int(c) not in seen:
                    seen.add(int(c))
                    stack.append(int(c))
        groups.append(sorted(group))
    return groups


def _world_inertia(i: int) -> np.ndarray:
    b = O._scene.bodies
    R = rotation(b.ori[i])
    return R @ np.diag(b.inertia[i]) @ R.T


def evalClump(clump_id, radius_ratio, tension_strength, compressive_strength, relative_gap=0, wei_V0=0.001,
              wei_P=0.63, wei_m=3, weibull=True, stress_correction=True, initial_packing_scale=1.5, max_scale=3,
              search_for_neighbours=True, outer_predicate=None, discretization=20, grow_radius=1.0,
              max_grow_radius=2.0) -> bool:
    """Break the most stressed member of clump ``clump_id`` if its effort exceeds 1 (module docstring);
    return whether it broke."""
    scene = O._scene
    b = scene.bodies
    c = int(clump_id)
    if not (0 <= c < scene.body_count and b.alive[c]):
        raise IndexError(f"evalClump: no body with id {clump_id!r}")
    if b.shape_kind[c] != ShapeKind.CLUMP:
        raise TypeError(f"evalClump: body {c} is not a clump")
    members = sorted(clump_members(scene, c))
    others = [m for m in members if b.shape_kind[m] != ShapeKind.SPHERE]
    if others:
        raise TypeError(f"evalClump: clump {c} has members that are not spheres: {others}")
    efforts = [checkFailure(m, tension_strength, compressive_strength, wei_V0, wei_P, wei_m, weibull,
                            stress_correction) for m in members]
    if max(efforts) <= 0:
        return False
    broken = members[int(np.argmax(efforts))]
    rest = [m for m in members if m != broken]
    groups = _groups(rest) if rest else []
    masses = [mass_properties(scene, g, discretization)[0] if len(g) > 1 else float(member_mass(scene, g)[0][0])
              for g in groups]
    sub_mass = float(b.mass[c]) - sum(masses)
    layout = None
    if sub_mass > 0:
        layout = subparticle_layout(broken, sub_mass, radius_ratio, relative_gap, rest, initial_packing_scale,
                                    max_scale, scale_multiplier=None, search_for_neighbours=search_for_neighbours,
                                    outer_predicate=outer_predicate, grow_radius=grow_radius,
                                    max_grow_radius=max_grow_radius)
        if layout is None:
            return False
    # the old clump's motion and momentum, before anything changes
    xc, v, w = b.pos[c].copy(), b.vel[c].copy(), b.ang_vel[c].copy()
    P = float(b.mass[c]) * v
    L = np.cross(xc, P) + _world_inertia(c) @ w
    src = O.bodies[broken]
    material, color = src.material, tuple(src.shape.color)
    radius = scene.shapes[ShapeKind.SPHERE].radius
    specs = [[(b.pos[m].copy(), float(radius[b.shape_row[m]]), O.bodies[m].material, tuple(O.bodies[m].shape.color))
              for m in g] for g in groups]
    if len(rest) == 1:
        O.bodies.erase(c)  # the last member stays, standalone, with its id (and the clump's motion)
        O.bodies.erase(broken)
    else:
        O.bodies.erase(c, True)
    new = _append_subparticles(material, color, layout[0], layout[1], P, L) if layout else []
    parts = rest if len(rest) == 1 else [_remake(spec, v, w, xc, discretization) for spec in specs]
    b = scene.bodies
    for k in parts:
        P = P - b.mass[k] * b.vel[k]
        L = L - np.cross(b.pos[k], b.mass[k] * b.vel[k]) - _world_inertia(k) @ b.ang_vel[k]
    if new:
        _set_rigid_motion(new, P, L)
    return True


def _remake(spec, v, w, xc, discretization: int) -> int:
    """A group of old members as new bodies (a sphere, or a clump of them) moving with the rigid
    motion ``v`` at ``xc``, ``w``; return the id of the sphere or clump."""
    from granum.yade import utils  # lazy: utils imports the scene code

    ids = O.bodies.append([utils.sphere(Vector3(*x), r, material=mat, color=col) for x, r, mat, col in spec])
    b = O._scene.bodies
    for k in ids:
        b.vel[k], b.ang_vel[k] = v + np.cross(w, b.pos[k] - xc), w
    return O.bodies.clump(ids, discretization) if len(ids) > 1 else ids[0]


# ------------------------------------------------------------------------------------------- growth
def growParticle(bodyID, multiplier, updateMass=True) -> None:
    """Multiply the radius of sphere ``bodyID`` by ``multiplier``; with ``updateMass`` its mass by
    ``multiplier^3`` and inertia by ``multiplier^5`` (YADE's utils.growParticle)."""
    i, r, _ = _sphere(int(bodyID), "growParticle")
    if not multiplier > 0:
        raise ValueError(f"growParticle: multiplier must be positive, got {multiplier!r}")
    scene = O._scene
    scene.shapes[ShapeKind.SPHERE].radius[scene.bodies.shape_row[i]] = r * multiplier
    if updateMass:
        scene.bodies.mass[i] *= multiplier ** 3
        scene.bodies.inertia[i] *= multiplier ** 5
    scene.needs_collider()
