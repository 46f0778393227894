"""Batched contact update: sphere-sphere contacts under the Cundall-Strack law, in loops LLVM vectorizes.

The interaction loop updates a contact by dispatching to its geometry functor and its law, one contact at a time;
that scalar code cannot use the vector units. The commonest contact of all, two spheres
(``Ig2_Sphere_Sphere_ScGeom``) under ``Law2_ScGeom_FrictPhys_CundallStrack``, is updated here a block of contacts at
a time instead, in two passes:

1. :func:`gather_bodies` copies what the block's batchable contacts (:func:`batchable`) read of their bodies (radii,
   centre, branch vector, velocities) into columns of a work area ``g``, with a mask of them (scalar: the rows of
   the bodies are scattered);
2. :func:`update_block` computes the geometry and the law of every contact of the block from those columns and
   the contact columns (where batches run, ``con_f`` is stored column after column:
   :func:`granum.core.contacts.laid_out`), a loop without calls or branches over contiguous columns, which LLVM
   vectorizes (8 contacts per AVX-512 instruction), and stores the results of the masked contacts only. The
   block's other contacts (a sphere on a facet, a new contact) then go through the dispatch.

The arithmetic is the scalar path's, to the bit: both call the same functions (:func:`~granum.physics.sphere.
sphere_contact`, :func:`~granum.physics.scgeom.shear_rotation`, :func:`~granum.physics.scgeom.ratchet_velocity`,
:func:`~granum.physics.frict.cundall_strack_forces`), and vector lanes round as scalar operations do (no fast-math
reassociation). Only contacts that the scalar path would leave in the same state are batched (:func:`batchable`):
alive, not new (their physics is computed), the anti-ratcheting geometry, the radial-arms flag as the law's
``sphericalBodies`` wants it; and the scene aperiodic without energy tracking (:func:`scene_batchable`).

Stand-alone (the dense lattice's 22,800 sphere-sphere contacts, one thread, AMD Zen 4): 27 ns a contact in scalar
code, 14 ns batched (gather 7.6 ns, vector loop 6-7 ns). In place: about 12 ns for the gather and 8 for the vector
loop (over every contact of a block), against about 35 through the dispatch.
"""

from __future__ import annotations

from granum._jit import BLOCK, jit
from granum.core.arrays import S_DT, SI_PERIODIC, SI_TRACK_ENERGY
from granum.core.contacts import (
    F_FN,
    F_FS,
    F_KN,
    F_KS,
    F_NORMAL,
    F_PEN,
    F_POINT,
    F_PREV_NORMAL,
    F_R1,
    F_R2,
    F_TANPHI,
    FLAG_ALIVE,
    FLAG_NEW,
    FLAG_PHYS_AGAIN,
    FLAG_RADIAL_ARMS,
    FLAG_RATCHET,
    I_FLAGS,
    I_GEOM,
    I_ID1,
    I_ID2,
    I_LAW,
)
from granum.kernels.dispatch import code_of
from granum.physics.frict import NEVER_ERASE, SPHERICAL_BODIES, cundall_strack_forces
from granum.physics.scgeom import ratchet_velocity, rotate_tangential, shear_rotation
from granum.physics.sphere import AVOID_RATCHETING, sphere_contact, sphere_pair
from granum.physics.vec import add, load3, norm

#: the functors whose contacts are batched
GEOM_CODE = code_of("Ig2_Sphere_Sphere_ScGeom")
LAW_CODE = code_of("Law2_ScGeom_FrictPhys_CundallStrack")

#: columns of the work area ``g`` (:func:`gather_bodies`): r1, r2, centre 1 (3), branch vector (3), v1 (3), v2 (3),
#: w1 (3), w2 (3), the mask (1.0: batched)
GATHERED = 21
MASK = 20
#: words between two columns of ``g``: a batch is a block, and a multiple of 512 words would put every column in
#: the same cache sets (4K aliasing: the gather took 53 ns a contact instead of 7.6 stand-alone)
STRIDE = BLOCK + 8
#: words of the work area of one thread
AREA_WORDS = GATHERED * STRIDE
#: the fewest batchable contacts in a block worth a batch: the vector loop computes every contact of the block
MIN_BATCH = 64
#: flags that decide whether a contact is batchable (:func:`batchable`)
FLAGS_TESTED = FLAG_ALIVE | FLAG_NEW | FLAG_PHYS_AGAIN | FLAG_RATCHET | FLAG_RADIAL_ARMS


@jit(inline="always")  # per contact: no call
def batchable(c, C, wanted):
    """Whether contact ``c`` is a sphere-sphere Cundall-Strack contact whose flags are ``wanted``
    (:func:`scene_batchable`): the batched update then leaves it as the scalar path would."""
    return (C.con_i[c, I_FLAGS] & FLAGS_TESTED) == wanted and C.con_i[c, I_GEOM] == GEOM_CODE and \
        C.con_i[c, I_LAW] == LAW_CODE


@jit
def scene_batchable(S, C, geom_tab, law_tab):
    """The flags a batchable contact has in this scene and step (:func:`batchable`), or -1 when none is: the
    scene periodic or tracking energy, the geometry without ``avoidGranularRatcheting``, the pool ``C.con_f`` in
    C order (:func:`granum.core.contacts.laid_out`). ``geom_tab``, ``law_tab``: the functor tables, which hold
    both functors (:func:`granum.kernels.interaction.batched`)."""
    if S.iscal[SI_PERIODIC] != 0 or S.iscal[SI_TRACK_ENERGY] != 0 or geom_tab[1][GEOM_CODE, AVOID_RATCHETING] == 0.0:
        return -1
    if C.con_f.strides[0] != C.con_f.itemsize:  # a pool in C order (a law's history): its columns are not
        return -1                               # contiguous, the loop would not vectorize
    wanted = FLAG_ALIVE | FLAG_RATCHET
    if law_tab[1][LAW_CODE, SPHERICAL_BODIES] != 0.0:
        wanted |= FLAG_RADIAL_ARMS
    return wanted


@jit
def gather_bodies(lo, hi, S, C, g, wanted):
    """Columns of ``g`` (GATHERED, STRIDE) for the contacts lo..hi-1 (at most a block): for a batchable one
    (:func:`batchable` with the flags ``wanted``) what :func:`update_block` reads of its bodies, computed as the
    scalar path computes it (:func:`~granum.physics.sphere.sphere_pair`, the image's velocity added), and the mask
    1; for another, zeros (its lane computes values nobody stores). Returns how many are batchable."""
    count = 0
    for c in range(lo, hi):
        k = c - lo
        if not batchable(c, C, wanted):
            for j in range(GATHERED):
                g[j, k] = 0.0
            continue
        count += 1
        id1 = C.con_i[c, I_ID1]
        id2 = C.con_i[c, I_ID2]
        # contact_shift's zeros in an aperiodic scene (scene_batchable), added as the scalar path adds them (x + 0
        # is x but for the sign of a zero)
        r1, r2, p1, d, _ = sphere_pair(id1, id2, (0.0, 0.0, 0.0), S)
        v2 = add(load3(S.vel, id2), (0.0, 0.0, 0.0))
        g[0, k] = r1
        g[1, k] = r2
        for j in range(3):
            g[2 + j, k] = p1[j]
            g[5 + j, k] = d[j]
            g[8 + j, k] = S.vel[id1, j]
            g[11 + j, k] = v2[j]
            g[14 + j, k] = S.ang_vel[id1, j]
            g[17 + j, k] = S.ang_vel[id2, j]
        g[MASK, k] = 1.0
    return count


@jit
def update_block(lo, hi, S, C, g, never_erase, died):
    """Geometry and Cundall-Strack forces of the masked contacts of lo..hi-1 (:func:`gather_bodies` filled ``g``),
    what :func:`~granum.physics.sphere.geom_sphere_sphere` and :func:`~granum.physics.frict.law_cundall_strack`
    write; such a contact whose penetration became negative ends (its block flagged in ``died``) or, with
    ``never_erase``, keeps zero forces. ``g``: the thread's work area, (GATHERED, STRIDE) float64."""
    n = hi - lo
    dt = S.scal[S_DT]
    f = C.con_f
    # the block's columns, contiguous: indexed from 0 (never negative, no wraparound test), the loop vectorizes
    nx, ny, nz = f[lo:hi, F_NORMAL], f[lo:hi, F_NORMAL + 1], f[lo:hi, F_NORMAL + 2]
    n0x, n0y, n0z = f[lo:hi, F_PREV_NORMAL], f[lo:hi, F_PREV_NORMAL + 1], f[lo:hi, F_PREV_NORMAL + 2]
    px, py, pz = f[lo:hi, F_POINT], f[lo:hi, F_POINT + 1], f[lo:hi, F_POINT + 2]
    pen_col, r1_col, r2_col = f[lo:hi, F_PEN], f[lo:hi, F_R1], f[lo:hi, F_R2]
    kn_col, ks_col, tan_col = f[lo:hi, F_KN], f[lo:hi, F_KS], f[lo:hi, F_TANPHI]
    fnx, fny, fnz = f[lo:hi, F_FN], f[lo:hi, F_FN + 1], f[lo:hi, F_FN + 2]
    fsx, fsy, fsz = f[lo:hi, F_FS], f[lo:hi, F_FS + 1], f[lo:hi, F_FS + 2]
    gr1, gr2 = g[0, :n], g[1, :n]
    g1x, g1y, g1z, gdx, gdy, gdz = g[2, :n], g[3, :n], g[4, :n], g[5, :n], g[6, :n], g[7, :n]
    v1x, v1y, v1z, v2x, v2y, v2z = g[8, :n], g[9, :n], g[10, :n], g[11, :n], g[12, :n], g[13, :n]
    w1x, w1y, w1z, w2x, w2y, w2z = g[14, :n], g[15, :n], g[16, :n], g[17, :n], g[18, :n], g[19, :n]
    mask = g[MASK, :n]
    for k in range(n):
        # every value the stores may keep is loaded first: a select between two values is what LLVM vectorizes;
        # a load inside the "keep" branch became a branch per lane (25 instead of 6 ns a contact)
        n0 = (nx[k], ny[k], nz[k])
        prev = (n0x[k], n0y[k], n0z[k])
        point0 = (px[k], py[k], pz[k])
        pen0, r10, r20 = pen_col[k], r1_col[k], r2_col[k]
        fn0 = (fnx[k], fny[k], fnz[k])
        fs0 = (fsx[k], fsy[k], fsz[k])
        r1 = gr1[k]
        r2 = gr2[k]
        d = (gdx[k], gdy[k], gdz[k])
        normal, pen, point = sphere_contact(r1, r2, (g1x[k], g1y[k], g1z[k]), d, norm(d))
        w1 = (w1x[k], w1y[k], w1z[k])
        w2 = (w2x[k], w2y[k], w2z[k])
        fs = rotate_tangential(fs0, shear_rotation(n0, normal, add(w1, w2), dt))
        v = ratchet_velocity(normal, r1, r2, pen, (v1x[k], v1y[k], v1z[k]), (v2x[k], v2y[k], v2z[k]), w1, w2)
        fn, fs, _ = cundall_strack_forces(normal, pen, kn_col[k], ks_col[k], tan_col[k], fs, v, dt)
        # the masked contacts' geometry as scgeom_write stores it (the flags stay: a batched contact has them
        # already), their forces unless they end (the law returns before writing them); the others' values kept
        take = mask[k] != 0.0
        forces = take and not pen < 0.0
        n0x[k], n0y[k], n0z[k] = select3(take, n0, prev)
        nx[k], ny[k], nz[k] = select3(take, normal, n0)
        px[k], py[k], pz[k] = select3(take, point, point0)
        pen_col[k] = pen if take else pen0
        r1_col[k] = r1 if take else r10
        r2_col[k] = r2 if take else r20
        fnx[k], fny[k], fnz[k] = select3(forces, fn, fn0)
        fsx[k], fsy[k], fsz[k] = select3(forces, fs, fs0)
    for k in range(n):  # the batched contacts that end, as law_cundall_strack and update_contact leave them
        if mask[k] != 0.0 and pen_col[k] < 0.0:
            c = lo + k
            if never_erase:
                for j in range(3):
                    f[c, F_FN + j] = 0.0
                    f[c, F_FS + j] = 0.0
            else:
                C.con_i[c, I_FLAGS] &= ~FLAG_ALIVE
                died[c // BLOCK] = 1


@jit(inline="always")  # per contact: no call
def select3(which, a, b):
    """``a`` if ``which`` else ``b``, for 3-tuples of values (selects LLVM vectorizes)."""
    return (a[0] if which else b[0]), (a[1] if which else b[1]), (a[2] if which else b[2])


@jit
def never_erase(law_tab):
    """The Cundall-Strack law's ``neverErase`` in the law table ``law_tab``."""
    return law_tab[1][LAW_CODE, NEVER_ERASE] != 0.0
