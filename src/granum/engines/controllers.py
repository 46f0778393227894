"""Boundary controllers of the periodic cell: PeriTriaxController (stress/strain control), PeriIsoCompressor
(isotropic compression through a series of stresses)."""

from __future__ import annotations

import math

import numpy as np

from granum.core.attrs import Attr, as_number, to_bool, to_float, to_int, to_str
from granum.engines.base import GlobalEngine
from granum.engines.pipeline import to_vec3
from granum.kernels import controllers as k
from granum.kernels import periiso as pk
from granum.mathtypes import Matrix3, Vector3


def _mask(owner, value):
    value = int(value)
    if not 0 <= value <= 7:
        raise ValueError(f"{type(owner).__name__}.stressMask must be in 0..7 (bit k: axis k stress-controlled), "
                         f"got {value}")
    return value


class PeriTriaxController(GlobalEngine):
    """Drive the periodic cell to mixed stress/strain goals (see :mod:`granum.kernels.controllers`).

    Bit k of ``stressMask`` makes ``goal[k]`` a stress [Pa] (compression negative),
    otherwise a logarithmic strain [-]. ``doneHook`` (Python source, run in the
    script's namespace) is executed after each step in which the goal is reached
    and the unbalanced force is below ``maxUnbalanced``.
    """

    stage = "granum.kernels.controllers:peri_triax_stage"
    _attrs = {
        "goal": Attr(Vector3(0, 0, 0), "Goal stresses [Pa] or strains [-] per axis", to_vec3),
        "stressMask": Attr(0, "Bit k set: axis k is stress-controlled", _mask),
        "maxStrainRate": Attr(Vector3(1, 1, 1), "Largest strain rate per axis [1/s]", to_vec3),
        "maxUnbalanced": Attr(1e-4, "Largest unbalanced force for the goal to count as reached [-]",
                              to_float("maxUnbalanced")),
        "absStressTol": Attr(1e3, "Absolute stress tolerance [Pa]", to_float("absStressTol")),
        "relStressTol": Attr(3e-5, "Relative stress tolerance [-]", to_float("relStressTol")),
        "growDamping": Attr(0.25, "Damping of the cell's motion (0: none, 1: no motion)", to_float("growDamping")),
        "globUpdate": Attr(5, "Recompute the stress every this many steps", to_int("globUpdate")),
        "doneHook": Attr("", "Python source run when the goal is reached", to_str("doneHook")),
        "dynCell": Attr(False, "Let the cell obey an equation of motion with mass ``mass``", to_bool),
        "mass": Attr(float("nan"), "Inertia of the cell's strain rate, d rate/dt = (goal - stress)/mass [Pa s^2] "
                                          "(default: the mass of all bodies)", to_float("mass")),
    }

    @property
    def externalWork(self) -> float:
        """The work of the cell on the packing (YADE); not computed by granum yet."""
        raise NotImplementedError("PeriTriaxController.externalWork is not computed by granum yet")

    def __init__(self, **kw):
        super().__init__(**kw)
        object.__setattr__(self, "_out", np.full(k.O_SIZE, np.nan))

    def params(self, scene, engines) -> k.PeriTriaxParams:
        if not scene.periodic:
            raise RuntimeError("PeriTriaxController needs a periodic scene (O.periodic = True)")
        mass = self.mass
        if not mass > 0:
            b = scene.bodies
            mass = float(b.mass[: b.count][b.alive[: b.count]].sum())
        return k.PeriTriaxParams(
            goal=np.array(self.goal._a), stress_mask=int(self.stressMask), max_rate=np.array(self.maxStrainRate._a),
            max_unbalanced=float(self.maxUnbalanced), abs_tol=float(self.absStressTol),
            rel_tol=float(self.relStressTol), grow_damping=float(self.growDamping), glob_update=int(self.globUpdate),
            dyn_cell=bool(self.dynCell), mass=float(mass), hook_id=int(self._plan_index), out=self._out)

    def run_hook(self, omega) -> None:
        if self.doneHook:
            exec(self.doneHook, omega.namespace())

    def _vec(self, first: int) -> Vector3:
        return Vector3(*self._out[first:first + 3])

    @property
    def stress(self) -> Vector3:
        """Diagonal of the stress tensor [Pa] (compression negative)."""
        return self._vec(k.O_STRESS)

    @property
    def strain(self) -> Vector3:
        """Logarithmic strain ln F_kk since ``O.cell.trsf`` was last reset [-]."""
        return self._vec(k.O_STRAIN)

    @property
    def strainRate(self) -> Vector3:
        return self._vec(k.O_RATE)

    @property
    def stiff(self) -> Vector3:
        """Stiffness moduli of the contact network per axis [Pa]."""
        return self._vec(k.O_STIFF)

    @property
    def stressTensor(self) -> Matrix3:
        return Matrix3(*self._out[k.O_TENSOR:k.O_TENSOR + 9])

    @property
    def currUnbalanced(self) -> float:
        return float(self._out[k.O_UNBALANCED])


def _stresses(owner, value):
    try:
        values = [as_number(v, f"{type(owner).__name__}.stresses") for v in value]
    except TypeError:
        if isinstance(value, str) or not hasattr(value, "__iter__"):
            raise TypeError(f"{type(owner).__name__}.stresses must be a list of stresses [Pa], got {value!r}") from None
        raise
    bad = [v for v in values if not (math.isfinite(v) and v != 0.0)]
    if bad:
        raise ValueError(f"{type(owner).__name__}.stresses must be finite and non-zero (a relative tolerance is "
                         f"taken on each), got {bad[0]!r}")
    return values


def _iso_state(slot: int, doc: str, convert=None):
    """A value of PeriIsoCompressor's state array exposed as an attribute (writable when ``convert``)."""

    def get(self):
        v = float(self._out[slot])
        return int(v) if slot == pk.P_STATE else v

    def set_(self, value):
        self._out[slot] = convert(self, value)

    return property(get, set_ if convert else None, doc=doc)


class PeriIsoCompressor(GlobalEngine):
    """Compress (or decompress) a periodic cloud by resizing the cell until the mean stress reaches each of
    ``stresses`` in turn, then run ``doneHook`` (see :mod:`granum.kernels.periiso` for the servo).

    A failure of the servo (a cell smaller than 2.1 ``maxSpan``) raises RuntimeError after the step.
    """

    stage = "granum.kernels.periiso:peri_iso_stage"
    _attrs = {
        "stresses": Attr([], "Stresses to reach, one after another [Pa] (compression negative)", _stresses),
        "maxUnbalanced": Attr(1e-4, "Unbalanced force below which the packing counts as stable [-]",
                              to_float("maxUnbalanced", allow_nan=False)),
        "globalUpdateInt": Attr(20, "Recompute the unbalanced force every this many steps",
                                to_int("globalUpdateInt", minimum=1)),
        "doneHook": Attr("", "Python source run when the last stress is reached", to_str("doneHook")),
        "keepProportions": Attr(True, "Control the mean stress and keep the cell's proportions", to_bool),
    }

    def __init__(self, **kw):
        out = np.zeros(pk.P_SIZE)
        out[[pk.P_UNBALANCED, pk.P_CHARLEN, pk.P_MAXSPAN]] = -1.0
        object.__setattr__(self, "_out", out)
        super().__init__(**kw)

    charLen = _iso_state(pk.P_CHARLEN, "Characteristic length [m] (the mean particle diameter; -1: from the "
                                       "bound of body 0 at the first step)", to_float("charLen", allow_nan=False))
    maxSpan = _iso_state(pk.P_MAXSPAN, "Largest extent of a bound [m], which the cell stays 2.1 times larger "
                                       "than (-1: measured at the first step)", to_float("maxSpan", allow_nan=False))
    state = _iso_state(pk.P_STATE, "Index of the stress being reached in ``stresses``",
                       to_int("state", minimum=0))
    currUnbalanced = _iso_state(pk.P_UNBALANCED, "The last unbalanced force computed [-] (-1: none yet)")

    @property
    def sigma(self) -> Vector3:
        """Stress per axis [Pa]: the sum of |contact force| components over the face area, negative."""
        return Vector3(*self._out[pk.P_SIGMA:pk.P_SIGMA + 3])

    def params(self, scene, engines) -> pk.PeriIsoParams:
        if not scene.periodic:
            raise RuntimeError("PeriIsoCompressor needs a periodic scene (O.periodic = True)")
        return pk.PeriIsoParams(
            stresses=np.array(self.stresses, dtype=np.float64), max_unbalanced=float(self.maxUnbalanced),
            global_update_int=int(self.globalUpdateInt), keep_proportions=bool(self.keepProportions),
            hook_id=int(self._plan_index), out=self._out)

    def run_hook(self, omega) -> None:
        error = int(self._out[pk.P_ERROR])
        if error:
            self._out[pk.P_ERROR] = 0
            raise RuntimeError(_ISO_ERRORS[error])
        if self.doneHook:
            exec(self.doneHook, omega.namespace())


_ISO_ERRORS = {   # YADE's messages
    pk.ERR_NO_BOUND: "PeriIsoCompressor: body 0 has no bound to take charLen from; set charLen",
    pk.ERR_CELL_SMALL: "Minimum cell size is smaller than 2.1*span_of_the_biggest_body! (periodic collider "
                       "requirement)",
    pk.ERR_NO_SHRINK: "Unable to shrink cell due to maximum body size (although required by stress condition). "
                      "Increase particle rigidity, increase total sample dimensions, or decrease goal stress.",
}
