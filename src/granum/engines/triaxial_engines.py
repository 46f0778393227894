"""TriaxialCompressionEngine: YADE's triaxial test as a state machine (isotropic compaction, unloading, loading)
around TriaxialStressController's wall servo (see :mod:`granum.kernels.triaxial_engines`)."""

from __future__ import annotations

import math
import os

import numpy as np

from granum.core.attrs import Attr, as_integer, as_number, to_bool, to_float, to_int, to_str
from granum.core.bodies import DOF_ALL
from granum.core.contacts import C_CONTACTS, F_TANPHI, FLAG_ALIVE, I_FLAGS, I_ID1, I_ID2
from granum.core.shapes import ShapeKind
from granum.engines.pipeline import NewtonIntegrator, to_vec3
from granum.engines.triaxial import WALLS, TriaxialStressController, _fraction, _state
from granum.kernels import triaxial_engines as k
from granum.mathtypes import Vector3

#: the scene a method called from a script acts on (set by the YADE layer: O's current scene)
scene_source = None


def _current_state(owner, value) -> float:
    s = as_integer(value, f"{type(owner).__name__}.currentState")
    if not 0 <= s < len(k.STATE_NAMES):
        raise ValueError(f"{type(owner).__name__}.currentState must be one of "
                         f"{', '.join(f'{i} ({n})' for i, n in enumerate(k.STATE_NAMES))}; got {s}")
    return float(s)


def _tc(slot: int, doc: str, convert=None):
    """A writable float of the engine's state array ``_tc``; with ``convert`` (the setter's check) an int, a
    state."""
    if convert is None:
        return _state(slot, doc, writable=True, array="_tc")

    def get(self):
        return int(self._tc[slot])

    def set_(self, value):
        self._tc[slot] = convert(self, value)

    return property(get, set_, doc=doc)


def contact_friction(scene, degrees: float) -> None:
    """YADE's setContactProperties: the friction angle of the materials of the dynamic bodies becomes
    ``degrees``, and tan φ of every live contact becomes tan(min(φ1, φ2)) of its two bodies' materials."""
    angle = math.radians(degrees)
    b = scene.bodies
    n = scene.body_count
    mats = scene.materials
    for m in {int(i) for i in b.material[:n][b.alive[:n] & (b.blocked[:n] != DOF_ALL)]}:
        if not hasattr(mats[m], "frictionAngle"):
            raise TypeError(f"setContactProperties: the material {type(mats[m]).__name__} of dynamic bodies has no "
                            "frictionAngle")
        mats[m].frictionAngle = angle
    C = scene.contacts
    rows = np.nonzero(C.con_i[:C.ctr[C_CONTACTS], I_FLAGS] & FLAG_ALIVE)[0]
    phi = np.array([getattr(m, "frictionAngle", math.nan) for m in mats])
    for end in (I_ID1, I_ID2):
        if np.isnan(phi[b.material[C.con_i[rows, end]]]).any():
            raise TypeError("setContactProperties: a contact's body has a material without frictionAngle")
    p1 = phi[b.material[C.con_i[rows, I_ID1]]]
    p2 = phi[b.material[C.con_i[rows, I_ID2]]]
    C.con_f[rows, F_TANPHI] = np.tan(np.minimum(p1, p2))


def spheres_file(scene, path: str) -> None:
    """Write ``x y z r`` of each dynamic sphere, one a line (6 significant digits, as YADE's .spheres files)."""
    b = scene.bodies
    n = scene.body_count
    ids = np.nonzero(b.alive[:n] & (b.shape_kind[:n] == int(ShapeKind.SPHERE)) & (b.blocked[:n] != DOF_ALL))[0]
    r = scene.shapes[ShapeKind.SPHERE].radius[b.shape_row[ids]]
    with open(path, "w") as f:
        for p, rad in zip(b.pos[ids], r, strict=True):
            f.write(f"{p[0]:g} {p[1]:g} {p[2]:g} {rad:g}\n")


class _ServoEngine(TriaxialStressController):
    """An engine whose stage changes the servo's goals, walls' activation and ``internalCompaction`` during a run:
    the stage works on copies (``_goal``, ``_active``, ``_tc[TC_INTERNAL]``), rewritten from the attributes when
    they were set from Python, and copied back to them by the hook the stage asks for."""

    def __init__(self, **kw):
        object.__setattr__(self, "_tc", np.zeros(k.TC_SIZE))
        object.__setattr__(self, "_goal", np.zeros(3))
        object.__setattr__(self, "_active", np.ones(6, np.uint8))
        object.__setattr__(self, "_synced", None)
        super().__init__(**kw)

    def setContactProperties(self, frictionDegree) -> None:
        """Set the friction angle [deg] of the dynamic bodies' materials and of the live contacts."""
        if scene_source is None:
            raise RuntimeError("setContactProperties: no scene (use it from the YADE namespace)")
        contact_friction(scene_source(), as_number(frictionDegree, "setContactProperties(frictionDegree)"))

    def _servo_attrs(self) -> tuple:
        """The attributes the stage changes (its copies: ``_goal``, ``_active``, ``_tc``), as plain values."""
        return (float(self.goal1), float(self.goal2), float(self.goal3),
                tuple(int(a) for a in self.activated()), bool(self.internalCompaction))

    def servo_copies(self, scene):
        """The servo's parameters on the stage's copies, rewritten first from attributes set from Python."""
        if self._servo_attrs() != self._synced:
            self._goal[:] = [self.goal1, self.goal2, self.goal3]
            self._active[:] = self.activated()
            self._tc[k.TC_INTERNAL] = float(self.internalCompaction)
            object.__setattr__(self, "_synced", self._servo_attrs())
        return self.servo_params(scene, self._goal, self._active)

    def run_hook(self, omega) -> None:
        """After a step the stage flagged: the attributes it changed, the friction (and the subclass' work)."""
        events = int(self._tc[k.TC_EVENTS])
        self._tc[k.TC_EVENTS] = 0.0
        if events & k.EV_SYNC:
            self.goal1, self.goal2, self.goal3 = (float(g) for g in self._goal)
            for w, on in zip(WALLS, self._active, strict=True):
                setattr(self, f"wall_{w}_activated", bool(on))
            self.internalCompaction = bool(self._tc[k.TC_INTERNAL])
            object.__setattr__(self, "_synced", self._servo_attrs())
        if events & k.EV_FRICTION and self.frictionAngleDegree > 0:
            contact_friction(omega._scene, self.frictionAngleDegree)
        self.after_hook(omega, events)

    def after_hook(self, omega, events: int) -> None:
        """The subclass' part of the hook (``events``: the stage's EV_* bits)."""


class TriaxialCompressionEngine(_ServoEngine):
    """YADE's triaxial test engine: compact the sample in its six walls to ``sigmaIsoCompaction``, unload to
    ``sigmaLateralConfinement``, then compress it along y at ``strainRate`` under that lateral stress (see
    :mod:`granum.kernels.triaxial_engines` for the states and their transitions).

    Stresses are in Pa (compression negative), ``strainRate`` in 1/s (positive compresses). At the end of the
    compaction and of the unloading the scene is saved as ``<Key>_Compacted_<iter>_<state>.xml`` and
    ``<Key>_Unloaded_<iter>_<state>.xml`` (with ``.spheres`` files; none with ``noFiles``); ``O.reload()``
    then reloads the last one. granum saves the scene at the end of the transition's step (YADE: during it).
    """

    stage = "granum.kernels.triaxial_engines:compression_stage"
    _attrs = {
        "sigmaIsoCompaction": Attr(1.0, "Isotropic stress of the compaction [Pa] (< 0: compression)",
                                   to_float("sigmaIsoCompaction", allow_nan=False)),
        "sigmaLateralConfinement": Attr(1.0, "Lateral stress of the triaxial loading [Pa] (< 0: compression)",
                                        to_float("sigmaLateralConfinement", allow_nan=False)),
        "strainRate": Attr(0.0, "Goal strain rate of the loading [1/s] (> 0: compression)",
                           to_float("strainRate", allow_nan=False)),
        "StabilityCriterion": Attr(0.001, "Unbalanced force below which a stage may end [-]",
                                   to_float("StabilityCriterion", allow_nan=False)),
        "testEquilibriumInterval": Attr(20, "Steps between the checks of the stages' ends",
                                        to_int("testEquilibriumInterval", minimum=1)),
        "autoUnload": Attr(True, "Unload to sigmaLateralConfinement after the compaction", to_bool),
        "autoCompressionActivation": Attr(True, "Start the loading after the compaction (or unloading)", to_bool),
        "autoStopSimulation": Attr(False, "Stop the simulation in STATE_LIMBO (YADE 2023.02a never enters it: "
                                          "no effect, as there)", to_bool),
        "isAxisymetric": Attr(True, "The three goals follow sigma_iso at every step", to_bool),
        "epsilonMax": Attr(0.5, "|axial strain| at which the loading walls stop [-]",
                           to_float("epsilonMax", allow_nan=False)),
        "uniaxialEpsilonCurr": Attr(1.0, "Kept for YADE's scripts (YADE 2023.02a never updates it: 1)",
                                    to_float("uniaxialEpsilonCurr")),
        "translationAxis": Attr(Vector3(0, 1, 0), "Direction of the loading (the top wall moves against it)",
                                to_vec3),
        "frictionAngleDegree": Attr(-1.0, "Friction angle set at the end of the compaction [deg] (<= 0: kept)",
                                    to_float("frictionAngleDegree", allow_nan=False)),
        "fixedPoroCompaction": Attr(0.0, "Compaction to fixedPorosity (not implemented in granum: refused)",
                                    lambda o, v: as_number(v, f"{type(o).__name__}.fixedPoroCompaction")),
        "fixedPorosity": Attr(0.0, "Goal porosity of fixedPoroCompaction [-]",
                              to_float("fixedPorosity", allow_nan=False)),
        "Key": Attr("", "Appended to the names of the files written", to_str("Key")),
        "noFiles": Attr(False, "Write no file", to_bool),
        "warn": Attr(0, "Counter of YADE's deprecation warning", to_int("warn")),
    }

    def __init__(self, **kw):
        super().__init__(**kw)
        self._tc[k.TC_UNBALANCED] = 1.0

    currentState = _tc(k.TC_STATE, "currentState: 0 (not started), 1 compaction, 2 unloading, 3 loading, "
                                   "4 fixed-porosity compaction, 5 limbo", _current_state)
    previousState = _tc(k.TC_PREV_STATE, "previousState: the state of the last step (a differing currentState "
                                         "set from Python is entered at the next step)", _current_state)
    UnbalancedForce = _tc(k.TC_UNBALANCED, "UnbalancedForce: mean resultant over mean contact force [-]")
    maxStress = _tc(k.TC_MAX_STRESS, "maxStress: largest |stress| on the top wall [Pa]")
    currentStrainRate = _tc(k.TC_RATE, "currentStrainRate: the loading's strain rate [1/s]")
    sigma_iso = _tc(k.TC_SIGMA_ISO, "sigma_iso: the isotropic stress goal of the current stage [Pa]")
    previousSigmaIso = _tc(k.TC_PREV_SIGMA_ISO, "previousSigmaIso: sigma_iso at the last step [Pa]")

    def params(self, scene, engines) -> k.CompressionParams:
        name = type(self).__name__
        if self.fixedPoroCompaction or int(self._tc[k.TC_STATE]) == k.STATE_FIXED_POROSITY_COMPACTION:
            raise NotImplementedError(f"{name}: fixedPoroCompaction (STATE_FIXED_POROSITY_COMPACTION) is not "
                                      "implemented in granum")
        if self.internalCompaction and int(self._tc[k.TC_STATE]) <= k.STATE_ISO_COMPACTION \
                and not self.sigmaIsoCompaction < 0:
            raise ValueError(f"{name}: internalCompaction grows the spheres to sigmaIsoCompaction, which must be "
                             f"negative (compression), got {self.sigmaIsoCompaction!r}")
        axis = np.array(self.translationAxis._a, float)
        gravity = np.zeros(3)
        for e in engines:
            if isinstance(e, NewtonIntegrator) and not e.dead:
                gravity = np.array(e.gravity._a, float)
        return k.CompressionParams(
            triax=self.servo_copies(scene), state=self._tc,
            sigma_iso_compaction=float(self.sigmaIsoCompaction), sigma_lateral=float(self.sigmaLateralConfinement),
            strain_rate=float(self.strainRate), stability=float(self.StabilityCriterion),
            test_interval=int(self.testEquilibriumInterval), auto_unload=bool(self.autoUnload),
            auto_compression=bool(self.autoCompressionActivation), axisymmetric=bool(self.isAxisymetric),
            epsilon_max=float(self.epsilonMax), axis=axis, gravity=gravity, hook_id=int(self._plan_index))

    def after_hook(self, omega, events: int) -> None:
        """After a transition: the checkpoint files."""
        if self.noFiles:
            return
        tc = self._tc
        for bit, what in ((k.EV_SAVE_COMPACTED, "Compacted"), (k.EV_SAVE_UNLOADED, "Unloaded")):
            if events & bit:
                base = os.path.join(".", f"{self.Key}_{what}_{int(tc[k.TC_EVENT_ITER])}_{int(tc[k.TC_STATE])}")
                spheres_file(omega._scene, base + ".spheres")
                omega.save(base + ".xml")


class ThreeDTriaxialEngine(_ServoEngine):
    """Stress control of axis a (the servo's goal a) when stressControl_a, otherwise its two walls move
    at a strain rate approaching strainRate a [1/s] (> 0 compresses); see
    :mod:`granum.kernels.triaxial_engines`."""

    stage = "granum.kernels.triaxial_engines:three_d_stage"
    _attrs = {
        **{f"strainRate{a}": Attr(0.0, f"Goal strain rate along axis {a} [1/s] (> 0: compression)",
                                  to_float(f"strainRate{a}", allow_nan=False)) for a in (1, 2, 3)},
        **{f"stressControl_{a}": Attr(True, f"Axis {a} is stress-controlled (else strain-rate-controlled)", to_bool)
           for a in (1, 2, 3)},
        "strainDamping": Attr(0.9997, "Factor by which the strain rates' distance to their goals shrinks per step "
                                      "[-]", _fraction("strainDamping")),
        "UnbalancedForce": Attr(1.0, "Kept for YADE's scripts (this engine does not compute it)",
                                to_float("UnbalancedForce")),
        "frictionAngleDegree": Attr(-1.0, "Friction angle set at the first step with updateFrictionAngle [deg]",
                                    to_float("frictionAngleDegree", allow_nan=False)),
        "updateFrictionAngle": Attr(False, "Set the friction to frictionAngleDegree at the first step", to_bool),
        "Key": Attr("", "Kept for YADE's scripts (this engine writes no file)", to_str("Key")),
    }

    currentStrainRate1 = _tc(k.TD_RATES, "currentStrainRate1: the strain rate along x [1/s]")
    currentStrainRate2 = _tc(k.TD_RATES + 1, "currentStrainRate2: along y [1/s]")
    currentStrainRate3 = _tc(k.TD_RATES + 2, "currentStrainRate3: along z [1/s]")

    def params(self, scene, engines) -> k.ThreeDParams:
        control = np.array([self.stressControl_1, self.stressControl_2, self.stressControl_3], np.uint8)
        if self.internalCompaction and not np.mean([self.goal1, self.goal2, self.goal3]) < 0:
            raise ValueError(f"{type(self).__name__}: internalCompaction grows the spheres to a compressive mean "
                             "goal: the mean of goal1..3 must be negative (compression)")
        return k.ThreeDParams(
            triax=self.servo_copies(scene), state=self._tc, stress_control=control,
            strain_rate=np.array([self.strainRate1, self.strainRate2, self.strainRate3], float),
            strain_damping=float(self.strainDamping), update_friction=bool(self.updateFrictionAngle),
            hook_id=int(self._plan_index))
