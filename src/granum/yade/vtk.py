"""``VTKRecorder``: periodic output of the scene to VTK XML files for ParaView.

``VTKRecorder(fileName='out/p-', recorders=['all'], iterPeriod=1000)`` writes, at each run, one
file per active base recorder, named as YADE names them (``<fileName><part>.<O.iter>.<ext>``):

=============  ==================  ========================================================
recorder       file                contents
=============  ==================  ========================================================
``spheres``    ``spheres.N.vtu``   one vertex per sphere; point data, ``coordNumber`` as cell data
``facets``     ``facets.N.vtu``    one triangle per facet (3 points each); cell data
``boxes``      ``boxes.N.vtu``     six quads per box (24 points); each face repeats the box's data
``intr``       ``intrs.N.vtp``     one line per contact between body centres; ``forceN``, ``absForceT``
``pericell``   ``pericell.N.vtu``  the periodic cell as a hexahedron (periodic scenes only)
=============  ==================  ========================================================

The shapes' recorders are those their view classes name (``Shape.vtk``); every shape but the
sphere is written as its polygons (``ShapeType.faces`` in :mod:`granum.core.shapes`), one cell each.

Generic recorders add arrays to those files, with YADE's names:

* ``id``, ``mask``, ``mass``, ``clumpId``, ``materialId``: scalars (spheres; ``mask``/``materialId``
  also facets and boxes);
* ``colors``: ``color``; ``velocity``: ``linVelVec``, ``linVelLen``, ``angVelVec``, ``angVelLen``;
* ``force``: ``forceVec``, ``forceLen``, ``torqueVec``, ``torqueLen``;
* ``stress``: ``normalStress``, ``shearStress``, ``normalStressNorm`` (spheres), ``stressVec``,
  ``stressLen`` (facets, boxes), see :func:`granum.yade.fields.contact_stresses`;
* ``bstresses``: ``sigI`` >= ``sigII`` >= ``sigIII`` and ``dirI``... of the per-sphere stress
  tensors (:func:`granum.yade.fields.body_stress_tensors`);
* ``coordNumber``: number of contacts (cell data of spheres and facets).

``'all'`` means every base and generic recorder. Everything is read from the storage arrays
(vectorised). Besides YADE's files, granum keeps a ParaView time collection per part,
``<fileName><part>.pvd``, listing every file written by this engine with its simulated time, so
ParaView can play the series against time. Files are written atomically.

Deliberate differences from YADE: points are Float64 (YADE: Float32); data blocks are raw
binary, zlib-compressed only with ``compress=True`` (YADE always compresses); in a periodic scene
a contact across the cell boundary gets its own end point at body 2's periodic image, so the line
is not drawn across the cell. Model-specific recorders (``cpm``, ``jcfpm``, ...) and
``multiblock``/``parallelMode`` belong to models granum does not have and are refused.
"""

from __future__ import annotations

import functools
import os

import numpy as np

from granum.core.attrs import Attr, to_bool, to_int, to_str
from granum.core.bodies import DOF_ALL
from granum.core.contacts import F_FN, F_FS, F_NORMAL
from granum.core.shapes import ShapeKind
from granum.engines.base import PeriodicEngine
from granum.io import vtkxml
from granum.yade import fields
from granum.yade.bodies import SHAPE_CLASSES

#: The shape kinds' recorders (each view class's ``vtk``: spheres, facets, boxes), then contacts and the cell.
BASE_RECORDERS = tuple(cls.vtk for cls in SHAPE_CLASSES.values() if cls.vtk) + ("intr", "pericell")
GENERIC_RECORDERS = ("id", "mass", "clumpId", "colors", "mask", "materialId", "coordNumber", "velocity", "stress",
                     "force", "bstresses")
# YADE's recorders for models that granum does not implement: naming one is an error, not a no-op.
MODEL_RECORDERS = ("cpm", "wpm", "jcfpm", "cracks", "moments", "thermal", "liquid", "cohfrict", "SPH", "deform",
                   "lubrication", "partialsat", "hertz", "lsBodies", "liquidcontrol")
#: other names YADE 2023.02a takes for a recorder (measured: ``ids`` writes the ``id`` array)
RECORDER_ALIASES = {"ids": "id"}


def _recorders(owner, value) -> list:
    if isinstance(value, str):
        raise TypeError(f"{type(owner).__name__}.recorders must be a list of strings, e.g. ['spheres', 'intr']")
    names = [RECORDER_ALIASES.get(str(v), str(v)) for v in value]
    for name in names:
        if name in MODEL_RECORDERS:
            raise ValueError(f"VTKRecorder: recorder {name!r} records a model granum does not implement")
        if name != "all" and name not in BASE_RECORDERS + GENERIC_RECORDERS:
            valid = ", ".join(("all",) + BASE_RECORDERS + GENERIC_RECORDERS)
            raise ValueError(f"VTKRecorder: unknown recorder {name!r}; valid recorders: {valid}")
    return names


def _only_default(name: str, default):
    def convert(owner, value):
        if value != default:
            raise ValueError(f"{type(owner).__name__}.{name}={value!r} is not implemented in granum "
                             f"(only {default!r})")
        return value

    return convert


def _norm(v: np.ndarray) -> np.ndarray:
    return np.linalg.norm(v, axis=1)


class VTKRecorder(PeriodicEngine):
    """Write spheres, facets, boxes, contacts and the periodic cell to VTK XML files (YADE ``VTKRecorder``).

    See the module documentation for the files and arrays. As in YADE the engine also runs the
    first time it is reached (``initRun=True``), so the initial state is recorded.
    """

    _attrs = {
        "fileName": Attr("", "Base file name; '<fileName>spheres.<iter>.vtu' etc. are written (its directory "
                             "must exist)", to_str("fileName")),
        "recorders": Attr(["all"], "Active recorders (see the module documentation)", _recorders),
        "ascii": Attr(False, "Write the values as text inside the XML instead of binary", to_bool),
        "compress": Attr(False, "zlib-compress the binary data blocks", to_bool),
        "skipFacetIntr": Attr(True, "Record only sphere-sphere contacts in the intrs files", to_bool),
        "skipNondynamic": Attr(False, "Leave out spheres that are not dynamic (all DOFs blocked)", to_bool),
        "mask": Attr(0, "If not 0, record only bodies whose groupMask & mask != 0", to_int("mask")),
        "Key": Attr("", "Accepted for compatibility (used by model-specific recorders)", to_str("Key")),
        "multiblock": Attr(False, "Multi-block .vtm output (not implemented)", _only_default("multiblock", False)),
        "multiblockLS": Attr(False, "Multi-block level-set output (not implemented)",
                             _only_default("multiblockLS", False)),
        "parallelMode": Attr(False, "MPI output (not implemented)", _only_default("parallelMode", False)),
    }

    def __init__(self, **kw):
        kw.setdefault("initRun", True)
        super().__init__(**kw)
        self._series: dict[str, list] = {}

    # ---- running -------------------------------------------------------------------------
    def active(self) -> set:
        """The recorders in effect, ``'all'`` expanded."""
        names = set(self.recorders)
        if "all" in names:
            names |= set(BASE_RECORDERS + GENERIC_RECORDERS)
            names.discard("all")
        return names

    def run_python(self, omega) -> None:
        self.record(omega._scene)

    def record(self, scene) -> list[str]:
        """Write the files of the active base recorders for the scene's current state; return their names."""
        rec = self.active()
        written = []
        shapes = [(cls.vtk, cls.vtk, "vtu", self._spheres if kind == ShapeKind.SPHERE else
                   functools.partial(self._polygons, kind, cls.vtk_coord_number))
                  for kind, cls in SHAPE_CLASSES.items() if cls.vtk]
        for recorder, part, ext, make in shapes + [("intr", "intrs", "vtp", self._intrs),
                                                   ("pericell", "pericell", "vtu", self._pericell)]:
            if recorder not in rec:
                continue
            if part == "pericell" and not scene.periodic:
                continue
            path = f"{self.fileName}{part}.{scene.iter}.{ext}"
            directory = os.path.dirname(os.path.abspath(path))
            if not os.path.isdir(directory):
                raise FileNotFoundError(f"VTKRecorder.fileName: directory {directory!r} does not exist "
                                        "(create it before running, as with YADE)")
            make(scene, rec, path)
            written.append(path)
            self._add_to_series(part, scene.time, path)
        return written

    def _write_kw(self) -> dict:
        return {"ascii": self.ascii, "compress": self.compress}

    def _add_to_series(self, part: str, time: float, path: str) -> None:
        series = self._series.setdefault(part, [])
        series[:] = [(t, p) for t, p in series if p != path]  # a re-run of the same step replaces its entry
        series.append((time, path))
        vtkxml.write_pvd(f"{self.fileName}{part}.pvd", series)

    # ---- shared per-body data ------------------------------------------------------------
    def _common(self, scene, ids: np.ndarray, rec: set, stress_key: str) -> dict:
        """Arrays shared by facets and boxes: color, stress, force, materialId, mask, (coordNumber)."""
        b = scene.bodies
        out = {}
        if "colors" in rec:
            out["color"] = b.color[ids]
        if "stress" in rec:
            normal, shear = fields.contact_stresses(scene)
            vec = normal[ids] + shear[ids]
            out[stress_key + "Vec"], out[stress_key + "Len"] = vec, _norm(vec)
        if "force" in rec:
            out["forceVec"], out["forceLen"] = b.force[ids], _norm(b.force[ids])
            out["torqueVec"], out["torqueLen"] = b.torque[ids], _norm(b.torque[ids])
        if "materialId" in rec:
            out["materialId"] = fields.material_ids(scene)[ids].astype(float)
        if "mask" in rec:
            out["mask"] = b.mask[ids].astype(float)
        return out

    # ---- parts ------------------------------------------------------------------------------
    def _spheres(self, scene, rec: set, path: str) -> None:
        b = scene.bodies
        ids = fields.ids_of_kind(scene, ShapeKind.SPHERE, self.mask)
        if self.skipNondynamic:
            ids = ids[b.blocked[ids] != DOF_ALL]
        radii = fields.sphere_radii(scene, ids)
        pd: dict = {"radii": radii}
        if "id" in rec:
            pd["id"] = ids.astype(float)
        if "mask" in rec:
            pd["mask"] = b.mask[ids].astype(float)
        if "mass" in rec:
            pd["mass"] = b.mass[ids]
        if "clumpId" in rec:
            pd["clumpId"] = b.clump_id[ids].astype(float)
        if "colors" in rec:
            pd["color"] = b.color[ids]
        if "velocity" in rec:
            pd["linVelVec"], pd["angVelVec"] = b.vel[ids], b.ang_vel[ids]
            pd["linVelLen"], pd["angVelLen"] = _norm(b.vel[ids]), _norm(b.ang_vel[ids])
        if "stress" in rec:
            normal, shear = fields.contact_stresses(scene)
            pd["normalStress"], pd["shearStress"] = normal[ids], shear[ids]
            pd["normalStressNorm"] = _norm(normal[ids])
        if "force" in rec:
            pd["forceVec"], pd["forceLen"] = b.force[ids], _norm(b.force[ids])
            pd["torqueVec"], pd["torqueLen"] = b.torque[ids], _norm(b.torque[ids])
        if "bstresses" in rec:
            sig, dirs = fields.principal_stresses(fields.body_stress_tensors(scene, ids, radii))
            for k, suffix in enumerate(("I", "II", "III")):
                pd["sig" + suffix] = sig[:, k]
            for k, suffix in enumerate(("I", "II", "III")):
                pd["dir" + suffix] = dirs[:, k]
        if "materialId" in rec:
            pd["materialId"] = fields.material_ids(scene)[ids].astype(float)
        cd = {"coordNumber": fields.coord_numbers(scene)[ids].astype(float)} if "coordNumber" in rec else {}
        n = len(ids)
        vtkxml.write_unstructured_grid(path, b.pos[ids], np.arange(n), np.arange(1, n + 1),
                                       np.full(n, vtkxml.VTK_VERTEX), pd, cd, **self._write_kw())

    def _polygons(self, kind: ShapeKind, coord_number: bool, scene, rec: set, path: str) -> None:
        """Bodies of shape kind ``kind`` as their polygons (:func:`granum.yade.fields.body_faces`), each polygon
        a cell carrying its body's data; ``coord_number``: with ``coordNumber`` cell data (facets)."""
        ids = fields.ids_of_kind(scene, kind, self.mask)
        faces = fields.body_faces(scene, kind, ids)
        n, nf, nv = faces.shape[:3]
        cd = self._common(scene, ids, rec, "stress")
        if coord_number and "coordNumber" in rec:
            cd["coordNumber"] = fields.coord_numbers(scene)[ids].astype(float)
        cd = {name: np.repeat(v, nf, axis=0) for name, v in cd.items()}
        vtkxml.write_unstructured_grid(path, faces.reshape(-1, 3), np.arange(n * nf * nv),
                                       nv * np.arange(1, n * nf + 1), np.full(n * nf, vtkxml.polygon_type(nv)), None,
                                       cd, **self._write_kw())

    def _intrs(self, scene, rec: set, path: str) -> None:
        rows = fields.live_contact_rows(scene)
        id1, id2 = fields.contact_ids(scene, rows)
        if self.skipFacetIntr:
            kind = scene.bodies.shape_kind
            keep = (kind[id1] == ShapeKind.SPHERE) & (kind[id2] == ShapeKind.SPHERE)
            rows, id1, id2 = rows[keep], id1[keep], id2[keep]
        if self.mask:
            m = scene.bodies.mask
            keep = ((m[id1] & self.mask) != 0) & ((m[id2] & self.mask) != 0)
            rows, id1, id2 = rows[keep], id1[keep], id2[keep]
        # points: every body centre, so a line's ends are the body ids (as YADE); contacts with a
        # periodic image of body 2 get an extra end point there
        points = scene.bodies.pos[:scene.body_count]
        shift = fields.contact_shift(scene, rows)
        shifted = np.nonzero(np.any(shift != 0, axis=1))[0]
        end2 = id2.copy()
        if shifted.size:
            end2[shifted] = len(points) + np.arange(shifted.size)
            points = np.concatenate([points, points[id2[shifted]] + shift[shifted]])
        f = scene.contacts.con_f[rows]
        cd = {"forceN": np.einsum("ki,ki->k", f[:, F_FN:F_FN + 3], f[:, F_NORMAL:F_NORMAL + 3]),
              "absForceT": np.abs(f[:, F_FS:F_FS + 3])}
        vtkxml.write_poly_lines(path, points, np.stack([id1, end2], axis=1), None, cd, **self._write_kw())

    def _pericell(self, scene, rec: set, path: str) -> None:
        a, b, c = np.asarray(scene.cell_hsize, float).T  # the cell's edge vectors are hSize's columns
        corners = np.array([c, b + c, a + b + c, a + c, 0 * a, b, a + b, a])  # YADE's hexahedron order
        vtkxml.write_unstructured_grid(path, corners, np.arange(8), [8], [12], None, None, **self._write_kw())
