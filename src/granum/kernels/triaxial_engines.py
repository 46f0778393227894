"""The stages of TriaxialCompressionEngine and ThreeDTriaxialEngine, built around the wall-box servo of
:mod:`granum.kernels.triaxial`.

**TriaxialCompressionEngine** (:func:`compression_stage`) is the state machine of a triaxial test.

States (``currentState``): 0 not started, 1 isotropic compaction to σ_iso = ``sigmaIsoCompaction``, 2 isotropic
unloading to ``sigmaLateralConfinement``, 3 triaxial loading, 4 compaction to a fixed porosity (refused by the
engine), 5 limbo. Per step, in this order (YADE 2023.02a's, measured on its walls and attributes):

1. a state set from Python (``currentState`` ≠ ``previousState``) is entered as a transition would; a
   ``sigma_iso`` set from Python becomes the three goals (``isAxisymetric``: at every step);
2. every ``testEquilibriumInterval`` steps (O.iter a multiple, step 0 included): ``UnbalancedForce`` (mean
   resultant force on the dynamic bodies over the mean contact force), ``maxStress`` = max(maxStress,
   |σ_top|) with σ_top the top wall's stress of the last stress update; then, in states 1 and 2, when
   UnbalancedForce ≤ ``StabilityCriterion`` and |σ_mean − σ_iso| < 0.005 |σ_iso|: state 1 goes to 2
   (``autoUnload`` and σ_lateral ≠ σ_iso) or else to 3 (``autoCompressionActivation``), state 2 goes to 3
   (``autoCompressionActivation``). Entering 2 or 3 sets σ_iso = σ_lateral and ends the internal compaction;
   entering 3 also frees the top and bottom walls from the servo, takes the current sizes as the strains'
   reference and restarts the strain rate from 0;
3. the servo of :func:`granum.kernels.triaxial.triaxial_control` (stresses, strains, walls or radii);
4. state 3, while |ε_y| < ``epsilonMax``: the strain rate approaches its goal, r ← r + (1 − 0.9997)(r_goal − r)
   (0.9997: YADE's, measured; not the controller's strainDamping), and the top and bottom walls are moved
   (positions, velocities zeroed) by ∓½ r·height·dt along ``translationAxis`` (r > 0 compresses).

A transition asks for the engine's Python hook (after the step): it copies the goals, the walls' activation and
``internalCompaction`` to the engine's attributes, sets the friction (``frictionAngleDegree``) and writes the
checkpoint files.

**ThreeDTriaxialEngine** (:func:`three_d_stage`): axis a is stress-controlled by the servo (goal a) when
``stressControl_a``; otherwise its two walls leave the servo and are moved like the loading walls above at the
rate r_a ← r_a + (1 − strainDamping)(strainRate_a − r_a) (strainDamping: the engine's own, 0.9997). At its first
step, with ``updateFrictionAngle``, the friction becomes ``frictionAngleDegree`` (once: YADE 2023.02a, measured).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from granum._jit import jit
from granum.core.arrays import S_DT, SI_HOOK, SI_ITER, SI_NBODIES
from granum.core.bodies import DOF_ALL
from granum.core.contacts import C_CONTACTS, F_FN, F_FS, FLAG_ALIVE, I_FLAGS
from granum.kernels.newton import counted_force
from granum.kernels.triaxial import T_MEAN, T_SIZE, T_SIZE0, T_STRAIN, T_STRESS, TriaxialParams, triaxial_control

# states (YADE's numbers)
STATE_UNINITIALIZED = 0
STATE_ISO_COMPACTION = 1
STATE_ISO_UNLOADING = 2
STATE_TRIAX_LOADING = 3
STATE_FIXED_POROSITY_COMPACTION = 4
STATE_LIMBO = 5
STATE_NAMES = ("STATE_UNINITIALIZED", "STATE_ISO_COMPACTION", "STATE_ISO_UNLOADING", "STATE_TRIAX_LOADING",
               "STATE_FIXED_POROSITY_COMPACTION", "STATE_LIMBO")

# slots of the engine's state array (floats)
TC_STATE = 0            # currentState
TC_PREV_STATE = 1       # previousState
TC_UNBALANCED = 2       # UnbalancedForce [-]
TC_MAX_STRESS = 3       # maxStress [Pa]
TC_RATE = 4             # currentStrainRate [1/s]
TC_SIGMA_ISO = 5        # sigma_iso [Pa]
TC_PREV_SIGMA_ISO = 6   # previousSigmaIso [Pa]
TC_INTERNAL = 7         # internalCompaction (0 or 1)
TC_EVENTS = 8           # EV_* bits for the Python hook
TC_EVENT_ITER = 9       # the step of the last transition
TD_RATES = 10           # 10..12 ThreeDTriaxialEngine's currentStrainRate1..3 [1/s]
TD_STARTED = 13         # ThreeDTriaxialEngine has run its first step (0 or 1)
TC_SIZE = 14

# what the Python hook does (bits of TC_EVENTS)
EV_SYNC = 1             # copy goals, walls' activation, internalCompaction to the attributes
EV_FRICTION = 2         # set the friction angle (frictionAngleDegree)
EV_SAVE_COMPACTED = 4   # write <Key>_Compacted_<iter>_<state>.xml/.spheres
EV_SAVE_UNLOADED = 8    # write <Key>_Unloaded_<iter>_<state>.xml/.spheres

#: factor of the strain rate's distance to its goal kept per step while loading (YADE 2023.02a, measured)
RATE_DAMPING = 0.9997
#: relative distance of the mean stress to σ_iso below which a stage may end
STRESS_TOLERANCE = 0.005
_TOP, _BOTTOM = 3, 2
#: unit vectors of the axes
AXES = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


class CompressionParams(NamedTuple):
    """Parameters of :func:`compression_stage` (TriaxialCompressionEngine's attributes of the same meaning)."""

    triax: TriaxialParams     #: the wall servo's parameters (its ``goal``/``activated`` are the engine's arrays)
    state: np.ndarray         #: slots TC_*, (TC_SIZE,) float64; written by the stage
    sigma_iso_compaction: float  #: sigmaIsoCompaction [Pa]
    sigma_lateral: float      #: sigmaLateralConfinement [Pa]
    strain_rate: float        #: strainRate, the goal of the loading [1/s] (> 0 compresses)
    stability: float          #: StabilityCriterion [-]
    test_interval: int        #: testEquilibriumInterval [steps]
    auto_unload: bool         #: autoUnload
    auto_compression: bool    #: autoCompressionActivation
    axisymmetric: bool        #: isAxisymetric: the goals follow sigma_iso at every step
    epsilon_max: float        #: epsilonMax: |ε_y| at which the loading walls stop [-]
    axis: np.ndarray          #: translationAxis, the loading direction of the top wall's motion, (3,)
    gravity: np.ndarray       #: NewtonIntegrator's gravity, part of the resultant forces [m/s^2], (3,)
    hook_id: int              #: what the stage writes to ``iscal[SI_HOOK]`` at a transition


@jit
def unbalanced_force(S, C, gravity):
    """Mean |F + m g| over the dynamic bodies (a clump with its members' forces: :func:`counted_force`)
    over the mean |contact force| [-]; NaN without contacts."""
    res = 0.0
    n = 0
    for i in range(S.iscal[SI_NBODIES]):
        if S.alive[i] and S.blocked[i] != DOF_ALL and (S.clump_id[i] < 0 or S.clump_id[i] == i):
            f = counted_force(i, S)
            fx = f[0] + S.mass[i] * gravity[0]
            fy = f[1] + S.mass[i] * gravity[1]
            fz = f[2] + S.mass[i] * gravity[2]
            res += math.sqrt(fx * fx + fy * fy + fz * fz)
            n += 1
    fsum = 0.0
    nc = 0
    con_i, con_f = C.con_i, C.con_f
    for c in range(C.ctr[C_CONTACTS]):
        if con_i[c, I_FLAGS] & FLAG_ALIVE:
            fx = con_f[c, F_FN] + con_f[c, F_FS]
            fy = con_f[c, F_FN + 1] + con_f[c, F_FS + 1]
            fz = con_f[c, F_FN + 2] + con_f[c, F_FS + 2]
            fsum += math.sqrt(fx * fx + fy * fy + fz * fz)
            nc += 1
    if n == 0 or nc == 0 or fsum == 0.0:
        return math.nan
    return (res / n) / (fsum / nc)


@jit
def enter(state, P, it):
    """Enter ``state``: set σ_iso, the walls' roles and the hook's events (see the module docstring)."""
    st, T = P.state, P.triax
    st[TC_STATE] = state
    st[TC_PREV_STATE] = state
    events = EV_SYNC
    if state == STATE_ISO_COMPACTION:
        st[TC_SIGMA_ISO] = P.sigma_iso_compaction
    elif state == STATE_ISO_UNLOADING or state == STATE_TRIAX_LOADING:
        st[TC_SIGMA_ISO] = P.sigma_lateral
        st[TC_INTERNAL] = 0.0
        events |= EV_FRICTION
    if state == STATE_ISO_UNLOADING:
        events |= EV_SAVE_COMPACTED
    if state == STATE_TRIAX_LOADING:
        events |= EV_SAVE_UNLOADED
        T.activated[_TOP] = 0
        T.activated[_BOTTOM] = 0
        for a in range(3):
            T.out[T_SIZE0 + a] = T.out[T_SIZE + a]
        st[TC_RATE] = 0.0
    st[TC_EVENTS] = int(st[TC_EVENTS]) | events
    st[TC_EVENT_ITER] = it


@jit
def compression_stage(S, C, P):
    """Engine stage of TriaxialCompressionEngine (see the module docstring); ``P``: :class:`CompressionParams`."""
    st, T = P.state, P.triax
    it = S.iscal[SI_ITER]
    state = int(st[TC_STATE])
    if state == STATE_UNINITIALIZED:
        enter(STATE_ISO_COMPACTION, P, it)
    elif state != int(st[TC_PREV_STATE]):
        enter(state, P, it)
    if P.axisymmetric or st[TC_SIGMA_ISO] != st[TC_PREV_SIGMA_ISO] or st[TC_EVENTS] != 0.0:
        st[TC_PREV_SIGMA_ISO] = st[TC_SIGMA_ISO]
        for a in range(3):
            if T.goal[a] != st[TC_SIGMA_ISO]:
                T.goal[a] = st[TC_SIGMA_ISO]
                st[TC_EVENTS] = int(st[TC_EVENTS]) | EV_SYNC
    if it % P.test_interval == 0:
        st[TC_UNBALANCED] = unbalanced_force(S, C, P.gravity)
        st[TC_MAX_STRESS] = max(st[TC_MAX_STRESS], abs(T.out[T_STRESS + _TOP]))
        state = int(st[TC_STATE])
        siso = st[TC_SIGMA_ISO]
        stable = (st[TC_UNBALANCED] <= P.stability
                  and abs(T.out[T_MEAN] - siso) < STRESS_TOLERANCE * abs(siso))
        if stable and state == STATE_ISO_COMPACTION:
            if P.auto_unload and P.sigma_lateral != P.sigma_iso_compaction:
                enter(STATE_ISO_UNLOADING, P, it)
            elif P.auto_compression:
                enter(STATE_TRIAX_LOADING, P, it)
        elif stable and state == STATE_ISO_UNLOADING and P.auto_compression:
            enter(STATE_TRIAX_LOADING, P, it)
        if st[TC_STATE] != state:
            for a in range(3):
                T.goal[a] = st[TC_SIGMA_ISO]
            st[TC_PREV_SIGMA_ISO] = st[TC_SIGMA_ISO]
    triaxial_control(S, C, T, st[TC_INTERNAL] != 0.0)
    if int(st[TC_STATE]) == STATE_TRIAX_LOADING and abs(T.out[T_STRAIN + 1]) < P.epsilon_max:
        st[TC_RATE] += (1.0 - RATE_DAMPING) * (P.strain_rate - st[TC_RATE])
        move_walls(S, T, _BOTTOM, _TOP, P.axis, st[TC_RATE], 1)
    if st[TC_EVENTS] != 0.0:
        S.iscal[SI_HOOK] = P.hook_id


@jit
def move_walls(S, T, lo, hi, direction, rate, axis):
    """Move walls ``lo`` and ``hi`` (indices in ``T.walls``) towards each other by ½·rate·size·dt each along
    ``direction`` (3,) (``hi`` against it), ``size`` the box's size along ``axis``; their velocities are zeroed
    (a strain rate ``rate`` [1/s], > 0 compresses)."""
    d = 0.5 * rate * T.out[T_SIZE + axis] * S.scal[S_DT]
    a, b = T.walls[lo], T.walls[hi]
    for k in range(3):
        S.pos[a, k] += d * direction[k]
        S.pos[b, k] -= d * direction[k]
        S.vel[a, k] = 0.0
        S.vel[b, k] = 0.0


class ThreeDParams(NamedTuple):
    """Parameters of :func:`three_d_stage` (ThreeDTriaxialEngine's attributes of the same meaning)."""

    triax: TriaxialParams     #: the wall servo's parameters (its ``activated`` is the engine's array)
    state: np.ndarray         #: slots TC_EVENTS, TC_INTERNAL, TD_*, (TC_SIZE,) float64; written by the stage
    stress_control: np.ndarray  #: stressControl_1..3, (3,) uint8
    strain_rate: np.ndarray   #: strainRate1..3, goal strain rates [1/s] (> 0 compresses), (3,)
    strain_damping: float     #: the engine's strainDamping [-]
    update_friction: bool     #: updateFrictionAngle: set the friction at the first step
    hook_id: int              #: what the stage writes to ``iscal[SI_HOOK]`` when the hook has work


@jit
def three_d_stage(S, C, P):
    """Engine stage of ThreeDTriaxialEngine (see the module docstring); ``P``: :class:`ThreeDParams`."""
    st, T = P.state, P.triax
    if st[TD_STARTED] == 0.0:
        st[TD_STARTED] = 1.0
        if P.update_friction:
            st[TC_EVENTS] = int(st[TC_EVENTS]) | EV_FRICTION
    for a in range(3):
        on = P.stress_control[a]
        if T.activated[2 * a] != on or T.activated[2 * a + 1] != on:
            T.activated[2 * a] = on
            T.activated[2 * a + 1] = on
            st[TC_EVENTS] = int(st[TC_EVENTS]) | EV_SYNC
        if not on:
            st[TD_RATES + a] += (1.0 - P.strain_damping) * (P.strain_rate[a] - st[TD_RATES + a])
    triaxial_control(S, C, T, st[TC_INTERNAL] != 0.0)
    for a in range(3):
        if not P.stress_control[a]:
            move_walls(S, T, 2 * a, 2 * a + 1, AXES[a], st[TD_RATES + a], a)
    if st[TC_EVENTS] != 0.0:
        S.iscal[SI_HOOK] = P.hook_id
