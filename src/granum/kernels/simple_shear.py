"""The simple-shear box's stage (YADE's KinemSimpleShearBox family: KinemCTDEngine, KinemCNDEngine,
KinemCNLEngine, KinemCNSEngine).

The box is six boxes: ``left``, ``bottom``, ``right``, ``top``, ``back``, ``front`` (YADE's ``id_boxleft``...,
by default bodies 0..5 as YADE's SimpleShear preprocessor appends them); x is the shear direction, y the normal
one. The stage only sets velocities (the boxes are fixed: NewtonIntegrator moves them by v·dt and turns them by
ω·dt in the next step, so an engine placed after NewtonIntegrator, as in YADE's scripts, moves the box one step
later). Per step (YADE 2023.02a, measured: tests/reference/yade/kinem_shear.py):

* the angle of the lateral boxes, measured at each move (not at a stop): θ = the rotation angle of the left box's
  orientation, 2·atan2(|q_xyz|, |q_w|) [rad], and ``alpha`` = π/2 − θ (the angle's magnitude whatever the axis);
* a move (dX, dY) [m] of the top box: its velocity is (dX, dY, 0)/dt, the left and right boxes' (dX/2, dY/2, 0)/dt
  (their centres stay halfway), both turn at ω_z = −(θ' − θ)/dt about z, where with h = y_top − y_left
  tan θ' = tan θ + dX/(2h) (the lateral boxes' upper ends follow the top box), but θ' = atan(dX/h) while
  alpha is exactly π/2 (YADE's first shear step from an upright box turns twice as far; measured);
* a stop: the three boxes' velocities and the lateral boxes' angular velocities become zero;
* the normal stress σ = F_y(top)/A/1000 [kPa], A = (x_right − x_left − e_left − e_right)·(z_front − z_back −
  e_back − e_front) the inner section between the lateral boxes (e: the boxes' half-extents across them);
* CTD (``compSpeed`` v): the top box moves by (0, −v·dt) while σ < ``targetSigma`` (v > 0, compression) or
  σ > ``targetSigma`` (v < 0, unloading), otherwise it stops; a stop after a move (or at the engine's first run)
  asks for the hook, which saves the simulation (``<Key>Sigmax_<floor(targetSigma)>kPaReached.xml``, ``Sigmin_``
  when v ≤ 0);
* CND, CNL, CNS (``shearSpeed`` s): while ``gamma`` ≤ ``gammalim`` the top box moves by (s·dt, dY) and
  ``gamma`` grows by s·dt, otherwise it stops (CND's stops after a move, or at its first run, ask for the hook,
  which saves ``<Key>endShear.xml``). dY = 0 for CND; CNL and CNS first (``firstRun``) keep
  ``f0`` = F_y(top) and ``y0`` = y_top, then dY = (1 − ``wallDamping``)·(F_y − F_t)/K, limited to ±``max_vel``·dt,
  K = Σ kn over the top box's contacts (dY = 0 while K = 0), with the target F_t = f0 for CNL and
  F_t = f0 + KnC·10⁹·A·(y_top − y0) for CNS (KnC in MPa/mm).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from granum._jit import jit
from granum.core.arrays import S_DT, SI_HOOK, SI_NBODIES
from granum.core.contacts import C_CSR_DIRTY
from granum.kernels.interaction import build_csr
from granum.kernels.triaxial import wall_stiffness

# the engine's kind
MODE_CTD = 0
MODE_CND = 1
MODE_CNL = 2
MODE_CNS = 3

# slots of the engine's state array (floats)
K_ALPHA = 0       # alpha: angle from the bottom box to the left box [rad]
K_GAMMA = 1       # gamma: horizontal displacement of the top box so far [m]
K_F0 = 2          # f0: normal force on the top box at the first run (CNL, CNS) [N]
K_Y0 = 3          # y0: height of the top box at the first run (CNL, CNS) [m]
K_FIRST_RUN = 4   # firstRun (1 or 0)
K_STOPPED = 5     # 1 while the boxes are stopped (from the step that stopped them), 0 while they move
K_SAVE_DUE = 6    # CTD, CND: 1 from a step that stopped the boxes until the hook has saved
K_SIZE = 7

# positions of the boxes in ShearBoxParams.boxes
B_LEFT, B_BOTTOM, B_RIGHT, B_TOP, B_BACK, B_FRONT = range(6)
HALF_PI = 0.5 * math.pi


class ShearBoxParams(NamedTuple):
    """Parameters of :func:`simple_shear_stage` (the engines' attributes of the same meaning)."""

    boxes: np.ndarray    #: body ids of the left, bottom, right, top, back, front boxes, (6,) int64
    mode: int            #: MODE_CTD, MODE_CND, MODE_CNL or MODE_CNS
    speed: float         #: compSpeed (CTD) or shearSpeed [m/s]
    gamma_lim: float     #: gammalim [m] (shear modes)
    target_sigma: float  #: targetSigma [kPa] (CTD)
    stiffness: float     #: KnC in Pa/m (CNS; 0 otherwise)
    max_vel: float       #: max_vel: bound of the normal speed of CNL, CNS [m/s]
    wall_damping: float  #: wallDamping [-]
    state: np.ndarray    #: slots K_*, (K_SIZE,) float64; written by the stage
    hook_id: int         #: what the stage writes to ``iscal[SI_HOOK]`` when a save of CTD or CND is due


@jit
def _inner_area(S, boxes):
    """The section between the lateral boxes, A [m²] (see the module docstring)."""
    ext, row = S.box_extents, S.shape_row
    left, right, back, front = boxes[B_LEFT], boxes[B_RIGHT], boxes[B_BACK], boxes[B_FRONT]
    length = S.pos[right, 0] - S.pos[left, 0] - ext[row[left], 0] - ext[row[right], 0]
    width = S.pos[front, 2] - S.pos[back, 2] - ext[row[back], 2] - ext[row[front], 2]
    return length * width


@jit
def _set_motion(S, boxes, vx, vy, w):
    """Velocities of the top box (vx, vy, 0) [m/s] and of the lateral boxes (vx/2, vy/2, 0), their angular
    velocity (0, 0, w) [rad/s]."""
    top = boxes[B_TOP]
    S.vel[top, 0] = vx
    S.vel[top, 1] = vy
    S.vel[top, 2] = 0.0
    for b in (boxes[B_LEFT], boxes[B_RIGHT]):
        S.vel[b, 0] = 0.5 * vx
        S.vel[b, 1] = 0.5 * vy
        S.vel[b, 2] = 0.0
        S.ang_vel[b, 0] = 0.0
        S.ang_vel[b, 1] = 0.0
        S.ang_vel[b, 2] = w


@jit
def _stop(S, P, st):
    """Stop the boxes; a stop after a move (or at the engine's first run) of CTD and CND asks for the hook (their
    save)."""
    _set_motion(S, P.boxes, 0.0, 0.0, 0.0)
    if st[K_STOPPED] == 0.0 and (P.mode == MODE_CTD or P.mode == MODE_CND):
        st[K_SAVE_DUE] = 1.0
        S.iscal[SI_HOOK] = P.hook_id
    st[K_STOPPED] = 1.0


@jit
def _move(S, boxes, st, dx, dy, dt):
    """Move the top box by (dx, dy) [m] in the next step, the lateral boxes halfway, turned to follow it; alpha
    is measured here (an engine that only stops keeps its last value)."""
    q = S.ori[boxes[B_LEFT]]
    theta = 2.0 * math.atan2(math.sqrt(q[1] * q[1] + q[2] * q[2] + q[3] * q[3]), abs(q[0]))
    alpha = HALF_PI - theta
    st[K_ALPHA] = alpha
    h = S.pos[boxes[B_TOP], 1] - S.pos[boxes[B_LEFT], 1]
    if alpha == HALF_PI:
        turned = math.atan(dx / h)
    else:
        turned = math.atan(math.tan(theta) + 0.5 * dx / h)
    _set_motion(S, boxes, dx / dt, dy / dt, -(turned - theta) / dt)
    st[K_STOPPED] = 0.0


@jit
def _normal_move(S, C, P, boxes, st, dt):
    """dY of CNL and CNS [m] (see the module docstring)."""
    top = boxes[B_TOP]
    if C.ctr[C_CSR_DIRTY]:
        build_csr(C, S.iscal[SI_NBODIES])
    k = wall_stiffness(C, top)
    if k == 0.0:
        return 0.0
    target = st[K_F0] + P.stiffness * _inner_area(S, boxes) * (S.pos[top, 1] - st[K_Y0])
    dy = (1.0 - P.wall_damping) * (S.force[top, 1] - target) / k
    cap = P.max_vel * dt
    return min(max(dy, -cap), cap)


@jit
def simple_shear_stage(S, C, P):
    """Engine stage of the KinemSimpleShearBox engines (see the module docstring); ``P``:
    :class:`ShearBoxParams`."""
    st, boxes = P.state, P.boxes
    dt = S.scal[S_DT]
    top = boxes[B_TOP]
    if P.mode == MODE_CTD:
        sigma = S.force[top, 1] / _inner_area(S, boxes) / 1000.0
        if (P.speed > 0.0 and sigma < P.target_sigma) or (P.speed < 0.0 and sigma > P.target_sigma):
            _move(S, boxes, st, 0.0, -P.speed * dt, dt)
        else:
            _stop(S, P, st)
        return
    if P.mode != MODE_CND and st[K_FIRST_RUN] != 0.0:
        st[K_F0] = S.force[top, 1]
        st[K_Y0] = S.pos[top, 1]
        st[K_FIRST_RUN] = 0.0
    if st[K_GAMMA] <= P.gamma_lim:
        dx = P.speed * dt
        dy = 0.0 if P.mode == MODE_CND else _normal_move(S, C, P, boxes, st, dt)
        _move(S, boxes, st, dx, dy, dt)
        st[K_GAMMA] += dx
    else:
        _stop(S, P, st)
