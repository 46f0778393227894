"""Dense packings of :mod:`granum.yade.pack`: ``randomDensePack``, ``randomPeriPack``, ``filterSpherePack``,
the periodic repetitions and size statistics of a ``SpherePack`` (``cellRepeat``, ``cellFill``, ``psd``,
``relDensity``), and the memoization database.

Dense packings are made by a DEM run in the alternative scene (``O.switchScene``), as YADE does, so the
script's scene is left untouched (a run in progress refuses the switch: "Please stop the simulation first").

* Periodic (``randomPeriPack``, ``randomDensePack(spheresInCell=n)``): a loose ``makeCloud`` in a cubic or
  box cell, then PeriIsoCompressor to -100 GPa and back to -0.1 GPa (FrictMat E 30 GPa, nu .3, rho 1000;
  randomPeriPack: friction angle .1, damping .8, globalUpdateInt 20; randomDensePack: friction .5, damping
  .6, globalUpdateInt 5; Verlet distance .05 r): YADE 2023.02a's set-up, read from its scene after a call.
  ``randomDensePack`` then repeats the cell (``cellFill``) over the predicate's box. randomDensePack's cell
  has the predicate box's proportions and the volume of ``spheresInCell`` spheres at porosity 0.75.
* Aperiodic (``randomDensePack`` without ``spheresInCell``), YADE's rules (measured on its calls): a
  TriaxialTest of N = int(0.6 V / (4/3 pi radius^3)) spheres (V: the volume of the box requested, ``cropLayers``
  included), ``radiusMean=radius``, ``upperCorner`` the box; TriaxialTest scales that box to hold the cloud at
  porosity 0.8, i.e. to 3 V, so the spheres, grown by ``internalCompaction`` to -40 kPa (friction 1 degree) and
  unloaded by the walls to -500 Pa, end about 3^(1/3) = 1.44 times ``radius`` (0.072 for 0.05). YADE returns
  that packing unscaled, and so does granum: same count, radii and porosity for the same call. It runs by 500
  steps until the unbalanced force is at most .005.
* ``memoizeDb``: an SQLite file (stdlib ``sqlite3``) of packings already made, with centres and radii as
  little-endian float64 blobs (no pickle: reading a file runs no code). A request reuses the stored packing
  with the fewest spheres among those of the same kind (periodic or not, same ``rRelFuzz``) that, scaled to
  the requested radius, are large enough: a periodic one for ``spheresInCell`` holds at least that many
  spheres, an aperiodic one covers the requested box, a ``randomPeriPack`` one was made for the same
  ``initSize``. A row keeps the requested radius and box (as YADE's rows do), so an aperiodic packing reused
  for half the radius is the stored one scaled by 1/2. The table is ``granum_packings``; YADE's own table in
  the same file (pickles) is left alone. YADE 2023.02a never reuses an aperiodic packing (it compacts again
  and adds a row each call); granum reuses it, as YADE's documentation says.
"""

from __future__ import annotations

import math
import os
import sqlite3
import time
import warnings

import numpy as np

from granum.mathtypes import Vector3, as_mat3, as_vec3

#: the stresses PeriIsoCompressor goes through (compress hard, then relax), YADE's values [Pa]
PERI_STRESSES = [-100e9, -1e8]
#: randomDensePack's periodic cell holds ``spheresInCell`` spheres of ``radius`` at this porosity (YADE's
#: initial cells: 0.8565^3 for 300 spheres of .05, the box's proportions, no account of rRelFuzz)
CELL_POROSITY = 0.75
#: aperiodic compaction, YADE 2023.02a's TriaxialTest call (read from its scene and the call's arguments): the
#: spheres of mean ``radius`` would fill this fraction of the requested box [-]; the stress their growth reaches
#: and the one the walls then unload to [Pa]; friction during the growth [deg], the unbalanced force ending
#: it [-]; TriaxialTest's strain rate [1/s], wall speed [m/s] and size of the walls' faces over the box's [-]
BOX_SOLID_FRACTION, BOX_STRESS, BOX_UNLOAD_STRESS = 0.6, -4e4, -500.0
BOX_FRICTION_DEG, BOX_STABILITY, BOX_STRAIN_RATE, BOX_WALL_VELOCITY, BOX_WALL_OVERSIZE = 1.0, 0.02, 0.2, 0.1, 1.5
#: the aperiodic compaction runs by chunks of this many steps until the unbalanced force is at most this
#: (YADE's stop rule, measured by substituting the unbalanced force it reads: .005 stops, 0.0050000001 goes on)
BOX_CHUNK, BOX_UNBALANCED = 500, 0.005
TABLE = "granum_packings"


# ---- SpherePack helpers -------------------------------------------------------------------------------
def sheared_domain(hSize):
    """``(H (3,3), lo (3,), hi (3,), volume)`` of a cell given as its base vectors: makeCloud then works in
    fractional coordinates lo = 0 .. hi = 1."""
    h = np.array(as_mat3(hSize), dtype=np.float64)
    vol = float(np.linalg.det(h))
    if not (math.isfinite(vol) and vol > 0):
        raise ValueError(f"makeCloud: hSize must have a positive volume (right-handed base vectors), got det {vol!r}")
    return h, np.zeros(3), np.ones(3), vol


def psd(radii, bins, mass):
    """``(edges, cumulative)`` of the diameters 2r (two lists of ``bins + 1``): edges evenly spaced from the
    smallest to the largest diameter, the cumulative fraction (by mass, i.e. d^3, or by count) of spheres in
    the bins below each edge. Each diameter falls in bin floor(bins (d - dmin)/(dmax - dmin)), the largest in
    the last; empty pack: two empty lists (YADE's results)."""
    bins = int(bins)
    if bins < 1:
        raise ValueError(f"SpherePack.psd: bins must be at least 1, got {bins}")
    d = 2.0 * np.asarray(radii, dtype=np.float64)
    if d.size == 0:
        return [], []
    lo, hi = float(d.min()), float(d.max())
    edges = [lo + i * (hi - lo) / bins for i in range(bins + 1)]
    k = np.zeros(d.size, np.int64) if hi == lo else np.minimum(((d - lo) / (hi - lo) * bins).astype(np.int64),
                                                                  bins - 1)
    w = d ** 3 if mass else np.ones_like(d)
    acc = np.cumsum(np.bincount(k, weights=w, minlength=bins))
    cumm = np.concatenate([[0.0], acc / acc[-1]])   # the last is exactly 1
    return edges, [float(x) for x in cumm]


def repeat_counts(count) -> np.ndarray:
    n = np.array([int(c) for c in count], dtype=np.int64)
    if n.shape != (3,) or np.any(n <= 0):
        raise ValueError("Repeat count components must be positive.")
    return n


def repeated(centers, radii, cell, n):
    """Centres and radii repeated ``n`` (3,) times along the cell's axes: the copies in order of x, then y,
    then z offsets with z innermost, each copy in the pack's order (YADE's order)."""
    ox, oy, oz = np.meshgrid(np.arange(n[0]), np.arange(n[1]), np.arange(n[2]), indexing="ij")
    shifts = np.stack([ox.ravel(), oy.ravel(), oz.ravel()], axis=1) * cell
    c = (centers[None, :, :] + shifts[:, None, :]).reshape(-1, 3)
    return c, np.tile(radii, len(shifts))


def rel_density(centers, radii) -> float:
    """Volume of the spheres over the volume of their bounding box (overlaps ignored; the box even for a
    periodic pack, as YADE)."""
    if len(radii) == 0:
        return math.nan
    lo = (centers - radii[:, None]).min(axis=0)
    hi = (centers + radii[:, None]).max(axis=0)
    return float(4.0 / 3.0 * math.pi * np.sum(radii ** 3) / np.prod(hi - lo))


# ---- filterSpherePack ----------------------------------------------------------------------------------
def filterSpherePack(predicate, spherePack, returnSpherePack=None, **kw):
    """The spheres of ``spherePack`` inside ``predicate`` (sphere included), after moving the pack so that
    its centre is the predicate's: a SpherePack if ``returnSpherePack``, else bodies made with
    ``utils.sphere(center, radius, **kw)`` (YADE's default today, with its FutureWarning when not given).
    Warns when the predicate is larger than the packing."""
    from granum.yade import pack

    if returnSpherePack is None:
        warnings.warn("The default behavior will change; specify returnSpherePack=True for the new behavior, and "
                      "False to get rid of this warning (your code will break in the future, however). The "
                      "returned SpherePack object can be added to the simulation using SpherePack.toSimulation()",
                      FutureWarning, stacklevel=2)
        returnSpherePack = False
    dim_p, dim_s = np.asarray(predicate.dim()), np.asarray(spherePack.dim())
    if np.any(dim_p > dim_s):
        warnings.warn(f"Packing's dimension ({Vector3(*dim_s)}) doesn't fully contain dimension of the predicate "
                      f"({Vector3(*dim_p)}).", stacklevel=2)
    spherePack.translate(np.asarray(predicate.center()) - np.asarray(spherePack.center()))
    c, r = np.asarray(spherePack.centers), np.asarray(spherePack.radii)
    if hasattr(predicate, "_inside"):   # vectorized per padding (one radius, or a few, in dense packs)
        keep = np.zeros(len(r), dtype=bool)
        for pad in np.unique(r):
            same = r == pad
            keep[same] = np.asarray(predicate._inside(c[same], float(pad)), dtype=bool)
    else:
        keep = np.array([bool(predicate(Vector3(*x), float(y))) for x, y in zip(c, r, strict=True)], dtype=bool)
    if returnSpherePack:
        out = pack.SpherePack()
        out.fromList(c[keep], r[keep])
        return out
    from granum.yade import utils

    return [utils.sphere(Vector3(*x), float(y), **kw) for x, y in zip(c[keep], r[keep], strict=True)]


# ---- memoization ---------------------------------------------------------------------------------------
def _connect(path):
    db = sqlite3.connect(path)
    db.execute(f"create table if not exists {TABLE} (radius real, rRelFuzz real, dimx real, dimy real, dimz real, "
               "n integer, periodic integer, kind text, cellx real, celly real, cellz real, timestamp real, "
               "centers blob, radii blob)")
    return db


def memo_store(path, sp, kind, radius, rRelFuzz, dims) -> None:
    """Store ``sp`` made for (``kind``: "peri" for randomPeriPack, "cell" or "box" for randomDensePack,
    ``radius``, ``rRelFuzz``, ``dims``: the requested initSize or box) in the database at ``path``."""
    if not path:
        return
    c = np.ascontiguousarray(sp.centers, dtype="<f8")
    r = np.ascontiguousarray(sp.radii, dtype="<f8")
    cell = np.asarray(sp.cellSize, dtype=float)
    with _connect(path) as db:
        db.execute(f"insert into {TABLE} values (?,?,?,?,?,?,?,?,?,?,?,?,?,?)",
                   (float(radius), float(rRelFuzz), *map(float, dims), len(r), int(sp.isPeriodic), kind,
                    *map(float, cell), time.time(), c.tobytes(), r.tobytes()))
    db.close()
    print("Packing saved to the database", path)


def memo_load(path, kind, radius, rRelFuzz, dims, spheresInCell=0):
    """The stored packing that fits the request (see the module docstring), scaled to ``radius``; None if
    none does or there is no database."""
    from granum.yade import pack

    if not path or not os.path.exists(path):
        return None
    dims = np.asarray(dims, dtype=float)
    with _connect(path) as db:
        rows = db.execute(f"select radius, dimx, dimy, dimz, n, cellx, celly, cellz, centers, radii from {TABLE} "
                          "where kind = ? and abs(rRelFuzz - ?) <= 1e-12 order by n, timestamp",
                          (kind, float(rRelFuzz))).fetchall()
    db.close()
    for R, dx, dy, dz, n, cx, cy, cz, cblob, rblob in rows:
        scale = radius / R
        stored = scale * np.array([dx, dy, dz])
        if kind == "peri" and not np.allclose(stored, dims, rtol=1e-9, atol=0):
            continue
        if kind == "cell" and n < spheresInCell:
            continue
        if kind == "box" and np.any(stored < dims * (1 - 1e-9)):
            continue
        if not (isinstance(cblob, bytes) and isinstance(rblob, bytes) and len(cblob) == 24 * n
                and len(rblob) == 8 * n):
            raise ValueError(f"memoizeDb {path!r}: a stored packing of {n} spheres is damaged (array sizes)")
        c = np.frombuffer(cblob, dtype="<f8")
        r = np.frombuffer(rblob, dtype="<f8")
        if not (np.all(np.isfinite(c)) and np.all(r > 0)):
            raise ValueError(f"memoizeDb {path!r}: a stored packing of {n} spheres is damaged")
        sp = pack.SpherePack()
        sp.fromList(c.reshape(n, 3) * scale, r * scale)
        if kind != "box":
            sp.cellSize = scale * np.array([cx, cy, cz])
        return sp
    return None


# ---- the DEM runs ----------------------------------------------------------------------------------------
class _OtherScene:
    """Run a block in the alternative scene, emptied first, and come back to the script's scene even when the
    block fails (the alternative scene keeps what the block made, as YADE's does)."""

    def __enter__(self):
        from granum.yade.omega import O

        O.switchScene()
        O.resetThisScene()
        return O

    def __exit__(self, *exc):
        from granum.yade.omega import O

        O.switchScene()
        return False


def _compress_periodic(O, cell, radius, rRelFuzz, num, seed, friction, damping, update_int):
    """A makeCloud in the box ``cell``, compressed by PeriIsoCompressor in the current (alternative) scene;
    the packing made (a periodic SpherePack)."""
    import granum.yade as y
    from granum.yade import pack, utils

    O.periodic = True
    O.cell.setBox(*cell)
    sp = pack.SpherePack()
    sp.makeCloud(Vector3(0, 0, 0), O.cell.refSize, radius, rRelFuzz, num, True, seed=seed)
    O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb()], verletDist=0.05 * radius),
                 y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom()], [y.Ip2_FrictMat_FrictMat_FrictPhys()],
                                   [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
                 y.PeriIsoCompressor(charLen=2 * radius, stresses=PERI_STRESSES, maxUnbalanced=1e-2,
                                     doneHook="O.pause()", globalUpdateInt=update_int, keepProportions=True),
                 y.NewtonIntegrator(damping=damping)]
    O.materials.append(y.FrictMat(young=30e9, frictionAngle=friction, poisson=0.3, density=1e3))
    sp.toSimulation()
    O.dt = utils.PWaveTimeStep()
    O.run()
    O.wait()
    out = pack.SpherePack()
    out.fromSimulation()
    return out


def randomPeriPack(radius, initSize, rRelFuzz=0.0, memoizeDb=None, noPrint=False, seed=-1):
    """A dense periodic packing: a cell of ``initSize`` filled with a loose cloud of spheres of ``radius``
    (uniform in radius (1 +- rRelFuzz)), compressed by PeriIsoCompressor (see the module docstring). Returns
    a periodic SpherePack (cellSize: the compressed cell). ``memoizeDb``: reuse or store (see above)."""
    radius, rRelFuzz, size = _positive(radius, "radius"), _fuzz(rRelFuzz), as_vec3(initSize)
    if not np.all(size > 0):
        raise ValueError(f"randomPeriPack: initSize must be positive, got {tuple(size)}")
    sp = memo_load(memoizeDb, "peri", radius, rRelFuzz, size)
    if sp is not None:
        if not noPrint:
            print("Found suitable packing in", memoizeDb)
        return sp
    with _OtherScene() as O:
        sp = _compress_periodic(O, size, radius, rRelFuzz, -1, seed, friction=0.1, damping=0.8, update_int=20)
    memo_store(memoizeDb, sp, "peri", radius, rRelFuzz, size)
    return sp


def randomDensePack(predicate, radius, material=-1, dim=None, cropLayers=0, rRelFuzz=0.0, spheresInCell=0,
                    memoizeDb=None, useOBB=False, memoDbg=False, color=None, returnSpherePack=None, seed=-1):
    """Spheres of mean ``radius`` (uniform in radius (1 +- rRelFuzz)) densely filling ``predicate`` (or a box
    of size ``dim``), made by a DEM compaction in the alternative scene (see the module docstring):
    periodic with ``spheresInCell`` spheres per cell repeated over the box, otherwise between walls
    (``cropLayers`` layers of 2 radius added around the box; the spheres then come out about 1.44 times
    ``radius``, as YADE's do). Returns what :func:`filterSpherePack` does
    (bodies with ``material``/``color``, or a SpherePack with ``returnSpherePack``)."""
    radius, rRelFuzz = _positive(radius, "radius"), _fuzz(rRelFuzz)
    if useOBB:
        raise NotImplementedError("randomDensePack(useOBB=True): oriented bounding boxes of GTS surfaces are not "
                                  "implemented in granum")
    spheresInCell = int(spheresInCell)
    if spheresInCell < 0:
        raise ValueError(f"randomDensePack: spheresInCell must be positive (periodic) or 0, got {spheresInCell}")
    size = np.asarray(dim if dim is not None else predicate.dim(), dtype=float)
    if not np.all(np.isfinite(size)):
        raise RuntimeError("Infinite predicate and no dimension of packing requested.")
    if not np.all(size > 0):
        raise ValueError(f"randomDensePack: the packing's dimension must be positive, got {tuple(size)}")
    full = size + 4 * int(cropLayers) * radius
    kw = {"material": material} if color is None else {"material": material, "color": color}
    if spheresInCell:
        sp = memo_load(memoizeDb, "cell", radius, rRelFuzz, full, spheresInCell)
        if sp is None:
            # the box's proportions, the volume of spheresInCell spheres at CELL_POROSITY
            v = spheresInCell * 4.0 / 3.0 * math.pi * radius ** 3 / (1 - CELL_POROSITY)
            cell = full * (v / np.prod(full)) ** (1.0 / 3.0)
            print("No suitable packing in database found, running PERIODIC compression")
            with _OtherScene() as O:
                sp = _compress_periodic(O, cell, radius, rRelFuzz, spheresInCell, seed, friction=0.5, damping=0.6,
                                        update_int=5)
            memo_store(memoizeDb, sp, "cell", radius, rRelFuzz, full)
        sp.cellFill(Vector3(*full))
    else:
        sp = memo_load(memoizeDb, "box", radius, rRelFuzz, full)
        if sp is None:
            with _OtherScene() as O:
                sp = _compact_in_box(O, full, radius, rRelFuzz, seed)
            memo_store(memoizeDb, sp, "box", radius, rRelFuzz, full)
    return filterSpherePack(predicate, sp, returnSpherePack=returnSpherePack, **kw)


def _compact_in_box(O, full, radius, rRelFuzz, seed):
    """YADE's aperiodic compaction (see the module docstring) in the current (alternative) scene: a
    TriaxialTest of ``BOX_SOLID_FRACTION`` times ``full``'s volume in spheres of ``radius``, its radii grown to
    ``BOX_STRESS`` and the walls then unloaded to ``BOX_UNLOAD_STRESS``, run by ``BOX_CHUNK`` steps until the
    unbalanced force is at most ``BOX_UNBALANCED``; the packing as it is then (an aperiodic SpherePack, radii
    about 1.44 ``radius``)."""
    from granum.yade import pack, utils
    from granum.yade.preprocessors import TriaxialTest

    grains = int(BOX_SOLID_FRACTION * float(np.prod(full)) / (4.0 / 3.0 * math.pi * radius ** 3))
    if grains < 1:
        raise ValueError(f"randomDensePack: radius {radius!r} is too large for a packing of dimension "
                         f"{tuple(full)} (no sphere)")
    TriaxialTest(numberOfGrains=grains, radiusMean=radius, radiusStdDev=rRelFuzz, lowerCorner=Vector3(0, 0, 0),
                 upperCorner=Vector3(*full), seed=seed, noFiles=True, sigmaIsoCompaction=BOX_STRESS,
                 sigmaLateralConfinement=BOX_UNLOAD_STRESS, compactionFrictionDeg=BOX_FRICTION_DEG,
                 StabilityCriterion=BOX_STABILITY, strainRate=BOX_STRAIN_RATE, thickness=0.0,
                 maxWallVelocity=BOX_WALL_VELOCITY, wallOversizeFactor=BOX_WALL_OVERSIZE, autoUnload=True,
                 autoCompressionActivation=False, internalCompaction=True).load()
    while True:   # YADE tests after each chunk (not before the first: no contact yet, unbalanced force NaN)
        O.run(BOX_CHUNK, True)
        unbalanced = utils.unbalancedForce()
        if unbalanced <= BOX_UNBALANCED:   # NaN (no contact) goes on, as in YADE
            break
    out = pack.SpherePack()
    out.fromSimulation()
    return out


def _positive(value, name):
    x = float(value)
    if not (math.isfinite(x) and x > 0):
        raise ValueError(f"{name} must be positive, got {value!r}")
    return x


def _fuzz(value):
    x = float(value)
    if not 0 <= x < 1:
        raise ValueError(f"rRelFuzz must be in [0, 1), got {value!r}")
    return x
