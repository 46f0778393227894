"""Editing clumps: ``O.bodies.addToClump``, ``releaseFromClump``, ``updateClumpProperties``,
``deleteClumpMember``, ``deleteClumpBody``, ``erase`` of clumps and members, ``getRoundness``.

Behaviour of YADE 2023.02a, used as a black box (``tests/reference/yade/clump_edit.json``):

* ``addToClump(ids, c, discretization=0)``: each body of the list joins clump ``c``; a clump in
  the list, or a member of another clump, brings all members of that clump, which is erased.
  The mass properties are computed anew from all members (:mod:`granum.yade.clumps`).
* ``releaseFromClump(b, c, discretization=0)``: member ``b`` becomes standalone and ``c`` is
  computed anew from the others; a clump of two members is left alone with a warning (YADE's
  message), since a clump of one member should be erased instead.
* ``updateClumpProperties(excludeList=[], discretization=5)`` recomputes every clump not in the
  list (after members were resized, for example).
* ``erase(member)`` takes the member out of its clump's member list and leaves the clump's mass
  properties as they were (``updateClumpProperties`` recomputes them); ``deleteClumpMember(clumpBody,
  memberBody)`` erases the member and recomputes the clump with discretization 0.
  ``erase(clump)`` makes its members standalone; ``erase(clump, True)`` and
  ``deleteClumpBody(clumpBody)`` erase them too.
* ``getRoundness(excludeList=[])`` is the mean over clumps and standalone spheres not in the
  list (members in the list do not exclude their clump; other bodies do not count) of
  ``R1 / R2``: ``R1`` the radius of the sphere of the members' summed volume (``4/3 pi r^3`` for
  spheres, mass / density for others), ``R2`` the largest ``|x_i - c| + r_i`` over the spherical
  members, ``c`` their mass centre; 1 for a sphere; 0 when nothing counts.

Deliberate differences (YADE defects): misuse that YADE only warns about (adding a clump's own
member or the clump itself, releasing a body that is not a member of the clump) or that crashes
it (an unknown clump or body id) raises an exception naming the value, before anything changes;
members brought by a merged clump get the new clump's id (YADE leaves them at -1, and its next
step fails an assertion); and momentum carries over (:func:`granum.yade.clumps.assign`) where
YADE sets an edited clump at rest.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from granum.core.shapes import ShapeKind
from granum.yade.clumps import (
    assign,
    clump_members,
    mass_properties,
    member_mass,
    member_velocities,
    write_members,
)


def _body(scene, i, what: str) -> int:
    if not isinstance(i, int | np.integer):
        raise TypeError(f"{what}: body ids must be integers, got {i!r}")
    i = int(i)
    b = scene.bodies
    if not (0 <= i < b.count and b.alive[i]):
        raise IndexError(f"{what}: no body with id {i}")
    return i


def _clump(scene, c, what: str) -> int:
    c = _body(scene, c, what)
    if scene.bodies.shape_kind[c] != ShapeKind.CLUMP:
        raise TypeError(f"{what}: body {c} is not a clump")
    return c


def add_to_clump(scene, ids, c, discretization: int = 0) -> None:
    """``O.bodies.addToClump(ids, c, discretization)``; see the module docstring."""
    what = "addToClump"
    if not isinstance(ids, list | tuple | np.ndarray):
        raise TypeError(f"{what}: give a list of body ids, got {ids!r}")
    c = _clump(scene, c, what)
    b = scene.bodies
    members = clump_members(scene, c)
    absorbed, new = [], []
    for i in ids:
        i = _body(scene, i, what)
        if i == c:
            raise ValueError(f"{what}: body {i} is clump {c} itself")
        owner = int(b.clump_id[i])
        if owner == c:
            raise ValueError(f"{what}: body {i} is already a member of clump {c}")
        if owner >= 0:  # a clump, or a member of one: all its members come
            if owner not in absorbed:
                absorbed.append(owner)
                new += [m for m in clump_members(scene, owner) if m not in new]
        elif i not in new:
            new.append(i)
    all_ids = members + [i for i in new if i not in members]
    mass_properties(scene, all_ids, discretization)  # errors before the scene changes
    vel, ang_vel = member_velocities(scene, all_ids)
    for k in absorbed:
        b.alive[k] = False
    assign(scene, c, all_ids, discretization, vel, ang_vel)


def release_from_clump(scene, i, c, discretization: int = 0) -> None:
    """``O.bodies.releaseFromClump(i, c, discretization)``; see the module docstring."""
    what = "releaseFromClump"
    c = _clump(scene, c, what)
    i = _body(scene, i, what)
    members = clump_members(scene, c)
    if i not in members:
        raise ValueError(f"{what}: body {i} is not a member of clump {c}")
    if len(members) <= 2:
        warnings.warn(f"Warning: Body {i} not released from clump {c}, because number of clump members would "
                      f"get < 2!", UserWarning, stacklevel=3)
        return
    rest = [m for m in members if m != i]
    mass_properties(scene, rest, discretization)
    vel, ang_vel = member_velocities(scene, members)
    _free(scene, [i], vel[members.index(i)], ang_vel[members.index(i)])
    keep = [members.index(m) for m in rest]
    assign(scene, c, rest, discretization, vel[keep], ang_vel[keep])


def _free(scene, ids, vel, ang_vel) -> None:
    """Make clump members ``ids`` standalone bodies moving with ``vel``, ``ang_vel``."""
    b = scene.bodies
    for i in ids:
        b.clump_id[i] = -1
        b.clump_rel_pos[i] = 0.0
        b.clump_rel_ori[i] = (1.0, 0.0, 0.0, 0.0)
    b.vel[ids] = vel
    b.ang_vel[ids] = ang_vel
    scene.needs_collider()


def update_clump_properties(scene, exclude=(), discretization: int = 5) -> None:
    """``O.bodies.updateClumpProperties(excludeList, discretization)``: every clump not excluded."""
    skip = {_checked_id(scene, i, "updateClumpProperties") for i in exclude}
    b = scene.bodies
    n = scene.body_count
    clumps = [int(k) for k in np.flatnonzero(b.alive[:n] & (b.shape_kind[:n] == ShapeKind.CLUMP)) if k not in skip]
    for k in clumps:  # every error before the first change
        mass_properties(scene, clump_members(scene, k), discretization)
    for k in clumps:
        members = clump_members(scene, k)
        vel, ang_vel = member_velocities(scene, members)
        assign(scene, k, members, discretization, vel, ang_vel)


def _checked_id(scene, i, what: str) -> int:
    """An id of an exclude list: any body that exists or existed (erased ones are allowed)."""
    if not isinstance(i, int | np.integer) or not 0 <= int(i) < scene.body_count:
        raise IndexError(f"{what}: no body with id {i!r} in the exclude list")
    return int(i)


def erase_member(scene, i: int) -> None:
    """Take member ``i`` out of its clump's member list (mass properties unchanged, as in YADE);
    the caller erases the body."""
    c = int(scene.bodies.clump_id[i])
    write_members(scene, c, [m for m in clump_members(scene, c) if m != i])
    scene.bodies.clump_id[i] = -1


def dissolve(scene, c: int) -> list[int]:
    """Make the members of clump ``c`` standalone (each keeps its motion); return their ids."""
    members = clump_members(scene, c)
    vel, ang_vel = member_velocities(scene, members)
    _free(scene, members, vel, ang_vel)
    return members


def delete_clump_member(bodies, clump_body, member_body) -> None:
    """``O.bodies.deleteClumpMember(clumpBody, memberBody)``: erase a member, recompute its clump
    (discretization 0) from the others."""
    scene = bodies._scene
    c = _clump(scene, _id_of(clump_body, "deleteClumpMember"), "deleteClumpMember")
    i = _body(scene, _id_of(member_body, "deleteClumpMember"), "deleteClumpMember")
    members = clump_members(scene, c)
    if i not in members:
        raise ValueError(f"deleteClumpMember: body {i} is not a member of clump {c}")
    vel, ang_vel = member_velocities(scene, members)
    bodies.erase(i)
    rest = [m for m in members if m != i]
    if rest:
        keep = [members.index(m) for m in rest]
        assign(scene, c, rest, 0, vel[keep], ang_vel[keep])


def delete_clump_body(bodies, clump_body) -> None:
    """``O.bodies.deleteClumpBody(clumpBody)``: erase a clump and its members."""
    c = _clump(bodies._scene, _id_of(clump_body, "deleteClumpBody"), "deleteClumpBody")
    bodies.erase(c, True)


def _id_of(body, what: str) -> int:
    if not hasattr(body, "id"):
        raise TypeError(f"{what}: expected a Body, got {body!r}")
    return body.id


def roundness(scene, exclude=()) -> float:
    """``O.bodies.getRoundness(excludeList)``; see the module docstring."""
    skip = {_checked_id(scene, i, "getRoundness") for i in exclude}
    b = scene.bodies
    n = scene.body_count
    values = []
    for k in range(n):
        if not b.alive[k] or k in skip:
            continue
        if b.shape_kind[k] == ShapeKind.SPHERE and b.clump_id[k] < 0:
            values.append(1.0)
        elif b.shape_kind[k] == ShapeKind.CLUMP:
            values.append(_clump_roundness(scene, k))
    return float(np.mean(values)) if values else 0.0


def _clump_roundness(scene, k: int) -> float:
    b = scene.bodies
    members = clump_members(scene, k)
    m, _ = member_mass(scene, members)
    density = np.array([float(scene.materials[b.material[i]].density) for i in members])
    r1 = (3.0 / (4.0 * math.pi) * float((m / density).sum())) ** (1.0 / 3.0)
    centre = (m[:, None] * b.pos[members]).sum(axis=0) / m.sum()
    sph = [i for i in members if b.shape_kind[i] == ShapeKind.SPHERE]
    if not sph:
        raise ValueError(f"getRoundness: clump {k} has no spherical member to measure")
    r = scene.shapes[ShapeKind.SPHERE].radius[b.shape_row[sph]]
    r2 = float((np.linalg.norm(b.pos[sph] - centre, axis=1) + r).max())
    return r1 / r2
