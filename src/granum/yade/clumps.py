"""Clumps: rigid aggregates of bodies (``O.bodies.clump``, ``appendClumped``, ``clumpTemplate``).

A clump is a body of shape ``Clump`` whose mass, centre of mass and principal inertia
come from its members (YADE section 3.5.3): with ``discretization = 0`` members are
summed with the parallel-axis theorem,

.. math::
    M = \\sum m_i, \\quad c = \\sum m_i x_i / M, \\quad
    I = \\sum \\big[ R_i I_i R_i^T + m_i (|d_i|^2 1 - d_i d_i^T) \\big],\\; d_i = x_i - c,

which counts overlapping volume twice; with ``discretization = n > 0`` the union of
spherical members is integrated on a grid of n cells across the smallest diameter.
The clump's local axes are the principal axes of I. Members are moved rigidly with
the clump by the integrator and keep their offsets in the clump frame.
"""

from __future__ import annotations

import math

import numpy as np

from granum.core.shapes import ShapeKind
from granum.mathtypes import Matrix3, Quaternion, as_quat_wxyz


def _rot(q) -> np.ndarray:
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def _quat_from_matrix(r: np.ndarray) -> np.ndarray:
    q = as_quat_wxyz(Quaternion(Matrix3(*r.ravel())))
    return q / np.linalg.norm(q)


def _quat_mul(a, b) -> np.ndarray:
    return np.array([a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
                     a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
                     a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
                     a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]])


def mass_properties(scene, ids, discretization: int = 0):
    """``(mass [kg], centre [m] (3,), inertia tensor about the centre [kg m^2] (3, 3))`` of members ``ids``."""
    b = scene.bodies
    ids = np.asarray(ids, dtype=np.int64)
    if discretization > 0:
        kind = b.shape_kind[ids]
        if not np.all(kind == ShapeKind.SPHERE):
            raise ValueError("clump: discretization > 0 needs spherical members")
        r = scene.shapes[ShapeKind.SPHERE].radius[b.shape_row[ids]]
        x = b.pos[ids]
        rho = b.mass[ids] / (4.0 / 3.0 * math.pi * r ** 3)
        lo, hi = (x - r[:, None]).min(axis=0), (x + r[:, None]).max(axis=0)
        h = 2.0 * r.min() / discretization
        axes = [np.arange(lo[k] + 0.5 * h, hi[k], h) for k in range(3)]
        g = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
        d2 = ((g[:, None, :] - x[None, :, :]) ** 2).sum(axis=2)
        inside = d2 <= r[None, :] ** 2
        hit = inside.any(axis=1)
        # a cell belongs to the first member containing it: density of that member
        owner = np.argmax(inside, axis=1)
        dm = rho[owner[hit]] * h ** 3
        pts = g[hit]
        mass = dm.sum()
        c = (dm[:, None] * pts).sum(axis=0) / mass
        d = pts - c
        inertia = np.einsum("p,pij->ij", dm, (d ** 2).sum(axis=1)[:, None, None] * np.eye(3)
                            - d[:, :, None] * d[:, None, :])
        return float(mass), c, inertia
    m = b.mass[ids]
    mass = float(m.sum())
    if not mass > 0:
        raise ValueError("clump: the members have no mass")
    c = (m[:, None] * b.pos[ids]).sum(axis=0) / mass
    inertia = np.zeros((3, 3))
    for i, mi in zip(ids, m, strict=True):
        R = _rot(b.ori[i])
        d = b.pos[i] - c
        inertia += R @ np.diag(b.inertia[i]) @ R.T + mi * (d @ d * np.eye(3) - np.outer(d, d))
    return mass, c, inertia


def make_clump(scene, ids, discretization: int = 0) -> int:
    """Turn bodies ``ids`` into members of a new clump body; return the clump's id."""
    b = scene.bodies
    ids = [int(i) for i in ids]
    if len(ids) < 1 or len(set(ids)) != len(ids):
        raise ValueError("clump: give a list of distinct body ids")
    for i in ids:
        if not (0 <= i < b.count and b.alive[i]):
            raise IndexError(f"clump: no body with id {i}")
        if b.clump_id[i] >= 0:
            raise ValueError(f"clump: body {i} already belongs to clump {b.clump_id[i]}")
    mass, c, inertia = mass_properties(scene, ids, discretization)
    principal, axes = np.linalg.eigh(inertia)
    if np.linalg.det(axes) < 0:
        axes[:, 2] *= -1.0
    q = _quat_from_matrix(axes)
    # momentum of the members becomes the clump's
    m = b.mass[ids]
    vel = (m[:, None] * b.vel[ids]).sum(axis=0) / mass
    mom = np.zeros(3)
    for i in ids:
        R = _rot(b.ori[i])
        mom += np.cross(b.pos[i] - c, b.mass[i] * b.vel[i]) + R @ (b.inertia[i] * (R.T @ b.ang_vel[i]))
    omega = axes @ ((axes.T @ mom) / np.where(principal > 0, principal, 1.0))

    k = scene.add_body_row()
    table = scene.shapes[ShapeKind.CLUMP]
    row = table.append_rows(1)
    first = scene.clump_members.append_rows(len(ids))
    scene.clump_members.id[first:first + len(ids)] = ids
    table.member_first[row], table.member_count[row] = first, len(ids)
    b.alive[k] = True
    b.shape_kind[k], b.shape_row[k] = int(ShapeKind.CLUMP), row
    b.material[k] = b.material[ids[0]]
    b.pos[k], b.ref_pos[k] = c, c
    b.ori[k], b.ref_ori[k] = q, q
    b.mass[k] = mass
    b.inertia[k] = principal
    b.aspherical[k] = True
    b.vel[k] = vel
    b.ang_vel[k] = omega
    b.ang_mom[k] = mom
    b.clump_id[k] = k
    b.mask[k] = b.mask[ids[0]]
    qc = np.array([q[0], -q[1], -q[2], -q[3]])
    for i in ids:
        b.clump_id[i] = k
        b.clump_rel_pos[i] = axes.T @ (b.pos[i] - c)
        b.clump_rel_ori[i] = _quat_mul(qc, b.ori[i])
        b.vel[i] = vel + np.cross(omega, b.pos[i] - c)
        b.ang_vel[i] = omega
    scene.needs_collider()
    return k


def clump_members(scene, k: int) -> list[int]:
    """Member ids of clump body ``k``."""
    table = scene.shapes[ShapeKind.CLUMP]
    row = int(scene.bodies.shape_row[k])
    first, count = int(table.member_first[row]), int(table.member_count[row])
    return [int(i) for i in scene.clump_members.id[first:first + count]]
