"""Rigid bodies of particles for iDEM, and their builders.

A :class:`RigidBody` is a set of particles (point masses, article §2) rigidly attached to a
body frame, with one outward unit normal per surface particle (article §3, computed by PCA
unless given). Builders:

* :func:`box_body` - a cuboid lattice of particles (surface and interior);
* :func:`plane_body` - a fixed flat sheet of particles with a given normal (floor, slope);
* :func:`body_from_particles` - any particle set, with masses or a density.

Like ``utils.sphere`` in YADE, a builder returns a body that owns its state; once added to an
:class:`~granum.idem.solver.IDEMSolver` the same object becomes a view: ``b.pos``, ``b.vel``,
``b.angVel`` and ``b.ori`` read and write the solver's arrays (a :class:`~granum.mathtypes.Vector3`
obtained before another body is added refers to the old arrays; fetch it again).
"""

from __future__ import annotations

import numpy as np

from granum._jit import call
from granum.idem.pca import detect_surface, nearest_distances, surface_normals
from granum.idem.rigid import mass_properties, rotation_matrix
from granum.mathtypes import Matrix3, Quaternion, Vector3, as_quat_wxyz, as_vec3

#: default neighbourhood radius of the PCA normals, in particle spacings ([A2])
NORMAL_RADIUS = 1.2


def _rotation(q: np.ndarray) -> np.ndarray:
    R = np.empty((3, 3))
    call(rotation_matrix, (float(q[0]), float(q[1]), float(q[2]), float(q[3])), R)
    return R


def _quat(ori) -> np.ndarray:
    """(w, x, y, z) array from None (identity), a Quaternion or an (axis, angle) pair."""
    if ori is None:
        return np.array([1.0, 0.0, 0.0, 0.0])
    q = as_quat_wxyz(ori)
    return q / np.linalg.norm(q)


class RigidBody:
    """A rigid body made of particles (see the module docstring).

    Body-frame particle data (read-only arrays): ``r0`` (n, 3) positions relative to the centre
    of mass [m], ``n0`` (n, 3) outward unit normals (zero for interior particles), ``masses``
    (n,) [kg], ``surface`` (n,) bool, ``sigma`` (n,) surface variation, ``spacing`` [m].
    """

    def __init__(self, r0, masses, n0, sigma, surface, spacing, fixed, pos, ori, mass, inertia0):
        self.r0 = np.ascontiguousarray(r0, dtype=np.float64)
        self.masses = np.ascontiguousarray(masses, dtype=np.float64)
        self.n0 = np.ascontiguousarray(n0, dtype=np.float64)
        self.sigma = np.ascontiguousarray(sigma, dtype=np.float64)
        self.surface = np.ascontiguousarray(surface, dtype=np.bool_)
        self.spacing = float(spacing)
        self.fixed = bool(fixed)
        self.mass = float(mass)
        self.inertia0 = np.ascontiguousarray(inertia0, dtype=np.float64)
        for arr in (self.r0, self.masses, self.n0, self.sigma, self.surface, self.inertia0):
            arr.flags.writeable = False
        self._own = {"pos": as_vec3(pos), "vel": np.zeros(3), "ang_vel": np.zeros(3), "ori": np.array(ori, float)}
        self._solver = None
        self.id = -1

    def _row(self, name: str) -> np.ndarray:
        if self._solver is None:
            return self._own[name]
        return getattr(self._solver, "_" + name)[self.id]

    @property
    def pos(self) -> Vector3:
        """Centre of mass X [m] (view)."""
        return Vector3._wrap(self._row("pos"))

    @pos.setter
    def pos(self, value):
        self._row("pos")[:] = as_vec3(value)
        self._moved()

    @property
    def vel(self) -> Vector3:
        """Translational velocity V [m/s] (view)."""
        return Vector3._wrap(self._row("vel"))

    @vel.setter
    def vel(self, value):
        self._row("vel")[:] = as_vec3(value)

    @property
    def angVel(self) -> Vector3:
        """Angular velocity w [rad/s], world frame (view)."""
        return Vector3._wrap(self._row("ang_vel"))

    @angVel.setter
    def angVel(self, value):
        self._row("ang_vel")[:] = as_vec3(value)

    @property
    def ori(self) -> Quaternion:
        """Orientation, body frame to world frame (view)."""
        return Quaternion._wrap(self._row("ori"))

    @ori.setter
    def ori(self, value):
        self._row("ori")[:] = _quat(value)
        self._moved()

    def _moved(self):
        if self._solver is not None:
            self._solver._geometry_changed()

    @property
    def nParticles(self) -> int:
        return self.r0.shape[0]

    @property
    def inertia(self) -> Matrix3:
        """Inertia tensor about the centre of mass in the world frame, R I0 R^T [kg m^2] (a copy)."""
        R = _rotation(self._row("ori"))
        return Matrix3(R @ self.inertia0 @ R.T)

    def particles(self) -> np.ndarray:
        """World positions of the particles (n, 3) [m] (a copy)."""
        return self._row("pos") + self.r0 @ _rotation(self._row("ori")).T

    def normals(self) -> np.ndarray:
        """World-frame outward normals of the particles (n, 3) (a copy)."""
        return self.n0 @ _rotation(self._row("ori")).T

    def __repr__(self) -> str:
        kind = "fixed " if self.fixed else ""
        return f"<RigidBody {self.id} {kind}{self.nParticles} particles, mass {self.mass:g} kg>"


def _make_body(local, masses, normals, surface, spacing, fixed, center, ori, com_local=None, normal_radius=None):
    """Body from particle positions in its own frame; normals given (n, 3) or None for PCA."""
    local = np.asarray(local, dtype=np.float64)
    n = local.shape[0]
    mass, com, inertia = mass_properties(local, masses)
    if com_local is not None:  # exact centre known by symmetry (avoids round-off in touching bodies)
        com = np.asarray(com_local, dtype=np.float64)
        r = local - com
        inertia = (np.eye(3) * float((masses * (r * r).sum(axis=1)).sum())
                   - np.einsum("i,ij,ik->jk", masses, r, r))
    r0 = local - com
    if normals is None:
        ns = int(surface.sum())
        if ns < 4:
            raise ValueError(f"iDEM: computing surface normals by PCA needs at least 4 surface particles per body, "
                             f"got {ns}; give the normals explicitly (normals=...)")
        radius = (normal_radius if normal_radius is not None else NORMAL_RADIUS * spacing)
        if not radius > 0:
            raise ValueError(f"iDEM: normal_radius must be > 0, got {radius}")
        n0 = np.zeros((n, 3))
        sigma = np.zeros(n)
        call(surface_normals, np.ascontiguousarray(r0), np.ascontiguousarray(surface), float(radius), np.zeros(3),
             n0, sigma)
    else:
        n0 = np.array(normals, dtype=np.float64)
        if n0.shape != (n, 3):
            raise ValueError(f"iDEM: normals must have shape ({n}, 3), got {n0.shape}")
        length = np.linalg.norm(n0, axis=1)
        if np.any(length[surface] == 0) or not np.all(np.isfinite(n0)):
            raise ValueError("iDEM: every surface particle needs a finite, non-zero normal")
        n0[surface] /= length[surface, None]
        n0[~surface] = 0.0
        sigma = np.where(surface, 0.0, 1.0 / 3.0)  # given normals are trusted as flat
    q = _quat(ori)
    pos = np.asarray(center, dtype=np.float64) + _rotation(q) @ com
    return RigidBody(r0, masses, n0, sigma, surface, spacing, fixed, pos, q, mass, inertia)


def _check_positive(name, value):
    if not (np.isfinite(value) and value > 0):
        raise ValueError(f"iDEM: {name} must be a finite number > 0, got {value}")


def box_body(center, size, spacing, density=1000.0, mass=None, ori=None, fixed=False, normals=None,
             normal_radius=None) -> RigidBody:
    """A cuboid of ``size`` (3,) [m] filled with a lattice of particles, centred at ``center`` [m].

    Each axis gets n = round(size / spacing) + 1 >= 2 particles at exactly symmetric positions
    (the actual step size / (n - 1) may differ slightly from ``spacing``). Total ``mass`` [kg], or
    ``density`` [kg/m^3] x volume, shared equally by the particles (point masses: the lattice
    inertia is that of the particles, slightly above the continuous box's, article §2).
    ``ori``: Quaternion or (axis, angle) of the box frame. Normals: PCA of the surface lattice
    (``normals=None``, needs >= 4 surface particles) or an (n, 3) array in the box frame.
    """
    size = np.asarray(size, dtype=np.float64)
    if size.shape != (3,):
        raise ValueError(f"iDEM: box size must have 3 components, got {size.shape}")
    for k in range(3):
        _check_positive("box size", size[k])
    _check_positive("spacing", spacing)
    counts = [max(2, int(round(size[k] / spacing)) + 1) for k in range(3)]
    steps = [size[k] / (counts[k] - 1) for k in range(3)]
    axes = [(np.arange(counts[k]) - 0.5 * (counts[k] - 1)) * steps[k] for k in range(3)]
    idx = np.stack(np.meshgrid(*[np.arange(c) for c in counts], indexing="ij"), axis=-1).reshape(-1, 3)
    local = np.stack([axes[k][idx[:, k]] for k in range(3)], axis=1)
    surface = np.zeros(len(local), bool)
    for k in range(3):
        surface |= (idx[:, k] == 0) | (idx[:, k] == counts[k] - 1)
    if mass is None:
        _check_positive("density", density)
        mass = density * float(np.prod(size))
    _check_positive("mass", mass)
    masses = np.full(len(local), mass / len(local))
    return _make_body(local, masses, normals, surface, max(steps), fixed, center, ori, com_local=np.zeros(3),
                      normal_radius=normal_radius)


def plane_body(center, size, spacing, ori=None) -> RigidBody:
    """A fixed flat sheet of particles (floor, slope) of ``size`` (2,) [m] in its local x-y plane.

    Its normal is the local +z axis rotated by ``ori`` (given, not computed: a single sheet has
    no inside to orient a PCA normal). The particles are at exactly symmetric lattice positions.
    """
    size = np.asarray(size, dtype=np.float64)
    if size.shape != (2,):
        raise ValueError(f"iDEM: plane size must have 2 components, got {size.shape}")
    for k in range(2):
        _check_positive("plane size", size[k])
    _check_positive("spacing", spacing)
    counts = [max(2, int(round(size[k] / spacing)) + 1) for k in range(2)]
    steps = [size[k] / (counts[k] - 1) for k in range(2)]
    gx, gy = np.meshgrid((np.arange(counts[0]) - 0.5 * (counts[0] - 1)) * steps[0],
                         (np.arange(counts[1]) - 0.5 * (counts[1] - 1)) * steps[1], indexing="ij")
    local = np.stack([gx.ravel(), gy.ravel(), np.zeros(gx.size)], axis=1)
    normals = np.tile([0.0, 0.0, 1.0], (len(local), 1))
    masses = np.ones(len(local))  # irrelevant: the plane is fixed
    return _make_body(local, masses, normals, np.ones(len(local), bool), max(steps), True, center, ori,
                      com_local=np.zeros(3))


def body_from_particles(points, masses=None, density=None, normals=None, surface=None, spacing=None, fixed=False,
                        normal_radius=None) -> RigidBody:
    """A rigid body from any particle set ``points`` (n, 3) [m], given in the world frame.

    Mass: ``masses`` (a number for every particle, or (n,)) [kg], or ``density`` [kg/m^3] with
    a volume spacing^3 per particle (default density 1000). ``spacing`` [m]: the particle size
    used by the contact cut-off and the PCA neighbourhood; default the median nearest-neighbour
    distance. ``surface``: None (every particle is a surface particle, e.g. a shell), ``"auto"``
    (a volume-filling cloud: particles with a one-sided neighbourhood) or an (n,) bool mask.
    ``normals``: None (PCA, needs >= 4 surface particles) or (n, 3) outward normals.
    The body frame is the world frame at creation; the orientation starts at identity.
    """
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != 3 or len(pts) == 0:
        raise ValueError(f"iDEM: points must be an (n, 3) array with n >= 1, got shape {pts.shape}")
    if not np.all(np.isfinite(pts)):
        raise ValueError("iDEM: points must be finite")
    n = len(pts)
    if spacing is None:
        if n < 2:
            raise ValueError("iDEM: a single particle needs an explicit spacing")
        spacing = float(np.median(call(nearest_distances, np.ascontiguousarray(pts))))
    _check_positive("spacing", spacing)
    if masses is not None and density is not None:
        raise ValueError("iDEM: give masses or density, not both")
    if masses is None:
        density = 1000.0 if density is None else density
        _check_positive("density", density)
        m = np.full(n, density * spacing ** 3)
    else:
        m = np.broadcast_to(np.asarray(masses, dtype=np.float64), (n,)).copy()
        if not np.all(np.isfinite(m)) or np.any(m <= 0):
            raise ValueError("iDEM: particle masses must be finite and > 0")
    if surface is None:
        surf = np.ones(n, bool)
    elif isinstance(surface, str):
        if surface != "auto":
            raise ValueError(f"iDEM: surface must be None, 'auto' or a mask, got {surface!r}")
        radius = normal_radius if normal_radius is not None else NORMAL_RADIUS * spacing
        surf = np.asarray(call(detect_surface, np.ascontiguousarray(pts), float(radius)), bool)
    else:
        surf = np.asarray(surface, dtype=bool)
        if surf.shape != (n,):
            raise ValueError(f"iDEM: surface mask must have shape ({n},), got {surf.shape}")
    return _make_body(pts, m, normals, surf, spacing, fixed, np.zeros(3), None, normal_radius=normal_radius)
