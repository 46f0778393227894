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
def advance_clock(scal, iscal, velgrad, prev_velgrad):
    """The end of a step: record the velocity gradient ``velgrad`` (3, 3) [1/s] as ``prev_velgrad``, advance the
    time ``scal[S_TIME]`` [s] by ``scal[S_DT]`` and the step count ``iscal[SI_ITER]`` by one. Its own arrays, not
    the scene's record: a step run item by item (a Python engine due) ends with it without building the record."""
    copy_rows(prev_velgrad, velgrad, 3)
    scal[S_TIME] += scal[S_DT]
    iscal[SI_ITER] += 1


@jit
def step_end(S):
    """The end of a step in the compiled step loop: :func:`advance_clock` on the scene's record."""
    advance_clock(S.scal, S.iscal, S.cell_velgrad, S.cell_prev_velgrad)
