"""UniaxialStrainer: constant strain rate between two groups of bodies (see :mod:`granum.kernels.strainer`)."""

from __future__ import annotations

import math

import numpy as np

from granum.core.attrs import Attr, as_integer, to_bool, to_float, to_int
from granum.engines.base import GlobalEngine
from granum.engines.triaxial import _state
from granum.kernels import strainer as k


def _ids(name: str):
    def convert(owner, value):
        return [as_integer(i, f"{type(owner).__name__}.{name}[]") for i in value]

    return convert


def _axis(owner, value):
    a = as_integer(value, f"{type(owner).__name__}.axis")
    if a not in (0, 1, 2):
        raise ValueError(f"{type(owner).__name__}.axis must be 0, 1 or 2 (x, y, z), got {a}")
    return a


def _asymmetry(owner, value):
    a = as_integer(value, f"{type(owner).__name__}.asymmetry")
    if a not in (-1, 0, 1):
        raise ValueError(f"{type(owner).__name__}.asymmetry must be -1, 0 or 1, got {a}")
    return a


class UniaxialStrainer(GlobalEngine):
    """Move ``posIds`` and ``negIds`` apart along ``axis`` at ``strainRate`` [1/s] (or ``absSpeed`` [m/s]);
    ``strain`` [-] and ``avgStress`` [Pa] (tension positive, over ``crossSectionArea``) are its outputs.

    At its first run the engine measures ``originalLength``, completes ``strainRate``/``absSpeed`` from each other
    and blocks the groups' DOF along the axis (and their other translations with ``blockDisplacements``, their
    rotations with ``blockRotations``); with ``setSpeeds`` the stage's first run gives every body the axial
    velocity of the uniform strain rate. ``initAccelTime`` is kept for YADE's scripts: YADE 2023.02a moves the
    groups at full speed from the first step whatever its value (measured), and so does granum.
    """

    stage = "granum.kernels.strainer:strainer_stage"
    _attrs = {
        "strainRate": Attr(math.nan, "Strain rate [1/s] (> 0: extension)", to_float("strainRate")),
        "absSpeed": Attr(math.nan, "Speed of the groups apart [m/s] (used when strainRate is not given)",
                         to_float("absSpeed")),
        "initAccelTime": Attr(-200.0, "Kept for YADE's scripts (no effect, as in YADE 2023.02a)",
                              to_float("initAccelTime")),
        "setSpeeds": Attr(False, "At the first run, give every body the axial velocity of the uniform strain rate",
                          to_bool),
        "stopStrain": Attr(math.nan, "Strain at which the straining stops [-] (NaN: never)", to_float("stopStrain")),
        "idleIterations": Attr(0, "Kept for YADE's scripts (YADE 2023.02a leaves it 0)", to_int("idleIterations")),
        "axis": Attr(2, "The strained axis (0, 1, 2)", _axis),
        "asymmetry": Attr(0, "0: both groups move; 1: only posIds; -1: only negIds", _asymmetry),
        "posIds": Attr([], "Bodies at the positive end", _ids("posIds")),
        "negIds": Attr([], "Bodies at the negative end", _ids("negIds")),
        "limitStrain": Attr(0.0, "Strain at which the straining reverses (not implemented: refused unless 0)",
                            to_float("limitStrain", allow_nan=False)),
        "notYetReversed": Attr(True, "Whether the straining has not reversed yet", to_bool),
        "crossSectionArea": Attr(math.nan, "Cross-section normal to the axis [m^2]", to_float("crossSectionArea")),
        "blockDisplacements": Attr(False, "Block the groups' translations across the axis", to_bool),
        "blockRotations": Attr(False, "Block the groups' rotations", to_bool),
        "stressUpdateInterval": Attr(10, "Steps between avgStress updates", to_int("stressUpdateInterval",
                                                                                 minimum=1)),
    }

    def __init__(self, **kw):
        st = np.zeros(k.U_SIZE)
        st[k.U_LENGTH0] = math.nan
        st[k.U_ACTIVE] = 1.0
        object.__setattr__(self, "_st", st)
        super().__init__(**kw)

    originalLength = _state(k.U_LENGTH0, "originalLength: distance of the groups' first bodies along the axis at "
                                         "the start [m]", writable=True, array="_st")
    strain = _state(k.U_STRAIN, "strain: elongation over originalLength [-]", array="_st")
    avgStress = _state(k.U_STRESS, "avgStress: force between the groups over crossSectionArea [Pa]", array="_st")

    @property
    def active(self) -> bool:
        """Whether the engine strains (False once stopStrain is reached)."""
        return bool(self._st[k.U_ACTIVE])

    @active.setter
    def active(self, on) -> None:
        self._st[k.U_ACTIVE] = float(to_bool(self, on))

    @property
    def currentStrainRate(self) -> float:
        """The strain rate applied [1/s] (strainRate: YADE 2023.02a applies no ramp)."""
        return self.strainRate

    def _start(self, scene) -> None:
        """The first run: originalLength, strainRate/absSpeed, blocked DOFs."""
        name = type(self).__name__
        pos, neg = self.posIds, self.negIds
        b = scene.bodies
        length = float(b.pos[pos[0], self.axis] - b.pos[neg[0], self.axis])
        if not length > 0:
            raise ValueError(f"{name}: posIds[0] must lie beyond negIds[0] along axis {self.axis} "
                             f"(their distance is {length!r})")
        self.originalLength = length
        if not math.isnan(self.strainRate):
            self.absSpeed = self.strainRate * length
        else:
            self.strainRate = self.absSpeed / length
        bits = 1 << self.axis | (0b111 if self.blockDisplacements else 0) | (0b111000 if self.blockRotations else 0)
        b.blocked[pos + neg] |= bits
        self._st[k.U_SET_SPEEDS] = float(self.setSpeeds)

    def params(self, scene, engines) -> k.StrainerParams:
        name = type(self).__name__
        if math.isnan(self.crossSectionArea):
            raise RuntimeError(f"{name}.crossSectionArea must be specified")
        if math.isnan(self.strainRate) and math.isnan(self.absSpeed):
            raise ValueError(f"{name}: give strainRate or absSpeed (both are NaN)")
        if not self.posIds or not self.negIds:
            raise ValueError(f"{name}: posIds and negIds must name the bodies to strain (got {self.posIds}, "
                             f"{self.negIds})")
        bad = [i for i in self.posIds + self.negIds if not 0 <= i < scene.body_count or not scene.bodies.alive[i]]
        if bad:
            raise ValueError(f"{name}: body {bad[0]} of posIds/negIds does not exist")
        if self.limitStrain != 0:
            raise NotImplementedError(f"{name}.limitStrain (reversing the straining) is not implemented in granum")
        if math.isnan(self.originalLength):
            self._start(scene)
        if not math.isnan(self.stopStrain) and self.strainRate < 0:
            raise NotImplementedError(f"{name}: stopStrain with a negative strainRate is not implemented in granum "
                                      "(YADE 2023.02a stops at once)")
        return k.StrainerParams(
            pos_ids=np.array(self.posIds, np.int64), neg_ids=np.array(self.negIds, np.int64), axis=int(self.axis),
            asymmetry=int(self.asymmetry), strain_rate=float(self.strainRate), area=float(self.crossSectionArea),
            stop_strain=float(self.stopStrain), stress_interval=int(self.stressUpdateInterval), state=self._st)
