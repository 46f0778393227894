"""Partial engines acting on listed bodies: ForceEngine, TranslationEngine, RotationEngine."""

from __future__ import annotations

import numpy as np

from granum.core.attrs import Attr, to_bool, to_float
from granum.engines.base import PartialEngine
from granum.engines.pipeline import to_vec3
from granum.mathtypes import Vector3


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


class ForceEngine(PartialEngine):
    """Add a constant force to the listed bodies every step."""

    stage = "granum.kernels.forces:force_stage"
    _attrs = {"force": Attr(Vector3(0, 0, 0), "Force added to each body [N]", to_vec3)}

    def params(self, scene, engines) -> tuple:
        return (self.id_array(scene), np.array(self.force._a, dtype=np.float64))


class TranslationEngine(PartialEngine):
    """Impose the velocity ``velocity * translationAxis`` (axis normalised) on the listed bodies."""

    stage = "granum.kernels.forces:translation_stage"
    _attrs = {
        "velocity": Attr(0.0, "Speed along the axis [m/s]", to_float("velocity")),
        "translationAxis": Attr(Vector3(1, 0, 0), "Direction of motion (normalised when assigned)", to_axis),
    }

    def params(self, scene, engines) -> tuple:
        return (self.id_array(scene), self.velocity * _unit(self, "translationAxis", self.translationAxis))


class RotationEngine(PartialEngine):
    """Impose the angular velocity ``angularVelocity * rotationAxis`` on the listed bodies.

    With ``rotateAroundZero`` the bodies also orbit the axis through ``zeroPoint``.
    """

    stage = "granum.kernels.forces:rotation_stage"
    _attrs = {
        "angularVelocity": Attr(0.0, "Angular speed [rad/s]", to_float("angularVelocity")),
        "rotationAxis": Attr(Vector3(1, 0, 0), "Axis of rotation (normalised when assigned)", to_axis),
        "rotateAroundZero": Attr(False, "Also move the bodies around zeroPoint", to_bool),
        "zeroPoint": Attr(Vector3(0, 0, 0), "A point of the rotation axis [m]", to_vec3),
    }

    def params(self, scene, engines) -> tuple:
        omega = self.angularVelocity * _unit(self, "rotationAxis", self.rotationAxis)
        return (self.id_array(scene), omega, bool(self.rotateAroundZero),
                np.array(self.zeroPoint._a, dtype=np.float64))
