"""YADE's scene generators (``FileGenerator``): ``TriaxialTest``, a triaxial test in six wall boxes, and
``SimpleShear``, the simple-shear box of the KinemSimpleShearBox engines (see :class:`SimpleShear`).

``TriaxialTest(numberOfGrains=400, ...).load()`` replaces the current scene by the generated one,
``generate(file)`` saves it to ``file`` and leaves the current scene as it was. The scene, as YADE 2023.02a
builds it (measured):

* a random cloud (``SpherePack.makeCloud``) of ``numberOfGrains`` spheres between ``lowerCorner`` and
  ``upperCorner``, radii ``radiusMean`` ± ``radiusStdDev`` (relative, uniform); ``radiusMean`` ≤ 0: from a cloud
  porosity of 0.8 in the box; ``radiusMean`` > 0: the box is scaled (proportions kept) to the volume
  N·(4/3)π·r³/(1 − 0.8);
* six fixed, massless boxes (ids 0..5: bottom, top, left, right, back, front; y is the loading axis), each
  ``thickness`` thick outside the box, its faces ``wallOversizeFactor`` times the box's size plus twice the
  thickness;
* the spheres' FrictMat (Young ``sphereYoungModulus``, poisson = ``sphereKsDivKn`` (ks/kn of
  Ip2_FrictMat_FrictMat_FrictPhys), friction ``compactionFrictionDeg``, ``density``), the boxes' (``box*``);
* ForceResetter, InsertionSortCollider, InteractionLoop (Cundall-Strack), GlobalStiffnessTimeStepper (its
  defaultDt and O.dt: r_min·√(density/sphereYoungModulus) unless ``defaultDt`` > 0), TriaxialCompressionEngine
  (isAxisymetric, frictionAngleDegree = ``sphereFrictionDeg`` before the loading), a TriaxialStateRecorder
  writing ``WallStressRecordFile`` every ``recordIntervalIter`` steps (not with ``noFiles``) and
  NewtonIntegrator (damping ``dampingForce``).
"""

from __future__ import annotations

import math

import numpy as np

from granum.core.attrs import Attr, Attributed, to_bool, to_float, to_int, to_str
from granum.engines.functors import CLASSES as FUNCTORS
from granum.engines.pipeline import (
    ForceResetter,
    GravityEngine,
    InsertionSortCollider,
    InteractionLoop,
    NewtonIntegrator,
    to_vec3,
)
from granum.engines.simple_shear import KinemCTDEngine
from granum.engines.timestepper import GlobalStiffnessTimeStepper
from granum.engines.triaxial_engines import TriaxialCompressionEngine
from granum.mathtypes import Vector3

#: porosity of the cloud TriaxialTest asks makeCloud for (YADE 2023.02a, measured)
CLOUD_POROSITY = 0.8
#: the boxes in id order: (axis, side) with side -1 below the sample, +1 above
WALL_ORDER = ((1, -1), (1, 1), (0, -1), (0, 1), (2, -1), (2, 1))


def _omega():
    from granum.yade.omega import O

    return O


class FileGenerator(Attributed):
    """Base of YADE's scene generators: :meth:`load` makes the scene current, :meth:`generate` saves it."""

    _attrs: dict = {}

    def check(self) -> None:
        """Refuse bad parameters before any scene is touched."""

    def build(self, omega) -> None:
        """Fill ``omega``'s (empty) current scene."""
        raise NotImplementedError

    def load(self) -> None:
        """Replace the current scene by the generated one."""
        self.check()
        O = _omega()
        O.resetThisScene()
        self.build(O)

    def generate(self, out) -> None:
        """Save the generated scene to ``out`` (format by extension, as O.save); the current scene stays."""
        self.check()
        O = _omega()
        O.switchScene()
        try:
            O.resetThisScene()
            self.build(O)
            O.save(str(out))
        finally:
            O.resetThisScene()
            O.switchScene()


def _unsupported(name: str, default):
    """An attribute granum only has at its default: any other value is refused by name."""

    def convert(owner, value):
        if value != default:
            raise NotImplementedError(f"{type(owner).__name__}.{name}={value!r} is not implemented in granum "
                                      f"(only {default!r})")
        return value

    return convert


class TriaxialTest(FileGenerator):
    """YADE's triaxial test generator (see :mod:`granum.yade.preprocessors`)."""

    _attrs = {
        "lowerCorner": Attr(Vector3(0, 0, 0), "Lower corner of the box [m]", to_vec3),
        "upperCorner": Attr(Vector3(1, 1, 1), "Upper corner of the box [m] (its proportions with radiusMean > 0)",
                            to_vec3),
        "importFilename": Attr("", "File of spheres (not implemented in granum: refused)",
                               _unsupported("importFilename", "")),
        "Key": Attr("", "Appended to the names of the files written", to_str("Key")),
        "fixedBoxDims": Attr("", "Axes kept when the box is scaled (not implemented in granum: refused)",
                             _unsupported("fixedBoxDims", "")),
        "WallStressRecordFile": Attr("./WallStresses", "File of the TriaxialStateRecorder (Key appended)",
                                     to_str("WallStressRecordFile")),
        "internalCompaction": Attr(False, "Compact by growing the spheres instead of moving the walls", to_bool),
        "autoCompressionActivation": Attr(True, "Start the loading after the compaction", to_bool),
        "autoUnload": Attr(True, "Unload to sigmaLateralConfinement after the compaction", to_bool),
        "autoStopSimulation": Attr(False, "TriaxialCompressionEngine.autoStopSimulation", to_bool),
        "noFiles": Attr(False, "Write no file (no recorder, no checkpoints)", to_bool),
        "facetWalls": Attr(False, "Facets as boundaries (not implemented in granum: refused)",
                           _unsupported("facetWalls", False)),
        "wallWalls": Attr(False, "Walls as boundaries (not implemented in granum: refused)",
                          _unsupported("wallWalls", False)),
        "thickness": Attr(0.001, "Thickness of the boxes [m]", to_float("thickness", allow_nan=False)),
        "maxMultiplier": Attr(1.01, "Growth factor bound of the radii, first stage [-]",
                              to_float("maxMultiplier", allow_nan=False)),
        "finalMaxMultiplier": Attr(1.001, "Growth factor bound of the radii, second stage [-]",
                                   to_float("finalMaxMultiplier", allow_nan=False)),
        "radiusStdDev": Attr(0.3, "Relative spread of the radii (makeCloud's rRelFuzz) [-]",
                             to_float("radiusStdDev", allow_nan=False)),
        "seed": Attr(0, "Seed of makeCloud", to_int("seed")),
        "radiusMean": Attr(-1.0, "Mean radius [m] (<= 0: from the box and numberOfGrains)",
                           to_float("radiusMean", allow_nan=False)),
        "sphereYoungModulus": Attr(15e6, "Young's modulus of the spheres [Pa]",
                                   to_float("sphereYoungModulus", positive=True)),
        "sphereKsDivKn": Attr(0.5, "ks/kn of the spheres [-]", to_float("sphereKsDivKn", allow_nan=False)),
        "sphereFrictionDeg": Attr(18.0, "Friction angle of the spheres for the loading [deg]",
                                  to_float("sphereFrictionDeg", allow_nan=False)),
        "compactionFrictionDeg": Attr(18.0, "Friction angle of the spheres during the compaction [deg]",
                                      to_float("compactionFrictionDeg", allow_nan=False)),
        "boxYoungModulus": Attr(15e6, "Young's modulus of the boxes [Pa]", to_float("boxYoungModulus", positive=True)),
        "maxWallVelocity": Attr(10.0, "TriaxialCompressionEngine.max_vel [m/s]",
                                to_float("maxWallVelocity", positive=True)),
        "boxKsDivKn": Attr(0.5, "ks/kn of the boxes [-]", to_float("boxKsDivKn", allow_nan=False)),
        "boxFrictionDeg": Attr(0.0, "Friction angle of the boxes [deg]", to_float("boxFrictionDeg", allow_nan=False)),
        "density": Attr(2600.0, "Density of the spheres [kg/m^3]", to_float("density", positive=True)),
        "strainRate": Attr(0.1, "Strain rate of the loading [1/s]", to_float("strainRate", allow_nan=False)),
        "defaultDt": Attr(-1.0, "Initial time step [s] (<= 0: r_min sqrt(density/E))",
                          to_float("defaultDt", allow_nan=False)),
        "dampingForce": Attr(0.2, "NewtonIntegrator.damping [-]", to_float("dampingForce", allow_nan=False)),
        "dampingMomentum": Attr(0.2, "Damping of the moments (YADE's NewtonIntegrator has one damping: must equal "
                                     "dampingForce)", to_float("dampingMomentum", allow_nan=False)),
        "StabilityCriterion": Attr(0.01, "TriaxialCompressionEngine.StabilityCriterion [-]",
                                   to_float("StabilityCriterion", allow_nan=False)),
        "wallOversizeFactor": Attr(1.3, "Size of the boxes' faces over the sample's [-]",
                                   to_float("wallOversizeFactor", positive=True)),
        "sigmaIsoCompaction": Attr(-50e3, "Stress of the compaction [Pa]", to_float("sigmaIsoCompaction",
                                                                                   allow_nan=False)),
        "sigmaLateralConfinement": Attr(-50e3, "Lateral stress of the loading [Pa]",
                                        to_float("sigmaLateralConfinement", allow_nan=False)),
        "timeStepUpdateInterval": Attr(50, "GlobalStiffnessTimeStepper.timeStepUpdateInterval",
                                       to_int("timeStepUpdateInterval", minimum=1)),
        "wallStiffnessUpdateInterval": Attr(10, "TriaxialCompressionEngine.stiffnessUpdateInterval",
                                            to_int("wallStiffnessUpdateInterval", minimum=1)),
        "radiusControlInterval": Attr(10, "TriaxialCompressionEngine.radiusControlInterval",
                                      to_int("radiusControlInterval", minimum=1)),
        "numberOfGrains": Attr(400, "Number of spheres", to_int("numberOfGrains", minimum=1)),
        "recordIntervalIter": Attr(20, "Steps between the recorder's lines", to_int("recordIntervalIter",
                                                                                   minimum=1)),
    }

    def corners(self) -> tuple[np.ndarray, np.ndarray]:
        """The box's corners [m]: as given, or scaled about the lower one to hold the grains (radiusMean > 0)."""
        lo, hi = np.array(self.lowerCorner._a, float), np.array(self.upperCorner._a, float)
        size = hi - lo
        if not (size > 0).all():
            raise ValueError(f"TriaxialTest: upperCorner {tuple(hi)} must lie above lowerCorner {tuple(lo)} on "
                             "every axis")
        if self.radiusMean > 0:
            volume = self.numberOfGrains * 4.0 / 3.0 * math.pi * self.radiusMean ** 3 / (1.0 - CLOUD_POROSITY)
            size = size * (volume / size.prod()) ** (1.0 / 3.0)
        return lo, lo + size

    def check(self) -> None:
        self.corners()
        if self.dampingMomentum != self.dampingForce:
            raise NotImplementedError("TriaxialTest: dampingMomentum different from dampingForce is not implemented "
                                      "in granum (NewtonIntegrator has one damping)")

    def build(self, omega) -> None:
        from granum.yade import utils
        from granum.yade.materials import CLASSES
        from granum.yade.pack import SpherePack
        from granum.yade.recorders import TriaxialStateRecorder

        lo, hi = self.corners()
        sp = SpherePack()
        sp.makeCloud(Vector3(*lo), Vector3(*hi), self.radiusMean, self.radiusStdDev, self.numberOfGrains, False,
                     CLOUD_POROSITY, seed=self.seed)
        frict = CLASSES["FrictMat"]
        spheres = frict(young=self.sphereYoungModulus, poisson=self.sphereKsDivKn, density=self.density,
                        frictionAngle=math.radians(self.compactionFrictionDeg))
        boxes = frict(young=self.boxYoungModulus, poisson=self.boxKsDivKn,
                      frictionAngle=math.radians(self.boxFrictionDeg))
        t = self.thickness
        center, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
        walls = []
        for axis, side in WALL_ORDER:
            c = center.copy()
            c[axis] = (hi if side > 0 else lo)[axis] + side * 0.5 * t
            ext = half * self.wallOversizeFactor + t
            ext[axis] = 0.5 * t
            w = utils.box(Vector3(*c), Vector3(*ext), fixed=True, wire=True, color=(1, 1, 1), material=boxes)
            w.state.mass = 0.0
            walls.append(w)
        omega.bodies.append(walls)
        omega.bodies.append([utils.sphere(c, r, material=spheres) for c, r in sp])
        radii = [r for _, r in sp]
        dt = self.defaultDt if self.defaultDt > 0 else min(radii) * math.sqrt(self.density / self.sphereYoungModulus)
        triax = TriaxialCompressionEngine(
            wall_bottom_id=0, wall_top_id=1, wall_left_id=2, wall_right_id=3, wall_back_id=4, wall_front_id=5,
            strainRate=self.strainRate, StabilityCriterion=self.StabilityCriterion,
            sigmaIsoCompaction=self.sigmaIsoCompaction, sigmaLateralConfinement=self.sigmaLateralConfinement,
            frictionAngleDegree=self.sphereFrictionDeg, fixedPorosity=1.0, isAxisymetric=True, thickness=t,
            maxMultiplier=self.maxMultiplier, finalMaxMultiplier=self.finalMaxMultiplier,
            max_vel=self.maxWallVelocity, internalCompaction=self.internalCompaction, Key=self.Key,
            noFiles=self.noFiles, autoCompressionActivation=self.autoCompressionActivation,
            autoUnload=self.autoUnload, autoStopSimulation=self.autoStopSimulation,
            stiffnessUpdateInterval=self.wallStiffnessUpdateInterval,
            radiusControlInterval=self.radiusControlInterval, warn=1)
        functor = {n: FUNCTORS[n] for n in ("Bo1_Sphere_Aabb", "Bo1_Box_Aabb", "Bo1_Facet_Aabb", "Bo1_Wall_Aabb",
                                         "Ig2_Sphere_Sphere_ScGeom", "Ig2_Facet_Sphere_ScGeom",
                                         "Ig2_Box_Sphere_ScGeom", "Ip2_FrictMat_FrictMat_FrictPhys",
                                         "Law2_ScGeom_FrictPhys_CundallStrack")}
        engines = [
            ForceResetter(),
            InsertionSortCollider([functor["Bo1_Sphere_Aabb"](), functor["Bo1_Box_Aabb"](),
                                   functor["Bo1_Facet_Aabb"](), functor["Bo1_Wall_Aabb"]()]),
            InteractionLoop([functor["Ig2_Sphere_Sphere_ScGeom"](), functor["Ig2_Facet_Sphere_ScGeom"](),
                             functor["Ig2_Box_Sphere_ScGeom"]()], [functor["Ip2_FrictMat_FrictMat_FrictPhys"]()],
                            [functor["Law2_ScGeom_FrictPhys_CundallStrack"]()]),
            GlobalStiffnessTimeStepper(defaultDt=dt, timestepSafetyCoefficient=0.8,
                                       timeStepUpdateInterval=self.timeStepUpdateInterval),
            triax,
        ]
        if not self.noFiles:
            engines.append(TriaxialStateRecorder(file=self.WallStressRecordFile + self.Key,
                                                 iterPeriod=self.recordIntervalIter))
        engines.append(NewtonIntegrator(damping=self.dampingForce))
        omega.engines = engines
        omega.dt = dt


def _frictional(functor) -> tuple[list, list, list]:
    """The bound, geometry and law functors of a box of spheres with Cundall-Strack contacts."""
    return ([functor["Bo1_Sphere_Aabb"](), functor["Bo1_Box_Aabb"]()],
            [functor["Ig2_Sphere_Sphere_ScGeom"](), functor["Ig2_Box_Sphere_ScGeom"]()],
            [functor["Ip2_FrictMat_FrictMat_FrictPhys"](), functor["Law2_ScGeom_FrictPhys_CundallStrack"]()])


#: SimpleShear's cloud: the spheres asked for, their volume fraction if all fit, the radii's relative spread and
#: granum's seed for the draws (YADE 2023.02a, measured: 907 of 1000 spheres of radius 0.0017894 ± 15 % with the
#: defaults; its own generator's numbers, which granum does not reproduce)
SHEAR_GRAINS, SHEAR_SOLID_FRACTION, SHEAR_FUZZ, SHEAR_SEED = 1000, 0.3, 0.15, 1


class SimpleShear(FileGenerator):
    """YADE's simple-shear box generator: ``load()`` builds, as YADE 2023.02a does (measured):

    * six fixed massless wire boxes ``thickness`` t thick around the box ``length`` L (x) × ``height`` H (y) ×
      ``width`` W (z), z centred on 0, in the order KinemSimpleShearBox names them: left (x = −t/2), bottom
      (y = −t/2), right (x = L + t/2), top (y = H + t/2), back (z = −W/2 − t/2), front (z = W/2 + t/2); the lateral
      boxes reach 2.5 H + 5 t above and below their centre (y = H/2), the back and front ones are 2.5 L long and
      H + 2t high; the bottom, top and spheres' FrictMat has ``matFrictionDeg``, the other boxes' none;
    * a loose cloud of spheres of radius r·(1 ± 0.15), r such that 1000 spheres would fill 30 % of the box, as
      many as fit (``SpherePack.makeCloud``: granum's draws, not YADE's generator's); their FrictMat has
      ``matYoungModulus``, ``matPoissonRatio`` and YADE's default density, their masses ``density``;
    * ForceResetter, GlobalStiffnessTimeStepper (defaultDt 3e-6, ``timeStepUpdateInterval``),
      InsertionSortCollider, InteractionLoop (Cundall-Strack), GravityEngine (``gravity``, with ``gravApplied``),
      NewtonIntegrator (damping 0.2) and KinemCTDEngine (compSpeed 10 m/s, targetSigma 2000 kPa); O.dt = 1e-8 s.
    """

    _attrs = {
        "thickness": Attr(0.001, "Thickness of the boxes [m]", to_float("thickness", positive=True)),
        "length": Attr(0.1, "Initial length (x) of the shear box [m]", to_float("length", positive=True)),
        "height": Attr(0.02, "Initial height (y) of the shear box [m]", to_float("height", positive=True)),
        "width": Attr(0.04, "Initial width (z) of the shear box [m]", to_float("width", positive=True)),
        "density": Attr(2600.0, "Density of the spheres (their masses) [kg/m^3]", to_float("density", positive=True)),
        "matYoungModulus": Attr(4.0e9, "FrictMat.young of the bodies [Pa]", to_float("matYoungModulus",
                                                                                     positive=True)),
        "matPoissonRatio": Attr(0.04, "FrictMat.poisson of the bodies [-]", to_float("matPoissonRatio",
                                                                                     allow_nan=False)),
        "matFrictionDeg": Attr(37.0, "Friction angle of the spheres, bottom and top boxes [deg]",
                               to_float("matFrictionDeg", allow_nan=False)),
        "gravApplied": Attr(False, "Whether a GravityEngine is added", to_bool),
        "gravity": Attr(Vector3(0, -9.81, 0), "Gravity if gravApplied [m/s^2]", to_vec3),
        "timeStepUpdateInterval": Attr(50, "GlobalStiffnessTimeStepper.timeStepUpdateInterval",
                                       to_int("timeStepUpdateInterval", minimum=1)),
    }

    def build(self, omega) -> None:
        from granum.yade import utils
        from granum.yade.materials import CLASSES
        from granum.yade.pack import SpherePack

        L, H, W, t = self.length, self.height, self.width, self.thickness
        frict = CLASSES["FrictMat"]
        rough = frict(young=self.matYoungModulus, poisson=self.matPoissonRatio,
                      frictionAngle=math.radians(self.matFrictionDeg))
        smooth = frict(young=self.matYoungModulus, poisson=self.matPoissonRatio, frictionAngle=0.0)
        tall, long_ = 2.5 * H + 5 * t, 1.25 * L
        boxes = [((-t / 2, H / 2, 0), (t / 2, tall, W / 2), smooth),
                 ((L / 2, -t / 2, 0), (L / 2, t / 2, W / 2), rough),
                 ((L + t / 2, H / 2, 0), (t / 2, tall, W / 2), smooth),
                 ((L / 2, H + t / 2, 0), (L / 2, t / 2, W / 2), rough),
                 ((L / 2, H / 2, -W / 2 - t / 2), (long_, H / 2 + t, t / 2), smooth),
                 ((L / 2, H / 2, W / 2 + t / 2), (long_, H / 2 + t, t / 2), smooth)]
        walls = []
        for c, e, m in boxes:
            w = utils.box(Vector3(*c), Vector3(*e), fixed=True, wire=True, color=(1, 0, 0), material=m)
            w.state.mass = 0.0
            w.state.inertia = Vector3(0, 0, 0)
            walls.append(w)
        omega.bodies.append(walls)
        r = (SHEAR_SOLID_FRACTION * L * H * W / (4.0 / 3.0 * math.pi * SHEAR_GRAINS)) ** (1.0 / 3.0)
        sp = SpherePack()
        sp.makeCloud(Vector3(0, 0, -W / 2), Vector3(L, H, W / 2), r, SHEAR_FUZZ, SHEAR_GRAINS, seed=SHEAR_SEED)
        spheres = []
        for c, radius in sp:
            b = utils.sphere(c, radius, color=(0.45, 0.45, 0.45), material=rough)
            b.state.mass = self.density * 4.0 / 3.0 * math.pi * radius ** 3
            b.state.inertia = Vector3(*[0.4 * b.state.mass * radius ** 2] * 3)
            spheres.append(b)
        omega.bodies.append(spheres)
        bounds, geoms, (phys, law) = _frictional(FUNCTORS)
        engines = [ForceResetter(),
                   GlobalStiffnessTimeStepper(defaultDt=3e-6, timestepSafetyCoefficient=0.8,
                                              timeStepUpdateInterval=self.timeStepUpdateInterval),
                   InsertionSortCollider(bounds), InteractionLoop(geoms, [phys], [law])]
        if self.gravApplied:
            engines.append(GravityEngine(gravity=self.gravity))
        engines += [NewtonIntegrator(damping=0.2), KinemCTDEngine(compSpeed=10.0, targetSigma=2000.0)]
        omega.engines = engines
        omega.dt = 1e-8


__all__ = ["FileGenerator", "SimpleShear", "TriaxialTest"]
