"""Peri3dController's servo: the six components of the periodic cell's stress or strain follow prescribed paths.

Vectors are Voigt-ordered (xx, yy, zz, yz, zx, xy); strains are engineering strains (shear gamma_ij =
2 eps_ij), stresses the Love-Weber tensor (compression negative). Bit k of ``stressMask`` makes component k a
stress, otherwise a strain. Per step, with progress p advanced by 1/nSteps:

* each component follows its path: the points (t_m, v_m) scaled to (t_m / t_last, goal_k v_m / v_last),
  preceded by (0, the component's value when the controller started: ``strain`` or ``stressIdeal``) unless the
  first point is at t = 0, linear in between and extended along the last segment beyond p = 1. The path is
  integrated: the step's change is the slope of the segment that holds the progress before the step times
  1/nSteps (YADE's: a segment's end reached only up to rounding switches one step late);
* a strain component gets the rate of that change, change / dt;
* a stress component's goal is ``stressIdeal``; at the first step its rate comes from an isotropic elastic
  estimate (``youngEstimation``, ``poissonEstimation``): the path's stress rates (new stressIdeal - old)/dt
  and the prescribed strain rates give the unknown strain rates; afterwards YADE's predictor: the error
  e = stress - stressIdeal, extrapolated as 2 e - e_previous, changes the rate by -+ mod max_k |rate_k|;
* rates are limited to +- maxStrainRate; a strain component's strain is its goal, a stress component's
  strain gains the last step's rate times dt (what the cell did since);
* the cell: with trsf T = U P (polar decomposition, U a rotation), P <- P + U^T (dt rate tensor) U, the next T
  is U P and the velocity gradient is (T_next T^-1 - 1)/dt;
* a step that ends with p >= 1 (the sum of the 1/nSteps, rounding included) or a strain beyond ``maxStrain``
  runs the engine's Python hook after it (doneHook, or the engine is set dead when there is none); YADE runs
  it inside the step, where O.iter reads one less.

Strain paths, the rate, the strain vector and the velocity gradient are YADE 2023.02a's as measured
(``tests/reference/yade/peri3d.py``), so are the stress predictor's first steps on a shared packing.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from granum._jit import jit
from granum.core.arrays import S_DT, SI_HOOK
from granum.kernels.controllers import O_SIZE as TRIAX_OUT_SIZE
from granum.kernels.controllers import O_TENSOR, contact_stress

# slots of the engine's state array (each vector 6 wide)
Q_STRESS = 0
Q_STRAIN = 6
Q_RATE = 12
Q_STRESS_RATE = 18
Q_STRESS_IDEAL = 24
Q_STRAIN_GOAL = 30
Q_STRESS_GOAL = 36
Q_ERR_PREV = 42     # stress error of the previous step
Q_INIT = 48         # each component's value when the controller started
Q_PROGRESS = 54
Q_STEPS_DONE = 55   # steps run (0: the first step is still to come)
Q_SIZE = 56

#: Voigt index -> tensor indices
VOIGT = ((0, 0), (1, 1), (2, 2), (1, 2), (2, 0), (0, 1))


class Peri3dParams(NamedTuple):
    """Parameters of :func:`peri3d_stage` (Peri3dController's attributes of the same meaning)."""

    goal: np.ndarray          #: final values, stresses [Pa] or strains [-], (6,) float64
    stress_mask: int          #: bit k set: component k is a stress
    n_steps: int              #: steps to reach the goal
    max_strain_rate: float    #: largest |rate| [1/s]
    max_strain: float         #: largest |strain| before the hook runs [-]
    mod: float                #: the predictor's step [-]
    young: float              #: Young's modulus estimate [Pa]
    poisson: float            #: Poisson's ratio estimate [-]
    paths: np.ndarray         #: path points (t, v), (6, K, 2) float64, path k in rows [0, path_len[k])
    path_len: np.ndarray      #: points of each path, (6,) int64
    hook_id: int              #: what the stage writes to ``iscal[SI_HOOK]``
    out: np.ndarray           #: the engine's state, slots Q_*, (Q_SIZE,) float64


@jit
def path_slope(paths, n, k, p, init, goal):
    """d value / d progress of path ``k`` (``n`` points) on the segment holding progress ``p`` (segments
    [t_m, t_m+1), the last one extended beyond p = 1; see the module docstring for the points)."""
    t_last = paths[k, n - 1, 0]
    v_last = paths[k, n - 1, 1]
    t0, v0 = 0.0, init
    m = 0
    if paths[k, 0, 0] == 0.0:
        v0 = goal * paths[k, 0, 1] / v_last
        m = 1
    t1, v1 = t0, v0
    while m < n:
        t1 = paths[k, m, 0] / t_last
        v1 = goal * paths[k, m, 1] / v_last
        if p < t1 or m == n - 1:
            break
        t0, v0 = t1, v1
        m += 1
    return 0.0 if t1 == t0 else (v1 - v0) / (t1 - t0)


@jit
def inverse3(a, out):
    """``out`` <- a^-1 for 3x3 ``a`` (cofactors)."""
    det = (a[0, 0] * (a[1, 1] * a[2, 2] - a[1, 2] * a[2, 1]) - a[0, 1] * (a[1, 0] * a[2, 2] - a[1, 2] * a[2, 0])
           + a[0, 2] * (a[1, 0] * a[2, 1] - a[1, 1] * a[2, 0]))
    for i in range(3):
        for j in range(3):
            i1, i2 = (j + 1) % 3, (j + 2) % 3
            j1, j2 = (i + 1) % 3, (i + 2) % 3
            out[i, j] = (a[i1, j1] * a[i2, j2] - a[i1, j2] * a[i2, j1]) / det


@jit
def polar(t, rot, stretch):
    """T = U P: ``rot`` <- U (Newton's iteration U <- (U + U^-T)/2), ``stretch`` <- P = U^T T, symmetrized."""
    u = t.copy()
    inv = np.empty((3, 3))
    for _ in range(100):
        inverse3(u, inv)
        change = 0.0
        for i in range(3):
            for j in range(3):
                new = 0.5 * (u[i, j] + inv[j, i])
                change = max(change, abs(new - u[i, j]))
                rot[i, j] = new
        for i in range(3):
            for j in range(3):
                u[i, j] = rot[i, j]
        if change < 1e-15:
            break
    for i in range(3):
        for j in range(3):
            acc = 0.0
            for m in range(3):
                acc += rot[m, i] * t[m, j]
            stretch[i, j] = acc
    for i in range(3):
        for j in range(i + 1, 3):
            s = 0.5 * (stretch[i, j] + stretch[j, i])
            stretch[i, j] = s
            stretch[j, i] = s


@jit
def elastic_rates(P, rate, stress_rate):
    """First step: the stress components' strain rates from the isotropic compliance C of the estimate (normal
    block 1/E on the diagonal, -nu/E off it; shear (1 + nu)/E), restricted to the stress components and scaled
    by 6 / (their number): rate_s = 6/n_s sum_s' C_ss' stress_rate_s', YADE's values as measured."""
    e, nu = P.young, P.poisson
    ns = 0
    for k in range(6):
        ns += P.stress_mask >> k & 1
    for a in range(6):
        if not P.stress_mask >> a & 1:
            continue
        acc = 0.0
        for b in range(6):
            if not P.stress_mask >> b & 1:
                continue
            if a < 3 and b < 3:
                c = 1.0 / e if a == b else -nu / e
            elif a == b:
                c = (1.0 + nu) / e
            else:
                c = 0.0
            acc += c * stress_rate[b]
        rate[a] = 6.0 / ns * acc


@jit
def peri3d_stage(S, C, P):
    """Engine stage of Peri3dController (see the module docstring). ``P``: :class:`Peri3dParams`."""
    out = P.out
    dt = S.scal[S_DT]
    triax = np.empty(TRIAX_OUT_SIZE)
    contact_stress(S, C, triax)
    for k in range(6):
        i, j = VOIGT[k]
        out[Q_STRESS + k] = triax[O_TENSOR + 3 * i + j]
    first = out[Q_STEPS_DONE] == 0.0
    if first:
        for k in range(6):
            out[Q_INIT + k] = out[(Q_STRESS_IDEAL if P.stress_mask >> k & 1 else Q_STRAIN) + k]
    p_old = out[Q_PROGRESS]
    out[Q_PROGRESS] += 1.0 / P.n_steps
    step = out[Q_PROGRESS] - p_old
    rate = np.empty(6)
    stress_rate = np.empty(6)
    peak = 0.0
    for k in range(6):
        peak = max(peak, abs(out[Q_RATE + k]))
    for k in range(6):
        change = path_slope(P.paths, P.path_len[k], k, p_old, out[Q_INIT + k], P.goal[k]) * step
        if P.stress_mask >> k & 1:
            err = out[Q_STRESS + k] - out[Q_STRESS_IDEAL + k]
            stress_rate[k] = change / dt
            out[Q_STRESS_IDEAL + k] += change
            out[Q_STRESS_GOAL + k] = P.goal[k]
            rate[k] = out[Q_RATE + k]
            # the strain reached with the last step's rate (the cell moves with it in this step)
            out[Q_STRAIN + k] += rate[k] * dt
            if not first:
                ext = 2.0 * err - out[Q_ERR_PREV + k]
                if ext > 0.0:
                    rate[k] -= peak * P.mod
                elif ext < 0.0:
                    rate[k] += peak * P.mod
            out[Q_ERR_PREV + k] = err
        else:
            out[Q_STRAIN_GOAL + k] = P.goal[k]
            rate[k] = change / dt
            stress_rate[k] = 0.0
    if first and P.stress_mask:
        elastic_rates(P, rate, stress_rate)
    for k in range(6):
        rate[k] = min(max(rate[k], -P.max_strain_rate), P.max_strain_rate)
        out[Q_RATE + k] = rate[k]
        out[Q_STRESS_RATE + k] = stress_rate[k]
        if not P.stress_mask >> k & 1:
            out[Q_STRAIN + k] += rate[k] * dt   # the goal (unless the rate was limited)
    # the cell: T = U P, P += U^T (dt D) U, velGrad = (U P_next T^-1 - 1) / dt
    t = S.cell_trsf
    rot = np.empty((3, 3))
    stretch = np.empty((3, 3))
    polar(t, rot, stretch)
    d = np.zeros((3, 3))
    for k in range(6):
        i, j = VOIGT[k]
        if k < 3:
            d[i, i] = rate[k] * dt
        else:
            d[i, j] = 0.5 * rate[k] * dt
            d[j, i] = d[i, j]
    for i in range(3):
        for j in range(3):
            acc = 0.0
            for a in range(3):
                for b in range(3):
                    acc += rot[a, i] * d[a, b] * rot[b, j]
            stretch[i, j] += acc
    tinv = np.empty((3, 3))
    inverse3(t, tinv)
    for i in range(3):
        for j in range(3):
            acc = 0.0
            for a in range(3):
                row = 0.0
                for b in range(3):
                    row += rot[i, b] * stretch[b, a]
                acc += row * tinv[a, j]
            S.cell_velgrad[i, j] = (acc - (1.0 if i == j else 0.0)) / dt
    out[Q_STEPS_DONE] += 1.0
    # finished: progress summed to 1 (0.1 ten times is 0.999..., so YADE's 10-step run ends one step later)
    done = out[Q_PROGRESS] >= 1.0
    for k in range(6):
        if abs(out[Q_STRAIN + k]) > P.max_strain:
            done = True
    if done:
        S.iscal[SI_HOOK] = P.hook_id
