"""SpheresFactory, CircularFactory and BoxFactory: spheres made at a mass flow rate in a region (YADE's engines
of the same names; the rules are in :mod:`granum.kernels.factory`).

The compiled stage meters the flow each step; only in a step where spheres are due does the engine's hook run
(after that step, or, in a step that runs Python engines, after the compiled segment holding the factory, so
that a PyRunner after it sees the new spheres as in YADE): one compiled call places all of them, and they are
appended to the scene's arrays at once. YADE makes them inside the step, at the engine's place in the list: an
engine placed before NewtonIntegrator moves its new spheres in that same step in YADE, in the next one in
granum. The new bodies are born at the step that made them (``iterBorn``, as YADE's).

``vAngle`` has no effect in YADE 2023.02a (every velocity is along ``normalVel``, or ``normal``): granum accepts
NaN (the default) and 0 and refuses other values. The speed is drawn once per step for all the spheres of that
step, as YADE does. The random numbers are granum's (YADE seeds its own from the clock): ``seed`` (granum's, not
YADE's) fixes them; the default, -1, takes a seed from the operating system.
"""

from __future__ import annotations

import math
import sys

import numpy as np

from granum._jit import call
from granum.core.attrs import Attr, as_number, to_bool, to_float, to_int, to_str
from granum.core.bodies import dofs_from_string
from granum.core.shapes import ShapeKind
from granum.engines.base import GlobalEngine
from granum.engines.pipeline import to_vec3
from granum.kernels import factory as k
from granum.mathtypes import Vector3, as_vec3
from granum.physics import registry

_NAN3 = Vector3(math.nan, math.nan, math.nan)


def _floats(name: str):
    def convert(owner, value):
        return [as_number(x, f"{type(owner).__name__}.{name}") for x in value]

    return convert


def _v_angle(owner, value):
    x = as_number(value, f"{type(owner).__name__}.vAngle")
    if not (math.isnan(x) or x == 0.0):
        raise NotImplementedError(f"{type(owner).__name__}.vAngle={x!r}: YADE 2023.02a gives every sphere the "
                                  f"velocity along the normal whatever vAngle is; granum accepts only NaN or 0 "
                                  f"rather than ignore it")
    return x


def _seed(owner, value):
    n = int(as_number(value, f"{type(owner).__name__}.seed"))
    if n < -1 or n >= 2 ** 64:
        raise ValueError(f"{type(owner).__name__}.seed must be -1 (from the operating system) or in [0, 2**64), "
                         f"got {value!r}")
    return n


class SpheresFactory(GlobalEngine):
    """Spheres made at ``massFlowRate`` [kg/s] in a region defined by a subclass (CircularFactory,
    BoxFactory); see the module's docstring and :mod:`granum.kernels.factory`."""

    stage = "granum.kernels.factory:factory_stage"
    adds_bodies = True
    _attrs = {
        "massFlowRate": Attr(math.nan, "Mass flow rate [kg/s]", to_float("massFlowRate")),
        "rMin": Attr(math.nan, "Smallest radius (uniform distribution) [m]", to_float("rMin")),
        "rMax": Attr(math.nan, "Largest radius (uniform distribution) [m]", to_float("rMax")),
        "vMin": Attr(math.nan, "Smallest speed (uniform distribution) [m/s]", to_float("vMin")),
        "vMax": Attr(math.nan, "Largest speed (uniform distribution) [m/s]", to_float("vMax")),
        "vAngle": Attr(math.nan, "No effect in YADE 2023.02a; only NaN or 0 accepted [rad]", _v_angle),
        "normal": Attr(_NAN3, "Orientation of the region; direction of the velocities without normalVel",
                       to_vec3),
        "normalVel": Attr(_NAN3, "Direction of the velocities (NaN: normal)", to_vec3),
        "materialId": Attr(-1, "Index in O.materials of the spheres' material (negative: from the end)",
                           to_int("materialId")),
        "mask": Attr(-1, "groupMask of the new spheres (-1: the default, 1)", to_int("mask")),
        "color": Attr(Vector3(-1, -1, -1), "Colour of the new spheres (-1, -1, -1: the default, white)", to_vec3),
        "ids": Attr([], "Ids of the spheres made", lambda o, v: [int(i) for i in v]),
        "totalMass": Attr(0.0, "Mass of the spheres made so far [kg]", to_float("totalMass")),
        "totalVolume": Attr(0.0, "Volume of the spheres made so far [m^3]", to_float("totalVolume")),
        "maxParticles": Attr(100, "No more spheres after this many (-1: no limit)", to_int("maxParticles")),
        "maxMass": Attr(-1.0, "No more spheres once this mass is made [kg] (-1: no limit)", to_float("maxMass")),
        "numParticles": Attr(0, "Number of spheres made so far", to_int("numParticles")),
        "maxAttempt": Attr(5000, "Draws of a centre before a sphere is given up", to_int("maxAttempt", 1)),
        "silent": Attr(False, "No warning when a sphere is given up", to_bool),
        "blockedDOFs": Attr("", "Blocked degrees of freedom of the new spheres ('xyzXYZ')", to_str("blockedDOFs")),
        "PSDsizes": Attr([], "Diameters of the PSD's classes [m]", _floats("PSDsizes")),
        "PSDcum": Attr([], "Cumulative shares of the PSD's classes [-]", _floats("PSDcum")),
        "PSDcalculateMass": Attr(True, "PSD shares by mass (True) or by count", to_bool),
        "stopIfFailed": Attr(True, "massFlowRate = 0 when a sphere is given up", to_bool),
        "exactDiam": Attr(True, "Diameters exactly PSDsizes (else uniform between two sizes)", to_bool),
        "seed": Attr(-1, "granum's: seed of the random numbers (-1: from the operating system)", _seed),
    }

    @property
    def goalMass(self) -> float:
        """Mass that should be made by the end of the current step [kg] (grows by massFlowRate * dt)."""
        return float(self._state[k.ST_GOAL])

    @goalMass.setter
    def goalMass(self, value) -> None:
        self._state[k.ST_GOAL] = as_number(value, f"{type(self).__name__}.goalMass")

    def __init__(self, **kw):
        object.__setattr__(self, "_state", np.zeros(k.ST_SIZE))
        object.__setattr__(self, "_rng", np.zeros(1, np.uint64))
        object.__setattr__(self, "_psd_done", np.zeros(0))
        super().__init__(**kw)
        if self.seed < 0:
            self._rng[0] = np.random.SeedSequence().generate_state(1, np.uint64)[0]

    def _changed(self, name: str) -> None:
        if name == "seed" and self.seed >= 0:
            self._rng[0] = np.uint64(self.seed)

    # ---- the region, defined by the subclasses ----------------------------------------------------------
    def region(self) -> tuple[int, np.ndarray, np.ndarray, np.ndarray]:
        """(kind, center (3,), frame (3, 3): the unit normal and two unit vectors across it, size (3,))."""
        raise NotImplementedError("SpheresFactory has no region: use CircularFactory or BoxFactory")

    def _unit(self, name: str) -> np.ndarray:
        v = as_vec3(getattr(self, name))
        n = float(np.linalg.norm(v))
        if not (math.isfinite(n) and n > 0):
            raise ValueError(f"{type(self).__name__}.{name} must be a finite non-zero vector, got {tuple(v)}")
        return v / n

    def _finite(self, name: str, positive: bool = False) -> float:
        x = getattr(self, name)
        if not math.isfinite(x) or (positive and not x > 0) or x < 0:
            need = "positive" if positive else "finite and not negative"
            raise ValueError(f"{type(self).__name__}.{name} must be {need}, got {x!r}")
        return x

    def _frame(self) -> np.ndarray:
        """The unit normal and two unit vectors across it, as rows."""
        n = self._unit("normal")
        a = np.eye(3)[int(np.argmin(np.abs(n)))]
        e1 = np.cross(n, a)
        e1 /= np.linalg.norm(e1)
        return np.array([n, e1, np.cross(n, e1)])

    def _center(self) -> np.ndarray:
        c = as_vec3(self.center)
        if not np.isfinite(c).all():
            raise ValueError(f"{type(self).__name__}.center must be finite, got {tuple(c)}")
        return c

    # ---- checks made before a run -----------------------------------------------------------------------
    def _sizes(self) -> tuple[float, float, np.ndarray, np.ndarray]:
        """(rMin, rMax, PSD sizes, PSD cumulative shares), checked."""
        name = type(self).__name__
        sizes, cum = np.array(self.PSDsizes, float), np.array(self.PSDcum, float)
        if len(cum) == 0:
            if len(sizes):
                raise ValueError(f"{name}: PSDsizes given without PSDcum")
            r_min, r_max = self._finite("rMin", True), self._finite("rMax", True)
            if r_min > r_max:
                raise ValueError(f"{name}: rMin ({r_min}) is larger than rMax ({r_max})")
            return r_min, r_max, sizes, cum
        want = len(cum) if self.exactDiam else len(cum) + 1
        if len(sizes) != want:
            raise ValueError(f"{name}: {len(sizes)} PSDsizes for {len(cum)} PSDcum; exactDiam={self.exactDiam} "
                             f"needs {want}")
        if not (np.isfinite(sizes).all() and (sizes > 0).all()):
            raise ValueError(f"{name}.PSDsizes must be positive diameters, got {list(sizes)}")
        if not (np.isfinite(cum).all() and (cum > 0).all() and (np.diff(cum) >= 0).all() and cum[-1] <= 1.0):
            raise ValueError(f"{name}.PSDcum must increase within (0, 1], got {list(cum)}")
        if not self.exactDiam and not (np.diff(sizes) > 0).all():
            raise ValueError(f"{name}.PSDsizes must increase when exactDiam is False, got {list(sizes)}")
        if len(self._psd_done) != len(cum):
            object.__setattr__(self, "_psd_done", np.zeros(len(cum)))
        return math.nan, math.nan, sizes, cum

    def params(self, scene, engines):
        rate = self.massFlowRate
        if not (math.isfinite(rate) and rate >= 0):
            raise ValueError(f"{type(self).__name__}.massFlowRate must be finite and not negative, got {rate!r}")
        self.region()
        self._sizes()
        if self._finite("vMin") > self._finite("vMax"):
            raise ValueError(f"{type(self).__name__}: vMin ({self.vMin}) is larger than vMax ({self.vMax})")
        self._velocity_direction()
        return k.FactoryParams(state=self._state, rate=float(rate), total_mass=float(self.totalMass),
                               num=int(self.numParticles), max_particles=int(self.maxParticles),
                               max_mass=float(self.maxMass), hook_id=self._plan_index)

    def _velocity_direction(self) -> np.ndarray:
        if np.isnan(as_vec3(self.normalVel)).all():
            return self._unit("normal")
        return self._unit("normalVel")

    def _material(self, omega):
        n = len(omega.materials)
        i = self.materialId + n if self.materialId < 0 else self.materialId
        if not 0 <= i < n:
            raise ValueError(f"{type(self).__name__}.materialId={self.materialId}: O.materials has {n} "
                             f"material(s)")
        mat = omega.materials[i]
        density = getattr(mat, "density", None)
        if density is None or not density > 0:
            raise ValueError(f"{type(self).__name__}: material {i} ({type(mat).__name__}) has no positive density")
        if "CpmMat" in registry.material_ancestry(mat.kind):
            raise NotImplementedError(f"{type(self).__name__}: spheres of a CpmMat (CpmState) are not made by "
                                      f"granum's factories yet")
        return mat, float(density)

    # ---- the hook: make the spheres due -----------------------------------------------------------------
    def hook_due(self) -> bool:
        return bool(self._state[k.ST_DUE])

    def run_hook(self, omega) -> None:
        """Place the spheres due in one compiled call and append them to the scene (once per step: the runner
        may call it after the step's segment and again at the step's end)."""
        if not self._state[k.ST_DUE]:
            return
        self._state[k.ST_DUE] = 0.0
        scene = omega._scene
        kind, center, frame, size = self.region()
        r_min, r_max, psd_sizes, psd_cum = self._sizes()
        mat, density = self._material(omega)
        blocked = dofs_from_string(self.blockedDOFs)
        r_big = 0.5 * float(psd_sizes.max()) if len(psd_cum) else r_max
        sph_pos, sph_r, box_lo, box_hi = call(k.factory_obstacles, scene.arrays(), kind, center, size, r_big)
        speed = self.vMin + call(k.uniform, self._rng) * (self.vMax - self.vMin)
        vel = speed * self._velocity_direction()
        r_small = 0.5 * float(psd_sizes.min()) if len(psd_cum) else r_min
        due = (self.goalMass - self.totalMass) / (density * 4.0 / 3.0 * math.pi * r_small ** 3) + 1
        if self.maxParticles >= 0:
            due = min(due, self.maxParticles - self.numParticles)
        cap = int(max(1, min(due, 100_000)))
        new_pos, new_r = np.empty((cap, 3)), np.empty(cap)
        while True:
            n, failed = call(k.factory_place, self._rng, kind, center, frame, size, r_min, r_max, psd_sizes,
                             psd_cum, self._psd_done, bool(self.PSDcalculateMass), bool(self.exactDiam), density,
                             self.goalMass, float(self.totalMass), int(self.numParticles), int(self.maxParticles),
                             float(self.maxMass), int(self.maxAttempt), sph_pos, sph_r, box_lo, box_hi, new_pos,
                             new_r)
            self._append(scene, mat, new_pos[:n], new_r[:n], vel, blocked)
            if failed:
                if not self.silent:
                    print(f"WARNING {type(self).__name__}: Unable to place new sphere after {self.maxAttempt} "
                          f"attempts!", file=sys.stderr)
                if self.stopIfFailed:   # YADE's: the flow stops and the goal falls back to the mass made
                    self.massFlowRate = 0.0
                    self.goalMass = self.totalMass
                return
            if n < cap:
                return
            sph_pos = np.concatenate([sph_pos, new_pos[:n]])  # the next batch must avoid this one too
            sph_r = np.concatenate([sph_r, new_r[:n]])

    def _append(self, scene, mat, pos, r, vel, blocked) -> None:
        """Append spheres (n, 3)/(n,) [m] of material ``mat`` moving at ``vel`` [m/s], born at the last step."""
        n = len(r)
        if not n:
            return
        spheres = scene.shapes[ShapeKind.SPHERE]
        density = float(mat.density)
        m = density * 4.0 / 3.0 * math.pi * r ** 3     # as granum.core.shapes's sphere mass
        mat_row = scene.material_index(mat)
        row = spheres.append_rows(n)
        spheres.radius[row:row + n] = r
        b = scene.bodies
        first = b.append_rows(n)
        ids = np.arange(first, first + n)
        b.pos[ids] = pos
        b.ref_pos[ids] = pos
        b.vel[ids] = vel
        b.mass[ids] = m
        b.inertia[ids] = (0.4 * m * r * r)[:, None]
        b.blocked[ids] = blocked
        b.shape_kind[ids] = ShapeKind.SPHERE
        b.shape_row[ids] = np.arange(row, row + n)
        b.material[ids] = mat_row
        b.mask[ids] = 1 if self.mask == -1 else self.mask
        if not (as_vec3(self.color) == -1).all():
            b.color[ids] = as_vec3(self.color)
        b.clump_id[ids] = -1
        b.alive[ids] = True
        born = scene.born.append_rows(n)
        scene.born.iter[born:born + n] = scene.iter - 1     # the step that made them (the hook runs after it)
        scene.born.time[born:born + n] = scene.time - scene.dt
        scene.bodies_appended()
        self.ids.extend(ids.tolist())
        self.numParticles += n
        total = float(self.totalMass)
        for x in m.tolist():                              # in order, as the placement summed them
            total += x
        self.totalMass = total
        self.totalVolume += float((4.0 / 3.0 * math.pi * r ** 3).sum())


class CircularFactory(SpheresFactory):
    """A SpheresFactory whose region is a disk (``length`` 0) or a cylinder of ``radius`` about ``center``,
    normal to ``normal``; sphere centres lie within ``radius - r`` of the axis and ``length / 2`` of the
    disk's plane."""

    _attrs = {
        "radius": Attr(math.nan, "Radius of the region [m]", to_float("radius")),
        "length": Attr(0.0, "Length of the cylindrical region along the normal [m]", to_float("length")),
        "center": Attr(_NAN3, "Centre of the region [m]", to_vec3),
    }

    def region(self):
        radius = self._finite("radius", True)
        length = self._finite("length")
        return k.KIND_CIRCLE, self._center(), self._frame(), np.array([radius, length, 0.0])


class BoxFactory(SpheresFactory):
    """A SpheresFactory whose region is the box ``center +- extents`` (half sizes); sphere centres anywhere in
    it."""

    _attrs = {
        "extents": Attr(_NAN3, "Half sizes of the region [m]", to_vec3),
        "center": Attr(_NAN3, "Centre of the region [m]", to_vec3),
    }

    def region(self):
        e = as_vec3(self.extents)
        if not (np.isfinite(e).all() and (e >= 0).all()):
            raise ValueError(f"BoxFactory.extents must be finite and not negative, got {tuple(e)}")
        return k.KIND_BOX, self._center(), np.eye(3), e
