"""PeriIsoCompressor's servo: isotropic compression of a periodic cell through a series of stresses.

Each step, while stresses are left (``state < len(stresses)``), with ``goal = stresses[state]``
(compression negative) and the cell sizes s_k = |H_k| (columns of ``hSize``), face areas
A = (s_1 s_2, s_0 s_2, s_0 s_1):

* the stress per axis is sigma_k = -(sum_c |f_c,k|) / A_k, f_c = fn + fs of each live contact (YADE's
  ``totalForceInVolume``: always compressive, a force sum, no branch vectors), and the mean contact
  stiffness is K = mean_c (kn/3 + 2 ks/3) (-1 without contacts, then taken as 1);
* ``keepProportions``: the mean size changes by
  g = 1e-4 (goal - mean(sigma)) mean(A) / K, limited to |g| s_max/mean(s) <= d (d = charLen/100, the
  largest displacement per step); each axis grows by g s_k / mean(s), so the cell keeps its shape;
  otherwise each axis grows by 1e-4 (goal - sigma_k) A_k / K, limited to |.| <= d;
* sigma (the reported one too) is then predicted to the end of the step: each component gains g K
  (g_k K without keepProportions) when K > 0, and the stress test below reads the prediction;
* the growth g_k becomes the velocity gradient L_kk = g_k / (dt s_k) (the diagonal only);
* the stress counts as reached when |(mean(sigma) - goal)/goal| <= 5e-3 (each sigma_k without
  keepProportions); then the unbalanced force below ``maxUnbalanced`` moves ``state`` to the next stress. It
  is measured only at steps that are multiples of ``globalUpdateInt`` and is -1 from the start and after each
  transition, so a stress reached between those steps passes at once (as in YADE 2023.02a); after the last
  stress the engine's Python ``doneHook`` runs after the step.

``charLen`` <= 0 is set at the first step to the mean size of body 0's bound, ``maxSpan`` <= 0 to
the largest extent of any bound; the cell may not become smaller than 2.1 maxSpan. These are YADE
2023.02a's rules, measured step by step on a shared packing (``tests/reference/yade/periiso.py``).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from granum._jit import jit
from granum.core.arrays import S_DT, SI_HOOK, SI_ITER, SI_NBODIES
from granum.core.contacts import C_CONTACTS, F_FN, F_FS, F_KN, F_KS, FLAG_ALIVE, I_FLAGS
from granum.kernels.controllers import unbalanced_force

# slots of the engine's state array
P_SIGMA = 0         # 0..2 stress per axis [Pa] (compression negative)
P_UNBALANCED = 3    # unbalanced force [-] (-1: not computed yet)
P_STATE = 4         # index of the stress being reached (as a float)
P_CHARLEN = 5       # characteristic length [m]
P_MAXSPAN = 6       # largest bound extent [m]
P_ERROR = 7         # ERR_* of a failed step (0: none)
P_SIZE = 8

ERR_NONE = 0
ERR_NO_BOUND = 1    # body 0 has no bound to take charLen from
ERR_CELL_SMALL = 2  # the cell is smaller than 2.1 maxSpan
ERR_NO_SHRINK = 3   # the stress asks for a cell smaller than 2.1 maxSpan

#: the largest displacement of a cell face per step, over charLen [-]
DISPL_PER_CHARLEN = 1e-2
#: the smallest cell size, over maxSpan [-]
MIN_CELL_SPANS = 2.1
#: relative distance to the goal stress below which it counts as reached [-]
STRESS_TOL = 5e-3
#: the growth per step is GAIN (goal - sigma) A / K [m]
GAIN = 1e-4


class PeriIsoParams(NamedTuple):
    """Parameters of :func:`peri_iso_stage` (PeriIsoCompressor's attributes of the same meaning)."""

    stresses: np.ndarray     #: the goal stresses, one after another [Pa], (n,) float64
    max_unbalanced: float    #: unbalanced force below which a stress counts as stable [-]
    global_update_int: int   #: the unbalanced force is recomputed every this many steps
    keep_proportions: bool   #: control the mean stress and keep the cell's shape
    hook_id: int             #: what the stage writes to ``iscal[SI_HOOK]`` (doneHook or an error)
    out: np.ndarray          #: the engine's state, slots P_*, (P_SIZE,) float64; read and written


@jit
def force_sums(C, fsum3):
    """Sum of |fn + fs| per axis into ``fsum3`` (3,); returns (sum of |fn + fs|, number of live contacts,
    mean kn/3 + 2 ks/3 [N/m] or -1 without contacts)."""
    con_i, con_f = C.con_i, C.con_f
    stiff = 0.0
    fsum = 0.0
    nc = 0
    for c in range(C.ctr[C_CONTACTS]):
        if not con_i[c, I_FLAGS] & FLAG_ALIVE:
            continue
        f2 = 0.0
        for a in range(3):
            f = con_f[c, F_FN + a] + con_f[c, F_FS + a]
            fsum3[a] += abs(f)
            f2 += f * f
        fsum += math.sqrt(f2)
        stiff += con_f[c, F_KN] / 3.0 + 2.0 * con_f[c, F_KS] / 3.0
        nc += 1
    return fsum, nc, stiff / nc if nc > 0 else -1.0


@jit
def bound_extents(S, out):
    """Set charLen (mean extent of body 0's bound) and maxSpan (largest extent of any bound) where they are
    not positive; False if body 0 has no bound."""
    bmin, bmax = S.bound_min, S.bound_max
    if not out[P_CHARLEN] > 0.0:
        ext = (bmax[0, 0] - bmin[0, 0]) + (bmax[0, 1] - bmin[0, 1]) + (bmax[0, 2] - bmin[0, 2])
        if S.iscal[SI_NBODIES] == 0 or not S.alive[0] or not ext == ext:
            return False
        out[P_CHARLEN] = ext / 3.0
    if not out[P_MAXSPAN] > 0.0:
        span = 0.0
        for i in range(S.iscal[SI_NBODIES]):
            if S.alive[i]:
                for a in range(3):
                    e = bmax[i, a] - bmin[i, a]
                    if e > span:
                        span = e
        out[P_MAXSPAN] = span
    return True


@jit
def fail(S, P, code):
    P.out[P_ERROR] = code
    S.iscal[SI_HOOK] = P.hook_id


@jit
def peri_iso_stage(S, C, P):
    """Engine stage of PeriIsoCompressor (see the module docstring). ``P``: :class:`PeriIsoParams`."""
    out = P.out
    state = int(out[P_STATE])
    if state >= P.stresses.shape[0]:
        return
    if not bound_extents(S, out):
        fail(S, P, ERR_NO_BOUND)
        return
    h = S.cell_hsize
    size = np.empty(3)
    for k in range(3):
        size[k] = math.sqrt(h[0, k] ** 2 + h[1, k] ** 2 + h[2, k] ** 2)
    area = np.array((size[1] * size[2], size[0] * size[2], size[0] * size[1]))
    s_min, s_max = size.min(), size.max()
    min_size = MIN_CELL_SPANS * out[P_MAXSPAN]
    if s_min < min_size:
        fail(S, P, ERR_CELL_SMALL)
        return
    fsum3 = np.zeros(3)
    fsum, nc, stiff = force_sums(C, fsum3)
    gain = GAIN / (stiff if stiff > 0.0 else 1.0)
    max_displ = DISPL_PER_CHARLEN * out[P_CHARLEN]
    goal = P.stresses[state]
    for k in range(3):
        out[P_SIGMA + k] = -fsum3[k] / area[k]
    grow = np.empty(3)
    reached = True
    if P.keep_proportions:
        sig_avg = (out[P_SIGMA] + out[P_SIGMA + 1] + out[P_SIGMA + 2]) / 3.0
        avg_size = (size[0] + size[1] + size[2]) / 3.0
        max_to_avg = s_max / avg_size
        g = gain * (goal - sig_avg) * (area[0] + area[1] + area[2]) / 3.0
        if abs(max_to_avg * g) > max_displ:
            g = math.copysign(max_displ / max_to_avg, g)
        if g < -(s_min - min_size) / max_to_avg:
            fail(S, P, ERR_NO_SHRINK)
            return
        if stiff > 0.0:
            sig_avg += g * stiff
        reached = abs((sig_avg - goal) / goal) <= STRESS_TOL
        for k in range(3):
            grow[k] = g / avg_size * size[k]
            if stiff > 0.0:
                out[P_SIGMA + k] += g * stiff
    else:
        for k in range(3):
            g = gain * (goal - out[P_SIGMA + k]) * area[k]
            if abs(g) > max_displ:
                g = math.copysign(max_displ, g)
            if g < -(size[k] - min_size):
                fail(S, P, ERR_NO_SHRINK)
                return
            if stiff > 0.0:
                out[P_SIGMA + k] += g * stiff
            reached = reached and abs((out[P_SIGMA + k] - goal) / goal) <= STRESS_TOL
            grow[k] = g
    dt = S.scal[S_DT]
    for k in range(3):
        S.cell_velgrad[k, k] = grow[k] / (dt * size[k])
    if not reached:
        return
    # YADE measures the unbalanced force only at multiples of globalUpdateInt: reached between them, the stress
    # passes on the -1 left by the last transition (measured: randomDensePack's cell moves on at iter 457)
    if S.iscal[SI_ITER] % P.global_update_int == 0:
        out[P_UNBALANCED] = unbalanced_force(S, fsum, nc)
    if out[P_UNBALANCED] < P.max_unbalanced:
        out[P_STATE] = state + 1
        out[P_UNBALANCED] = -1.0   # measured afresh for the next stress (YADE shows -1 after each)
        if state + 1 == P.stresses.shape[0]:
            S.iscal[SI_HOOK] = P.hook_id
