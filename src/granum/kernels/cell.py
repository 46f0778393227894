"""The periodic cell's kinematics at the boundaries of a step.

The cell is deformed by its velocity gradient L (YADE ``Cell.velGrad``) with
(3.6,1): H <- (1 + L dt) H and F <- (1 + L dt) F for the base vectors H
(``hSize``) and the deformation gradient F (``trsf``). As in YADE, the update at
the start of a step uses the gradient of the previous step, and the gradient
that bodies follow (velocity jumps in NewtonIntegrator) is the current one; the
previous gradient is recorded at the end of each step, the base vectors before the deformation
(``prevHSize``) at its start.
"""

from __future__ import annotations

from granum._jit import jit
from granum.core.arrays import S_DT, S_TIME, SI_ITER, SI_PERIODIC
from granum.kernels.copy import copy_rows


@jit
def deform(m, lg, dt):
    """m <- (1 + lg dt) m for 3x3 arrays, in place."""
    out = m.copy()
    for i in range(3):
        for j in range(3):
            acc = m[i, j]
            for k in range(3):
                acc += dt * lg[i, k] * m[k, j]
            out[i, j] = acc
    copy_rows(m, out, 3)


@jit
def step_begin(S):
    """Deform the periodic cell by the velocity gradient of the previous step."""
    if S.iscal[SI_PERIODIC]:
        dt = S.scal[S_DT]
        copy_rows(S.cell_prev_hsize, S.cell_hsize, 3)
        deform(S.cell_hsize, S.cell_prev_velgrad, dt)
        deform(S.cell_trsf, S.cell_prev_velgrad, dt)


@jit
def step_end(S):
    """Record the velocity gradient and advance the clock."""
    copy_rows(S.cell_prev_velgrad, S.cell_velgrad, 3)
    S.scal[S_TIME] += S.scal[S_DT]
    S.iscal[SI_ITER] += 1
