"""The kinematic engines' stage (YADE's KinematicEngine and its combinations by ``+``).

Every kinematic engine is one *part*: a row of ``parts`` (its parameters, columns ``K_*``) and a row of
``state`` (what it keeps from step to step or reports, columns ``ST_*``). Each step the stage resets the
velocity and angular velocity of the listed bodies, then each part adds its motion, in order:

- ``KIND_CONSTANT``: TranslationEngine, RotationEngine, HelixEngine (a velocity, an angular velocity, an
  orbit about an axis);
- ``KIND_HARMONIC_MOTION``: HarmonicMotionEngine, v = -A w sin(w t + fi) per component, w = 2 pi f;
- ``KIND_HARMONIC_ROTATION``: HarmonicRotationEngine, a RotationEngine of speed -A w sin(w t + fi);
- ``KIND_INTERPOLATED_HELIX``: InterpolatingHelixEngine, a HelixEngine whose angular speed is interpolated
  in a table at t and whose linear speed is slope times it;
- ``KIND_PEDAL``: BicyclePedalEngine, the chord of a circle the bodies follow without turning;
- ``KIND_SERVO``: ServoPIDController, a TranslationEngine whose speed a PID controller sets from the force on
  the bodies.

t is the time at the start of the step (``O.time``), as in YADE 2023.02a (tests/reference/yade/engines_extra.py).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from granum._jit import jit
from granum.core.arrays import S_DT, S_TIME, SI_ITER
from granum.physics.vec import load3, quat_from_rotvec, quat_rotate, scale, sub

#: part kinds (column K_KIND)
KIND_CONSTANT, KIND_HARMONIC_MOTION, KIND_HARMONIC_ROTATION, KIND_INTERPOLATED_HELIX, KIND_PEDAL, KIND_SERVO = range(6)

#: columns of a part row: kind; velocity (3) [m/s]; unit axis (3); angular speed [rad/s]; point of the axis (3)
#: [m]; 1.0 if the bodies orbit the axis; amplitude (3) [m or rad], frequency (3) [Hz], phase (3) [rad] (harmonic
#: and pedal parts: component 0 for a scalar); slope [m/rad]; 1.0 to wrap the table; first row and length of the
#: part's table in ``tables``; radius [m] and the circle's unit vectors u (3), w (3) (pedal); PID gains kP, kI, kD,
#: target [N], maximum speed [m/s] and period [steps] (servo)
(K_KIND, K_VEL, K_AXIS, K_SPEED, K_ZERO, K_ORBIT, K_AMP, K_FREQ, K_PHASE, K_SLOPE, K_WRAP, K_TABLE, K_TABLE_LEN,
 K_RADIUS, K_U, K_W, K_KP, K_KI, K_KD, K_TARGET, K_MAX_SPEED, K_PERIOD, K_COLS) = (
    0, 1, 4, 7, 8, 11, 12, 15, 18, 21, 22, 23, 24, 25, 26, 29, 32, 33, 34, 35, 36, 37, 38)

#: columns of a part's state: angle turned [rad]; angular and linear speed of the last step [rad/s, m/s];
#: the servo's force along its axis (3) [N], speed [m/s], integral term, current and previous error [N] and the
#: step of its last update (-1: none yet)
ST_TURNED, ST_SPEED, ST_LINEAR, ST_CURRENT, ST_CUR_VEL, ST_I_TERM, ST_ERROR, ST_ERROR_PREV, ST_ITER_PREV, ST_COLS = (
    0, 1, 2, 3, 6, 7, 8, 9, 10, 11)


class KinematicParams(NamedTuple):
    """Parameters of :func:`kinematic_stage`."""

    ids: np.ndarray     #: the bodies, (n,) int64
    parts: np.ndarray   #: one row per part, in order, (K, K_COLS) float64
    state: np.ndarray   #: each part's state, (K, ST_COLS) float64; the stage updates it
    tables: np.ndarray  #: the parts' interpolation tables, rows (time [s], value), (T, 2) float64


@jit
def interpolate(table, start, n, t, wrap):
    """Value at ``t`` of the table rows ``start`` to ``start + n`` (time, value), linear between its points:
    the first value before the first time, the last after the last, or with ``wrap`` t brought into
    [t0, tn) by whole periods tn - t0 first (YADE's interpolating engines)."""
    t0 = table[start, 0]
    tn = table[start + n - 1, 0]
    if wrap and tn > t0:
        t = t0 + (t - t0) - math.floor((t - t0) / (tn - t0)) * (tn - t0)
    if t <= t0:
        return table[start, 1]
    if t >= tn:
        return table[start + n - 1, 1]
    j = start
    while table[j + 1, 0] < t:
        j += 1
    s = (t - table[j, 0]) / (table[j + 1, 0] - table[j, 0])
    return table[j, 1] + s * (table[j + 1, 1] - table[j, 1])


@jit
def servo_update(part, st, ids, force, it):
    """ServoPIDController's update, every ``K_PERIOD`` steps from its first: the force on the bodies F
    (summed), current = F * axis per component, error = |current| - target, the integral term += kI error,
    speed = kP error + integral + kD (error - previous error), limited to +-maxVelocity (YADE 2023.02a)."""
    if st[ST_ITER_PREV] >= 0 and it - st[ST_ITER_PREV] < part[K_PERIOD]:
        return
    f = np.zeros(3)
    for i in ids:
        for j in range(3):
            f[j] += force[i, j]
    mag = 0.0
    for j in range(3):
        st[ST_CURRENT + j] = f[j] * part[K_AXIS + j]
        mag += st[ST_CURRENT + j] ** 2
    error = math.sqrt(mag) - part[K_TARGET]
    st[ST_I_TERM] += part[K_KI] * error
    speed = part[K_KP] * error + st[ST_I_TERM] + part[K_KD] * (error - st[ST_ERROR_PREV])
    st[ST_CUR_VEL] = max(-part[K_MAX_SPEED], min(part[K_MAX_SPEED], speed))
    st[ST_ERROR] = error
    st[ST_ERROR_PREV] = error
    st[ST_ITER_PREV] = it


@jit
def pedal_point(part, phase):
    """Point at ``phase`` [rad] of a BicyclePedalEngine's circle, relative to its centre: r (cos u + sin w)."""
    c, s, r = math.cos(phase), math.sin(phase), part[K_RADIUS]
    return (r * (c * part[K_U] + s * part[K_W]), r * (c * part[K_U + 1] + s * part[K_W + 1]),
            r * (c * part[K_U + 2] + s * part[K_W + 2]))


@jit
def kinematic_stage(S, C, P):
    """Kinematic engines: the velocity and angular velocity of the listed bodies are reset, then each part
    adds its own motion, in order (see the module). ``P``: :class:`KinematicParams`.

    Part k adds vel += velocity_k, angVel += speed_k axis_k and, if it orbits, the chord of the circle about
    the axis through zero_k, vel += (R(speed_k dt, axis_k)(x - zero_k) + zero_k - x) / dt, which puts the body
    on the circle after the step; turned[k] += speed_k dt [rad] (HelixEngine.angleTurned).
    """
    ids, parts, state, tables = P.ids, P.parts, P.state, P.tables
    dt = S.scal[S_DT]
    t = S.scal[S_TIME]
    vel, ang_vel, pos = S.vel, S.ang_vel, S.pos  # read once: a store could make the loop reload them
    for i in ids:
        for j in range(3):
            vel[i, j] = 0.0
            ang_vel[i, j] = 0.0
    for k in range(parts.shape[0]):
        part, st = parts[k], state[k]
        kind = int(part[K_KIND])
        axis = (part[K_AXIS], part[K_AXIS + 1], part[K_AXIS + 2])
        v = np.zeros(3)
        for j in range(3):
            v[j] = part[K_VEL + j]
        speed = part[K_SPEED]
        if kind == KIND_HARMONIC_MOTION:
            for j in range(3):
                w = 2.0 * math.pi * part[K_FREQ + j]
                v[j] = -part[K_AMP + j] * w * math.sin(w * t + part[K_PHASE + j])
        elif kind == KIND_HARMONIC_ROTATION:
            w = 2.0 * math.pi * part[K_FREQ]
            speed = -part[K_AMP] * w * math.sin(w * t + part[K_PHASE])
        elif kind == KIND_INTERPOLATED_HELIX:
            speed = interpolate(tables, int(part[K_TABLE]), int(part[K_TABLE_LEN]), t, part[K_WRAP] != 0.0)
            for j in range(3):
                v[j] = part[K_SLOPE] * speed * axis[j]
            st[ST_LINEAR] = part[K_SLOPE] * speed
        elif kind == KIND_PEDAL:
            phase = part[K_PHASE] + speed * t
            a = pedal_point(part, phase)
            b = pedal_point(part, phase + speed * dt)
            for j in range(3):
                v[j] = (b[j] - a[j]) / dt
            speed = 0.0  # the bodies do not turn
        elif kind == KIND_SERVO:
            servo_update(part, st, ids, S.force, S.iscal[SI_ITER])
            for j in range(3):
                v[j] = st[ST_CUR_VEL] * axis[j]
        st[ST_SPEED] = speed
        zero = (part[K_ZERO], part[K_ZERO + 1], part[K_ZERO + 2])
        q = quat_from_rotvec(scale(axis, speed * dt))
        orbit = part[K_ORBIT] != 0.0
        for i in ids:
            for j in range(3):
                vel[i, j] += v[j]
                ang_vel[i, j] += speed * axis[j]
            if orbit:
                r = sub(load3(pos, i), zero)
                chord = sub(quat_rotate(q, r), r)
                for j in range(3):
                    vel[i, j] += chord[j] / dt
        st[ST_TURNED] += speed * dt
