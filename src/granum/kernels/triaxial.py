"""TriaxialStressController's stage: stress or strain control of a cuboid sample by its six wall boxes.

The walls are boxes (``utils.aabbWalls``) in the order left, right (x), bottom, top (y), back, front (z);
``n_w`` is the inward normal of wall w (+x for left, -x for right, ...), ``a`` its axis. Per step:

* sizes: ``width = x_right - x_left - t`` (likewise height along y, depth along z), t the wall
  thickness (``thickness``; negative: the two boxes' half-extents along the axis); the porosity
  (V - V_s)/V of the box volume V = width·height·depth and the spheres' volume V_s;
* every ``computeStressStrainInterval`` steps (O.iter a multiple): the stress on each wall,
  s_w = (F_w · n_w) / A_w (compression negative), F_w the force on the wall and A_w its face of
  the box (height·depth for x walls...); ``meanStress`` = mean of the six; the logarithmic strain
  ε_a = ln(size_a / size0_a) (size0: the sizes at the first step) and ``volumetricStrain`` = Σ ε_a;
* every ``stiffnessUpdateInterval`` steps: each wall's stiffness k_w = Σ kn over its contacts;
* ``internalCompaction``: the walls stay still; every ``radiusControlInterval`` steps the spheres'
  radii are multiplied by m = 1 + (M - 1)(σ_g - σ_mean)/σ_g, σ_g the mean of the three goals and M
  ``maxMultiplier``; once |σ_mean| exceeds |σ_g|, M becomes ``finalMaxMultiplier`` for good (YADE 2023.02a's
  rule, measured). Masses follow by m³, inertias by m⁵; the collider's budgets shrink by the growth
  (:func:`spend_budgets`); kn and ks of every existing contact, whatever its bodies, are multiplied by m
  (:func:`scale_stiffnesses`: kn ∝ R in Ip2_FrictMat_FrictMat_FrictPhys; YADE 2023.02a scales them all,
  measured on the triax tutorial and on two blocked spheres in contact); the porosity reported at a growth step
  is the one before the growth (YADE's);
* otherwise each active wall moves along n_w by T_w per step (set as its velocity T_w n_w / dt,
  which NewtonIntegrator integrates). Stress axis (bit a of ``stressMask``):
  T_w = (1 - stressDamping)·clamp(ΔF / k_w, ±c_a) + 0.8·T_w(previous step), with
  ΔF = F_w·n_w - goal_a·A_w (±c_a by the sign of ΔF while k_w = 0): a damped servo that
  accumulates (the 0.8 is YADE's, measured on its walls' motion). The cap c_a = max_vel·dt·size_a/s̄,
  s̄ the mean of width, height and depth, lets a longer axis move proportionally faster (YADE 2023.02a,
  measured on a 4 x 1 x 1.5 sample: tests/reference/yade/triaxial_maxvel.py). Strain axis: the rate
  r_a ← strainDamping·r_a + (1 - strainDamping)·goal_a approaches the goal rate [1/s] and each wall
  moves by -½ r_a·size_a·dt inwards.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from granum._jit import jit
from granum.core.arrays import S_DT, S_VERLET, SI_ITER, SI_NBODIES
from granum.core.bodies import DOF_ALL
from granum.core.contacts import C_CONTACTS, C_CSR_DIRTY, C_PAIRS, F_KN, F_KS, FLAG_ALIVE, FLAG_NEW, I_FLAGS
from granum.core.shapes import ShapeKind
from granum.kernels.interaction import build_csr
from granum.kernels.motion import budget_f32

# slots of the controller's state array ``out`` (all floats)
T_STRESS = 0          # 0..5 stress on each wall, s_w [Pa]
T_STIFF = 6           # 6..11 stiffness of each wall, k_w [N/m]
T_TRANSLATION = 12    # 12..17 each wall's displacement along its inward normal in the last step [m]
T_SIZE = 18           # 18..20 width, height, depth [m]
T_SIZE0 = 21          # 21..23 their reference values (set at the first step when 0) [m]
T_STRAIN = 24         # 24..26 logarithmic strain per axis [-]
T_RATE = 27           # 27..29 strain rate per axis, d/dt ln(size) [1/s]
T_GOAL_RATE = 30      # 30..32 current (damped) strain rate of the strain-controlled axes [1/s]
T_MEAN = 33           # mean stress [Pa]
T_VOL_STRAIN = 34     # volumetric strain [-]
T_POROSITY = 35       # porosity of the box [-]
T_BOX_VOLUME = 36     # width * height * depth [m^3]
T_SPHERES_VOLUME = 37  # volume of the spheres [m^3]; NaN (never computed) or -1 (updatePorosity): to be computed
T_MAX_MULT = 38       # maxMultiplier (becomes finalMaxMultiplier) [-]
T_PREV_MULT = 39      # the last radius multiplier [-]
T_PREV_STRESS = 40    # the mean stress it was computed from [Pa]
T_WORK = 41           # externalWork: Σ T_w (F_w · n_w) over steps and walls, as YADE sums it [J]
T_SIZE_STATE = 42

_SPHERE = int(ShapeKind.SPHERE)
_BOX = int(ShapeKind.BOX)
#: weight of the previous step's displacement in a stress-controlled wall's (YADE 2023.02a, measured)
MEMORY = 0.8


class TriaxialParams(NamedTuple):
    """Parameters of :func:`triaxial_stage` (TriaxialStressController's attributes of the same meaning)."""

    walls: np.ndarray         #: body ids of the left, right, bottom, top, back, front walls, (6,) int64
    activated: np.ndarray     #: wall_*_activated in the same order, (6,) uint8
    goal: np.ndarray          #: goal1..3: stress [Pa] (bit set in stress_mask) or strain rate [1/s], (3,)
    stress_mask: int          #: bit a set: axis a is stress-controlled
    internal: bool            #: internalCompaction: grow the spheres instead of moving the walls
    final_max_multiplier: float  #: the multiplier bound once the mean stress has reached the goal [-]
    max_vel: float            #: largest wall displacement per step over dt [m/s]
    stress_damping: float     #: [-]
    strain_damping: float     #: [-]
    thickness: float          #: wall thickness [m] (negative: from the boxes)
    stiffness_interval: int   #: stiffnessUpdateInterval [steps]
    radius_interval: int      #: radiusControlInterval [steps]
    stress_interval: int      #: computeStressStrainInterval [steps]
    out: np.ndarray           #: state and outputs, slots T_*, (T_SIZE_STATE,) float64; written by the stage


@jit
def spheres_volume(S):
    """Volume of the live spheres [m^3]."""
    v = 0.0
    for i in range(S.iscal[SI_NBODIES]):
        if S.alive[i] and S.shape_kind[i] == _SPHERE:
            v += 4.0 / 3.0 * math.pi * S.sphere_radius[S.shape_row[i]] ** 3
    return v


@jit
def box_sizes(S, walls, thickness, out):
    """Write width, height, depth (``T_SIZE``), the box volume and the porosity."""
    vol = 1.0
    for a in range(3):
        lo = walls[2 * a]
        hi = walls[2 * a + 1]
        t = thickness
        if t < 0.0:
            t = S.box_extents[S.shape_row[lo], a] + S.box_extents[S.shape_row[hi], a]
        size = S.pos[hi, a] - S.pos[lo, a] - t
        out[T_SIZE + a] = size
        vol *= size
    out[T_BOX_VOLUME] = vol
    out[T_POROSITY] = (vol - out[T_SPHERES_VOLUME]) / vol


@jit
def face_area(out, a):
    """Area of the faces normal to axis ``a`` [m^2]."""
    return out[T_SIZE + (a + 1) % 3] * out[T_SIZE + (a + 2) % 3]


@jit
def inward(w):
    """Sign of wall ``w``'s inward normal along its axis (+1 for left, bottom, back)."""
    return 1.0 if w % 2 == 0 else -1.0


@jit
def wall_stiffness(C, wall):
    """Σ kn over the live contacts of body ``wall`` [N/m] (through the CSR index)."""
    k = 0.0
    for j in range(C.csr_start[wall], C.csr_start[wall + 1]):
        k += C.con_f[C.csr_con[j], F_KN]
    return k


@jit
def grow_spheres(S, m):
    """Multiply the radii of the free spheres by ``m``, their masses by m³ and inertias by m⁵; the largest
    radius increase [m] (0 when they shrink)."""
    grown = 0.0
    for i in range(S.iscal[SI_NBODIES]):
        if S.alive[i] and S.shape_kind[i] == _SPHERE and S.blocked[i] != DOF_ALL and S.clump_id[i] < 0:
            r = S.sphere_radius[S.shape_row[i]]
            grown = max(grown, r * (m - 1.0))
            S.sphere_radius[S.shape_row[i]] = r * m
            S.mass[i] *= m ** 3
            for k in range(3):
                S.inertia[i, k] *= m ** 5
    return grown


@jit
def scale_stiffnesses(C, m):
    """Multiply kn and ks of the live contacts whose physics exists by the radius multiplier ``m`` (contacts
    still flagged new get theirs from the grown radii at the next step)."""
    for c in range(C.ctr[C_CONTACTS]):
        if C.con_i[c, I_FLAGS] & FLAG_ALIVE and not C.con_i[c, I_FLAGS] & FLAG_NEW:
            C.con_f[c, F_KN] *= m
            C.con_f[c, F_KS] *= m


@jit
def spend_budgets(S, C, grown):
    """Radii grew by up to ``grown`` [m]: a gap between two bodies shrinks by up to twice that without any
    motion. Take it from the Verlet distance of the bounds (the collider runs once a body has moved farther
    than what is left) and from every pair's detection budget (``pair_gap``), as if the bodies had moved."""
    S.scal[S_VERLET] -= grown
    gap = C.pair_gap
    for p in range(C.ctr[C_PAIRS]):
        g = gap[p]
        if g > -math.inf and g < math.inf:
            gap[p] = budget_f32(g - 2.0 * grown)


@jit
def triaxial_stage(S, C, P):
    """Engine stage of TriaxialStressController (see the module docstring); ``P``: :class:`TriaxialParams`."""
    triaxial_control(S, C, P, P.internal)


@jit
def triaxial_control(S, C, P, internal):
    """One step of the controller with ``P``'s walls and goals; ``internal``: grow the spheres instead of moving
    the walls (the engines built on the controller switch it during a run)."""
    out, walls, goal = P.out, P.walls, P.goal
    it = S.iscal[SI_ITER]
    dt = S.scal[S_DT]
    if not out[T_SPHERES_VOLUME] >= 0.0:
        out[T_SPHERES_VOLUME] = spheres_volume(S)
    box_sizes(S, walls, P.thickness, out)
    for a in range(3):
        if out[T_SIZE0 + a] == 0.0:
            out[T_SIZE0 + a] = out[T_SIZE + a]
    if it % P.stress_interval == 0:
        mean = 0.0
        for w in range(6):
            s = inward(w) * S.force[walls[w], w // 2] / face_area(out, w // 2)
            out[T_STRESS + w] = s
            mean += s
        out[T_MEAN] = mean / 6.0
        vs = 0.0
        for a in range(3):
            out[T_STRAIN + a] = math.log(out[T_SIZE + a] / out[T_SIZE0 + a])
            vs += out[T_STRAIN + a]
        out[T_VOL_STRAIN] = vs
    if it % P.stiffness_interval == 0:
        if C.ctr[C_CSR_DIRTY]:
            build_csr(C, S.iscal[SI_NBODIES])
        for w in range(6):
            out[T_STIFF + w] = wall_stiffness(C, walls[w])
    if internal:
        for w in range(6):
            out[T_TRANSLATION + w] = 0.0
            for k in range(3):
                S.vel[walls[w], k] = 0.0
        if it % P.radius_interval == 0:
            sigma = (goal[0] + goal[1] + goal[2]) / 3.0
            if abs(out[T_MEAN]) > abs(sigma):
                out[T_MAX_MULT] = P.final_max_multiplier
            m = 1.0 + (out[T_MAX_MULT] - 1.0) * (sigma - out[T_MEAN]) / sigma
            out[T_PREV_MULT] = m
            out[T_PREV_STRESS] = out[T_MEAN]
            spend_budgets(S, C, grow_spheres(S, m))
            scale_stiffnesses(C, m)
            # the porosity of this step stays the one before the growth (YADE 2023.02a reports it so, measured:
            # tests/reference/yade/triax_tutorial_start.py); the grown volume counts from the next step
            out[T_SPHERES_VOLUME] = spheres_volume(S)
    else:
        for a in range(3):
            if not P.stress_mask >> a & 1:
                out[T_GOAL_RATE + a] = P.strain_damping * out[T_GOAL_RATE + a] + (1.0 - P.strain_damping) * goal[a]
        mean_size = (out[T_SIZE] + out[T_SIZE + 1] + out[T_SIZE + 2]) / 3.0
        for w in range(6):
            a = w // 2
            if not P.activated[w]:
                out[T_TRANSLATION + w] = 0.0
                continue
            body = walls[w]
            f = inward(w) * S.force[body, a]
            if P.stress_mask >> a & 1:
                err = f - goal[a] * face_area(out, a)
                cap = P.max_vel * dt * out[T_SIZE + a] / mean_size
                if out[T_STIFF + w] > 0.0:
                    t = min(max(err / out[T_STIFF + w], -cap), cap)
                elif err != 0.0:
                    t = math.copysign(cap, err)
                else:
                    t = 0.0
                t = (1.0 - P.stress_damping) * t + MEMORY * out[T_TRANSLATION + w]
            else:
                t = -0.5 * out[T_GOAL_RATE + a] * out[T_SIZE + a] * dt
            out[T_TRANSLATION + w] = t
            S.vel[body, a] = inward(w) * t / dt
            out[T_WORK] += t * f
    for a in range(3):
        out[T_RATE + a] = -(out[T_TRANSLATION + 2 * a] + out[T_TRANSLATION + 2 * a + 1]) / (dt * out[T_SIZE + a])
