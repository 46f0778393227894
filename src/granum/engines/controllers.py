"""Boundary controllers: PeriTriaxController (stress/strain control of the periodic cell)."""

from __future__ import annotations

import numpy as np

from granum.core.attrs import Attr, to_bool, to_float, to_int, to_str
from granum.engines.base import GlobalEngine
from granum.engines.pipeline import to_vec3
from granum.kernels import controllers as k
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
        "mass": Attr(float("nan"), "Mass of the cell [kg] (default: the mass of all bodies)", to_float("mass")),
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
