"""The iDEM solver: an engine-like object that owns rigid bodies of particles and advances them.

    from granum import idem
    s = idem.IDEMSolver(e=0.5, mu=0.3, alpha0=15, dt=5e-4)
    s.add(idem.plane_body((0, 0, 0), (4, 3), 0.25))
    box = s.add(idem.box_body((0, 0, 1.6), (2, 1, 2), 0.25))
    s.run(2000)
    print(s.bodies[box].vel, s.energy())

State is stored as structure-of-arrays (bodies: ``_pos`` (nb, 3), ``_vel``, ``_ang_vel``,
``_ori`` (nb, 4), mass properties; particles: ``_pbody``, ``_r0``, ``_n0``, ``_x``, ``_nw`` ...)
and every step runs compiled (:mod:`granum.idem.stepper`). Material parameters are only the
restitution ``e`` (Stronge, e^2 = W_rel / W_comp) and the friction coefficient ``mu``; ``alpha0``
sets the fraction 1/alpha0 of the velocity removed or released per iteration, ``tol`` when the
iterations stop. See :mod:`granum.idem.impulse` for the algorithm and the choices [A#].
"""

from __future__ import annotations

import math
import time as _time

import numpy as np

from granum._jit import call
from granum.idem import impulse as imp
from granum.idem.bodies import RigidBody
from granum.idem.rigid import rotation_matrix, update_particles, world_inverse_inertia
from granum.idem.stepper import run_steps
from granum.mathtypes import as_vec3

_MODES = {"sequential": imp.SEQUENTIAL, "simultaneous": imp.SIMULTANEOUS}


def _inverse(inertia: np.ndarray) -> np.ndarray:
    """Inverse inertia tensor; the pseudo-inverse when singular (one particle, or particles on a line:
    their lever arms give no torque about the degenerate axes, which then do not rotate)."""
    if np.linalg.cond(inertia) < 1e12:
        return np.linalg.inv(inertia)
    return np.linalg.pinv(inertia, rcond=1e-12, hermitian=True)


def _check(name: str, value):
    """Validated parameter value (ValueError with the admissible range otherwise)."""
    if name == "impact":
        if value not in _MODES:
            raise ValueError(f"iDEM: impact must be one of {sorted(_MODES)}, got {value!r}")
        return value
    if name == "gravity":
        return as_vec3(value)
    if name in ("max_rounds", "max_iter"):
        if int(value) != value or value < 1:
            raise ValueError(f"iDEM: {name} must be a positive integer, got {value}")
        return int(value)
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"iDEM: {name} must be a number, got {value!r}") from None
    if math.isnan(v):
        raise ValueError(f"iDEM: {name} must be a number, got nan")
    if name == "e" and not 0.0 <= v <= 1.0:
        raise ValueError(f"iDEM: the restitution coefficient e must lie in [0, 1], got {v}")
    if name == "mu" and not 0.0 <= v < math.inf:
        raise ValueError(f"iDEM: the friction coefficient mu must be finite and >= 0, got {v}")
    if name in ("alpha0", "dt", "cutoff") and not 0.0 < v < math.inf:
        raise ValueError(f"iDEM: {name} must be finite and > 0, got {v}")
    if name in ("tol", "tie") and not 0.0 < v < 1.0:
        raise ValueError(f"iDEM: {name} must lie in (0, 1), got {v}")
    return v


class IDEMSolver:
    """Impulse-based DEM solver (article: "力積型個別要素法").

    Parameters (all attributes, validated on assignment):

    * ``e`` restitution coefficient in [0, 1]; ``mu`` Coulomb friction coefficient >= 0;
    * ``alpha0`` > 0: each iteration removes (compression) a fraction 1/(alpha0 N_comp) of the
      approach velocity, or releases 1/alpha0 of the velocity change that would give back the
      stored energy (the article uses 15 and 150);
    * ``tol`` in (0, 1): iterations stop when no pair approaches faster than tol x the step's
      fastest approach and no pair stores more than tol x the largest stored energy;
      ``tie`` in (0, 1): relative tolerance of "tied" pairs (N_comp);
    * ``gravity`` (3,) [m/s^2] (default (0, 0, -9.81): g is not given by the article, [A13]), ``dt`` [s];
    * ``cutoff``: contact reach as a fraction of the particle spacing (default 0.8);
    * ``impact``: "sequential" (default) or "simultaneous" (see :mod:`granum.idem.impulse`);
    * ``max_rounds``, ``max_iter``: safeguards of the iteration (reported in ``stats``).
    """

    _PARAMS = ("e", "mu", "alpha0", "tol", "tie", "gravity", "dt", "cutoff", "impact", "max_rounds", "max_iter")

    def __init__(self, e=0.5, mu=0.0, alpha0=15.0, tol=1e-6, tie=1e-6, gravity=(0.0, 0.0, -9.81), dt=5e-4,
                 cutoff=0.8, impact="sequential", max_rounds=1000, max_iter=10_000_000, record=True):
        for name, value in zip(self._PARAMS, (e, mu, alpha0, tol, tie, gravity, dt, cutoff, impact, max_rounds,
                                              max_iter), strict=True):
            setattr(self, name, value)
        self.record = bool(record)
        self.bodies: list[RigidBody] = []
        self.time = 0.0
        self.iter = 0
        self.wall = 0.0  # wall-clock seconds spent in run()
        self.history = np.zeros((0, imp.ST_SIZE))
        self._totals = np.zeros(imp.ST_SIZE)
        self._last = np.zeros(imp.ST_SIZE)
        nb0 = np.zeros((0, 3))
        self._pos, self._vel, self._ang_vel = nb0, nb0.copy(), nb0.copy()
        self._ori = np.zeros((0, 4))
        self._mass = np.zeros(0)
        self._inv_mass = np.zeros(0)
        self._fixed = np.zeros(0, np.bool_)
        self._inertia0 = np.zeros((0, 3, 3))
        self._inv_inertia0 = np.zeros((0, 3, 3))
        self._inv_inertia = np.zeros((0, 3, 3))
        self._pbody = np.zeros(0, np.int64)
        self._r0, self._n0 = nb0.copy(), nb0.copy()
        self._x, self._nw = nb0.copy(), nb0.copy()
        self._pspacing = np.zeros(0)
        self._sigma = np.zeros(0)
        self._surf = np.zeros(0, np.int64)

    def __setattr__(self, name, value):
        if name in self._PARAMS:
            value = _check(name, value)
        object.__setattr__(self, name, value)

    # ------------------------------------------------------------------ bodies
    def add(self, body):
        """Add a :class:`RigidBody` (or a list of them); returns its id (or the list of ids)."""
        if isinstance(body, list | tuple):
            return [self.add(b) for b in body]
        if not isinstance(body, RigidBody):
            raise TypeError(f"iDEM: expected a RigidBody, got {type(body).__name__}")
        if body._solver is not None:
            raise ValueError(f"iDEM: body {body.id} is already in a solver")
        bid = len(self.bodies)
        own = body._own

        def cat(a, row):
            return np.ascontiguousarray(np.concatenate([a, np.asarray(row)[None]]))

        self._pos = cat(self._pos, own["pos"])
        self._vel = cat(self._vel, own["vel"])
        self._ang_vel = cat(self._ang_vel, own["ang_vel"])
        self._ori = cat(self._ori, own["ori"])
        self._mass = cat(self._mass, body.mass)
        self._inv_mass = cat(self._inv_mass, 0.0 if body.fixed else 1.0 / body.mass)
        self._fixed = cat(self._fixed, body.fixed)
        self._inertia0 = cat(self._inertia0, body.inertia0)
        self._inv_inertia0 = cat(self._inv_inertia0, np.zeros((3, 3)) if body.fixed else _inverse(body.inertia0))
        self._inv_inertia = cat(self._inv_inertia, np.zeros((3, 3)))
        n = body.nParticles
        first = len(self._pbody)
        self._pbody = np.concatenate([self._pbody, np.full(n, bid, np.int64)])
        self._r0 = np.ascontiguousarray(np.concatenate([self._r0, body.r0]))
        self._n0 = np.ascontiguousarray(np.concatenate([self._n0, body.n0]))
        self._pspacing = np.concatenate([self._pspacing, np.full(n, body.spacing)])
        self._sigma = np.concatenate([self._sigma, body.sigma])
        self._surf = np.concatenate([self._surf, first + np.nonzero(body.surface)[0]]).astype(np.int64)
        self._x = np.zeros_like(self._r0)
        self._nw = np.zeros_like(self._r0)
        body._solver = self
        body.id = bid
        self.bodies.append(body)
        self._geometry_changed()
        return bid

    def _geometry_changed(self):
        """Recompute the world-frame particles and inverse inertia after positions were set."""
        call(update_particles, self._pbody, self._pos, self._ori, self._r0, self._n0, self._x, self._nw)
        call(world_inverse_inertia, self._fixed, self._ori, self._inv_inertia0, self._inv_inertia)

    # ------------------------------------------------------------------ running
    def step(self):
        """Advance by one time step."""
        self.run(1)

    def run(self, nsteps: int, callback=None, every: int | None = None):
        """Advance by ``nsteps`` steps; with ``callback`` call ``callback(self)`` every ``every`` steps
        (default: once at the end)."""
        nsteps = int(nsteps)
        if nsteps < 0:
            raise ValueError(f"iDEM: nsteps must be >= 0, got {nsteps}")
        if every is not None and int(every) < 1:
            raise ValueError(f"iDEM: every must be >= 1, got {every}")
        chunk = nsteps if every is None else int(every)
        done = 0
        while done < nsteps:
            k = min(chunk, nsteps - done)
            self._run_compiled(k)
            done += k
            if callback is not None:
                callback(self)

    def _run_compiled(self, k: int):
        self._geometry_changed()  # positions or orientations may have been edited through the views
        t0 = _time.perf_counter()
        st = call(run_steps, k, self.dt, np.asarray(self.gravity, float), self.e, self.mu, self.alpha0, self.tol,
                  self.tie, _MODES[self.impact], self.max_rounds, self.max_iter, self.cutoff, self._fixed,
                  self._pos, self._vel, self._ang_vel, self._ori, self._inv_mass, self._inertia0,
                  self._inv_inertia0, self._inv_inertia, self._pbody, self._surf, self._r0, self._n0,
                  self._pspacing, self._sigma, self._x, self._nw)
        self.wall += _time.perf_counter() - t0
        self.iter += k
        self.time += k * self.dt
        if k:
            self._last = st[-1].copy()
            capped = int(self._totals[imp.ST_CAPPED]) | int(np.bitwise_or.reduce(st[:, imp.ST_CAPPED].astype(int)))
            self._totals += st.sum(axis=0)
            self._totals[imp.ST_CAPPED] = capped  # bit flags, not a count
        if self.record:
            self.history = np.concatenate([self.history, st])

    # ------------------------------------------------------------------ diagnostics
    @property
    def stats(self) -> dict:
        """Counters of the last step: contacts, rounds, compression/release iterations, impulses,
        the works [J] (compression, released, residual, friction, overshoot) and ``capped`` (bit
        flags: 1 the round limit was reached, 2 the iteration limit)."""
        return _stats_dict(self._last)

    @property
    def totals(self) -> dict:
        """The same counters summed over all steps run so far."""
        return _stats_dict(self._totals)

    def _spin(self, b: int) -> np.ndarray:
        """Angular momentum of body ``b`` about its centre, R I0 R^T w (3,) [kg m^2/s]."""
        R = np.empty((3, 3))
        call(rotation_matrix, tuple(float(c) for c in self._ori[b]), R)
        return R @ self._inertia0[b] @ R.T @ self._ang_vel[b]

    def kinetic(self) -> float:
        """Kinetic energy sum 1/2 M V^2 + 1/2 w.I w of the free bodies [J]."""
        free = ~self._fixed
        ke = 0.5 * float((self._mass[free] * (self._vel[free] ** 2).sum(axis=1)).sum())
        for b in np.nonzero(free & np.any(self._ang_vel != 0.0, axis=1))[0]:
            ke += 0.5 * float(self._ang_vel[b] @ self._spin(b))
        return ke

    def potential(self) -> float:
        """Gravitational potential energy -sum M g.X of the free bodies [J] (zero at the origin)."""
        free = ~self._fixed
        return -float((self._mass[free] * (self._pos[free] @ np.asarray(self.gravity, float))).sum())

    def momentum(self) -> np.ndarray:
        """Total linear momentum sum M V of the free bodies (3,) [kg m/s]."""
        free = ~self._fixed
        return (self._mass[free, None] * self._vel[free]).sum(axis=0)

    def angular_momentum(self) -> np.ndarray:
        """Total angular momentum about the origin sum (X x M V + I w) of the free bodies (3,) [kg m^2/s]."""
        out = np.zeros(3)
        for b in np.nonzero(~self._fixed)[0]:
            out += np.cross(self._pos[b], self._mass[b] * self._vel[b]) + self._spin(b)
        return out

    def energy(self) -> dict:
        """Energies [J]: kinetic, potential, their sum, and the contact works accumulated so far:
        ``compression`` (normal W_comp stored), ``released`` (normal W_rel given back),
        ``dissipated`` (compression - released: (1 - e^2) W_comp plus the unreleased residual) and
        ``friction`` (energy removed by the tangential impulses)."""
        t = self._totals
        ke, pe = self.kinetic(), self.potential()
        comp, rel, fric = float(t[imp.ST_W_COMP]), float(t[imp.ST_W_REL]), float(t[imp.ST_FRICTION])
        return {"kinetic": ke, "potential": pe, "total": ke + pe, "compression": comp, "released": rel,
                "dissipated": comp - rel, "friction": 0.0 - fric}

    def iterations(self) -> np.ndarray:
        """Iterations (compression + release) of every recorded step, shape (steps,)."""
        return self.history[:, imp.ST_COMP_ITERS] + self.history[:, imp.ST_REL_ITERS]


_NAMES = {"contacts": imp.ST_CONTACTS, "rounds": imp.ST_ROUNDS, "compression_iterations": imp.ST_COMP_ITERS,
          "release_iterations": imp.ST_REL_ITERS, "impulses": imp.ST_IMPULSES, "W_comp": imp.ST_W_COMP,
          "W_rel": imp.ST_W_REL, "residual": imp.ST_RESIDUAL, "friction_work": imp.ST_FRICTION,
          "overshoot": imp.ST_OVERSHOOT, "capped": imp.ST_CAPPED}


def _stats_dict(a: np.ndarray) -> dict:
    return {name: (float(a[i]) if name.startswith(("W_", "residual", "friction", "overshoot")) else int(a[i]))
            for name, i in _NAMES.items()}
