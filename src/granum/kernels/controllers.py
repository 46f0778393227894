"""Boundary controllers of the periodic cell: PeriTriaxController's servo.

The controller drives the diagonal of the cell's velocity gradient L so that each
axis k reaches its goal: a stress sigma_kk (bit k of ``stressMask`` set) or a
logarithmic strain eps_k = ln F_kk. Per step:

* the stress is the Love-Weber tensor (1/V) sum_c f_c (x) l_c (compression
  negative) and the stiffness modulus along k is K_k = (1/V) sum_c kn (n_k l_k)^2,
  the stress change per unit strain of affine contacts, both every step (the unbalanced
  force every ``globUpdate`` steps);
* strain axis: the rate that reaches the goal in one step, limited by maxStrainRate;
* stress axis, ``dynCell``: the strain rate obeys d L_kk / dt = (goal - sigma_kk) / M with
  Cundall's damping growDamping on that acceleration (YADE 2023.02a's rule, measured step by
  step: the "mass" M scales a stress, not a force, and the cell's size does not enter);
* stress axis otherwise: the rate (goal - sigma_kk) / (K_k dt) scaled by
  (1 - growDamping), i.e. the affine estimate of the rate that reaches the goal;
* the goal is reached when every stress is within max(absStressTol, relStressTol |goal|),
  every strain within one step of its goal, and the unbalanced force is below
  maxUnbalanced; then the engine's Python ``doneHook`` runs after the step.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from granum._jit import jit
from granum.core.arrays import S_DT, SI_HOOK, SI_ITER, SI_NBODIES
from granum.core.bodies import DOF_ALL
from granum.core.contacts import C_CONTACTS, F_FN, F_FS, F_KN, F_NORMAL, FLAG_ALIVE, I_CELL, I_FLAGS, I_ID1, I_ID2
from granum.kernels.interaction import load3_row
from granum.kernels.newton import counted_force
from granum.physics.vec import add, det3, load3, matvec, sub

# slots of the controller's output array
O_STRESS = 0        # 0..2 diagonal stress [Pa]
O_STRAIN = 3        # 3..5 log strain [-]
O_RATE = 6          # 6..8 strain rate [1/s]
O_STIFF = 9         # 9..11 stiffness modulus [Pa]
O_TENSOR = 12       # 12..20 stress tensor, row by row [Pa]
O_UNBALANCED = 21   # unbalanced force [-]
O_SIZE = 22


class PeriTriaxParams(NamedTuple):
    """Parameters of :func:`peri_triax_stage` (PeriTriaxController's attributes of the same meaning)."""

    goal: np.ndarray        #: goal stress [Pa] or log strain [-] per axis, (3,) float64
    stress_mask: int        #: bit k set: axis k is stress-controlled
    max_rate: np.ndarray    #: largest strain rate per axis [1/s], (3,) float64
    max_unbalanced: float   #: largest unbalanced force for the goal to count as reached [-]
    abs_tol: float          #: absolute stress tolerance [Pa]
    rel_tol: float          #: relative stress tolerance [-]
    grow_damping: float     #: damping of the cell's motion [-]
    glob_update: int        #: the stress is recomputed every this many steps
    dyn_cell: bool          #: the cell obeys an equation of motion with mass ``mass``
    mass: float             #: inertia of the strain rate, d rate/dt = (goal - stress)/mass [Pa s^2]
    hook_id: int            #: what the stage writes to ``iscal[SI_HOOK]`` when the goal is reached
    out: np.ndarray         #: the controller's output, slots O_*, (O_SIZE,) float64; written by the stage


@jit
def contact_stress(S, C, out, unbalanced=True):
    """Write the Love-Weber stress tensor, the stiffness moduli and (with ``unbalanced``) the unbalanced force
    into ``out``."""
    h = S.cell_hsize
    vol = det3(h)
    sig = np.zeros((3, 3))
    stiff = np.zeros(3)
    fsum = 0.0
    nc = 0
    # columns read once (a field read from the record counts a reference); f and the branch are
    # tuples, not arrays: no allocation per contact; the branch runs to body 1 from body 2's image
    con_i, con_f, pos = C.con_i, C.con_f, S.pos
    for c in range(C.ctr[C_CONTACTS]):
        if not con_i[c, I_FLAGS] & FLAG_ALIVE:
            continue
        i1 = con_i[c, I_ID1]
        i2 = con_i[c, I_ID2]
        f = add(load3_row(con_f, c, F_FN), load3_row(con_f, c, F_FS))
        br = sub(sub(load3(pos, i1), load3(pos, i2)), matvec(h, load3_row(con_i, c, I_CELL)))
        for a in range(3):
            for b in range(3):
                sig[a, b] += f[a] * br[b]
            stiff[a] += con_f[c, F_KN] * (con_f[c, F_NORMAL + a] * br[a]) ** 2
        fsum += math.sqrt(f[0] ** 2 + f[1] ** 2 + f[2] ** 2)
        nc += 1
    for a in range(3):
        out[O_STIFF + a] = stiff[a] / vol
        out[O_STRESS + a] = sig[a, a] / vol
        for b in range(3):
            out[O_TENSOR + 3 * a + b] = sig[a, b] / vol
    if unbalanced:
        out[O_UNBALANCED] = unbalanced_force(S, fsum, nc)
    return vol


@jit
def unbalanced_force(S, fsum, nc):
    """YADE's unbalanced force: the mean resultant force on free bodies (a clump with its members' forces) over
    the mean contact force (``fsum``: the sum of |f| over the ``nc`` live contacts) [-]; NaN without contacts
    or free bodies."""
    res = 0.0
    nfree = 0
    alive, blocked, clump_id = S.alive, S.blocked, S.clump_id
    for i in range(S.iscal[SI_NBODIES]):
        if alive[i] and blocked[i] != DOF_ALL and (clump_id[i] < 0 or clump_id[i] == i):
            f = counted_force(i, S)
            res += math.sqrt(f[0] ** 2 + f[1] ** 2 + f[2] ** 2)
            nfree += 1
    return (res / nfree) / (fsum / nc) if nc > 0 and nfree > 0 and fsum > 0 else math.nan


@jit
def peri_triax_stage(S, C, P):
    """Engine stage of PeriTriaxController (see the module docstring for the servo).

    ``P``: :class:`PeriTriaxParams`.
    """
    goal, max_rate, grow_damp, out = P.goal, P.max_rate, P.grow_damping, P.out
    dt = S.scal[S_DT]
    # the stress every step, the unbalanced force (a loop over the bodies) every globUpdate steps: YADE
    # 2023.02a's controller reads the stress of the current step (measured: its stress equals getStress() after
    # every step, with the default globUpdate 5)
    contact_stress(S, C, out, P.glob_update <= 1 or S.iscal[SI_ITER] % P.glob_update == 0
                   or not out[O_UNBALANCED] == out[O_UNBALANCED])
    if P.dyn_cell:  # the stiffness only serves the affine servo: YADE reports 0 with dynCell (measured)
        for k in range(3):
            out[O_STIFF + k] = 0.0
    done = out[O_UNBALANCED] < P.max_unbalanced
    for k in range(3):
        out[O_STRAIN + k] = math.log(S.cell_trsf[k, k])
        rate = S.cell_velgrad[k, k]
        if P.stress_mask >> k & 1:
            err = goal[k] - out[O_STRESS + k]
            if abs(err) > max(P.abs_tol, P.rel_tol * abs(goal[k])):
                done = False
            if P.dyn_cell:
                acc = err / P.mass   # YADE's rule, measured: the strain rate itself is the cell's velocity
                if acc * rate > 0.0:
                    acc *= 1.0 - grow_damp
                elif acc * rate < 0.0:
                    acc *= 1.0 + grow_damp
                rate += acc * dt
            elif out[O_STIFF + k] > 0.0:
                rate = (1.0 - grow_damp) * err / (out[O_STIFF + k] * dt)
            else:
                rate = max_rate[k] if err > 0.0 else -max_rate[k]
        else:
            err = goal[k] - out[O_STRAIN + k]
            if abs(err) > max_rate[k] * dt:
                done = False
            rate = err / dt
        rate = min(max(rate, -max_rate[k]), max_rate[k])
        S.cell_velgrad[k, k] = rate
        out[O_RATE + k] = rate
    if done:
        S.iscal[SI_HOOK] = P.hook_id
