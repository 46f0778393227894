"""``O.cell``: the periodic cell (YADE ``Cell``), a view onto the scene's cell arrays.

The cell is the parallelepiped spanned by the columns of ``hSize`` (H). It deforms
with the velocity gradient ``velGrad`` (L); ``trsf`` (F) accumulates that deformation
and may be reset to the identity to start measuring strain from the current state.
Matrices are returned as copies, as in YADE; assign the whole matrix to change it.
"""

from __future__ import annotations

import numpy as np

from granum.core import validate
from granum.core.contacts import C_CONTACTS, I_CELL
from granum.mathtypes import Matrix3, Vector3, as_mat3, as_vec3
from granum.physics.vec import det3 as _compiled_det3

#: the kernels' determinant, run as Python (no compilation for a cell's volume)
det3 = _compiled_det3.py_func


def _matrix(a) -> Matrix3:
    return Matrix3(*np.asarray(a, dtype=float).ravel())


def flip_matrix(h) -> np.ndarray:
    """The integer matrix F of :meth:`Cell.flipCell` for base vectors ``h`` (3, 3) as columns: each column
    c_i in turn (x, y, z) is projected on the plane of the two others (as already flipped), its coordinates
    (a, b) in their basis rounded half up, floor(a + 1/2), and that lattice vector subtracted."""
    cols = [np.array(h[:, k], dtype=float) for k in range(3)]
    flip = np.eye(3, dtype=np.int64)
    for i in range(3):
        j, k = (m for m in range(3) if m != i)
        gram = np.array([[cols[j] @ cols[j], cols[j] @ cols[k]], [cols[k] @ cols[j], cols[k] @ cols[k]]])
        a, b = np.floor(np.linalg.solve(gram, [cols[i] @ cols[j], cols[i] @ cols[k]]) + 0.5).astype(np.int64)
        if a or b:
            cols[i] = cols[i] - a * cols[j] - b * cols[k]
            flip[:, i] -= a * flip[:, j] + b * flip[:, k]
    return flip


class DegenerateCellError(ValueError, RuntimeError):
    """A cell without a positive finite volume (a ValueError; also the RuntimeError YADE raises)."""


class Cell:
    """YADE's periodic cell."""

    __slots__ = ("_omega",)

    def __init__(self, omega=None):
        """The cell of ``omega``'s current scene; ``Cell()`` is a detached cell of an empty scene of its own
        (as YADE's bare ``Cell()``), not the simulation's."""
        if omega is None:
            import types

            from granum.core.scene import Scene

            omega = types.SimpleNamespace(_scene=Scene())
        object.__setattr__(self, "_omega", omega)

    def __setattr__(self, name, value):
        if not hasattr(type(self), name):
            raise AttributeError(f"Cell has no attribute {name!r}")
        object.__setattr__(self, name, value)

    @property
    def _scene(self):
        return self._omega._scene

    # ---- geometry -------------------------------------------------------------------
    @property
    def hSize(self) -> Matrix3:
        """Base vectors of the cell as columns [m]. Assigning it also sets ``refHSize``."""
        return _matrix(self._scene.cell_hsize)

    @hSize.setter
    def hSize(self, value) -> None:
        h = as_mat3(value)
        validate.CELL_BASE.check(h, "Cell.hSize", DegenerateCellError)
        s = self._scene
        s.cell_hsize[:] = h
        s.cell_ref_hsize[:] = h
        s.cell_prev_hsize[:] = h
        # the collider runs again; cell_bound_hsize stays the cell its pairs' budgets were measured from
        s.needs_collider()

    @property
    def refHSize(self) -> Matrix3:
        """Reference base vectors (set with hSize or setBox) [m]."""
        return _matrix(self._scene.cell_ref_hsize)

    @refHSize.setter
    def refHSize(self, value) -> None:
        self._scene.cell_ref_hsize[:] = as_mat3(value)

    hSize0 = refHSize

    def setBox(self, x, y=None, z=None) -> None:
        """Make the cell the box of sizes (x, y, z) [m] with no deformation."""
        size = as_vec3(x) if y is None else np.array([x, y, z], dtype=float)
        if not np.all(size > 0):
            raise ValueError(f"Cell.setBox: sizes must be positive, got {tuple(size)}")
        self.hSize = np.diag(size)
        self._scene.cell_trsf[:] = np.eye(3)

    @property
    def prevHSize(self) -> Matrix3:
        """Base vectors before the last step's deformation [m] (hSize when it was assigned)."""
        return _matrix(self._scene.cell_prev_hsize)

    @property
    def shearTrsf(self) -> Matrix3:
        """The cell's skew and rotation: hSize with unit columns [-]."""
        h = self._scene.cell_hsize
        return _matrix(h / np.linalg.norm(h, axis=0))

    @property
    def unshearTrsf(self) -> Matrix3:
        """Inverse of :attr:`shearTrsf` [-]."""
        return _matrix(np.linalg.inv(np.asarray(self.shearTrsf)))

    @property
    def velGradChanged(self) -> bool:
        """Whether velGrad differs from the gradient of the last step (then bodies get a velocity jump)."""
        s = self._scene
        return not np.array_equal(s.cell_velgrad, s.cell_prev_velgrad)

    @property
    def flipFlippable(self) -> bool:
        """Flip the cell automatically whenever a more compact one is possible: not implemented in granum
        (False; assigning True is refused). Call :meth:`flipCell` from a PyRunner instead."""
        return False

    @flipFlippable.setter
    def flipFlippable(self, value) -> None:
        if value:
            raise NotImplementedError("Cell.flipFlippable=True (automatic flipping at each step) is not implemented "
                                      "in granum; call O.cell.flipCell() from a PyRunner instead")

    def flipCell(self) -> Matrix3:
        """Replace the base vectors by an equivalent, more compact set of the same lattice (the periodic
        images are the same points): each column in turn, x then y then z, loses the lattice vector of the
        two others nearest to its projection on their plane (:func:`flip_matrix`). Returns
        the integer matrix F (new hSize = hSize F); the periodic images of the contacts (cellDist) become
        F^-1 cellDist, so every contact keeps its branch, and the collider runs again. Positions, trsf and
        refHSize are unchanged (YADE's rules, checked on its results)."""
        s = self._scene
        flip = flip_matrix(s.cell_hsize)
        if np.array_equal(flip, np.eye(3)):
            return _matrix(flip)
        inv = np.rint(np.linalg.inv(flip)).astype(np.int64)
        s.cell_hsize[:] = s.cell_hsize @ flip
        s.cell_prev_hsize[:] = s.cell_prev_hsize @ flip
        s.cell_bound_hsize[:] = s.cell_bound_hsize @ flip
        C = s.contacts
        if C.con_i.shape[1] > I_CELL:
            rows = slice(0, int(C.ctr[C_CONTACTS]))
            C.con_i[rows, I_CELL:I_CELL + 3] = C.con_i[rows, I_CELL:I_CELL + 3] @ inv.T
        if C.pair_cell.shape[0]:
            C.pair_cell[:] = C.pair_cell @ inv.T
        s.needs_collider()
        return _matrix(flip)

    @property
    def size(self) -> Vector3:
        """Lengths of the base vectors [m]."""
        return Vector3(*np.linalg.norm(self._scene.cell_hsize, axis=0))

    @property
    def refSize(self) -> Vector3:
        """Lengths of the reference base vectors [m]."""
        return Vector3(*np.linalg.norm(self._scene.cell_ref_hsize, axis=0))

    @refSize.setter
    def refSize(self, value) -> None:
        self.setBox(value)

    @property
    def volume(self) -> float:
        """Volume of the cell [m^3]."""
        return det3(self._scene.cell_hsize)

    # ---- kinematics -------------------------------------------------------------------
    @property
    def velGrad(self) -> Matrix3:
        """Velocity gradient L of the homogeneous deformation [1/s]."""
        return _matrix(self._scene.cell_velgrad)

    @velGrad.setter
    def velGrad(self, value) -> None:
        L = as_mat3(value)
        validate.FINITE_MATRIX.check(L, "Cell.velGrad")
        self._scene.cell_velgrad[:] = L

    nextVelGrad = velGrad

    @property
    def prevVelGrad(self) -> Matrix3:
        """Velocity gradient of the previous step [1/s]."""
        return _matrix(self._scene.cell_prev_velgrad)

    @property
    def trsf(self) -> Matrix3:
        """Deformation gradient F accumulated since it was last reset [-]."""
        return _matrix(self._scene.cell_trsf)

    @trsf.setter
    def trsf(self, value) -> None:
        self._scene.cell_trsf[:] = as_mat3(value)

    @property
    def homoDeform(self) -> int:
        """0: bodies do not follow the cell; 1: velocity jumps when velGrad changes; 2: also convection."""
        from granum.core.arrays import SI_HOMO_DEFORM

        return int(self._scene.iscal[SI_HOMO_DEFORM])

    @homoDeform.setter
    def homoDeform(self, value: int) -> None:
        from granum.core.arrays import SI_HOMO_DEFORM

        validate.HOMO_DEFORM.check(value, "Cell.homoDeform")
        self._scene.iscal[SI_HOMO_DEFORM] = value

    # ---- points ------------------------------------------------------------------------
    def wrap(self, pt) -> Vector3:
        """The image of ``pt`` inside the cell [m]."""
        h = self._scene.cell_hsize
        s = np.linalg.solve(h, as_vec3(pt))
        return Vector3(*(h @ (s - np.floor(s))))

    wrapPt = wrap

    def shearPt(self, pt) -> Vector3:
        """Point of the reference (unsheared) cell mapped to the current cell."""
        return Vector3(*(self._scene.cell_trsf @ as_vec3(pt)))

    def unshearPt(self, pt) -> Vector3:
        """Point of the current cell mapped back to the reference cell."""
        return Vector3(*np.linalg.solve(self._scene.cell_trsf, as_vec3(pt)))

    # ---- strain measures of F = trsf ---------------------------------------------------------
    def getDefGrad(self) -> Matrix3:
        return self.trsf

    def getSmallStrain(self) -> Matrix3:
        """(F + F^T)/2 - 1."""
        F = self._scene.cell_trsf
        return _matrix(0.5 * (F + F.T) - np.eye(3))

    def getRCauchyGreenDef(self) -> Matrix3:
        F = self._scene.cell_trsf
        return _matrix(F.T @ F)

    def getLCauchyGreenDef(self) -> Matrix3:
        F = self._scene.cell_trsf
        return _matrix(F @ F.T)

    def getLagrangianStrain(self) -> Matrix3:
        """(F^T F - 1)/2."""
        F = self._scene.cell_trsf
        return _matrix(0.5 * (F.T @ F - np.eye(3)))

    def getEulerianAlmansiStrain(self) -> Matrix3:
        """(1 - (F F^T)^-1)/2."""
        F = self._scene.cell_trsf
        return _matrix(0.5 * (np.eye(3) - np.linalg.inv(F @ F.T)))

    def getPolarDecOfDefGrad(self):
        """``(R, U)`` with F = R U, R a rotation and U symmetric positive."""
        u, sv, vt = np.linalg.svd(self._scene.cell_trsf)
        return _matrix(u @ vt), _matrix(vt.T @ np.diag(sv) @ vt)

    def getRotation(self) -> Matrix3:
        return self.getPolarDecOfDefGrad()[0]

    def getRightStretch(self) -> Matrix3:
        return self.getPolarDecOfDefGrad()[1]

    def getLeftStretch(self) -> Matrix3:
        R, U = (np.asarray(m) for m in self.getPolarDecOfDefGrad())
        return _matrix(R @ U @ R.T)

    def getSpin(self) -> Vector3:
        """Rotation rate of the velocity gradient: the axial vector of (L - L^T)/2 [rad/s]."""
        w = 0.5 * (self._scene.cell_velgrad - self._scene.cell_velgrad.T)
        return Vector3(w[2, 1], w[0, 2], w[1, 0])

    def __repr__(self):
        return f"<Cell instance at {hex(id(self))}>"
