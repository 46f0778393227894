"""YADE's simple-shear box engines: KinemSimpleShearBox (their base) and KinemCTDEngine, KinemCNDEngine,
KinemCNLEngine, KinemCNSEngine (see :mod:`granum.kernels.simple_shear` for what a step does)."""

from __future__ import annotations

import math
import warnings

import numpy as np

from granum.core.attrs import Attr, as_flag, as_integer, only_default, to_float, to_str
from granum.core.shapes import ShapeKind
from granum.engines.base import GlobalEngine
from granum.engines.triaxial import _state
from granum.kernels import simple_shear as k

#: YADE's attributes naming the boxes, in the order of the stage's ``boxes``
BOX_IDS = ("id_boxleft", "id_boxbas", "id_boxright", "id_topbox", "id_boxback", "id_boxfront")


def _body_id(name: str):
    def convert(owner, value):
        return as_integer(value, f"{type(owner).__name__}.{name}")

    return convert


def _floats(name: str):
    def convert(owner, value):
        convert_one = to_float(f"{name}[]", allow_nan=False)
        return [convert_one(owner, v) for v in value]

    return convert


def _no_saves(name: str):
    """The save list ``name``: the checkpoints YADE writes there are not implemented in granum, so a non-empty
    list is refused by name."""

    def convert(owner, value):
        values = _floats(name)(owner, value)
        if values:
            raise NotImplementedError(f"{type(owner).__name__}.{name}={values!r}: the checkpoints the engine writes "
                                      "at these values are not implemented in granum (only [])")
        return values

    return convert


class KinemSimpleShearBox(GlobalEngine):
    """The simple-shear box: six boxes (``id_boxleft``, ``id_boxbas``, ``id_boxright``, ``id_topbox``,
    ``id_boxback``, ``id_boxfront``) whose top box an engine of this family moves, the lateral boxes following
    it. A base: as in YADE, it refuses to run by itself."""

    stage = "granum.kernels.simple_shear:simple_shear_stage"
    #: the stage's mode (None: the base, which does not run)
    _mode: int | None = None
    _attrs = {
        "id_boxleft": Attr(0, "Id of the left box", _body_id("id_boxleft")),
        "id_boxbas": Attr(1, "Id of the lower box", _body_id("id_boxbas")),
        "id_boxright": Attr(2, "Id of the right box", _body_id("id_boxright")),
        "id_topbox": Attr(3, "Id of the upper box (the one moved)", _body_id("id_topbox")),
        "id_boxback": Attr(4, "Id of the box at the back of the sample", _body_id("id_boxback")),
        "id_boxfront": Attr(5, "Id of the box in front of the sample", _body_id("id_boxfront")),
        "max_vel": Attr(1.0, "Bound of the top box's vertical speed under CNL and CNS [m/s]",
                        to_float("max_vel", allow_nan=False)),
        "wallDamping": Attr(0.2, "Damping of the top box's vertical moves under CNL and CNS [-]",
                            to_float("wallDamping", allow_nan=False)),
        "temoin_save": Attr([], "Whether each save has been done (1) or not (0) (no saves in granum)",
                            _floats("temoin_save")),
        "LOG": Attr(False, "Messages on the screen at each step (not implemented in granum: refused)",
                    only_default("LOG", False)),
        "Key": Attr("", "String added to the names of the saved files", to_str("Key")),
    }

    def __init__(self, **kw):
        st = np.zeros(k.K_SIZE)
        st[k.K_ALPHA] = 0.5 * math.pi
        st[k.K_FIRST_RUN] = 1.0
        object.__setattr__(self, "_st", st)  # the stage's state (slots K_*)
        super().__init__(**kw)

    alpha = _state(k.K_ALPHA, "alpha: angle from the lower box to the left box, measured by the engine [rad]",
                   writable=True, array="_st")
    f0 = _state(k.K_F0, "f0: normal force on the top box at the first run (CNL, CNS) [N]", writable=True,
                array="_st")
    y0 = _state(k.K_Y0, "y0: height of the top box at the first run (CNL, CNS) [m]", writable=True, array="_st")

    @property
    def firstRun(self) -> bool:
        """Whether f0 and y0 are still to be measured (CNL, CNS)."""
        return bool(self._st[k.K_FIRST_RUN])

    @firstRun.setter
    def firstRun(self, value) -> None:
        self._st[k.K_FIRST_RUN] = float(as_flag(value, f"{type(self).__name__}.firstRun"))

    def dict(self) -> dict:
        d = super().dict()
        d.update(alpha=self.alpha, firstRun=self.firstRun, f0=self.f0, y0=self.y0)
        return d

    def _boxes(self, scene) -> np.ndarray:
        """The six box ids, checked: live boxes, all different."""
        name = type(self).__name__
        ids = [getattr(self, a) for a in BOX_IDS]
        for attr, i in zip(BOX_IDS, ids, strict=True):
            if not 0 <= i < scene.body_count or not scene.bodies.alive[i]:
                raise ValueError(f"{name}.{attr}={i}: no such body")
            if scene.bodies.shape_kind[i] != ShapeKind.BOX:
                raise ValueError(f"{name}.{attr}={i}: body {i} is not a Box")
        if len(set(ids)) != 6:
            raise ValueError(f"{name}: the six boxes must be different bodies, got " +
                             ", ".join(f"{a}={i}" for a, i in zip(BOX_IDS, ids, strict=True)))
        if not np.array_equal(scene.bodies.ori[ids[0]], scene.bodies.ori[ids[2]]):
            warnings.warn(f"{name}: the lateral boxes ({ids[0]} and {ids[2]}) have different orientations; the "
                          f"engine turns both by the angle of the left one", stacklevel=2)
        return np.array(ids, np.int64)

    def _shear(self) -> tuple[float, float, float, float]:
        """(speed [m/s], gammalim [m], targetSigma [kPa], KnC [Pa/m]) of the engine's mode."""
        raise NotImplementedError(f"{type(self).__name__} has no mode")

    def params(self, scene, engines) -> k.ShearBoxParams:
        if self._mode is None:
            raise RuntimeError(f"{type(self).__name__} must not be used in simulations directly (it is the base "
                               "of KinemCTDEngine, KinemCNDEngine, KinemCNLEngine and KinemCNSEngine)")
        speed, gamma_lim, target, stiffness = self._shear()
        return k.ShearBoxParams(boxes=self._boxes(scene), mode=self._mode, speed=speed, gamma_lim=gamma_lim,
                                target_sigma=target, stiffness=stiffness, max_vel=float(self.max_vel),
                                wall_damping=float(self.wallDamping), state=self._st,
                                hook_id=int(self._plan_index))

    def hook_due(self) -> bool:
        return self._st[k.K_SAVE_DUE] == 1.0

    def _save_name(self) -> str:
        """The file saved when the engine stops the boxes (CTD, CND)."""
        raise NotImplementedError(f"{type(self).__name__} saves nothing")

    def run_hook(self, omega) -> None:
        """The save of a step that stopped the boxes (YADE writes it during the step, granum at its end)."""
        if self._st[k.K_SAVE_DUE] != 1.0:
            return
        self._st[k.K_SAVE_DUE] = 0.0
        omega.save(self._save_name())


class KinemCTDEngine(KinemSimpleShearBox):
    """Compression (``compSpeed`` > 0) or unloading (< 0) of the box by moving its top box vertically at
    ``compSpeed`` [m/s] until the normal stress on it reaches ``targetSigma`` [kPa]; the lateral boxes follow."""

    _mode = k.MODE_CTD
    _attrs = {
        "compSpeed": Attr(0.0, "Vertical speed of the top box: > 0 compresses, < 0 unloads [m/s]",
                          to_float("compSpeed", allow_nan=False)),
        "targetSigma": Attr(0.0, "Normal stress at which the top box stops [kPa]",
                            to_float("targetSigma", allow_nan=False)),
        "sigma_save": Attr([], "Stresses at which YADE saves the simulation [kPa] (not implemented: only [])",
                           _no_saves("sigma_save")),
    }

    def _shear(self):
        return self.compSpeed, 0.0, self.targetSigma, 0.0

    def _save_name(self) -> str:
        bound = "Sigmax_" if self.compSpeed > 0 else "Sigmin_"
        return f"{self.Key}{bound}{math.floor(self.targetSigma)}kPaReached.xml"


class _ShearEngine(KinemSimpleShearBox):
    """The shear engines' common part: the top box moves horizontally at ``shearSpeed`` [m/s] until ``gamma``
    (its horizontal displacement [m]) reaches ``gammalim``."""

    _attrs = {
        "shearSpeed": Attr(0.0, "Horizontal speed of the top box [m/s]", to_float("shearSpeed", allow_nan=False)),
        "gammalim": Attr(0.0, "Horizontal displacement of the top box at which the shear stops [m]",
                         to_float("gammalim", allow_nan=False)),
    }

    gamma = _state(k.K_GAMMA, "gamma: horizontal displacement of the top box so far [m]", writable=True,
                   array="_st")

    def dict(self) -> dict:
        d = super().dict()
        d["gamma"] = self.gamma
        return d

    def _stiffness(self) -> float:
        return 0.0

    def _shear(self):
        return self.shearSpeed, self.gammalim, 0.0, self._stiffness()


class KinemCNDEngine(_ShearEngine):
    """Constant normal displacement: the top box moves horizontally only."""

    _mode = k.MODE_CND
    _attrs = {"gamma_save": Attr([], "Values of gamma at which YADE saves the simulation [m] (not implemented: "
                                     "only [])", _no_saves("gamma_save"))}

    def _save_name(self) -> str:
        return f"{self.Key}endShear.xml"


class KinemCNLEngine(_ShearEngine):
    """Constant normal load: the top box also moves vertically to keep the normal force it had at the first
    run (``f0``)."""

    _mode = k.MODE_CNL
    _attrs = {"gamma_save": Attr([], "Values of gamma at which YADE saves the simulation [m] (not implemented: "
                                     "only [])", _no_saves("gamma_save"))}


class KinemCNSEngine(_ShearEngine):
    """Constant normal stiffness: the top box also moves vertically so that the normal force changes by
    ``KnC`` times the section times its vertical displacement since the first run."""

    _mode = k.MODE_CNS
    _attrs = {"KnC": Attr(10.0e6, "Normal stiffness imposed [MPa/mm] (10^9 Pa/m)", to_float("KnC", allow_nan=False))}

    def _stiffness(self) -> float:
        return self.KnC * 1e9
