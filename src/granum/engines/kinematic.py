"""Partial engines acting on listed bodies: ForceEngine and the kinematic engines.

A kinematic engine (YADE's ``KinematicEngine``: TranslationEngine, RotationEngine, HelixEngine) imposes
the motion of its bodies. Each step it resets their velocity and angular velocity, then adds its own motion,
so that engines combined with ``+`` (a :class:`CombinedKinematicEngine`) add up. Every kinematic engine
describes its motion as one *part* row of :func:`granum.kernels.forces.kinematic_stage`.
"""

from __future__ import annotations

import numpy as np

from granum.core.attrs import Attr, to_bool, to_float
from granum.engines.base import PartialEngine
from granum.engines.pipeline import to_vec3
from granum.kernels.forces import (
    K_AXIS,
    K_COLS,
    K_ORBIT,
    K_SPEED,
    K_VEL,
    K_ZERO,
    ForceParams,
    KinematicParams,
)
from granum.mathtypes import Vector3

KINEMATIC_STAGE = "granum.kernels.forces:kinematic_stage"


def _unit(owner, name: str, v) -> np.ndarray:
    a = np.array(v._a, dtype=np.float64)
    n = np.linalg.norm(a)
    if n == 0:
        raise ValueError(f"{type(owner).__name__}.{name} must be a non-zero vector")
    return a / n


def to_axis(owner, value) -> Vector3:
    """An axis attribute, normalised on assignment as YADE does (a zero vector is refused when the scene
    runs, by :func:`_unit`)."""
    v = to_vec3(owner, value)
    n = v.norm()
    return v / n if n > 0 else v


def part_row(velocity=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 0.0), speed: float = 0.0, zero=(0.0, 0.0, 0.0),
             orbit: bool = False) -> np.ndarray:
    """One part of :func:`~granum.kernels.forces.kinematic_stage`: a velocity [m/s] added to the bodies',
    an angular speed [rad/s] about a unit axis, and whether the bodies orbit that axis through ``zero`` [m]."""
    row = np.zeros(K_COLS)
    row[K_VEL:K_VEL + 3] = velocity
    row[K_AXIS:K_AXIS + 3] = axis
    row[K_SPEED] = speed
    row[K_ZERO:K_ZERO + 3] = zero
    row[K_ORBIT] = float(orbit)
    return row


def kinematic_params(engine, parts: list, scene) -> KinematicParams:
    """Parameters of :func:`~granum.kernels.forces.kinematic_stage` for ``engine``'s ids and the kinematic
    engines ``parts``, run in order; the angle each part turns is accumulated in a (K,) array that the
    parts keeping ``angleTurned`` take as their storage (:meth:`KinematicEngine.share_turned`)."""
    rows = np.array([e.part() for e in parts], dtype=np.float64).reshape(len(parts), K_COLS)
    turned = np.zeros(len(parts))
    for k, e in enumerate(parts):
        e.share_turned(turned, k)
    return KinematicParams(ids=engine.id_array(scene), parts=rows, turned=turned)


class ForceEngine(PartialEngine):
    """Add a constant force to the listed bodies every step."""

    stage = "granum.kernels.forces:force_stage"
    _attrs = {"force": Attr(Vector3(0, 0, 0), "Force added to each body [N]", to_vec3)}

    def params(self, scene, engines) -> ForceParams:
        return ForceParams(ids=self.id_array(scene), force=np.array(self.force._a, dtype=np.float64))


class KinematicEngine(PartialEngine):
    """Base of the engines imposing motion (YADE ``KinematicEngine``); ``a + b`` combines two of them
    into a :class:`CombinedKinematicEngine` acting on ``a.ids``."""

    stage = KINEMATIC_STAGE

    def part(self) -> np.ndarray:
        """This engine's motion as a row of :func:`part_row`."""
        raise NotImplementedError(f"{type(self).__name__} imposes no motion; use TranslationEngine, RotationEngine "
                                  f"or HelixEngine")

    def share_turned(self, turned: np.ndarray, k: int) -> None:
        """Keep the angle turned in ``turned[k]`` from now on (engines with ``angleTurned``)."""

    def params(self, scene, engines) -> KinematicParams:
        return kinematic_params(self, [self], scene)

    def __add__(self, other):
        if not isinstance(other, KinematicEngine):
            return NotImplemented
        return CombinedKinematicEngine(ids=list(self.ids), comb=[self, other])


class TranslationEngine(KinematicEngine):
    """Impose the velocity ``velocity * translationAxis`` (axis normalised) on the listed bodies."""

    _attrs = {
        "velocity": Attr(0.0, "Speed along the axis [m/s]", to_float("velocity")),
        "translationAxis": Attr(Vector3(1, 0, 0), "Direction of motion (normalised when assigned)", to_axis),
    }

    def part(self) -> np.ndarray:
        return part_row(velocity=self.velocity * _unit(self, "translationAxis", self.translationAxis))


class RotationEngine(KinematicEngine):
    """Impose the angular velocity ``angularVelocity * rotationAxis`` on the listed bodies.

    With ``rotateAroundZero`` the bodies also orbit the axis through ``zeroPoint``: each step they move
    along the chord of their circle, landing on it (YADE's behaviour).
    """

    _attrs = {
        "angularVelocity": Attr(0.0, "Angular speed [rad/s]", to_float("angularVelocity")),
        "rotationAxis": Attr(Vector3(1, 0, 0), "Axis of rotation (normalised when assigned)", to_axis),
        "rotateAroundZero": Attr(False, "Also move the bodies around zeroPoint", to_bool),
        "zeroPoint": Attr(Vector3(0, 0, 0), "A point of the rotation axis [m]", to_vec3),
    }

    def part(self) -> np.ndarray:
        return part_row(axis=_unit(self, "rotationAxis", self.rotationAxis), speed=self.angularVelocity,
                        zero=self.zeroPoint._a, orbit=self.rotateAroundZero)


class HelixEngine(RotationEngine):
    """Rotation about the axis through ``zeroPoint`` plus translation along it (YADE ``HelixEngine``):
    angVel = angularVelocity * axis, the bodies orbit the axis (whatever ``rotateAroundZero`` says; YADE
    sets it True when the engine runs) and move at ``linearVelocity * axis``; ``angleTurned`` grows by
    angularVelocity dt each step."""

    _attrs = {
        "linearVelocity": Attr(0.0, "Speed along rotationAxis [m/s]", to_float("linearVelocity")),
        "angleTurned": Attr(0.0, "Angle turned so far [rad]", to_float("angleTurned")),
    }

    def __init__(self, **kw):
        object.__setattr__(self, "_turned", np.zeros(1))  # the storage of angleTurned, written by the stage
        super().__init__(**kw)

    @property
    def angleTurned(self) -> float:
        return float(self._turned[0])

    @angleTurned.setter
    def angleTurned(self, value: float) -> None:
        self._turned[0] = value

    def share_turned(self, turned: np.ndarray, k: int) -> None:
        turned[k] = self._turned[0]
        object.__setattr__(self, "_turned", turned[k:k + 1])

    def part(self) -> np.ndarray:
        object.__setattr__(self, "rotateAroundZero", True)
        axis = _unit(self, "rotationAxis", self.rotationAxis)
        return part_row(velocity=self.linearVelocity * axis, axis=axis, speed=self.angularVelocity,
                        zero=self.zeroPoint._a, orbit=True)


def _kinematic_list(owner, value) -> list:
    engines = list(value)
    for e in engines:
        if not isinstance(e, KinematicEngine):
            raise TypeError(f"{type(owner).__name__}.comb holds kinematic engines only, got {e!r}")
    return engines


class CombinedKinematicEngine(PartialEngine):
    """Kinematic engines acting together on ``ids`` (YADE's, made by ``a + b``; ``ids`` are ``a.ids`` when
    combined): each step the bodies' velocities are reset, then every live engine of ``comb`` adds its
    motion, in order (a dead one is skipped). ``c + d`` appends ``d`` to ``c.comb`` and returns ``c``."""

    stage = KINEMATIC_STAGE
    _attrs = {"comb": Attr([], "Kinematic engines combined, run in the order given", _kinematic_list)}

    def params(self, scene, engines) -> KinematicParams:
        return kinematic_params(self, [e for e in self.comb if not e.dead], scene)

    def labelled_parts(self) -> list:
        return list(self.comb)

    def __add__(self, other):
        if not isinstance(other, KinematicEngine):
            return NotImplemented
        self.comb = self.comb + [other]
        return self
