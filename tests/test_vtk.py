"""VTK output read back with VTK's own readers and compared with what real YADE writes.

``VTKRecorder`` (binary VTK XML) and ``export.VTKExporter`` / ``export.text`` (legacy VTK and text)
are run on small scenes; the files are read with the ``vtk`` package (an independent reader) and
their counts and values are checked against the scene and against the files that YADE 2023.02a
wrote for the same scene (``YADE_FILES`` below).
"""

from __future__ import annotations

import glob
import os
import xml.etree.ElementTree as ET

import numpy as np
import pytest

vtk = pytest.importorskip("vtk", reason="the vtk package reads the files back (pip install vtk)")
from vtk.util.numpy_support import vtk_to_numpy  # noqa: E402

# The scene of YADE_FILES, as run by YADE 2023.02a (``yade -j1 -n -x``); the recorder wrote
# w-spheres.3.vtu, w-facets.3.vtu, w-boxes.3.vtu and (with recorders=['intr']) w-intrs.3.vtp:
#
#   O.materials.append(FrictMat(young=1e7, density=2000, label='m'))
#   O.materials.append(FrictMat(young=1e7, density=3000, label='m2'))
#   O.bodies.append([sphere((0, 0, 0), 0.5, color=(1, 0, 0), material='m'),
#                    sphere((0.1, 0.2, 0.95), 0.5, material='m2', mask=3, color=(0, 1, 0)),
#                    sphere((2, 0, 0), 0.3, fixed=True, color=(0, 0, 1))])
#   O.bodies.append(facet([(-2, -2, -0.3), (2, -2, -0.7), (0, 2, -0.5)], wire=False, color=(.5, .5, .5)))
#   O.bodies.append(box((0, 0, 1.5), (0.6, 0.6, 0.1), orientation=Quaternion((0, 0, 1), 0.3), fixed=True,
#                       color=(1, 1, 0)))
#   O.bodies[1].state.vel = (1, 2, -3)
#   O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb(), Bo1_Box_Aabb()]),
#                InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom(), Ig2_Box_Sphere_ScGeom()],
#                                [Ip2_FrictMat_FrictMat_FrictPhys()], [Law2_ScGeom_FrictPhys_CundallStrack()]),
#                NewtonIntegrator(gravity=(0, 0, -10)),
#                VTKRecorder(fileName='w-', recorders=[...], skipFacetIntr=False, iterPeriod=3, initRun=False)]
#   O.dt = 1e-4
#   O.run(4, True)
#
# Values are rounded to 10 digits; 'P:' is point data, 'C:' cell data (boxes: the first face only),
# 'lines' the body ids at the ends of each intrs line. Points are Float32 in YADE's files.
YADE_FILES = {'boxes': {'C:color': [[1.0, 1.0, 0.0]],
                        'C:forceLen': [245480.1226],
                        'C:forceVec': [[500.4620782, 1000.924158, 245477.5718]],
                        'C:mask': [1.0],
                        'C:materialId': [1.0],
                        'C:stressLen': [312551.7518],
                        'C:stressVec': [[-9.634317848e-12, 4.907459608e-15, -312551.7518]],
                        'C:torqueLen': [532.0630236],
                        'C:torqueVec': [[475.8916358, -237.9458175, -1.464683398e-14]]},
              'facets': {'C:color': [[0.5, 0.5, 0.5]],
                         'C:coordNumber': [1.0],
                         'C:forceLen': [16577.04884],
                         'C:forceVec': [[-1649.475908, -1.956269489, -16494.78019]],
                         'C:mask': [1.0],
                         'C:materialId': [1.0],
                         'C:stressLen': [21106.55373],
                         'C:stressVec': [[2100.18088, 1.432773165e-13, 21001.80589]],
                         'C:torqueLen': [1.953838427],
                         'C:torqueVec': [[1.944140778, 0.002098033513, -0.1944140778]],
                         'Points': [[-2.0, -2.0, -0.3000000119], [2.0, -2.0, -0.6999999881], [0.0, 2.0, -0.5]]},
              'intrs': {'C:absForceT': [[0.002090220098, 1.956269489, 0.0002090220098],
                                        [500.4620782, 1000.924158, 1.154874509e-14],
                                        [639.9498433, 1280.093218, 338.1902334]],
                        'C:forceN': [16577.04872, 245477.5718, 123799.1429],
                        'Points': [[-8.012098078e-07, -1.854008588e-06, -8.581443581e-06],
                                   [0.1004006043, 0.2008012086, 0.9487925768], [2.0, 0.0, 0.0],
                                   [0.0, -0.7605333924, -0.5], [0.0, 0.0, 1.5]],
                        'lines': [[3, 0], [4, 1], [0, 1]]},
              'spheres': {'C:coordNumber': [2.0, 2.0, 0.0],
                          'P:angVelLen': [0.001367729992, 0.0002355318658, 0.0],
                          'P:angVelVec': [[-0.001223110825, 0.0006121153734, -1.107141042e-07],
                                          [-0.0002106816967, 0.0001053018634, 8.196610092e-09], [0.0, 0.0, 0.0]],
                          'P:clumpId': [-1.0, -1.0, -1.0],
                          'P:color': [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                          'P:dirI': [[-0.9601555609, -0.2389779462, 0.1448821596],
                                     [-0.8944268897, 0.447214198, -7.574311357e-08], [0.0, 0.0, 1.0]],
                          'P:dirII': [[-0.2600054361, 0.9539499701, -0.1495881942],
                                      [-0.4458405755, -0.891679636, 0.07831735427], [0.0, 1.0, 0.0]],
                          'P:dirIII': [[0.1024620523, 0.1812980856, 0.9780759336],
                                       [-0.03502456524, -0.07004918136, -0.9969284789], [1.0, 0.0, 0.0]],
                          'P:forceLen': [107598.4759, 127324.7533, 0.0],
                          'P:forceVec': [[-10442.9853, -24182.79177, -104324.3436],
                                         [11591.99913, 23183.82388, -124658.448], [0.0, 0.0, 0.0]],
                          'P:id': [0.0, 1.0, 2.0],
                          'P:linVelLen': [0.03544562881, 3.768498173, 0.0],
                          'P:linVelVec': [[-0.003201437512, -0.007409470205, -0.03451439049],
                                          [1.002406212, 2.00481241, -3.029436823], [0.0, 0.0, 0.0]],
                          'P:mask': [1.0, 3.0, 1.0],
                          'P:mass': [1047.197551, 1570.796327, 339.2920066],
                          'P:materialId': [0.0, 1.0, 1.0],
                          'P:normalStress': [[18311.58986, 32422.84288, 174402.8951],
                                             [16211.40924, 32422.84288, -159150.6628], [0.0, 0.0, 0.0]],
                          'P:normalStressNorm': [178333.7458, 163226.787, 0.0],
                          'P:radii': [0.5, 0.5, 0.3],
                          'P:shearStress': [[83.80123919, 335.2548355, -419.0560747],
                                            [83.80097438, 335.2548355, -419.0558099], [0.0, 0.0, 0.0]],
                          'P:sigI': [90.92211743, -0.007391037402, 0.0],
                          'P:sigII': [-372.2230432, -3773.563404, 0.0],
                          'P:sigIII': [-130802.3602, -334507.1766, 0.0],
                          'P:torqueLen': [716.2068716, 185.0116345, 0.0],
                          'P:torqueVec': [[-640.4185807, 320.6498352, -0.08742864079],
                                          [-165.4978053, 82.70296998, 0.009657392231], [0.0, 0.0, 0.0]],
                          'Points': [[-8.012098078e-07, -1.854008588e-06, -8.581443581e-06],
                                     [0.1004006043, 0.2008012086, 0.9487925768], [2.0, 0.0, 0.0]]}}


def read(path):
    """The data set in a VTK file (XML .vtu/.vtp or legacy .vtk), read by VTK."""
    path = str(path)
    if path.endswith(".vtu"):
        reader = vtk.vtkXMLUnstructuredGridReader()
    elif path.endswith(".vtp"):
        reader = vtk.vtkXMLPolyDataReader()
    else:
        reader = vtk.vtkGenericDataObjectReader()
        for read_all in ("Scalars", "Vectors", "Tensors", "Fields"):  # not only the first of each kind
            getattr(reader, f"ReadAll{read_all}On")()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def arrays(ds) -> dict:
    """'P:name' / 'C:name' -> array of every point / cell data array."""
    out = {}
    for prefix, data in (("P", ds.GetPointData()), ("C", ds.GetCellData())):
        for k in range(data.GetNumberOfArrays()):
            a = data.GetArray(k)
            out[f"{prefix}:{a.GetName()}"] = vtk_to_numpy(a).astype(float)
    return out


def points(ds) -> np.ndarray:
    return vtk_to_numpy(ds.GetPoints().GetData()).astype(float) if ds.GetNumberOfPoints() else np.zeros((0, 3))


def cells(ds) -> list[list[int]]:
    return [[ds.GetCell(c).GetPointId(k) for k in range(ds.GetCell(c).GetNumberOfPoints())]
            for c in range(ds.GetNumberOfCells())]


def assert_close(actual, expected, what: str) -> None:
    actual, expected = np.asarray(actual, float), np.asarray(expected, float)
    assert actual.shape == expected.shape, f"{what}: shape {actual.shape} != {expected.shape}"
    scale = float(np.abs(expected).max()) if expected.size else 0.0
    np.testing.assert_allclose(actual, expected, rtol=2e-6, atol=1e-7 * max(scale, 1.0), err_msg=what)


def reference_scene(y, recorder):
    """The scene of YADE_FILES with ``recorder`` as the last engine."""
    O = y.O
    O.materials.append(y.FrictMat(young=1e7, density=2000, label="m"))
    O.materials.append(y.FrictMat(young=1e7, density=3000, label="m2"))
    O.bodies.append([y.sphere((0, 0, 0), 0.5, color=(1, 0, 0), material="m"),
                     y.sphere((0.1, 0.2, 0.95), 0.5, material="m2", mask=3, color=(0, 1, 0)),
                     y.sphere((2, 0, 0), 0.3, fixed=True, color=(0, 0, 1))])
    O.bodies.append(y.facet([(-2, -2, -0.3), (2, -2, -0.7), (0, 2, -0.5)], wire=False, color=(.5, .5, .5)))
    O.bodies.append(y.box((0, 0, 1.5), (0.6, 0.6, 0.1), orientation=y.Quaternion((0, 0, 1), 0.3), fixed=True,
                          color=(1, 1, 0)))
    O.bodies[1].state.vel = (1, 2, -3)
    O.engines = [y.ForceResetter(),
                 y.InsertionSortCollider([y.Bo1_Sphere_Aabb(), y.Bo1_Facet_Aabb(), y.Bo1_Box_Aabb()]),
                 y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom(), y.Ig2_Facet_Sphere_ScGeom(),
                                    y.Ig2_Box_Sphere_ScGeom()],
                                   [y.Ip2_FrictMat_FrictMat_FrictPhys()], [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
                 y.NewtonIntegrator(gravity=(0, 0, -10)),
                 recorder]
    O.dt = 1e-4


def test_recorder_matches_yade_files(yade, tmp_path):
    from granum.yade.vtk import VTKRecorder

    base = str(tmp_path / "w-")
    reference_scene(yade, VTKRecorder(fileName=base, recorders=["all"], skipFacetIntr=False, iterPeriod=3,
                                      initRun=False))
    yade.O.run(4, True)
    for part, ext in (("spheres", "vtu"), ("facets", "vtu"), ("boxes", "vtu"), ("intrs", "vtp")):
        ds = read(f"{base}{part}.3.{ext}")
        ref = YADE_FILES[part]
        got = arrays(ds)
        if part == "intrs":
            # YADE lists contacts in its container's order, granum in creation order: match by ids
            lines = [tuple(c) for c in cells(ds)]
            assert sorted(lines) == sorted(tuple(c) for c in ref["lines"])
            order = [lines.index(tuple(c)) for c in ref["lines"]]
            got = {k: v[order] for k, v in got.items()}
            assert_close(points(ds), ref["Points"], "intrs points (body centres by id)")
        elif part == "boxes":
            assert ds.GetNumberOfCells() == 6 and ds.GetNumberOfPoints() == 24
            assert all(np.allclose(v, v[0]) for v in got.values()), "every face repeats the box's data"
            got = {k: v[:1] for k, v in got.items()}
        else:
            assert_close(points(ds), ref["Points"], f"{part} points")
        names = {k for k in ref if ":" in k}
        assert names <= set(got), f"{part}: arrays missing: {sorted(names - set(got))}"
        for name in sorted(names):
            if name.startswith("P:dir"):  # principal directions: the sign of an eigenvector is arbitrary
                dots = np.abs(np.einsum("ki,ki->k", got[name], np.asarray(ref[name])))
                assert_close(dots, np.ones(len(dots)), f"{part} {name}")
            else:
                assert_close(got[name], ref[name], f"{part} {name}")


def test_box_faces_in_yade_order(yade, tmp_path):
    from granum.yade.vtk import VTKRecorder

    rec = VTKRecorder(fileName=str(tmp_path / "b-"), recorders=["boxes"])
    yade.O.bodies.append(yade.box((0, 0, 1.5), (0.6, 0.6, 0.1), orientation=yade.Quaternion((0, 0, 1), 0.3)))
    rec.record(yade.O._scene)
    ds = read(tmp_path / "b-boxes.0.vtu")
    assert cells(ds) == [[4 * f + k for k in range(4)] for f in range(6)]
    assert {ds.GetCellType(c) for c in range(6)} == {9}  # VTK_QUAD
    # YADE's file for this box, first two faces (bottom, top)
    expected = [[-0.3958897591, -0.7505140305, 1.4], [-0.7505140305, 0.3958897591, 1.4],
                [0.3958897591, 0.7505140305, 1.4], [0.7505140305, -0.3958897591, 1.4],
                [-0.3958897591, -0.7505140305, 1.6], [0.7505140305, -0.3958897591, 1.6],
                [0.3958897591, 0.7505140305, 1.6], [-0.7505140305, 0.3958897591, 1.6]]
    assert_close(points(ds)[:8], expected, "box corners")


def scene_with_contacts(y):
    """Two touching spheres on a facet, a free sphere, a fixed sphere and a box; run 3 steps."""
    O = y.O
    O.bodies.append([y.sphere((0, 0, 0), 0.5), y.sphere((0, 0, 0.95), 0.5, mask=3), y.sphere((3, 0, 0), 0.2),
                     y.sphere((0, 3, 0), 0.2, fixed=True)])
    O.bodies.append(y.facet([(-2, -2, -0.45), (2, -2, -0.45), (0, 2, -0.45)]))
    O.bodies.append(y.box((5, 5, 5), (1, 1, 1)))
    O.engines = [y.ForceResetter(),
                 y.InsertionSortCollider([y.Bo1_Sphere_Aabb(), y.Bo1_Facet_Aabb(), y.Bo1_Box_Aabb()]),
                 y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom(), y.Ig2_Facet_Sphere_ScGeom(),
                                    y.Ig2_Box_Sphere_ScGeom()],
                                   [y.Ip2_FrictMat_FrictMat_FrictPhys()], [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
                 y.NewtonIntegrator(gravity=(0, 0, -10))]
    O.dt = 1e-4
    O.run(3, True)
    assert O.interactions.countReal() == 2


def test_file_names_times_and_pvd(yade, tmp_path):
    from granum.yade.vtk import VTKRecorder

    scene_with_contacts(yade)
    O = yade.O
    (tmp_path / "out").mkdir()
    O.engines = O.engines + [VTKRecorder(fileName=str(tmp_path / "out" / "p1-"), iterPeriod=2, label="rec")]
    t0 = O.time
    O.run(5, True)
    # initRun is True by default (as in YADE): steps 3, 5 and 7 are recorded
    names = sorted(os.listdir(tmp_path / "out"))
    expected = [f"p1-{part}.{i}.{ext}" for part, ext in (("boxes", "vtu"), ("facets", "vtu"), ("intrs", "vtp"),
                                                         ("spheres", "vtu")) for i in (3, 5, 7)]
    expected += [f"p1-{part}.pvd" for part in ("boxes", "facets", "intrs", "spheres")]
    assert names == sorted(expected)
    collection = ET.parse(tmp_path / "out" / "p1-spheres.pvd").getroot()
    sets = collection.findall("./Collection/DataSet")
    assert [s.get("file") for s in sets] == [f"p1-spheres.{i}.vtu" for i in (3, 5, 7)]
    times = [float(s.get("timestep")) for s in sets]
    np.testing.assert_allclose(times, [t0, t0 + 2 * O.dt, t0 + 4 * O.dt], rtol=1e-12)
    ds = read(tmp_path / "out" / "p1-spheres.7.vtu")
    assert ds.GetNumberOfPoints() == 4
    assert_close(arrays(ds)["P:radii"], [0.5, 0.5, 0.2, 0.2], "radii")
    assert not glob.glob(str(tmp_path / "out" / ".*")), "temporary files left behind"


def test_counts_and_values_against_the_scene(yade, tmp_path):
    from granum.yade.vtk import VTKRecorder

    scene_with_contacts(yade)
    O = yade.O
    rec = VTKRecorder(fileName=str(tmp_path / "a-"))
    rec.record(O._scene)
    it = O.iter
    sph = read(tmp_path / f"a-spheres.{it}.vtu")
    got = arrays(sph)
    assert sph.GetNumberOfPoints() == sph.GetNumberOfCells() == 4
    assert {sph.GetCellType(c) for c in range(4)} == {1}  # VTK_VERTEX
    for k, b in enumerate(list(O.bodies)[:4]):
        assert_close(points(sph)[k], b.state.pos, "position")
        assert got["P:id"][k] == b.id
        assert_close(got["P:linVelVec"][k], b.state.vel, "linVelVec")
        assert_close(got["P:linVelLen"][k], b.state.vel.norm(), "linVelLen")
        assert_close(got["P:forceVec"][k], O.forces.f(b.id), "forceVec")
        assert_close(got["P:torqueVec"][k], O.forces.t(b.id), "torqueVec")
        assert_close(got["P:color"][k], b.shape.color, "color")
        assert got["P:mass"][k] == pytest.approx(b.state.mass)
        assert got["P:mask"][k] == b.mask
        assert got["C:coordNumber"][k] == len(b.intrs())
    fac = read(tmp_path / f"a-facets.{it}.vtu")
    assert fac.GetNumberOfCells() == 1 and fac.GetCellType(0) == 5  # VTK_TRIANGLE
    assert_close(points(fac), [[-2, -2, -0.45], [2, -2, -0.45], [0, 2, -0.45]], "facet vertices")
    assert arrays(fac)["C:coordNumber"][0] == 1
    intr = read(tmp_path / f"a-intrs.{it}.vtp")
    # default skipFacetIntr: only the sphere-sphere contact is written
    assert cells(intr) == [[0, 1]]
    i = O.interactions[0, 1]
    assert arrays(intr)["C:forceN"][0] == pytest.approx(i.phys.normalForce.dot(i.geom.normal), rel=1e-12)
    assert_close(arrays(intr)["C:absForceT"][0], np.abs(np.asarray(i.phys.shearForce)), "absForceT")
    assert_close(points(intr), [b.state.pos for b in O.bodies], "intrs points are all body centres")


def test_recorder_options(yade, tmp_path):
    from granum.yade.vtk import VTKRecorder

    scene_with_contacts(yade)
    scene = yade.O._scene
    it = yade.O.iter
    VTKRecorder(fileName=str(tmp_path / "f-"), recorders=["intr"], skipFacetIntr=False).record(scene)
    assert sorted(cells(read(tmp_path / f"f-intrs.{it}.vtp"))) == [[0, 1], [4, 0]]
    VTKRecorder(fileName=str(tmp_path / "m-"), recorders=["spheres", "id"], mask=2).record(scene)
    assert list(arrays(read(tmp_path / f"m-spheres.{it}.vtu"))["P:id"]) == [1.0]
    VTKRecorder(fileName=str(tmp_path / "d-"), recorders=["spheres", "id"], skipNondynamic=True).record(scene)
    assert list(arrays(read(tmp_path / f"d-spheres.{it}.vtu"))["P:id"]) == [0.0, 1.0, 2.0]
    # only base recorders write files; generic ones only add arrays
    assert VTKRecorder(fileName=str(tmp_path / "g-"), recorders=["velocity", "mass"]).record(scene) == []
    only = arrays(read(VTKRecorder(fileName=str(tmp_path / "o-"), recorders=["spheres"]).record(scene)[0]))
    assert set(only) == {"P:radii"}
    # the periodic cell is written only in a periodic scene
    assert VTKRecorder(fileName=str(tmp_path / "c-"), recorders=["pericell"]).record(scene) == []


@pytest.mark.parametrize("mode", [{"ascii": True}, {"compress": True}])
def test_ascii_and_compressed_files_hold_the_same_data(yade, tmp_path, mode):
    from granum.yade.vtk import VTKRecorder

    scene_with_contacts(yade)
    scene = yade.O._scene
    plain = VTKRecorder(fileName=str(tmp_path / "x-")).record(scene)
    other = VTKRecorder(fileName=str(tmp_path / "y-"), **mode).record(scene)
    assert len(plain) == len(other) == 4
    for a, b in zip(plain, other, strict=True):
        da, db = read(a), read(b)
        np.testing.assert_array_equal(points(da), points(db))
        assert cells(da) == cells(db)
        ga, gb = arrays(da), arrays(db)
        assert ga.keys() == gb.keys()
        for k in ga:
            np.testing.assert_array_equal(ga[k], gb[k])
    if "ascii" in mode:
        assert b"<AppendedData" not in open(other[0], "rb").read()


def test_periodic_cell_hexahedron_in_yade_order(yade, tmp_path):
    from granum.yade.vtk import VTKRecorder

    scene = yade.O._scene
    scene.periodic = True
    scene.cell_hsize[:] = [[2, 0.5, 0], [0, 3, 0], [0, 0, 4]]
    path = VTKRecorder(fileName=str(tmp_path / "pc-"), recorders=["pericell"]).record(scene)[0]
    assert os.path.basename(path) == "pc-pericell.0.vtu"
    ds = read(path)
    assert ds.GetNumberOfCells() == 1 and ds.GetCellType(0) == 12  # VTK_HEXAHEDRON
    # YADE's file for this cell
    assert_close(points(ds), [[0, 0, 4], [0.5, 3, 4], [2.5, 3, 4], [2, 0, 4], [0, 0, 0], [0.5, 3, 0], [2.5, 3, 0],
                              [2, 0, 0]], "cell corners")


def test_ids_is_yades_other_name_for_id(yade):
    """YADE 2023.02a writes the ``id`` array for the recorder ``ids`` (hourglass.py names it; measured)."""
    from granum.yade.vtk import VTKRecorder

    assert VTKRecorder(recorders=["spheres", "ids"]).recorders == ["spheres", "id"]


def test_bad_recorder_settings_are_refused(yade, tmp_path):
    from granum.yade.vtk import VTKRecorder

    with pytest.raises(ValueError, match="unknown recorder 'sphere'"):
        VTKRecorder(recorders=["sphere"])
    with pytest.raises(ValueError, match="does not implement"):
        VTKRecorder(recorders=["cpm"])
    with pytest.raises(ValueError, match="multiblock"):
        VTKRecorder(multiblock=True)
    with pytest.raises(TypeError, match="list of strings"):
        VTKRecorder(recorders="spheres")
    yade.O.bodies.append(yade.sphere((0, 0, 0), 1))
    with pytest.raises(FileNotFoundError, match="does not exist"):
        VTKRecorder(fileName=str(tmp_path / "no" / "such" / "dir-")).record(yade.O._scene)


# ---- export ----------------------------------------------------------------------------------------
def test_exporter_spheres_what_and_numbering(yade, tmp_path):
    from granum.yade import export

    scene_with_contacts(yade)
    O = yade.O
    ex = export.VTKExporter(str(tmp_path / "ex"))
    ex.exportSpheres(what=dict(dist="b.state.pos.norm()", vel="b.state.vel", m="Matrix3(1,2,3,4,5,6,7,8,9)"))
    ex.exportSpheres(ids=[0, 4, 3], useRef=True, numLabel=7)  # 4 is a facet: skipped
    ex.exportSpheres(ids=[1])
    # each part counts its exports; numLabel names one file without changing the count (YADE)
    assert sorted(os.listdir(tmp_path)) == ["ex-spheres-00000000.vtk", "ex-spheres-00000002.vtk",
                                            "ex-spheres-00000007.vtk"]
    ds = read(tmp_path / "ex-spheres-00000000.vtk")
    got = arrays(ds)
    bodies = list(O.bodies)[:4]
    assert_close(points(ds), [b.state.pos for b in bodies], "centres")
    assert_close(got["P:radius"], [0.5, 0.5, 0.2, 0.2], "radius")
    assert_close(got["P:dist"], [b.state.pos.norm() for b in bodies], "dist")
    assert_close(got["P:vel"], [b.state.vel for b in bodies], "vel")
    assert_close(got["P:m"], np.tile(np.arange(1.0, 10.0), (4, 1)), "tensor")
    ref = read(tmp_path / "ex-spheres-00000007.vtk")
    assert_close(points(ref), [O.bodies[0].state.refPos, O.bodies[3].state.refPos], "reference positions")


def test_exporter_facets_interactions_contact_points(yade, tmp_path):
    from granum.yade import export

    scene_with_contacts(yade)
    O = yade.O
    ex = export.VTKExporter(str(tmp_path / "ex"), startSnap=3)
    ex.exportFacets(what=dict(n="b.shape.normal"))
    fac = read(tmp_path / "ex-facets-00000003.vtk")
    assert cells(fac) == [[0, 1, 2]]
    assert_close(arrays(fac)["C:n"], [[0, 0, 1]], "facet normal")
    ex.exportInteractions(what=dict(forceN="i.phys.normalForce.norm()", fs="i.phys.shearForce"),
                          verticesWhat=dict(m="b.state.mass"))
    it = read(tmp_path / "ex-intrs-00000003.vtk")
    intrs = list(O.interactions)
    assert it.GetNumberOfCells() == len(intrs) == 2 and it.GetNumberOfPoints() == 4
    got = arrays(it)
    for k, i in enumerate(intrs):
        assert cells(it)[k] == [2 * k, 2 * k + 1]
        assert_close(points(it)[2 * k:2 * k + 2], [O.bodies[i.id1].state.pos, O.bodies[i.id2].state.pos], "ends")
        assert got["C:forceN"][k] == pytest.approx(i.phys.normalForce.norm(), rel=1e-12)
        assert_close(got["C:fs"][k], i.phys.shearForce, "shear force")
        assert_close(got["P:m"][2 * k:2 * k + 2], [O.bodies[i.id1].state.mass, O.bodies[i.id2].state.mass], "m")
    ex.exportInteractions(ids=[(1, 0)], what=dict(kn="i.phys.kn"))
    one = read(tmp_path / "ex-intrs-00000004.vtk")
    assert one.GetNumberOfCells() == 1
    assert arrays(one)["C:kn"][0] == pytest.approx(O.interactions[0, 1].phys.kn)
    ex.exportContactPoints(what={"fn": "i.phys.normalForce"})
    cp = read(tmp_path / "ex-cps-00000003.vtk")
    assert_close(points(cp), [i.geom.contactPoint for i in intrs], "contact points")
    assert_close(arrays(cp)["P:fn"], [i.phys.normalForce for i in intrs], "normal forces")
    with pytest.warns(UserWarning, match="skipped"):
        ex.exportSpheres(what=dict(bad="(1, 2)"))
    assert "P:bad" not in arrays(read(tmp_path / "ex-spheres-00000003.vtk"))


def test_text_export_round_trip(yade, tmp_path):
    from granum.yade import export

    O = yade.O
    O.materials.append(yade.FrictMat(label="shared"))
    private = yade.FrictMat()  # not in O.materials: id -1
    O.bodies.append([yade.sphere((1, 2, 3), 0.25, material="shared"),
                     yade.sphere((0.1, 0.2, 0.3), 0.125, mask=2, material=private),
                     yade.facet([(0, 0, 0), (1, 0, 0), (0, 1, 0)])])
    O.bodies[1].state.vel = (1, 2, 3)
    assert export.text(str(tmp_path / "t.txt")) == 2
    lines = (tmp_path / "t.txt").read_text().splitlines()
    assert lines[0] == "#format x_y_z_r"
    np.testing.assert_array_equal(np.loadtxt(tmp_path / "t.txt"), [[1, 2, 3, 0.25], [0.1, 0.2, 0.3, 0.125]])
    assert export.text(str(tmp_path / "m.txt"), mask=2) == 1
    assert export.textExt(str(tmp_path / "id.txt"), "x_y_z_r_matId", comment="hello") == 2
    lines = (tmp_path / "id.txt").read_text().splitlines()
    assert lines[:2] == ["#format x_y_z_r_matId", "# hello"]
    assert [line.split("\t")[-1] for line in lines[2:]] == ["0", "-1"]  # id in O.materials; -1: not shared
    export.textExt(str(tmp_path / "a.txt"), "x_y_z_r_attrs", comment="vx vy vz", attrs=["b.state.vel"])
    assert (tmp_path / "a.txt").read_text().splitlines()[1] == "# x y z r vx vy vz"
    np.testing.assert_array_equal(np.loadtxt(tmp_path / "a.txt")[1], [0.1, 0.2, 0.3, 0.125, 1, 2, 3])
    with pytest.raises(RuntimeError, match="correct format"):
        export.textExt(str(tmp_path / "bad.txt"), "id_x_y_z_r")


def test_periodic_contact_gets_an_image_end_point(yade, tmp_path):
    from granum.yade.vtk import VTKRecorder

    O = yade.O
    O.periodic = True
    O.cell.hSize = yade.Matrix3(2, 0, 0, 0, 2, 0, 0, 0, 2)
    O.bodies.append([yade.sphere((0.1, 1, 1), 0.15), yade.sphere((1.9, 1, 1), 0.15)])
    O.engines = [yade.ForceResetter(), yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb()]),
                 yade.InteractionLoop([yade.Ig2_Sphere_Sphere_ScGeom()], [yade.Ip2_FrictMat_FrictMat_FrictPhys()],
                                      [yade.Law2_ScGeom_FrictPhys_CundallStrack()]),
                 yade.NewtonIntegrator()]
    O.dt = 1e-5
    O.run(1, True)
    i = O.interactions[0, 1]
    assert tuple(i.cellDist) == (-1, 0, 0)
    files = VTKRecorder(fileName=str(tmp_path / "p-"), recorders=["intr", "pericell", "spheres", "bstresses"]
                        ).record(O._scene)
    ds = read(files[1])
    # the line goes from body 1 to the image of body 2 across the boundary, not through the cell
    assert cells(ds) == [[0, 2]]
    assert_close(points(ds)[2], np.asarray(O.bodies[1].state.pos) + (-2, 0, 0), "image of body 2")
    assert read(files[2]).GetNumberOfCells() == 1
    # the per-sphere stress uses the lever arm to the image: both spheres are compressed along x
    sig = arrays(read(files[0]))["P:sigIII"]
    assert np.all(sig < 0)
    assert_close(sig[0], sig[1], "symmetric compression")
