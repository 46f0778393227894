"""Engines applying forces and displacements: ForceEngine, TorqueEngine, InterpolatingDirectedForceEngine,
StepDisplacer, DragEngine, LinearDragEngine (partial engines, on ``ids``) and the field appliers
AxialGravityEngine and CentralConstantAccelerationEngine (on every body their mask selects).
Their stages are in :mod:`granum.kernels.forces` and :mod:`granum.kernels.fields`.
"""

from __future__ import annotations

import math

import numpy as np

from granum.core.attrs import Attr, to_bool, to_float, to_int
from granum.engines.base import GlobalEngine, PartialEngine
from granum.engines.kinematic import _floats, _non_negative, _table, _unit, to_axis
from granum.engines.pipeline import to_vec3
from granum.kernels.fields import (
    AxialGravityParams,
    CentralAccelerationParams,
    DragParams,
    InterpolatedForceParams,
    StepDisplacerParams,
)
from granum.kernels.forces import ForceParams
from granum.mathtypes import Quaternion, Vector3, as_quat_wxyz

_ZERO3 = np.zeros(3)


class ForceEngine(PartialEngine):
    """Add a constant force to the listed bodies every step."""

    stage = "granum.kernels.forces:force_stage"
    _attrs = {"force": Attr(Vector3(0, 0, 0), "Force added to each body [N]", to_vec3)}

    def params(self, scene, engines) -> ForceParams:
        return ForceParams(ids=self.id_array(scene), force=np.array(self.force._a, dtype=np.float64), torque=_ZERO3)


class TorqueEngine(PartialEngine):
    """Add a constant torque to the listed bodies every step (YADE ``TorqueEngine``)."""

    stage = "granum.kernels.forces:force_stage"
    _attrs = {"moment": Attr(Vector3(0, 0, 0), "Torque added to each body [N m]", to_vec3)}

    def params(self, scene, engines) -> ForceParams:
        return ForceParams(ids=self.id_array(scene), force=_ZERO3, torque=np.array(self.moment._a, dtype=np.float64))


class InterpolatingDirectedForceEngine(ForceEngine):
    """A ForceEngine whose force is ``direction`` times a magnitude interpolated linearly in ``times``/
    ``magnitudes`` at each step's time (the first value before the first time, the last after the last; with
    ``wrap`` the time goes round the table); ``force`` reports the last step's force."""

    stage = "granum.kernels.fields:interpolated_force_stage"
    _attrs = {
        "times": Attr([], "Times of the table, not decreasing [s]", _floats("times")),
        "magnitudes": Attr([], "Force magnitudes at those times [N]", _floats("magnitudes")),
        "direction": Attr(Vector3(1, 0, 0), "Direction of the force (normalised when assigned)", to_axis),
        "wrap": Attr(False, "Wrap the time around the table", to_bool),
    }

    def __init__(self, **kw):
        object.__setattr__(self, "_force", np.zeros(3))  # the storage of force, written by the stage
        super().__init__(**kw)

    @property
    def force(self) -> Vector3:
        return Vector3(*self._force)

    @force.setter
    def force(self, value) -> None:
        self._force[:] = to_vec3(self, value)._a

    def params(self, scene, engines) -> InterpolatedForceParams:
        return InterpolatedForceParams(ids=self.id_array(scene), wrap=bool(self.wrap), force=self._force,
                                       table=_table(self, self.times, self.magnitudes, ("times", "magnitudes")),
                                       direction=_unit(self, "direction", self.direction))


def _rotation(owner, value) -> Quaternion:
    return Quaternion(*as_quat_wxyz(value)).normalized()


class StepDisplacer(PartialEngine):
    """Move the listed bodies by ``mov`` and turn them by ``rot`` every step, or with ``setVelocities`` give them
    the velocities that do so over the step (YADE ``StepDisplacer``)."""

    stage = "granum.kernels.fields:step_displacer_stage"
    _attrs = {
        "mov": Attr(Vector3(0, 0, 0), "Displacement per step [m]", to_vec3),
        "rot": Attr(Quaternion(1, 0, 0, 0), "Rotation per step (normalised when assigned)", _rotation),
        "setVelocities": Attr(False, "Impose velocities instead of moving the bodies", to_bool),
    }

    def params(self, scene, engines) -> StepDisplacerParams:
        return StepDisplacerParams(ids=self.id_array(scene), move=np.array(self.mov._a, dtype=np.float64),
                                   rotation=np.array(self.rot._a, dtype=np.float64),
                                   set_velocities=bool(self.setVelocities))


class DragEngine(PartialEngine):
    """Quadratic drag on the listed spheres: F = -rho Cd / 2 |v| v pi r^2 (YADE ``DragEngine``; other shapes
    are left alone)."""

    stage = "granum.kernels.fields:drag_stage"
    _attrs = {
        "Rho": Attr(1.225, "Density of the medium [kg/m^3] (air)", _non_negative("Rho")),
        "Cd": Attr(0.47, "Drag coefficient (a sphere's)", _non_negative("Cd")),
    }

    def params(self, scene, engines) -> DragParams:
        return DragParams(ids=self.id_array(scene), quadratic=0.5 * self.Rho * self.Cd, linear=0.0)


class LinearDragEngine(PartialEngine):
    """Stokes drag on the listed spheres: F = -6 pi nu r v (YADE ``LinearDragEngine``; other shapes are left
    alone)."""

    stage = "granum.kernels.fields:drag_stage"
    _attrs = {"nu": Attr(0.001, "Viscosity of the medium [Pa s]", _non_negative("nu"))}

    def params(self, scene, engines) -> DragParams:
        return DragParams(ids=self.id_array(scene), quadratic=0.0, linear=6.0 * math.pi * self.nu)


class AxialGravityEngine(GlobalEngine):
    """An acceleration of constant magnitude towards an axis, on every body the mask selects (YADE
    ``AxialGravityEngine``)."""

    stage = "granum.kernels.fields:axial_gravity_stage"
    _attrs = {
        "axisPoint": Attr(Vector3(0, 0, 0), "A point of the axis [m]", to_vec3),
        "axisDirection": Attr(Vector3(1, 0, 0), "Direction of the axis (normalised when assigned)", to_axis),
        "acceleration": Attr(0.0, "Acceleration towards the axis [m/s^2]", to_float("acceleration")),
        "mask": Attr(0, "Only bodies sharing a bit with this mask (0: all)", to_int("mask")),
    }

    def params(self, scene, engines) -> AxialGravityParams:
        return AxialGravityParams(point=np.array(self.axisPoint._a, dtype=np.float64),
                                  axis=_unit(self, "axisDirection", self.axisDirection),
                                  acceleration=float(self.acceleration), mask=int(self.mask))


class CentralConstantAccelerationEngine(GlobalEngine):
    """An acceleration of constant magnitude towards ``centralBody``, on every other body the mask selects;
    with ``reciprocal`` the central body gets the opposite forces (YADE ``CentralConstantAccelerationEngine``)."""

    stage = "granum.kernels.fields:central_acceleration_stage"
    _attrs = {
        "centralBody": Attr(-1, "Id of the body the others are drawn to", to_int("centralBody")),
        "accel": Attr(0.0, "Acceleration towards the central body [m/s^2]", to_float("accel")),
        "reciprocal": Attr(False, "Apply the opposite forces to the central body", to_bool),
        "mask": Attr(0, "Only bodies sharing a bit with this mask (0: all)", to_int("mask")),
    }

    def params(self, scene, engines) -> CentralAccelerationParams:
        c = int(self.centralBody)
        if not 0 <= c < scene.body_count or not scene.bodies.alive[c]:
            raise IndexError(f"CentralConstantAccelerationEngine.centralBody: no body {c}")
        return CentralAccelerationParams(central=c, accel=float(self.accel), reciprocal=bool(self.reciprocal),
                                         mask=int(self.mask))
