"""Kinematic engines (YADE's ``KinematicEngine`` family) and their combinations.

A kinematic engine imposes the motion of its bodies. Each step their velocity and angular velocity are reset,
then every engine adds its own motion, so that engines combined with ``+`` (a :class:`CombinedKinematicEngine`)
add up. Every kinematic engine describes its motion as one *part* of
:func:`granum.kernels.kinematic.kinematic_stage`: a row of parameters (:meth:`KinematicEngine.part`), an
optional interpolation table, and a row of state the stage updates, which the engine's changing attributes
(``angleTurned``, an interpolated ``angularVelocity``, the servo's errors...) view.
"""

from __future__ import annotations

import math

import numpy as np

from granum.core.attrs import Attr, as_number, to_bool, to_float, to_int
from granum.engines.base import PartialEngine
from granum.engines.pipeline import to_vec3
from granum.kernels.kinematic import (
    K_AMP,
    K_AXIS,
    K_COLS,
    K_FREQ,
    K_KD,
    K_KI,
    K_KIND,
    K_KP,
    K_MAX_SPEED,
    K_ORBIT,
    K_PERIOD,
    K_PHASE,
    K_RADIUS,
    K_SLOPE,
    K_SPEED,
    K_TABLE,
    K_TABLE_LEN,
    K_TARGET,
    K_U,
    K_VEL,
    K_W,
    K_WRAP,
    K_ZERO,
    KIND_CONSTANT,
    KIND_HARMONIC_MOTION,
    KIND_HARMONIC_ROTATION,
    KIND_INTERPOLATED_HELIX,
    KIND_PEDAL,
    KIND_SERVO,
    ST_COLS,
    ST_CUR_VEL,
    ST_CURRENT,
    ST_ERROR,
    ST_ERROR_PREV,
    ST_I_TERM,
    ST_ITER_PREV,
    ST_LINEAR,
    ST_SPEED,
    ST_TURNED,
    KinematicParams,
)
from granum.mathtypes import Quaternion, Vector3

KINEMATIC_STAGE = "granum.kernels.kinematic:kinematic_stage"

#: the part row's fields by keyword of :func:`part_row`: (first column, width)
_FIELDS = {"velocity": (K_VEL, 3), "axis": (K_AXIS, 3), "speed": (K_SPEED, 1), "zero": (K_ZERO, 3),
           "orbit": (K_ORBIT, 1), "amplitude": (K_AMP, 3), "frequency": (K_FREQ, 3), "phase": (K_PHASE, 3),
           "slope": (K_SLOPE, 1), "wrap": (K_WRAP, 1), "radius": (K_RADIUS, 1), "u": (K_U, 3), "w": (K_W, 3),
           "kP": (K_KP, 1), "kI": (K_KI, 1), "kD": (K_KD, 1), "target": (K_TARGET, 1),
           "max_speed": (K_MAX_SPEED, 1), "period": (K_PERIOD, 1)}


def part_row(kind: int = KIND_CONSTANT, **fields) -> np.ndarray:
    """One part of :func:`~granum.kernels.kinematic.kinematic_stage`, (K_COLS,): ``kind`` and the fields
    named in ``_FIELDS`` (vectors of 3, or for a scalar of a vector field its component 0); others are 0."""
    row = np.zeros(K_COLS)
    row[K_KIND] = kind
    for name, value in fields.items():
        col, width = _FIELDS[name]
        row[col:col + width] = value
    return row


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


def _non_negative_vec3(name: str):
    def convert(owner, value):
        v = to_vec3(owner, value)
        if not all(x >= 0 for x in v):
            raise ValueError(f"{type(owner).__name__}.{name} must not be negative, got {tuple(v)!r}")
        return v

    return convert


def _non_negative(name: str):
    def convert(owner, value):
        x = to_float(name)(owner, value)
        if not x >= 0:
            raise ValueError(f"{type(owner).__name__}.{name} must be >= 0, got {value!r}")
        return x

    return convert


def _floats(name: str):
    def convert(owner, value):
        return [as_number(x, f"{type(owner).__name__}.{name}") for x in value]

    return convert


def _table(owner, times: list, values: list, names: tuple) -> np.ndarray:
    """An interpolation table (n, 2) of ``times`` [s] and ``values``; refuses unequal lengths, an empty
    table and times that decrease, naming the attributes."""
    what = type(owner).__name__
    if len(times) != len(values):
        raise ValueError(f"{what}.{names[0]} and {what}.{names[1]} must have the same length, got {len(times)} "
                         f"and {len(values)}")
    if not times:
        raise ValueError(f"{what}.{names[0]} is empty: give at least one time and value")
    t = np.array(times, dtype=np.float64)
    bad = np.nonzero(np.diff(t) < 0)[0]
    if bad.size:
        raise ValueError(f"{what}.{names[0]} must not decrease, got {t[bad[0]]!r} then {t[bad[0] + 1]!r}")
    return np.stack([t, np.array(values, dtype=np.float64)], axis=1)


def kinematic_params(engine, parts: list, scene) -> KinematicParams:
    """Parameters of :func:`~granum.kernels.kinematic.kinematic_stage` for ``engine``'s ids and the kinematic
    engines ``parts``, run in order; each part's state row is copied into the (K, ST_COLS) array, which the
    parts take as their storage from then on (:meth:`KinematicEngine.share_state`)."""
    rows = np.zeros((len(parts), K_COLS))
    state = np.zeros((len(parts), ST_COLS))
    tables, start = [], 0
    for k, e in enumerate(parts):
        rows[k] = e.part()
        table = e.table()
        if table is not None:
            rows[k, K_TABLE], rows[k, K_TABLE_LEN] = start, len(table)
            tables.append(table)
            start += len(table)
        e.share_state(state, k)
    table = np.concatenate(tables) if tables else np.zeros((0, 2))
    return KinematicParams(ids=engine.id_array(scene), parts=rows, state=state, tables=table)


def _state_property(column: int, name: str, doc: str):
    """The float attribute ``name``, stored in the engine's state row (written by the stage)."""

    def get(self) -> float:
        return float(self._state[column])

    def put(self, value) -> None:
        self._state[column] = as_number(value, f"{type(self).__name__}.{name}")

    return property(get, put, doc=doc)


class KinematicEngine(PartialEngine):
    """Base of the engines imposing motion (YADE ``KinematicEngine``); ``a + b`` combines two of them
    into a :class:`CombinedKinematicEngine` acting on ``a.ids``."""

    stage = KINEMATIC_STAGE

    def __init__(self, **kw):
        state = np.zeros(ST_COLS)
        state[ST_ITER_PREV] = -1
        object.__setattr__(self, "_state", state)  # this engine's state row, written by the stage
        super().__init__(**kw)

    def part(self) -> np.ndarray:
        """This engine's motion as a row of :func:`part_row`."""
        raise NotImplementedError(f"{type(self).__name__} imposes no motion; use TranslationEngine, RotationEngine "
                                  f"or another kinematic engine")

    def table(self):
        """This engine's interpolation table, (n, 2) rows (time [s], value), or None."""
        return None

    def share_state(self, state: np.ndarray, k: int) -> None:
        """Keep this engine's state in row ``k`` of ``state`` from now on."""
        state[k] = self._state
        object.__setattr__(self, "_state", state[k])

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
    angleTurned = _state_property(ST_TURNED, "angleTurned", "Angle turned so far [rad]")

    def part(self) -> np.ndarray:
        object.__setattr__(self, "rotateAroundZero", True)
        axis = _unit(self, "rotationAxis", self.rotationAxis)
        return part_row(velocity=self.linearVelocity * axis, axis=axis, speed=self.angularVelocity,
                        zero=self.zeroPoint._a, orbit=True)


class InterpolatingHelixEngine(HelixEngine):
    """A HelixEngine whose angular speed [rad/s] is interpolated linearly in ``times``/``angularVelocities`` at
    each step's time (the first value before the first time, the last after the last; with ``wrap`` the time
    goes round the table) and whose linear speed is ``slope`` [m/rad] times it. ``angularVelocity`` and
    ``linearVelocity`` report the last step's speeds."""

    _attrs = {
        "times": Attr([], "Times of the table, not decreasing [s]", _floats("times")),
        "angularVelocities": Attr([], "Angular speeds at those times [rad/s]", _floats("angularVelocities")),
        "wrap": Attr(False, "Wrap the time around the table", to_bool),
        "slope": Attr(0.0, "Axial translation per radian turned [m/rad]", to_float("slope")),
    }
    angularVelocity = _state_property(ST_SPEED, "angularVelocity", "Angular speed of the last step [rad/s]")
    linearVelocity = _state_property(ST_LINEAR, "linearVelocity", "Speed along the axis of the last step [m/s]")

    def table(self):
        return _table(self, self.times, self.angularVelocities, ("times", "angularVelocities"))

    def part(self) -> np.ndarray:
        object.__setattr__(self, "rotateAroundZero", True)
        return part_row(KIND_INTERPOLATED_HELIX, axis=_unit(self, "rotationAxis", self.rotationAxis),
                        zero=self.zeroPoint._a, orbit=True, slope=self.slope, wrap=self.wrap)


class HarmonicMotionEngine(KinematicEngine):
    """Harmonic oscillation of the bodies: vel = -A w sin(w t + fi) per component, w = 2 pi f, t the time at the
    start of the step; with the default phase pi/2 the bodies oscillate about where they start, pos = pos0 -
    A sin(w t) (YADE ``HarmonicMotionEngine``)."""

    _attrs = {
        "A": Attr(Vector3(0, 0, 0), "Amplitude [m]", to_vec3),
        "f": Attr(Vector3(0, 0, 0), "Frequency [Hz], >= 0", _non_negative_vec3("f")),
        "fi": Attr(Vector3(math.pi / 2, math.pi / 2, math.pi / 2), "Initial phase [rad]", to_vec3),
    }

    def part(self) -> np.ndarray:
        return part_row(KIND_HARMONIC_MOTION, amplitude=self.A._a, frequency=self.f._a, phase=self.fi._a)


class HarmonicRotationEngine(RotationEngine):
    """A RotationEngine whose angular speed is -A w sin(w t + fi), w = 2 pi f (YADE ``HarmonicRotationEngine``);
    ``angularVelocity`` reports the last step's speed."""

    _attrs = {
        "A": Attr(0.0, "Amplitude [rad]", to_float("A")),
        "f": Attr(0.0, "Frequency [Hz], >= 0", _non_negative("f")),
        "fi": Attr(math.pi / 2, "Initial phase [rad]", to_float("fi")),
    }
    angularVelocity = _state_property(ST_SPEED, "angularVelocity", "Angular speed of the last step [rad/s]")

    def part(self) -> np.ndarray:
        return part_row(KIND_HARMONIC_ROTATION, axis=_unit(self, "rotationAxis", self.rotationAxis),
                        zero=self.zeroPoint._a, orbit=self.rotateAroundZero, amplitude=self.A, frequency=self.f,
                        phase=self.fi)


def _circle_basis(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The unit vectors (u, w) of a BicyclePedalEngine's circle about ``axis``: -x and -y turned by the
    shortest rotation taking z onto the axis (YADE 2023.02a's, measured)."""
    rot = np.asarray(Quaternion((0.0, 0.0, 1.0), tuple(axis)).toRotationMatrix()._a)
    return -rot[:, 0], -rot[:, 1]


class BicyclePedalEngine(KinematicEngine):
    """The bodies move around a circle of ``radius`` about ``rotationAxis`` without turning, like a bicycle's
    pedal: the point r (cos phi u + sin phi w) of phase phi = fi + angularVelocity t; each step they take the
    chord to the next phase (YADE ``BicyclePedalEngine``)."""

    _attrs = {
        "angularVelocity": Attr(0.0, "Angular speed [rad/s]", to_float("angularVelocity")),
        "rotationAxis": Attr(Vector3(1, 0, 0), "Axis of the circle (normalised when assigned)", to_axis),
        "radius": Attr(-1.0, "Radius of the circle [m] (a negative one starts opposite)", to_float("radius")),
        "fi": Attr(math.pi / 2, "Initial phase [rad]", to_float("fi")),
    }

    def part(self) -> np.ndarray:
        u, w = _circle_basis(_unit(self, "rotationAxis", self.rotationAxis))
        return part_row(KIND_PEDAL, speed=self.angularVelocity, phase=self.fi, radius=self.radius, u=u, w=w)


class ServoPIDController(TranslationEngine):
    """A TranslationEngine along ``axis`` whose speed a PID controller sets from the force on the bodies,
    every ``iterPeriod`` steps from the first (YADE ``ServoPIDController``, as YADE 2023.02a computes it):
    current = F * axis per component (F the summed force on the bodies at the engine's place in the step),
    error = |current| - target, iTerm += kI error, speed = kP error + iTerm + kD (error - errorPrev), limited to
    +-maxVelocity. As in YADE, put it after NewtonIntegrator (or in a CombinedKinematicEngine there)."""

    _attrs = {
        "maxVelocity": Attr(0.0, "Largest speed [m/s]", _non_negative("maxVelocity")),
        "axis": Attr(Vector3(0, 0, 0), "Direction of motion (normalised when the engine runs)", to_vec3),
        "target": Attr(0.0, "Target force [N]", to_float("target")),
        "kP": Attr(0.0, "Proportional gain [m/(s N)]", to_float("kP")),
        "kI": Attr(0.0, "Integral gain [m/(s N)]", to_float("kI")),
        "kD": Attr(0.0, "Derivative gain [m/(s N)]", to_float("kD")),
        "iterPeriod": Attr(100, "Steps between two updates of the speed", to_int("iterPeriod", minimum=1)),
        "current": Attr(Vector3(0, 0, 0), "Force times axis, per component, at the last update [N]"),
        "iTerm": Attr(0.0, "Integral term [m/s]"),
        "curVel": Attr(0.0, "Speed applied [m/s]"),
        "errorCur": Attr(0.0, "Error at the last update [N]"),
        "errorPrev": Attr(0.0, "Error at the update before [N]"),
        "iterPrevStart": Attr(-1, "Step of the last update (-1: none yet)"),
    }
    iTerm = _state_property(ST_I_TERM, "iTerm", "Integral term [m/s]")
    curVel = _state_property(ST_CUR_VEL, "curVel", "Speed applied [m/s]")
    velocity = _state_property(ST_CUR_VEL, "velocity", "Speed applied [m/s] (curVel)")
    errorCur = _state_property(ST_ERROR, "errorCur", "Error at the last update [N]")
    errorPrev = _state_property(ST_ERROR_PREV, "errorPrev", "Error at the update before [N]")

    @property
    def iterPrevStart(self) -> int:
        return int(self._state[ST_ITER_PREV])

    @iterPrevStart.setter
    def iterPrevStart(self, value) -> None:
        self._state[ST_ITER_PREV] = to_int("iterPrevStart", minimum=-1)(self, value)

    @property
    def current(self) -> Vector3:
        return Vector3(*self._state[ST_CURRENT:ST_CURRENT + 3])

    @current.setter
    def current(self, value) -> None:
        self._state[ST_CURRENT:ST_CURRENT + 3] = to_vec3(self, value)._a

    @property
    def translationAxis(self) -> Vector3:
        """The direction of motion: ``axis`` normalised."""
        n = self.axis.norm()
        return self.axis / n if n > 0 else Vector3(self.axis)

    @translationAxis.setter
    def translationAxis(self, value) -> None:
        self.axis = to_axis(self, value)

    def part(self) -> np.ndarray:
        return part_row(KIND_SERVO, axis=_unit(self, "axis", self.axis), kP=self.kP, kI=self.kI, kD=self.kD,
                        target=self.target, max_speed=self.maxVelocity, period=self.iterPeriod)


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
