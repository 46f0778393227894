"""Peri3dController: the six stress/strain components of a periodic cell along prescribed paths (see
:mod:`granum.kernels.peri3d` for the servo)."""

from __future__ import annotations

import numpy as np

from granum.core.attrs import Attr, as_number, to_float, to_int, to_str
from granum.engines.base import GlobalEngine
from granum.kernels import peri3d as k
from granum.mathtypes import Vector2, Vector6, Vector6i

PATHS = ("xxPath", "yyPath", "zzPath", "yzPath", "zxPath", "xyPath")


def _vec6(owner, value):
    try:
        return Vector6(*[as_number(v, f"{type(owner).__name__}.goal") for v in value])
    except TypeError as e:
        raise TypeError(f"{type(owner).__name__}: a 6-vector (xx, yy, zz, yz, zx, xy) is expected: {e}") from None


def _mask(owner, value):
    value = to_int("stressMask")(owner, value)
    if not 0 <= value <= 63:
        raise ValueError(f"{type(owner).__name__}.stressMask must be in 0..63 (bit k: component k of xx, yy, zz, yz, "
                         f"zx, xy is a stress), got {value}")
    return value


def _path(name):
    def convert(owner, value):
        try:
            points = [Vector2(*[as_number(x, f"{type(owner).__name__}.{name}") for x in pt]) for pt in value]
        except TypeError:
            raise TypeError(f"{type(owner).__name__}.{name} must be a list of (time, value) pairs, got {value!r}") \
                from None
        if not points:
            raise ValueError(f"{type(owner).__name__}.{name} must have at least one point")
        t = [float(pt[0]) for pt in points]
        if any(b < a for a, b in zip(t, t[1:], strict=False)) or not t[-1] > 0 or t[0] < 0:
            raise ValueError(f"{type(owner).__name__}.{name}: times must be non-negative, increasing, the last "
                             f"positive, got {t}")
        if float(points[-1][1]) == 0.0:
            raise ValueError(f"{type(owner).__name__}.{name}: the last value scales the path and must not be 0")
        return points
    return convert


def _state6(slot: int, doc: str, writable: bool = False):
    def get(self):
        return Vector6(*self._out[slot:slot + 6])

    def set_(self, value):
        self._out[slot:slot + 6] = np.asarray(_vec6(self, value)._a)

    return property(get, set_ if writable else None, doc=doc)


class Peri3dController(GlobalEngine):
    """Control the 6 stress/strain components of the periodic cell along paths (YADE's Peri3dController)."""

    stage = "granum.kernels.peri3d:peri3d_stage"
    _attrs = {
        "goal": Attr(Vector6(0, 0, 0, 0, 0, 0), "Final values (xx, yy, zz, yz, zx, xy): stresses [Pa] or "
                     "engineering strains [-] by stressMask", _vec6),
        "stressMask": Attr(0, "Bit k set: component k is a stress (order xx, yy, zz, yz, zx, xy)", _mask),
        "nSteps": Attr(1000, "Steps to reach the goal", to_int("nSteps", minimum=1)),
        "maxStrainRate": Attr(1e3, "Largest |strain rate| of a component [1/s]",
                              to_float("maxStrainRate", positive=True)),
        "maxStrain": Attr(1e6, "Largest |strain| of a component: beyond it the run is finished [-]",
                          to_float("maxStrain", positive=True)),
        "mod": Attr(0.1, "Step of the stress predictor, relative to the largest strain rate [-]",
                    to_float("mod", allow_nan=False)),
        "youngEstimation": Attr(1e20, "Young's modulus estimate for the first step [Pa]",
                                to_float("youngEstimation", positive=True)),
        "poissonEstimation": Attr(0.25, "Poisson's ratio estimate for the first step [-]",
                                  to_float("poissonEstimation", allow_nan=False)),
        "doneHook": Attr("", "Python source run when nSteps are done (empty: the engine becomes dead)",
                         to_str("doneHook")),
        **{name: Attr([Vector2(1, 1)], f"Path of {name[:2]}: (time, value) points relative to the last one",
                      _path(name)) for name in PATHS},
    }

    def __init__(self, **kw):
        object.__setattr__(self, "_out", np.zeros(k.Q_SIZE))
        super().__init__(**kw)

    stress = _state6(k.Q_STRESS, "Stress (xx, yy, zz, yz, zx, xy) [Pa]", writable=True)
    strain = _state6(k.Q_STRAIN, "Engineering strain (xx, yy, zz, yz, zx, xy) [-]", writable=True)
    strainRate = _state6(k.Q_RATE, "Strain rate [1/s]", writable=True)
    stressRate = _state6(k.Q_STRESS_RATE, "Prescribed stress rate [Pa/s]", writable=True)
    stressIdeal = _state6(k.Q_STRESS_IDEAL, "The stress the paths prescribe now [Pa]", writable=True)
    strainGoal = _state6(k.Q_STRAIN_GOAL, "The strain the paths prescribe now [-]")
    stressGoal = _state6(k.Q_STRESS_GOAL, "The stress the paths prescribe now [Pa]")

    @property
    def progress(self) -> float:
        """Fraction of nSteps done [-]."""
        return float(self._out[k.Q_PROGRESS])

    @progress.setter
    def progress(self, value) -> None:
        self._out[k.Q_PROGRESS] = to_float("progress", allow_nan=False)(self, value)

    @property
    def pathSizes(self) -> Vector6i:
        return Vector6i(*[len(getattr(self, n)) for n in PATHS])

    @property
    def ps(self) -> Vector6i:
        """Indices of the stress components, then zeros."""
        idx = [i for i in range(6) if self.stressMask >> i & 1]
        return Vector6i(*(idx + [0] * (6 - len(idx))))

    @property
    def pe(self) -> Vector6i:
        """Indices of the strain components, then zeros."""
        idx = [i for i in range(6) if not self.stressMask >> i & 1]
        return Vector6i(*(idx + [0] * (6 - len(idx))))

    @property
    def lenPs(self) -> int:
        return bin(self.stressMask).count("1")

    @property
    def lenPe(self) -> int:
        return 6 - self.lenPs

    def params(self, scene, engines) -> k.Peri3dParams:
        if not scene.periodic:
            raise RuntimeError("Peri3dController needs a periodic scene (O.periodic = True)")
        paths = [np.array([list(pt) for pt in getattr(self, n)], dtype=float) for n in PATHS]
        size = max(len(p) for p in paths)
        table = np.zeros((6, size, 2))
        for i, p in enumerate(paths):
            table[i, :len(p)] = p
        return k.Peri3dParams(
            goal=np.array(self.goal._a), stress_mask=int(self.stressMask), n_steps=int(self.nSteps),
            max_strain_rate=float(self.maxStrainRate), max_strain=float(self.maxStrain), mod=float(self.mod),
            young=float(self.youngEstimation), poisson=float(self.poissonEstimation), paths=table,
            path_len=np.array([len(p) for p in paths], np.int64), hook_id=int(self._plan_index), out=self._out)

    def run_hook(self, omega) -> None:
        if self.doneHook:
            exec(self.doneHook, omega.namespace())
        else:
            self.dead = True
