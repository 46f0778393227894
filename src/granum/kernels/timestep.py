"""GlobalStiffnessTimeStepper's stage: the time step from the stiffness of each body's contacts.

A body of mass m and principal inertia I_w with contacts c (normal n, stiffnesses kn, ks, reference
radius r of the body's side) has the diagonal translational and rotational stiffnesses
(Chareyre & Villard 2005; YADE's documentation, eq. (3.5,32))

.. math::
    K_w = \\sum_c (k_n - k_s) n_w^2 + k_s,\\qquad
    K^R_w = \\sum_c \\big(k_s r^2 + k_r\\big)(1 - n_w^2) + k_{tw} n_w^2 \\qquad (w = x, y, z),

k_r and k_tw the rolling (bending) and twisting stiffnesses [N m/rad] of the contacts whose physics is a
RotStiffFrictPhys (CohFrictPhys, MindlinPhys: YADE counts them whether or not the law applies moments,
``momentRotationLaw``, ``includeMoment``), 0 for the others. A bending spring resists rotations about the
axes normal to n, the twisting spring rotations about n (YADE 2023.02a, measured on two spheres with rolling
and twisting stiffness and oblique normals: tests/reference/yade/timestepper_rot.py).

Each degree of freedom is taken as an uncoupled oscillator of critical step √2·√(m/K) (eq. (3.5,30)), so

.. math::
    \\Delta t_{body} = s\\,\\min\\Big(q\\sqrt{m / \\max_w K_w},\\; q \\min_w \\sqrt{I_w / K^R_w}\\Big),

s the safety coefficient ``timestepSafetyCoefficient`` and q = 1.41044, the rounded √2 YADE 2023.02a
uses (measured: its steps are 1.41044·s·√(m/K) to the last digit, tests/reference/yade/timestepper.py).
With ``viscEl`` the dashpots of ViscElPhys contacts (cn, cs) add the overdamped limits 2m/C and
2I/C^R, C_w = Σ (c_n - c_s) n_w² + c_s and C^R_w = Σ c_s (1 - n_w²) r², to the minimum (YADE's
results, same script). The step is the smallest over the bodies that are not fixed (all six DOFs
blocked), clump members excepted, and bodies without contacts give none. A clump sums the contacts of all
its members, each with the member's own radius r, and uses the clump's mass and principal inertia I_w
(indexed by the global axes w, as for any body): YADE 2023.02a, measured on clumps touched on one or two
members (tests/reference/yade/timestepper_clump.py).
A contact whose normal force is exactly zero (touching without overlap, e.g. aabbWalls' walls at the first
step) adds no stiffness, as in YADE 2023.02a (measured: a sphere on a box at zero penetration and on an
overlapping sphere, same script).

An update (at the steps that start with ``O.iter`` a multiple of ``timeStepUpdateInterval``, or 1, and
at every step until one has found a contact: YADE's schedule, measured) sets O.dt to that minimum, at
most 1.05 times the previous computed step and at most ``maxDt``. Until then O.dt is ``defaultDt``, or
s·PWaveTimeStep() when it is negative.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from granum._jit import BLOCK, PARALLEL_THRESHOLD, jit, kernel, prange
from granum.core.arrays import S_DT, SI_ITER, SI_NBODIES
from granum.core.bodies import DOF_ALL
from granum.core.contacts import C_CSR_DIRTY, F_FN, F_KN, F_KS, F_NORMAL, F_R1, F_R2, I_ID2, I_PHYS
from granum.core.records import raw
from granum.core.shapes import ShapeKind
from granum.kernels.interaction import build_csr
from granum.kernels.schedule import block_queue, next_block, queue_workers
from granum.physics.materials import M_DENSITY, M_YOUNG
from granum.physics.viscel import F_CN, F_CS

#: YADE's factor for √2 in the critical step √2·√(m/K) (YADE 2023.02a, measured)
SQRT2_YADE = 1.41044
#: an update may make the step at most this much larger than the previous computed one
MAX_GROWTH = 1.05
#: ``previousDt`` before any computed step (YADE's: the largest double)
NEVER = np.finfo(np.float64).max
_SPHERE = int(ShapeKind.SPHERE)
_CLUMP = int(ShapeKind.CLUMP)


class TimeStepperParams(NamedTuple):
    """Parameters of :func:`stiffness_time_step_stage` (GlobalStiffnessTimeStepper's attributes)."""

    active: bool              #: the stepper sets O.dt (YADE ``active``, ``O.dynDt``)
    interval: int             #: update every this many steps [-]
    safety: float             #: safety coefficient s [-]
    default_dt: float         #: O.dt before any contact [s]; <= 0: s·PWaveTimeStep()
    max_dt: float             #: largest step [s]
    visc_el: bool             #: add the dashpots of ViscElPhys contacts
    viscel_phys: np.ndarray   #: 1 where the Ip2 functor of that code makes a ViscElPhys, (nphys,) uint8
    rot_columns: np.ndarray   #: contact columns of k_r and k_tw per Ip2 functor code, -1: none, (nphys, 2) int64
    state: np.ndarray         #: (1,) float64: the previous computed step [s] (``previousDt``), NEVER before


@jit
def body_time_step(i, S, C, safety, visc_el, viscel_phys, rot_columns):
    """Critical step of body ``i`` times ``safety`` [s] (see the module docstring); inf without contacts.
    ``S``, ``C``: raw views; a clump ``i`` sums its members' contacts. The sums are scalars: no array per body."""
    kx = ky = kz = 0.0     # translational stiffness K_w [N/m]
    rx = ry = rz = 0.0     # rotational stiffness K^R_w [N m]
    cx = cy = cz = 0.0     # translational damping C_w [N s/m]
    qx = qy = qz = 0.0     # rotational damping C^R_w [N m s]
    con_i, con_f, csr_con = C.con_i, C.con_f, C.csr_con
    damped = visc_el and con_f.shape[1] > F_CS
    first, count = -1, 1   # t = -1: the body itself
    if S.shape_kind[i] == _CLUMP:
        first = S.clump_member_first[S.shape_row[i]]
        count = S.clump_member_count[S.shape_row[i]]
    for t in range(first, first + count):
        member = i if t < 0 else S.clump_members[t]
        for j in range(C.csr_start[member], C.csr_start[member + 1]):
            c = csr_con[j]
            if con_f[c, F_FN] == 0.0 and con_f[c, F_FN + 1] == 0.0 and con_f[c, F_FN + 2] == 0.0:
                continue       # YADE counts no stiffness for a contact that carries no normal force
            kn = con_f[c, F_KN]
            ks = con_f[c, F_KS]
            r2 = (con_f[c, F_R2] if con_i[c, I_ID2] == member else con_f[c, F_R1]) ** 2
            nx = con_f[c, F_NORMAL] ** 2
            ny = con_f[c, F_NORMAL + 1] ** 2
            nz = con_f[c, F_NORMAL + 2] ** 2
            kx += (kn - ks) * nx + ks
            ky += (kn - ks) * ny + ks
            kz += (kn - ks) * nz + ks
            rx += ks * (1.0 - nx) * r2
            ry += ks * (1.0 - ny) * r2
            rz += ks * (1.0 - nz) * r2
            kr_col = rot_columns[con_i[c, I_PHYS], 0]
            if kr_col >= 0:  # bending resists rotations about the axes normal to n, twisting about n [N m]
                bend = con_f[c, kr_col]
                twist = con_f[c, rot_columns[con_i[c, I_PHYS], 1]]
                rx += bend * (1.0 - nx) + twist * nx
                ry += bend * (1.0 - ny) + twist * ny
                rz += bend * (1.0 - nz) + twist * nz
            if damped and viscel_phys[con_i[c, I_PHYS]] != 0:
                cn = con_f[c, F_CN]
                cs = con_f[c, F_CS]
                cx += (cn - cs) * nx + cs
                cy += (cn - cs) * ny + cs
                cz += (cn - cs) * nz + cs
                qx += cs * (1.0 - nx) * r2
                qy += cs * (1.0 - ny) * r2
                qz += cs * (1.0 - nz) * r2
    m = S.mass[i]
    ix = S.inertia[i, 0]
    iy = S.inertia[i, 1]
    iz = S.inertia[i, 2]
    ratio = math.inf  # smallest m/K or I/K^R [s^2]
    kmax = max(kx, ky, kz)
    if kmax > 0.0:
        ratio = m / kmax
    if rx > 0.0:
        ratio = min(ratio, ix / rx)
    if ry > 0.0:
        ratio = min(ratio, iy / ry)
    if rz > 0.0:
        ratio = min(ratio, iz / rz)
    dt = SQRT2_YADE * safety * math.sqrt(ratio)
    cmax = max(cx, cy, cz)
    if cmax > 0.0:
        dt = min(dt, safety * 2.0 * m / cmax)
    if qx > 0.0:
        dt = min(dt, safety * 2.0 * ix / qx)
    if qy > 0.0:
        dt = min(dt, safety * 2.0 * iy / qy)
    if qz > 0.0:
        dt = min(dt, safety * 2.0 * iz / qz)
    return dt


@jit
def step_block(b, S, C, nb, safety, visc_el, viscel_phys, rot_columns, out):
    """Smallest step (:func:`body_time_step`) of the free bodies of block ``b`` into ``out[b]`` (inf: none)."""
    best = math.inf
    alive, blocked, clump_id = S.alive, S.blocked, S.clump_id
    for i in range(b * BLOCK, min(nb, (b + 1) * BLOCK)):
        if alive[i] and blocked[i] != DOF_ALL and (clump_id[i] < 0 or clump_id[i] == i):
            best = min(best, body_time_step(i, S, C, safety, visc_el, viscel_phys, rot_columns))
    out[b] = best


def _steps(S, C, nb, safety, visc_el, viscel_phys, rot_columns, out):
    queue = block_queue((nb + BLOCK - 1) // BLOCK)
    for w in prange(queue_workers(queue)):
        b = next_block(queue, w, -1)
        while b >= 0:
            step_block(b, S, C, nb, safety, visc_el, viscel_phys, rot_columns, out)
            b = next_block(queue, w, b)


steps, steps_par = kernel(_steps, over="bodies")


@jit
def p_wave_time_step(S):
    """min over spheres of r √(ρ/E) [s], ρ = m / (4/3 π r³) (the material's density for a massless sphere);
    spheres whose material has no positive Young's modulus are left out (PWaveTimeStep)."""
    best = math.inf
    for i in range(S.iscal[SI_NBODIES]):
        if not S.alive[i] or S.shape_kind[i] != _SPHERE:
            continue
        r = S.sphere_radius[S.shape_row[i]]
        row = S.material[i]
        young = S.mat[row, M_YOUNG]
        if not young > 0.0:
            continue
        rho = S.mass[i] / (4.0 / 3.0 * math.pi * r ** 3) if S.mass[i] > 0.0 else S.mat[row, M_DENSITY]
        best = min(best, r * math.sqrt(rho / young))
    return best


@jit
def stiffness_time_step_stage(S, C, P):
    """GlobalStiffnessTimeStepper: set O.dt (``S.scal[S_DT]``) from the contact stiffnesses; ``P``:
    :class:`TimeStepperParams`."""
    if not P.active:
        return
    state = P.state
    previous = state[0]
    it = S.iscal[SI_ITER]
    if it % P.interval != 0 and it != 1 and previous != NEVER:
        return
    nb = S.iscal[SI_NBODIES]
    if C.ctr[C_CSR_DIRTY]:
        build_csr(C, nb)
    out = np.empty((nb + BLOCK - 1) // BLOCK)
    if nb < PARALLEL_THRESHOLD:
        steps(raw(S), raw(C), nb, P.safety, P.visc_el, P.viscel_phys, P.rot_columns, out)
    else:
        steps_par(raw(S), raw(C), nb, P.safety, P.visc_el, P.viscel_phys, P.rot_columns, out)
    best = math.inf
    for b in range(out.shape[0]):
        best = min(best, out[b])
    if best < math.inf:
        dt = min(best, MAX_GROWTH * previous, P.max_dt)
        state[0] = dt
        S.scal[S_DT] = dt
    elif previous == NEVER:
        S.scal[S_DT] = P.default_dt if P.default_dt > 0.0 else P.safety * p_wave_time_step(S)
