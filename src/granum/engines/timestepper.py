"""Time steppers: engines that set O.dt while a simulation runs (YADE's ``TimeStepper`` family).

``O.dynDt`` reads whether a live TimeStepper in O.engines is ``active`` and switches them on or off.
"""

from __future__ import annotations

import functools

import numpy as np

from granum.core.attrs import Attr, only_default, to_bool, to_float, to_int
from granum.engines.base import GlobalEngine
from granum.kernels import timestep as k
from granum.kernels.dispatch import code_of, functors
from granum.physics import registry


class TimeStepper(GlobalEngine):
    """Base of the engines that set O.dt (YADE ``TimeStepper``)."""

    _attrs = {
        "active": Attr(True, "Whether the stepper sets O.dt (``O.dynDt`` switches it)", to_bool),
        "timeStepUpdateInterval": Attr(1, "Update O.dt at the steps whose O.iter is a multiple of this [-]",
                                       to_int("timeStepUpdateInterval", minimum=1)),
    }


@functools.lru_cache(maxsize=8)
def _viscel_phys(nphys: int) -> np.ndarray:
    """1 for each Ip2 functor code (``I_PHYS``) whose contacts are ViscElPhys (or derived), (nphys,) uint8;
    ``nphys`` keys the functors registered (user laws may add some)."""
    out = np.zeros(max(nphys, 1), np.uint8)
    for spec in functors("phys"):
        if "ViscElPhys" in registry.phys_ancestry(spec.produces):
            out[code_of(spec.yade_name)] = 1
    return out


@functools.lru_cache(maxsize=8)
def _rot_columns(nphys: int) -> np.ndarray:
    """The contact columns of the rolling and twisting stiffnesses ``kr``, ``ktw`` for each Ip2 functor code
    whose contacts are RotStiffFrictPhys (CohFrictPhys, MindlinPhys), -1 for the others, (nphys, 2) int64."""
    out = np.full((max(nphys, 1), 2), -1, np.int64)
    for spec in functors("phys"):
        if "RotStiffFrictPhys" not in registry.phys_ancestry(spec.produces):
            continue
        fields = registry.type_fields(registry.PHYS_TYPES, spec.produces)
        missing = [name for name in ("kr", "ktw") if name not in fields]
        if missing:
            raise TypeError(f"GlobalStiffnessTimeStepper: {spec.produces} (made by {spec.yade_name}) is a "
                            f"RotStiffFrictPhys without the field(s) {missing}: declare the columns of its rolling "
                            f"and twisting stiffnesses")
        out[code_of(spec.yade_name)] = (fields["kr"][0], fields["ktw"][0])
    return out


class GlobalStiffnessTimeStepper(TimeStepper):
    """O.dt from each body's contact stiffness (see :mod:`granum.kernels.timestep` for the formula).

    Every ``timeStepUpdateInterval`` steps O.dt becomes ``timestepSafetyCoefficient`` times the smallest
    critical step of the free bodies, at most 1.05 times the previous computed step and at most ``maxDt``;
    before any contact it is ``defaultDt`` (or the safety coefficient times PWaveTimeStep() when
    ``defaultDt`` is negative).
    """

    stage = "granum.kernels.timestep:stiffness_time_step_stage"
    _attrs = {
        "timestepSafetyCoefficient": Attr(0.8, "Safety coefficient s on the critical step [-]",
                                          to_float("timestepSafetyCoefficient", positive=True)),
        "defaultDt": Attr(-1.0, "O.dt before any contact [s] (negative: s·PWaveTimeStep())",
                          to_float("defaultDt", allow_nan=False)),
        "maxDt": Attr(float(k.NEVER), "Largest step [s]", to_float("maxDt", positive=True)),
        "viscEl": Attr(False, "Also count the dashpots of ViscElPhys contacts (cn, cs)", to_bool),
        "densityScaling": Attr(False, "Scale the bodies' densities so that their steps are targetDt "
                                      "(not implemented yet: only False)", only_default("densityScaling", False)),
        "targetDt": Attr(1.0, "Step that densityScaling aims at [s] (no effect without densityScaling)",
                         to_float("targetDt")),
        "parallelMode": Attr(False, "MPI mode (not implemented: only False)", only_default("parallelMode", False)),
    }

    def __init__(self, **kw):
        object.__setattr__(self, "_state", np.array([k.NEVER]))
        super().__init__(**kw)

    @property
    def previousDt(self) -> float:
        """The last step the stepper computed [s] (the largest double before any)."""
        return float(self._state[0])

    @previousDt.setter
    def previousDt(self, value) -> None:
        self._state[0] = to_float("previousDt", allow_nan=False)(self, value)

    def params(self, scene, engines) -> k.TimeStepperParams:
        return k.TimeStepperParams(
            active=bool(self.active), interval=int(self.timeStepUpdateInterval),
            safety=float(self.timestepSafetyCoefficient), default_dt=float(self.defaultDt),
            max_dt=float(self.maxDt), visc_el=bool(self.viscEl),
            viscel_phys=_viscel_phys(len(functors("phys"))), rot_columns=_rot_columns(len(functors("phys"))),
            state=self._state)
