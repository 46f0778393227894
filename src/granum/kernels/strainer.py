"""UniaxialStrainer's stage: two groups of bodies (``posIds``, ``negIds``) pulled apart (or pushed together) along
an axis at a constant strain rate.

With L0 = x_p0 − x_n0 (``originalLength``: the axis coordinates of the first body of each group when the engine
starts) and e the axis' unit vector, per step while ``active`` (YADE 2023.02a, measured; the engine runs before
NewtonIntegrator and the bodies' axis DOF is blocked, so their velocities are what moves them):

* strain ε = (x_p0 − x_n0 − L0)/L0 from the positions at the start of the step;
* every ``stressUpdateInterval`` steps: ``avgStress`` = (Σ_neg F·e − Σ_pos F·e)/(2A), A = ``crossSectionArea``
  (tension positive);
* the groups move apart at the speed v = ε̇·L0 (``absSpeed``): symmetric, ±v/2 (positive group +); with
  ``asymmetry`` 1 only the positive group moves (+v), with −1 only the negative one (−v);
* ``setSpeeds``, at the engine's first run only: every live body first takes the axial velocity of the uniform
  strain rate, v_n + ε̇·(x − x_n0) (v_n the negative group's speed, x_n0 its first body's coordinate, positions
  as the engine finds them: after NewtonIntegrator's move when it comes after it), its other components kept,
  fixed bodies included (YADE 2023.02a, measured: tests/reference/yade/strainer_speeds.py); the specimen then
  strains from the first step instead of waiting for the groups' pull to cross it;
* ``stopStrain``: when ε + ε̇·dt ≥ stopStrain, v becomes (stopStrain − ε)·L0/dt for this last step (the groups
  reach it exactly) and the engine becomes inactive; the bodies keep the velocities it gave them.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from granum._jit import jit
from granum.core.arrays import S_DT, SI_ITER, SI_NBODIES

# slots of the engine's state array
U_LENGTH0 = 0     # originalLength [m]
U_STRAIN = 1      # strain [-]
U_STRESS = 2      # avgStress [Pa]
U_ACTIVE = 3      # active (0 or 1)
U_SET_SPEEDS = 4  # 1 until the first run when setSpeeds is on, then 0
U_SIZE = 5


class StrainerParams(NamedTuple):
    """Parameters of :func:`strainer_stage` (UniaxialStrainer's attributes of the same meaning)."""

    pos_ids: np.ndarray     #: posIds, (P,) int64
    neg_ids: np.ndarray     #: negIds, (N,) int64
    axis: int               #: the strained axis, 0..2
    asymmetry: int          #: 0 symmetric, 1 only posIds move, -1 only negIds move
    strain_rate: float      #: strainRate [1/s]
    area: float             #: crossSectionArea [m^2]
    stop_strain: float      #: stopStrain [-] (NaN: none)
    stress_interval: int    #: stressUpdateInterval [steps]
    state: np.ndarray       #: slots U_*, (U_SIZE,) float64; written by the stage


@jit
def strainer_stage(S, C, P):
    """Engine stage of UniaxialStrainer (see the module docstring); ``P``: :class:`StrainerParams`."""
    st = P.state
    if st[U_ACTIVE] == 0.0:
        return
    a = P.axis
    l0 = st[U_LENGTH0]
    strain = (S.pos[P.pos_ids[0], a] - S.pos[P.neg_ids[0], a] - l0) / l0
    st[U_STRAIN] = strain
    if S.iscal[SI_ITER] % P.stress_interval == 0:
        f = 0.0
        for i in P.neg_ids:
            f += S.force[i, a]
        for i in P.pos_ids:
            f -= S.force[i, a]
        st[U_STRESS] = f / (2.0 * P.area)
    dt = S.scal[S_DT]
    speed = P.strain_rate * l0
    if not math.isnan(P.stop_strain) and strain + P.strain_rate * dt >= P.stop_strain:
        speed = (P.stop_strain - strain) * l0 / dt
        st[U_ACTIVE] = 0.0
    vp = 0.5 * speed
    vn = -0.5 * speed
    if P.asymmetry == 1:
        vp, vn = speed, 0.0
    elif P.asymmetry == -1:
        vp, vn = 0.0, -speed
    if st[U_SET_SPEEDS] != 0.0:
        st[U_SET_SPEEDS] = 0.0
        x_n, pos, vel, alive = S.pos[P.neg_ids[0], a], S.pos, S.vel, S.alive
        for i in range(S.iscal[SI_NBODIES]):
            if alive[i]:
                vel[i, a] = vn + P.strain_rate * (pos[i, a] - x_n)
    for i in P.pos_ids:
        S.vel[i, a] = vp
    for i in P.neg_ids:
        S.vel[i, a] = vn
