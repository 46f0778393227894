"""TriaxialStressController: stress/strain control of a sample in a box of six walls (see
:mod:`granum.kernels.triaxial` for the servo and the outputs)."""

from __future__ import annotations

import math

import numpy as np

from granum.core.attrs import Attr, as_integer, to_bool, to_float, to_int
from granum.core.shapes import ShapeKind
from granum.engines.base import GlobalEngine
from granum.kernels import triaxial as k
from granum.mathtypes import Vector3

#: YADE's names of the six walls, in the order of the stage's ``walls`` (left/right: x, bottom/top: y,
#: back/front: z)
WALLS = ("left", "right", "bottom", "top", "back", "front")


def _stress_mask(owner, value):
    value = as_integer(value, f"{type(owner).__name__}.stressMask")
    if not 0 <= value <= 7:
        raise ValueError(f"{type(owner).__name__}.stressMask must be in 0..7 (bit a set: goal a+1 is a stress, "
                         f"otherwise a strain rate), got {value}")
    return value


def _fraction(name: str):
    def convert(owner, value):
        x = to_float(name, allow_nan=False)(owner, value)
        if not 0.0 <= x <= 1.0:
            raise ValueError(f"{type(owner).__name__}.{name} must be in [0, 1], got {x!r}")
        return x

    return convert


def _multiplier(name: str):
    def convert(owner, value):
        x = to_float(name, allow_nan=False)(owner, value)
        if not x > 1.0:
            raise ValueError(f"{type(owner).__name__}.{name} must be above 1 (a growth factor of the radii), "
                             f"got {x!r}")
        return x

    return convert


def _state(slot: int, doc: str, writable: bool = False, array: str = "_out"):
    """A float of an engine's state array (the attribute ``array``, by default the controller's) exposed as an
    attribute (``doc``: "name: description")."""
    convert = to_float(doc.split(":")[0], allow_nan=False)

    def get(self):
        return float(getattr(self, array)[slot])

    def set_(self, value):
        getattr(self, array)[slot] = convert(self, value)

    return property(get, set_ if writable else None, doc=doc)


class TriaxialStressController(GlobalEngine):
    """Drive the six walls of a cuboid sample (``utils.aabbWalls``) to stress or strain-rate goals, or grow the
    spheres until the mean stress reaches the goal (``internalCompaction``).

    ``goal1..3`` are stresses [Pa] (compression negative) on the axes whose bit is set in ``stressMask``
    (1: x, 2: y, 4: z) and strain rates [1/s] on the others. ``wall_*_id`` name the walls (default: bodies
    0..5, as ``O.bodies.append(aabbWalls(...))`` appends them first).
    """

    stage = "granum.kernels.triaxial:triaxial_stage"
    _attrs = {
        "goal1": Attr(0.0, "Goal along x: stress [Pa] (bit 1 of stressMask) or strain rate [1/s]",
                      to_float("goal1", allow_nan=False)),
        "goal2": Attr(0.0, "Goal along y", to_float("goal2", allow_nan=False)),
        "goal3": Attr(0.0, "Goal along z", to_float("goal3", allow_nan=False)),
        "stressMask": Attr(7, "Bit a set: goal a+1 is a stress, otherwise a strain rate (0..7)", _stress_mask),
        "internalCompaction": Attr(True, "Grow the spheres (walls fixed) instead of moving the walls", to_bool),
        "finalMaxMultiplier": Attr(1.00001, "Growth factor bound once the mean stress has reached the goal [-]",
                                   _multiplier("finalMaxMultiplier")),
        "max_vel": Attr(1.0, "Largest wall speed [m/s] on an axis of the mean size (scaled by size/mean size)",
                        to_float("max_vel", positive=True)),
        "stressDamping": Attr(0.25, "Damping of the stress servo (0: none, 1: walls do not move) [-]",
                              _fraction("stressDamping")),
        "strainDamping": Attr(0.99, "Factor by which the strain rate's distance to its goal shrinks per step [-]",
                              _fraction("strainDamping")),
        "thickness": Attr(-1.0, "Wall thickness [m] (negative: from the wall boxes)",
                          to_float("thickness", allow_nan=False)),
        "stiffnessUpdateInterval": Attr(10, "Steps between updates of the walls' stiffness",
                                        to_int("stiffnessUpdateInterval", minimum=1)),
        "radiusControlInterval": Attr(10, "Steps between radius changes (internalCompaction)",
                                      to_int("radiusControlInterval", minimum=1)),
        "computeStressStrainInterval": Attr(10, "Steps between stress and strain updates",
                                            to_int("computeStressStrainInterval", minimum=1)),
        **{f"wall_{w}_id": Attr(i, f"Body id of the {w} wall", lambda o, v, w=w: as_integer(v, f"wall_{w}_id"))
           for i, w in enumerate(WALLS)},
        **{f"wall_{w}_activated": Attr(True, f"Whether the {w} wall is moved by the servo", to_bool)
           for w in WALLS},
    }

    def __init__(self, **kw):
        out = np.zeros(k.T_SIZE_STATE)
        out[k.T_SPHERES_VOLUME] = math.nan
        out[k.T_MAX_MULT] = 1.001
        out[k.T_PREV_MULT] = 1.0
        object.__setattr__(self, "_out", out)
        super().__init__(**kw)

    maxMultiplier = _state(k.T_MAX_MULT, "maxMultiplier: growth factor bound of the radii per control [-] "
                                         "(becomes finalMaxMultiplier once the goal is reached)", writable=True)
    previousMultiplier = _state(k.T_PREV_MULT, "previousMultiplier: the last growth factor [-]", writable=True)
    previousStress = _state(k.T_PREV_STRESS, "previousStress: the mean stress of the last growth [Pa]",
                            writable=True)
    width0 = _state(k.T_SIZE0, "width0: reference width for the strain [m] (0: the width at the first step)",
                    writable=True)
    height0 = _state(k.T_SIZE0 + 1, "height0: reference height [m]", writable=True)
    depth0 = _state(k.T_SIZE0 + 2, "depth0: reference depth [m]", writable=True)
    width = _state(k.T_SIZE, "width: distance between the x walls, less the thickness [m]")
    height = _state(k.T_SIZE + 1, "height: along y [m]")
    depth = _state(k.T_SIZE + 2, "depth: along z [m]")
    meanStress = _state(k.T_MEAN, "meanStress: mean of the six wall stresses [Pa]")
    volumetricStrain = _state(k.T_VOL_STRAIN, "volumetricStrain: sum of the three strains [-]")
    porosity = _state(k.T_POROSITY, "porosity: (V - V_spheres)/V of the box [-]")
    boxVolume = _state(k.T_BOX_VOLUME, "boxVolume: width * height * depth [m^3]")
    spheresVolume = _state(k.T_SPHERES_VOLUME, "spheresVolume: volume of the spheres [m^3]")
    particlesVolume = spheresVolume
    externalWork = _state(k.T_WORK, "externalWork: work of the walls, as YADE sums it [J]")

    @property
    def updatePorosity(self) -> bool:
        """Set True to recompute the spheres' volume at the next step (bodies erased...); reads False after."""
        return bool(self._out[k.T_SPHERES_VOLUME] < 0)

    @updatePorosity.setter
    def updatePorosity(self, on) -> None:
        if on:
            self._out[k.T_SPHERES_VOLUME] = -1.0

    @property
    def strain(self) -> Vector3:
        """Logarithmic strains ln(size/size0) along x, y, z [-] (compression negative)."""
        return Vector3(*self._out[k.T_STRAIN:k.T_STRAIN + 3])

    def strainRate(self) -> Vector3:
        """Strain rates along x, y, z in the last step [1/s]."""
        return Vector3(*self._out[k.T_RATE:k.T_RATE + 3])

    def stress(self, wall: int) -> Vector3:
        """Stress on wall ``wall`` (0..5: left, right, bottom, top, back, front) along its axis [Pa]
        (compression negative)."""
        wall = as_integer(wall, "TriaxialStressController.stress(id)")
        if not 0 <= wall <= 5:
            raise IndexError(f"TriaxialStressController.stress: wall index must be in 0..5 (left, right, bottom, "
                             f"top, back, front), got {wall}")
        v = [0.0, 0.0, 0.0]
        v[wall // 2] = float(self._out[k.T_STRESS + wall])
        return Vector3(*v)

    def wall_ids(self) -> list[int]:
        return [getattr(self, f"wall_{w}_id") for w in WALLS]

    def check_walls(self, scene) -> list[int]:
        """The six wall ids, checked: live boxes, all different."""
        name = type(self).__name__
        ids = self.wall_ids()
        b = scene.bodies
        for w, i in zip(WALLS, ids, strict=True):
            what = (None if not 0 <= i < scene.body_count or not b.alive[i] else ShapeKind(int(b.shape_kind[i])))
            if what is not ShapeKind.BOX:
                found = "no such body" if what is None else f"body {i} is a {what.name.capitalize()}"
                raise RuntimeError(f"{name}: wall_{w}_id={i} is not a Box ({found}); append the six walls of "
                                   "utils.aabbWalls first, or set the wall_*_id")
        if len(set(ids)) != 6:
            raise RuntimeError(f"{name}: the six wall ids must differ, got {ids}")
        return ids

    def activated(self) -> np.ndarray:
        """wall_*_activated in the order of :data:`WALLS`, (6,) uint8."""
        return np.array([getattr(self, f"wall_{w}_activated") for w in WALLS], np.uint8)

    def params(self, scene, engines) -> k.TriaxialParams:
        goal = np.array([self.goal1, self.goal2, self.goal3])
        if self.internalCompaction and not goal.mean() < 0:
            raise ValueError(f"{type(self).__name__}: internalCompaction grows the spheres to a compressive mean "
                             f"goal: the mean of goal1..3 must be negative (compression), got {float(goal.mean())!r}")
        return self.servo_params(scene, goal, self.activated())

    def servo_params(self, scene, goal: np.ndarray, activated: np.ndarray) -> k.TriaxialParams:
        """The servo's parameters with the goals ``goal`` (3,) and the walls' activation ``activated`` (6,)
        (arrays an engine built on the controller keeps and its stage may change)."""
        return k.TriaxialParams(
            walls=np.array(self.check_walls(scene), np.int64), activated=activated,
            goal=goal, stress_mask=int(self.stressMask), internal=bool(self.internalCompaction),
            final_max_multiplier=float(self.finalMaxMultiplier), max_vel=float(self.max_vel),
            stress_damping=float(self.stressDamping), strain_damping=float(self.strainDamping),
            thickness=float(self.thickness), stiffness_interval=int(self.stiffnessUpdateInterval),
            radius_interval=int(self.radiusControlInterval), stress_interval=int(self.computeStressStrainInterval),
            out=self._out)
