"""Clumps: rigid aggregates of bodies (``O.bodies.clump``, ``appendClumped``, and the edits of
:mod:`granum.yade.clump_edits`).

A clump is a body of shape ``Clump`` whose mass, centre of mass and principal inertia come from
its members (YADE section 3.5.3). The rules, checked against YADE 2023.02a used as a black box
(``tests/reference/yade/clump_edit.json``):

* a spherical member weighs ``m = rho 4/3 pi r^3`` with ``rho`` its material's density and has
  ``I = 2/5 m r^2`` (its ``state.mass`` and ``state.inertia`` are not read); any other member
  counts with its ``state.mass`` and principal ``state.inertia``;
* with ``discretization = 0``, or when no two spherical members overlap (centre distance
  ``< r1 + r2``), the members are summed with the parallel-axis theorem,

  .. math::
      M = \\sum m_i, \\quad c = \\sum m_i x_i / M, \\quad
      I = \\sum \\big[ R_i I_i R_i^T + m_i (|d_i|^2 1 - d_i d_i^T) \\big],\\; d_i = x_i - c,

  which counts overlapping volume twice;
* with ``discretization = n > 0`` and overlapping spheres, the union is integrated on a grid:
  cells of edge ``h = L_min / n`` (``L_min`` the shortest edge of the members' axis-aligned box)
  are laid from the box's lower corner while their centres stay below its upper end
  (``ceil(L / h - 1/2)`` of them along an axis of length ``L``, a centre on the end excluded); a cell whose
  centre lies strictly inside a member (lowest member id first) has that member's density, and adds
  ``dm h^2 / 6`` about each axis as a small cube;
* the clump's local axes are the principal axes of I (eigenvalues ascending).

Members move rigidly with the clump (the integrator places them) and keep their offsets in the
clump frame. Momentum, unlike in YADE (which sets a new or edited clump at rest), carries over:
the members' momenta give the clump's velocity and angular velocity (see :func:`assign`).
"""

from __future__ import annotations

import math

import numpy as np

from granum.core.contacts import C_CONTACTS, FLAG_ALIVE, I_FLAGS, I_ID1, I_ID2, end_contact
from granum.core.shapes import ShapeKind
from granum.mathtypes import Matrix3, Quaternion, as_quat_wxyz

#: Grid cells integrated at once (memory: this many points times the member count).
_GRID_CHUNK = 1 << 16


def rotation(q) -> np.ndarray:
    """Rotation matrix (3, 3) of the unit quaternion ``q`` = (w, x, y, z)."""
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


def member_mass(scene, ids):
    """``(m (K,) [kg], I (K, 3, 3) [kg m^2] about each member's centre, global frame)`` of bodies
    ``ids`` as a clump weighs them: spheres from radius and density, other shapes from their state."""
    b = scene.bodies
    ids = np.asarray(ids, dtype=np.int64)
    m = b.mass[ids].astype(np.float64)
    inertia = np.empty((len(ids), 3, 3))
    for k, i in enumerate(ids):
        if b.shape_kind[i] == ShapeKind.SPHERE:
            r = float(scene.shapes[ShapeKind.SPHERE].radius[b.shape_row[i]])
            m[k] = _density(scene, i) * 4.0 / 3.0 * math.pi * r ** 3
            inertia[k] = 0.4 * m[k] * r * r * np.eye(3)
        else:
            R = rotation(b.ori[i])
            inertia[k] = R @ np.diag(b.inertia[i]) @ R.T
    return m, inertia


def _density(scene, i: int) -> float:
    k = int(scene.bodies.material[i])
    density = getattr(scene.materials[k], "density", None) if k >= 0 else None
    if density is None:
        raise ValueError(f"clump: body {i} has no material density to weigh it by")
    return float(density)


def spheres_overlap(scene, ids) -> bool:
    """Whether two spherical members of ``ids`` overlap (centre distance < r1 + r2)."""
    b = scene.bodies
    sph = [int(i) for i in ids if b.shape_kind[i] == ShapeKind.SPHERE]
    if len(sph) < 2:
        return False
    x = b.pos[sph]
    r = scene.shapes[ShapeKind.SPHERE].radius[b.shape_row[sph]]
    d = np.linalg.norm(x[:, None] - x[None], axis=2)
    gap = d - (r[:, None] + r[None])
    np.fill_diagonal(gap, np.inf)
    return bool((gap < 0).any())


def _sum_properties(scene, ids):
    m, inertia_i = member_mass(scene, ids)
    mass = float(m.sum())
    if not mass > 0:
        raise ValueError(f"clump: the members {list(ids)} have no mass")
    x = scene.bodies.pos[np.asarray(ids, dtype=np.int64)]
    c = (m[:, None] * x).sum(axis=0) / mass
    d = x - c
    inertia = inertia_i.sum(axis=0) + np.einsum("k,kij->ij", m, (d * d).sum(axis=1)[:, None, None] * np.eye(3)
                                                 - d[:, :, None] * d[:, None, :])
    return mass, c, inertia


def _grid_properties(scene, ids, discretization: int):
    b = scene.bodies
    ids = sorted(int(i) for i in ids)  # YADE keeps members by id: the lowest id owns a shared cell
    other = [i for i in ids if b.shape_kind[i] != ShapeKind.SPHERE]
    if other:
        raise ValueError(f"clump: discretization={discretization} integrates spheres only; bodies {other} are not "
                         f"spheres (use discretization=0)")
    x = b.pos[ids]
    r = scene.shapes[ShapeKind.SPHERE].radius[b.shape_row[ids]]
    rho = np.array([_density(scene, i) for i in ids])
    lo, hi = (x - r[:, None]).min(axis=0), (x + r[:, None]).max(axis=0)
    h = float((hi - lo).min()) / discretization
    # a centre on the upper end (L / h = k + 1/2 up to rounding) is out, however L / h rounds
    axes = [lo[k] + h * (np.arange(int(math.ceil((hi[k] - lo[k]) / h - 0.5 - 1e-9))) + 0.5) for k in range(3)]
    shape = tuple(len(a) for a in axes)
    total = math.prod(shape)
    mass, first, second = 0.0, np.zeros(3), np.zeros((3, 3))
    for start in range(0, total, _GRID_CHUNK):
        flat = np.arange(start, min(start + _GRID_CHUNK, total))
        ix, iy, iz = np.unravel_index(flat, shape)
        g = np.stack([axes[0][ix], axes[1][iy], axes[2][iz]], axis=1)
        # strictly inside: a centre on a surface (grids of round numbers have them) is out, however it rounds
        inside = ((g[:, None, :] - x[None]) ** 2).sum(axis=2) < r[None] ** 2 * (1.0 - 1e-10)
        hit = inside.any(axis=1)
        dm = rho[np.argmax(inside[hit], axis=1)] * h ** 3
        p = g[hit]
        mass += dm.sum()
        first += dm @ p
        second += np.einsum("p,pi,pj->ij", dm, p, p)
    if not mass > 0:
        raise ValueError(f"clump: discretization={discretization} found no grid cell inside the members {ids}")
    c = first / mass
    # second moment about the centre -> inertia tensor, plus each cell's own inertia (a cube)
    s = second - mass * np.outer(c, c)
    inertia = np.trace(s) * np.eye(3) - s + mass * h * h / 6.0 * np.eye(3)
    return float(mass), c, inertia


def mass_properties(scene, ids, discretization: int = 0):
    """``(mass [kg], centre [m] (3,), inertia tensor about the centre, global frame [kg m^2] (3, 3))``
    of a clump of bodies ``ids`` (rules in the module docstring)."""
    if discretization > 0 and spheres_overlap(scene, ids):
        return _grid_properties(scene, ids, int(discretization))
    return _sum_properties(scene, ids)


def principal_frame(inertia: np.ndarray):
    """``(principal moments (3,) ascending, orientation quaternion (w, x, y, z), axes (3, 3))``."""
    principal, axes = np.linalg.eigh(inertia)
    if np.linalg.det(axes) < 0:
        axes[:, 2] *= -1.0
    return principal, _quat_from_matrix(axes), axes


def member_velocities(scene, ids):
    """``(vel (K, 3), angVel (K, 3))`` of bodies ``ids``: a clump member moves with its clump
    (``v_c + w_c x (x - x_c)``, ``w_c``), which a body's own columns only show after a step."""
    b = scene.bodies
    ids = np.asarray(ids, dtype=np.int64)
    v, w = b.vel[ids].copy(), b.ang_vel[ids].copy()
    for k, i in enumerate(ids):
        c = int(b.clump_id[i])
        if c >= 0 and c != i:
            w[k] = b.ang_vel[c]
            v[k] = b.vel[c] + np.cross(b.ang_vel[c], b.pos[i] - b.pos[c])
    return v, w


def write_members(scene, k: int, ids) -> None:
    """Store ``ids`` as the members of clump body ``k`` (in place when they fit in its old range)."""
    table = scene.shapes[ShapeKind.CLUMP]
    row = int(scene.bodies.shape_row[k])
    if len(ids) > table.member_count[row]:
        table.member_first[row] = scene.clump_members.append_rows(len(ids))
    first = int(table.member_first[row])
    scene.clump_members.id[first:first + len(ids)] = ids
    table.member_count[row] = len(ids)


def end_internal_contacts(scene, ids) -> None:
    """End the live contacts between two of ``ids`` (members of one clump do not interact)."""
    C = scene.contacts
    n = int(C.ctr[C_CONTACTS])
    inside = np.isin(C.con_i[:n, I_ID1], ids) & np.isin(C.con_i[:n, I_ID2], ids)
    for c in np.flatnonzero(inside):
        if C.con_i[c, I_FLAGS] & FLAG_ALIVE:
            end_contact(C, c)


def assign(scene, k: int, ids, discretization: int, vel, ang_vel) -> None:
    """Make ``ids`` the members of clump body ``k`` with velocities ``vel``, ``ang_vel`` (K, 3).

    Mass, centre, inertia and axes follow :func:`mass_properties`. The members' momenta, with
    each weighed as in :func:`member_mass`, give the motion: ``v = sum m_i v_i / sum m_i`` at the
    members' mass centre ``c_m``, and ``w = I_m^-1 L`` with ``L`` their angular momentum about
    ``c_m`` and ``I_m`` their summed inertia there. The clump moves with that rigid motion, so a
    clump that was moving rigidly keeps its motion, and with ``discretization = 0`` (where
    ``c = c_m`` and ``I = I_m``) linear and angular momentum are conserved exactly.
    """
    b = scene.bodies
    ids = [int(i) for i in ids]
    mass, c, inertia = mass_properties(scene, ids, discretization)
    principal, q, axes = principal_frame(inertia)
    m, inertia_i = member_mass(scene, ids)
    msum, cm, inertia_m = _sum_properties(scene, ids)
    x = b.pos[ids]
    vel, ang_vel = np.asarray(vel, dtype=np.float64), np.asarray(ang_vel, dtype=np.float64)
    vm = (m[:, None] * vel).sum(axis=0) / msum
    mom = (np.cross(x - cm, m[:, None] * vel).sum(axis=0) + np.einsum("kij,kj->i", inertia_i, ang_vel))
    omega = np.linalg.lstsq(inertia_m, mom, rcond=None)[0]
    v = vm + np.cross(omega, c - cm)

    write_members(scene, k, ids)
    b.pos[k], b.ref_pos[k] = c, c
    b.ori[k], b.ref_ori[k] = q, q
    b.mass[k] = mass
    b.inertia[k] = principal
    b.aspherical[k] = True
    b.vel[k] = v
    b.ang_vel[k] = omega
    b.ang_mom[k] = inertia @ omega
    b.clump_id[k] = k
    qc = np.array([q[0], -q[1], -q[2], -q[3]])
    for i in ids:
        b.clump_id[i] = k
        b.clump_rel_pos[i] = axes.T @ (b.pos[i] - c)
        b.clump_rel_ori[i] = _quat_mul(qc, b.ori[i])
        b.vel[i] = v + np.cross(omega, b.pos[i] - c)
        b.ang_vel[i] = omega
    end_internal_contacts(scene, ids)
    scene.needs_collider()


def check_new_members(scene, ids, what: str) -> list[int]:
    """``ids`` as ints after checking they are distinct live bodies in no clump; errors name ``what``."""
    b = scene.bodies
    ids = [int(i) for i in ids]
    if len(ids) < 1 or len(set(ids)) != len(ids):
        raise ValueError(f"{what}: give a list of distinct body ids, got {ids}")
    for i in ids:
        if not (0 <= i < b.count and b.alive[i]):
            raise IndexError(f"{what}: no body with id {i}")
        if b.clump_id[i] >= 0:
            raise ValueError(f"{what}: body {i} already belongs to clump {b.clump_id[i]}")
    return ids


def make_clump(scene, ids, discretization: int = 0) -> int:
    """Turn bodies ``ids`` into members of a new clump body; return the clump's id."""
    ids = check_new_members(scene, ids, "clump")
    mass_properties(scene, ids, discretization)  # any error before the scene changes
    vel, ang_vel = member_velocities(scene, ids)
    b = scene.bodies
    k = scene.add_body_rows()
    table = scene.shapes[ShapeKind.CLUMP]
    row = table.append_rows(1)
    table.member_first[row], table.member_count[row] = 0, 0
    b.alive[k] = True
    b.shape_kind[k], b.shape_row[k] = int(ShapeKind.CLUMP), row
    b.material[k] = b.material[ids[0]]
    b.mask[k] = b.mask[ids[0]]
    assign(scene, k, ids, discretization, vel, ang_vel)
    return k


def clump_members(scene, k: int) -> list[int]:
    """Member ids of clump body ``k``."""
    table = scene.shapes[ShapeKind.CLUMP]
    row = int(scene.bodies.shape_row[k])
    first, count = int(table.member_first[row]), int(table.member_count[row])
    return [int(i) for i in scene.clump_members.id[first:first + count]]
