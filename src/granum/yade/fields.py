"""Per-body and per-contact quantities for output, computed with NumPy straight from the storage.

These are the quantities that YADE's VTK recorder, its exporters and the snapshot renderer
derive from a scene. Each function takes a :class:`granum.core.scene.Scene` and works on whole
columns at once (no per-body Python objects), so output stays cheap for large scenes. ``N`` is
the number of body rows (``scene.body_count``, erased ids included), ``K`` the number of live
contacts.

The formulas of the stress measures were checked against the files YADE 2023.02a writes, as a
black box (see ``tests/test_vtk.py``).
"""

from __future__ import annotations

import numpy as np

from granum.core.contacts import (
    C_CONTACTS,
    F_FN,
    F_FS,
    F_NORMAL,
    F_POINT,
    F_R1,
    F_R2,
    FLAG_ALIVE,
    I_CELL,
    I_FLAGS,
    I_ID1,
    I_ID2,
)
from granum.core.shapes import ShapeKind, shape_type


def live_contact_rows(scene) -> np.ndarray:
    """(K,) rows of ``con_i``/``con_f`` holding live contacts, in pool (creation) order."""
    C = scene.contacts
    n = int(C.ctr[C_CONTACTS])
    return np.nonzero(C.con_i[:n, I_FLAGS] & FLAG_ALIVE)[0]


def contact_ids(scene, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(K,) ids of body 1 and body 2 of the contacts in ``rows`` (functor order: facet/box first)."""
    con_i = scene.contacts.con_i
    return con_i[rows, I_ID1].astype(np.int64), con_i[rows, I_ID2].astype(np.int64)


def contact_shift(scene, rows: np.ndarray) -> np.ndarray:
    """(K, 3) offset of body 2's periodic image (``hSize @ cellDist``) [m]; zero when aperiodic."""
    if not scene.periodic:
        return np.zeros((len(rows), 3))
    cell = scene.contacts.con_i[rows, I_CELL:I_CELL + 3].astype(float)
    return cell @ np.asarray(scene.cell_hsize, float).T


def wrap_shift(scene, ids: np.ndarray) -> np.ndarray:
    """(M, 3) shift bringing the centres of bodies ``ids`` into the periodic cell [m]; zero when aperiodic.

    YADE keeps unwrapped positions (and so do the output files) but draws bodies inside the cell.
    """
    pos = scene.bodies.pos[ids]
    if not scene.periodic:
        return np.zeros_like(pos)
    h = np.asarray(scene.cell_hsize, float)
    frac = np.linalg.solve(h, pos.T).T
    return -np.floor(frac) @ h.T


def coord_numbers(scene) -> np.ndarray:
    """(N,) number of live contacts of each body (YADE's ``coordNumber``)."""
    id1, id2 = contact_ids(scene, live_contact_rows(scene))
    n = scene.body_count
    return np.bincount(id1, minlength=n)[:n] + np.bincount(id2, minlength=n)[:n]


def material_ids(scene) -> np.ndarray:
    """(N,) ``b.material.id`` of each body: index in ``O.materials``, -1 if none or not shared."""
    mats = scene.materials
    table = np.array([getattr(m, "id", -1) for m in mats] + [-1], dtype=np.int64)
    k = scene.bodies.material[:scene.body_count].astype(np.int64)
    return table[np.where(k >= 0, k, len(mats))]


def _contact_area(r1: np.ndarray, r2: np.ndarray) -> np.ndarray:
    # The cross-section of the smaller reference radius; a radius <= 0 (walls, boxes in some
    # geometries) does not count.
    rmin = np.where(r1 <= 0, r2, np.where(r2 <= 0, r1, np.minimum(r1, r2)))
    return np.pi * rmin * rmin


def contact_stresses(scene) -> tuple[np.ndarray, np.ndarray]:
    """Per-body sums of the contacts' normal and "shear" stress vectors [Pa], each (N, 3).

    For each contact, with the normal ``n``, the normal and shear forces ``Fn``, ``Fs`` and the
    area ``A = pi min(R1, R2)^2`` of the two reference radii:
    ``normal = (n . Fn) n / A`` and ``shear_i = (n_j Fs_j + n_k Fs_k) / A`` for the other two
    axes ``j, k`` of ``i`` (YADE's ``Shop::getStressForEachBody`` measure). Both bodies of a
    contact get the same vectors added (no sign flip), as in YADE.
    """
    n = scene.body_count
    rows = live_contact_rows(scene)
    f = scene.contacts.con_f[rows]
    nrm, fn, fs = f[:, F_NORMAL:F_NORMAL + 3], f[:, F_FN:F_FN + 3], f[:, F_FS:F_FS + 3]
    area = _contact_area(f[:, F_R1], f[:, F_R2])
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = np.where(area > 0, 1.0 / area, 0.0)
    normal = (np.einsum("ki,ki->k", nrm, fn) * inv)[:, None] * nrm
    nfs = nrm * fs
    shear = (nfs.sum(axis=1)[:, None] - nfs) * inv[:, None]  # n_j Fs_j + n_k Fs_k = n.Fs - n_i Fs_i
    id1, id2 = contact_ids(scene, rows)
    out_n = np.zeros((n, 3))
    out_s = np.zeros((n, 3))
    for ids in (id1, id2):
        np.add.at(out_n, ids, normal)
        np.add.at(out_s, ids, shear)
    return out_n, out_s


def body_stress_tensors(scene, ids: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """Average stress in each sphere of ``ids`` [Pa], (len(ids), 3, 3) (YADE's ``bodyStressTensors``).

    ``sigma = 1/V sum_c f_c (x_c - x_b)^T`` over the sphere's contacts, with ``f_c`` the contact
    force acting on the sphere, ``x_c`` the contact point and ``V = 4/3 pi r^3``.
    """
    n = scene.body_count
    rows = live_contact_rows(scene)
    f = scene.contacts.con_f[rows]
    force2 = f[:, F_FN:F_FN + 3] + f[:, F_FS:F_FS + 3]  # force on body 2; body 1 gets the opposite
    point = f[:, F_POINT:F_POINT + 3]
    id1, id2 = contact_ids(scene, rows)
    pos = scene.bodies.pos[:n]
    sums = np.zeros((n, 3, 3))
    np.add.at(sums, id1, np.einsum("ki,kj->kij", -force2, point - pos[id1]))
    np.add.at(sums, id2, np.einsum("ki,kj->kij", force2, point - (pos[id2] + contact_shift(scene, rows))))
    volume = 4.0 / 3.0 * np.pi * np.asarray(radii, float) ** 3
    return sums[ids] / volume[:, None, None]


def principal_stresses(tensors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal values and directions of (M, 3, 3) stress tensors.

    Returns ``(values (M, 3), directions (M, 3, 3))`` ordered from the most tensile (largest,
    YADE's ``sigI``) to the most compressive (``sigIII``); ``directions[:, k]`` is the unit vector
    of value ``k`` (its sign is arbitrary). As YADE's self-adjoint solver, only the lower triangle
    of each tensor is read, which symmetrises it by mirroring.
    """
    values, vectors = np.linalg.eigh(np.asarray(tensors, float), UPLO="L")
    return values[:, ::-1], np.swapaxes(vectors, 1, 2)[:, ::-1]


def rotation_matrices(ori: np.ndarray) -> np.ndarray:
    """(M, 3, 3) rotation matrices of (M, 4) unit quaternions (w, x, y, z), local to global."""
    q = np.asarray(ori, float)
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1),
    ], axis=1)


def ids_of_kind(scene, kind: ShapeKind, mask: int = 0) -> np.ndarray:
    """(M,) ids of the live bodies of a shape kind, in id order; ``mask`` != 0 keeps groupMask & mask."""
    b = scene.bodies
    n = scene.body_count
    keep = b.alive[:n] & (b.shape_kind[:n] == int(kind))
    if mask:
        keep &= (b.mask[:n] & int(mask)) != 0
    return np.nonzero(keep)[0]


def clipped(points: np.ndarray, planes: np.ndarray) -> np.ndarray:
    """(M,) mask of the (M, 3) ``points`` behind any of the (P, 2, 3) clipping ``planes`` (point [m], unit
    normal): a point is behind a plane when its offset from the plane's point has a negative component
    along the normal (YADE's 3D view hides a body whose centre is behind an active clipping plane)."""
    points = np.asarray(points, float).reshape(-1, 3)
    hidden = np.zeros(len(points), bool)
    for point, normal in np.asarray(planes, float).reshape(-1, 2, 3):
        hidden |= (points - point) @ normal < 0
    return hidden


def sphere_radii(scene, ids: np.ndarray) -> np.ndarray:
    """(M,) radii of the spheres ``ids`` [m]."""
    return scene.shapes[ShapeKind.SPHERE].radius[scene.bodies.shape_row[ids]]


def body_faces(scene, kind: ShapeKind, ids: np.ndarray) -> np.ndarray:
    """(M, F, V, 3) global corners of the polygons of the bodies ``ids`` [m], all of shape kind ``kind``:
    the F polygons of V vertices per body its declaration gives (:attr:`granum.core.shapes.ShapeType.faces`,
    one triangle per facet, six quadrilaterals per box in YADE's VTK order)."""
    local = shape_type(kind).faces(scene.shapes[kind], scene.bodies.shape_row[ids])
    rot = rotation_matrices(scene.bodies.ori[ids])
    return scene.bodies.pos[ids][:, None, None, :] + np.einsum("mij,mfkj->mfki", rot, local)


def facet_vertices(scene, ids: np.ndarray) -> np.ndarray:
    """(F, 3, 3) global vertex positions of the facets ``ids`` [m]; ``[f, k]`` is vertex k."""
    return body_faces(scene, ShapeKind.FACET, ids)[:, 0]
