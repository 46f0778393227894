"""The scripting API against real YADE: defaults, body factories, containers, engine semantics."""

from __future__ import annotations

import builtins
import math

import numpy as np
import pytest
from conftest import frict_engines, reference

from granum.mathtypes import as_quat_wxyz

DEFAULT_CLASSES = [
    "ForceResetter", "InsertionSortCollider", "Bo1_Sphere_Aabb", "Bo1_Facet_Aabb", "Bo1_Wall_Aabb", "Bo1_Box_Aabb",
    "InteractionLoop", "Ig2_Sphere_Sphere_ScGeom", "Ig2_Facet_Sphere_ScGeom", "Ig2_Wall_Sphere_ScGeom",
    "Ig2_Box_Sphere_ScGeom", "Ip2_FrictMat_FrictMat_FrictPhys", "Ip2_ViscElMat_ViscElMat_ViscElPhys",
    "Law2_ScGeom_FrictPhys_CundallStrack", "Law2_ScGeom_ViscElPhys_Basic", "NewtonIntegrator", "GravityEngine",
    "PyRunner", "ForceEngine", "RotationEngine", "FrictMat", "ViscElMat",
]


def _plain(v):
    if hasattr(v, "_a"):
        return np.asarray(v).tolist()
    return v


@pytest.mark.parametrize("name", DEFAULT_CLASSES)
def test_defaults_match_yade(yade, name):
    """Every attribute YADE reports for a fresh instance exists with the same default value."""
    ref = reference("defaults")["classes"][name]
    obj = getattr(yade, name)()
    for key, want in ref.items():
        if key in ("realLast",) or isinstance(want, str) and want.startswith("<"):
            assert hasattr(obj, key), key
            continue
        got = _plain(getattr(obj, key))
        if isinstance(want, float) and math.isnan(want):
            assert math.isnan(got), key
        else:
            assert got == want, key


def test_body_factories_match_yade(yade):
    """sphere, box, facet and wall create the same state, mass, inertia and shape as YADE."""
    ref = reference("bodies")
    made = {
        "sphere((1,2,3),.5)": yade.sphere((1, 2, 3), 0.5),
        "sphere((1,2,3),.5,fixed=True)": yade.sphere((1, 2, 3), 0.5, fixed=True),
        "box((0,0,0),(1,2,3))": yade.box((0, 0, 0), (1, 2, 3)),
        "box((0,0,0),(1,2,3),fixed=True)": yade.box((0, 0, 0), (1, 2, 3), fixed=True),
        "facet([(0,0,0),(1,0,0),(0,1,0)])": yade.facet([(0, 0, 0), (1, 0, 0), (0, 1, 0)]),
        "facet([(1,1,1),(3,1,1),(1,4,2)])": yade.facet([(1, 1, 1), (3, 1, 1), (1, 4, 2)]),
        "wall(1.5,axis=2)": yade.wall(1.5, axis=2),
        "wall((0,0,1),axis=1,sense=-1)": yade.wall((0, 0, 1), axis=1, sense=-1),
    }
    for key, b in made.items():
        r = ref[key]
        assert yade.O.bodies.append(b) == r["id"], key
        st = b.state
        assert type(b.shape).__name__ == r["shape_class"]
        for attr in ("pos", "refPos", "vel", "angVel", "inertia"):
            np.testing.assert_allclose(np.asarray(getattr(st, attr)), r[attr], rtol=1e-14, err_msg=f"{key} {attr}")
        np.testing.assert_allclose(as_quat_wxyz(st.ori), r["ori"])
        assert st.mass == pytest.approx(r["mass"], rel=1e-14)
        assert (st.blockedDOFs, b.dynamic, st.isDamped, b.aspherical, b.mask) == (
            r["blockedDOFs"], r["dynamic"], r["isDamped"], r["aspherical"], r["mask"]), key
        assert type(b.material).__name__ == r["material_class"]
        for attr, want in r["shape"].items():
            if attr == "color":
                continue
            got = getattr(b.shape, attr)
            got = [np.asarray(v).tolist() for v in got] if attr == "vertices" else _plain(got)
            np.testing.assert_allclose(got, want, rtol=1e-14, atol=1e-15, err_msg=f"{key} {attr}")
    # the default material is YADE's defaultMat, appended once and shared
    assert len(yade.O.materials) == 1 and yade.O.materials[0].label == "defaultMat"
    assert (yade.O.materials[0].young, yade.O.materials[0].poisson) == (1e7, 0.3)


def test_aabb_walls_and_facet_box_match_yade(yade):
    """aabbWalls and geom.facetBox produce YADE's boxes and facets, in YADE's order."""
    ref = reference("bodies")
    walls = yade.aabbWalls([(0, 0, 0), (1, 1, 1)])
    for b, r in zip(walls, ref["aabbWalls([(0,0,0),(1,1,1)])"], strict=True):
        np.testing.assert_allclose(np.asarray(b.state.pos), r["pos"])
        np.testing.assert_allclose(np.asarray(b.shape.extents), r["extents"])
        assert (b.dynamic, b.shape.wire, b.state.mass) == (r["dynamic"], r["wire"], r["mass"])
    thick = yade.aabbWalls([(0, 0, 0), (1, 1, 1)], thickness=0.1)
    for b, r in zip(thick, ref["aabbWalls([(0,0,0),(1,1,1)],thickness=0.1)"], strict=True):
        np.testing.assert_allclose(np.asarray(b.state.pos), r["pos"], atol=1e-15)
        np.testing.assert_allclose(np.asarray(b.shape.extents), r["extents"], atol=1e-15)
    box = ref["facetBox((0,0,0),(1,2,3),wallMask=31)"]
    facets = yade.geom.facetBox((0, 0, 0), (1, 2, 3), wallMask=31)
    assert len(facets) == box["n_facets"]
    for f, r in zip(facets, box["facets"], strict=True):
        glob = [np.asarray(f.state.pos) + np.asarray(v) for v in f.shape.vertices]
        np.testing.assert_allclose(glob, r["global_vertices"], atol=1e-14)
        np.testing.assert_allclose(np.asarray(f.shape.normal), r["normal"], atol=1e-14)
        assert f.shape.area == pytest.approx(r["area"])
    assert len(yade.geom.facetBox((0, 0, 0), (1, 2, 3))) == ref["facetBox((0,0,0),(1,2,3)) default wallMask n_facets"]


def test_a_flat_facet_box_is_one_rectangle_as_in_yade(yade):
    """geom.facetBox with one zero extent (YADE's rotationalResistance.py): the two facets of one face, whatever
    wallMask, normal along the flat axis; two zero extents are refused."""
    ref = reference("viscel_pairs")["flat_facet_box"]
    for e in ((1, 2, 0), (0, 2, 1), (1, 0, 1)):
        facets = yade.geom.facetBox((0.1, 0.2, 0.3), e, orientation=yade.Quaternion(yade.Vector3(1, 0, 0), 0.3),
                                    wallMask=12)
        assert len(facets) == len(ref[str(e)])
        for f, r in zip(facets, ref[str(e)], strict=True):
            np.testing.assert_allclose(np.asarray(f.state.pos), r["pos"], atol=1e-15)
            np.testing.assert_allclose([np.asarray(v) for v in f.shape.vertices], r["vertices"], atol=1e-15)
            np.testing.assert_allclose(np.asarray(f.shape.normal), r["normal"], atol=1e-15)
    with pytest.raises(ValueError, match=r"at least two extents must be nonzero, got extents=\(1.0, 0.0, 0.0\)"):
        yade.geom.facetBox((0, 0, 0), (1, 0, 0))


def test_state_views_write_into_the_scene(yade):
    """b.state.pos/vel and shape attributes read and write the storage, also through components."""
    b = yade.sphere((0, 0, 0), 1)
    yade.O.bodies.append(b)
    yade.O.bodies[0].state.vel = (1, 0, 0)
    yade.O.bodies[0].state.pos[2] = 5.0
    v = yade.O.bodies[0].state.vel
    v += yade.Vector3(0, 2, 0)
    assert np.asarray(b.state.vel).tolist() == [1, 2, 0]
    assert b.state.pos[2] == 5.0 and yade.O._scene.bodies.pos[0, 2] == 5.0
    b.state.blockedDOFs = "xZ"
    assert b.state.blockedDOFs == "xZ" and b.dynamic
    b.dynamic = False
    assert b.state.blockedDOFs == "xyzXYZ" and np.asarray(b.state.vel).tolist() == [0, 0, 0]
    with pytest.raises(ValueError, match="blockedDOFs"):
        b.state.blockedDOFs = "xq"
    b.shape.color = (1, 0, 0)
    assert isinstance(b.shape, yade.Sphere) and np.asarray(b.shape.color).tolist() == [1, 0, 0]


def test_pyrunner_schedule_matches_yade(yade):
    """PyRunner periods (steps, simulated time, initRun, nDo, firstIterRun) fire exactly as in YADE."""
    ref = reference("pyrunner")["schedule"]
    log = []
    builtins._granum_test_log = log
    try:
        def runner(label, **kw):
            return yade.PyRunner(command=f"_granum_test_log.append(({label!r}, O.iter, O.time))", label=label, **kw)

        yade.O.bodies.append(yade.sphere((0, 0, 0), 1))
        engines = [yade.ForceResetter(), runner("before_newton", iterPeriod=1)]
        engines += [runner(name, **kw) for name, kw in ref["runners"].items()]
        engines += [yade.NewtonIntegrator(), runner("after_newton", iterPeriod=1)]
        yade.O.engines = engines
        yade.O.dt = 0.25
        for _ in range(20):
            yade.O.step()
        assert [(a, b, pytest.approx(c)) for a, b, c in ref["log"]] == log
        # the same schedule when the steps run in one call (compiled chunks between the runners)
        log.clear()
        yade.O.reset()
        yade.O.bodies.append(yade.sphere((0, 0, 0), 1))
        yade.O.engines = [yade.ForceResetter(), runner("before_newton", iterPeriod=1)] + [
            runner(name, **kw) for name, kw in ref["runners"].items()] + [
            yade.NewtonIntegrator(), runner("after_newton", iterPeriod=1)]
        yade.O.dt = 0.25
        yade.O.run(20, True)
        assert [(a, b, pytest.approx(c)) for a, b, c in ref["log"]] == log
    finally:
        del builtins._granum_test_log


def test_engines_assigned_inside_a_pyrunner_start_at_the_next_step(yade):
    """O.engines = O.engines + [...] from a running engine takes effect at the next step (YADE)."""
    yade.O.bodies.append(yade.sphere((0, 0, 0), 1))
    seen = []
    builtins._granum_seen = seen
    try:
        yade.O.engines = [
            yade.PyRunner(command="O.engines = O.engines + [PyRunner(command='_granum_seen.append(O.iter)', "
                                  "iterPeriod=1, initRun=True)]; checker.dead = True", iterPeriod=1, initRun=True,
                          label="checker"),
            yade.PyRunner(command="_granum_seen.append(-O.iter)", iterPeriod=1, initRun=True),
            yade.NewtonIntegrator()]
        yade.O.run(3, True)
    finally:
        del builtins._granum_seen
    # step 0: the old list runs to its end (-0); the appended runner (last in the list) starts at step 1
    assert seen == [0, -1, 1, -2, 2]
    assert yade.O.namespace()["checker"].dead


def test_pause_inside_a_pyrunner_finishes_the_step(yade):
    """O.pause() from an engine stops the run after the current step; O.wait() returns."""
    yade.O.bodies.append(yade.sphere((0, 0, 0), 1))
    yade.O.engines = [yade.NewtonIntegrator(), yade.PyRunner(command="O.pause() if O.iter == 6 else None",
                                                             iterPeriod=1)]
    yade.O.run()
    yade.O.wait()
    assert yade.O.iter == 7 and not yade.O.running
    yade.O.run(5, True)
    assert yade.O.iter == 12


def test_stop_at_iter_and_background_run(yade):
    """O.run(n) runs in the background and stops after n steps; O.stopAtIter bounds an open run."""
    yade.O.bodies.append(yade.sphere((0, 0, 0), 1))
    yade.O.engines = frict_engines(yade, gravity=(0, 0, -9.81))
    yade.O.run(50)
    yade.O.wait()
    assert yade.O.iter == 50
    yade.O.stopAtIter = 80
    yade.O.run()
    yade.O.wait()
    assert yade.O.iter == 80


def test_labels_become_global_names(yade):
    """Labelled engines and functors are names of the script's namespace (YADE makes them builtins; granum
    never touches builtins); a name the namespace or the builtins give to something else keeps its meaning."""
    ns = yade.O.namespace()
    yade.O.engines = [yade.NewtonIntegrator(label="newtonCustomLabel"),
                      yade.InteractionLoop([yade.Ig2_Sphere_Sphere_ScGeom(label="ig2ss")], [], [])]
    assert ns["newtonCustomLabel"] is yade.O.engines[0]
    assert ns["ig2ss"] is yade.O.engines[1].geomDispatcher.functors[0]
    assert not hasattr(builtins, "newtonCustomLabel")
    yade.O.engines = [yade.NewtonIntegrator(label="newtonCustomLabel")]   # a label moves to its new engine
    assert ns["newtonCustomLabel"] is yade.O.engines[0]
    yade.O.engines = [yade.PyRunner(label="print"), yade.PyRunner(label="plot"), yade.ForceResetter(label="O")]
    assert builtins.print is print and "print" not in ns and ns["plot"] is yade.plot and ns["O"] is yade.O
    assert yade.O.labeledEngine("plot") is yade.O.engines[1]
    for bad in ("virt0.5", "lambda"):
        with pytest.raises(ValueError, match="identifier"):
            yade.O.engines = [yade.NewtonIntegrator(label=bad)]


def test_utilities_match_yade(yade):
    """PWaveTimeStep, sphere volume/mass, aabbExtrema and porosity of YADE's recorded state."""
    ref = reference("utilities")
    yade.O.bodies.append(yade.geom.facetBox((0.5, 0.5, 0.5), (0.5, 0.5, 0.5), wallMask=31))
    for s in ref["initial_spheres"]:
        yade.O.bodies.append(yade.sphere(s["pos"], s["radius"]))
    assert yade.PWaveTimeStep() == pytest.approx(ref["PWaveTimeStep_initial"], rel=1e-14)
    final = {b["id"]: b for b in ref["bodies"]}
    for b in yade.O.bodies:
        b.state.pos = final[b.id]["pos"]
    u = ref["utils"]
    assert yade.getSpheresVolume() == pytest.approx(u["getSpheresVolume()"], rel=1e-14)
    assert yade.getSpheresMass() == pytest.approx(u["getSpheresMass()"], rel=1e-14)
    lo, hi = yade.aabbExtrema()
    np.testing.assert_allclose([np.asarray(lo), np.asarray(hi)], u["aabbExtrema()"], rtol=1e-14)
    assert yade.porosity() == pytest.approx(u["porosity()"], rel=1e-12)
    assert yade.porosity(1.0) == pytest.approx(u["porosity(1.0)"], rel=1e-12)


def test_unbalanced_force_and_coordination_from_their_definitions(yade):
    """unbalancedForce = mean |F + m g| / mean contact force; avgNumInteractions = 2C/N (Thornton's Z_m)."""
    yade.O.bodies.append([yade.sphere((0, 0, 0), 1, fixed=True), yade.sphere((0, 0, 1.98), 1),
                          yade.sphere((3, 0, 0), 1), yade.sphere((0, 0, 3.96), 1)])
    yade.O.engines = frict_engines(yade, gravity=(0, 0, -10), damping=0.3)
    assert math.isnan(yade.unbalancedForce())  # no contact yet, as YADE
    yade.O.dt = 0.1 * yade.PWaveTimeStep()
    yade.O.step()
    ids = [1, 2, 3]  # dynamic bodies
    res = [np.linalg.norm(np.asarray(yade.O.forces.f(i)) + yade.O.bodies[i].state.mass * np.array([0, 0, -10]))
           for i in ids]
    contacts = [np.linalg.norm(np.asarray(i.phys.normalForce) + np.asarray(i.phys.shearForce))
                for i in yade.O.interactions]
    assert len(contacts) == 2
    assert yade.unbalancedForce() == pytest.approx(np.mean(res) / np.mean(contacts), rel=1e-12)
    assert yade.unbalancedForce(True) == pytest.approx(np.max(res) / np.mean(contacts), rel=1e-12)
    assert yade.avgNumInteractions() == pytest.approx(2 * 2 / 4)
    # Thornton: (2C - N1) / (N - N0 - N1) with N0 = 1 (the lone sphere), N1 = 2
    assert yade.avgNumInteractions(skipFree=True) == pytest.approx((4 - 2) / (4 - 1 - 2))
    e = yade.kineticEnergy()
    want = sum(0.5 * b.state.mass * np.dot(b.state.vel, b.state.vel)
               + 0.5 * np.dot(np.asarray(b.state.inertia), np.asarray(b.state.angVel) ** 2)
               for b in yade.O.bodies if b.dynamic)
    assert e == pytest.approx(want, rel=1e-12)


def test_interactions_container(yade):
    """Symmetric lookup, iteration over real interactions only, counts, withBody, erase."""
    yade.O.bodies.append([yade.sphere((0, 0, 0), 1), yade.sphere((0, 0, 1.9), 1), yade.sphere((0, 0, 3.8), 1),
                          yade.sphere((0, 2.3, 0), 1)])
    yade.O.engines = frict_engines(yade)
    yade.O.step()
    assert yade.O.interactions[0, 1].id1 == yade.O.interactions[1, 0].id1 == 0
    real = sorted((i.id1, i.id2) for i in yade.O.interactions)
    assert real == [(0, 1), (1, 2)]
    assert yade.O.interactions.countReal() == 2
    assert len(yade.O.interactions) >= 3           # (0, 3) is potential only: bounds overlap
    assert yade.O.interactions.has(0, 3) and not yade.O.interactions.has(0, 3, onlyReal=True)
    assert not yade.O.interactions[0, 3].isReal and yade.O.interactions[0, 3].phys is None
    assert sorted((i.id1, i.id2) for i in yade.O.interactions.withBody(1)) == [(0, 1), (1, 2)]
    assert sorted((i.id1, i.id2) for i in yade.O.bodies[1].intrs()) == [(0, 1), (1, 2)]
    yade.O.interactions.erase(0, 1)
    assert yade.O.interactions.countReal() == 1
    i = yade.O.interactions[1, 2]
    i.phys.tangensOfFrictionAngle = 0.25
    assert yade.O.interactions[2, 1].phys.tangensOfFrictionAngle == 0.25


def test_forces_container_and_permanent_forces(yade):
    """addF acts for one step, permanent forces survive ForceResetter; f/t read the last step."""
    yade.O.bodies.append(yade.sphere((0, 0, 0), 1))
    yade.O.engines = frict_engines(yade)
    yade.O.dt = 1e-3
    yade.O.forces.addF(0, (0, 0, 5), permanent=True)
    yade.O.step()
    m = yade.O.bodies[0].state.mass
    assert np.asarray(yade.O.forces.f(0)).tolist() == [0, 0, 5]
    assert yade.O.bodies[0].state.vel[2] == pytest.approx(5 / m * 1e-3)
    yade.O.forces.reset()
    yade.O.step()
    assert np.asarray(yade.O.forces.f(0)).tolist() == [0, 0, 0]


def test_energy_terms_appear_as_in_yade(yade):
    """Energy keys appear once computed: kinetic, gravWork (gravity), nonviscDamp (damping), elastPotential."""
    ref = reference("energy")
    yade.O.bodies.append([yade.sphere((0, 0, 0), 0.5, fixed=True), yade.sphere((0, 0, 2), 0.5)])
    yade.O.engines = frict_engines(yade, gravity=(0, 0, -9.81), damping=0.1)
    yade.O.dt = 1e-5
    yade.O.trackEnergy = True
    rows = {r["iter"]: r for r in ref["damping_0.1"]["every_1000_steps"]}
    for it in (1000, 2000, 3000):
        yade.O.run(it - yade.O.iter, True)
        r = rows[it]
        assert sorted(yade.O.energy.keys()) == sorted(r["energy"])
        for k, v in r["energy"].items():
            assert yade.O.energy[k] == pytest.approx(v, rel=1e-9), k
    yade.O.run(50000, True)
    assert set(yade.O.energy.keys()) >= {"elastPotential", "gravWork", "kinetic", "nonviscDamp"}


def test_save_and_load_tmp_restore_the_scene(yade):
    """O.saveTmp/O.loadTmp restore bodies, engines, time and contacts; the run continues identically."""
    yade.O.bodies.append([yade.sphere((0, 0, 0), 0.5, fixed=True), yade.sphere((0, 0, 0.99), 0.5)])
    yade.O.engines = frict_engines(yade, gravity=(0, 0, -9.81), damping=0.1)
    yade.O.dt = 1e-5
    yade.O.run(100, True)
    yade.O.saveTmp()
    yade.O.run(100, True)
    first = np.asarray(yade.O.bodies[1].state.pos).copy()
    yade.O.loadTmp()
    assert yade.O.iter == 100 and yade.O.interactions.countReal() == 1
    yade.O.run(100, True)
    assert np.asarray(yade.O.bodies[1].state.pos).tolist() == first.tolist()
    with pytest.raises(RuntimeError, match="mark"):
        yade.O.loadTmp("nothing")


def test_gui_names_are_accepted_headless(yade):
    """qt views and display functors exist and do nothing harmful without a screen."""
    yade.Gl1_Sphere.stripes = True
    v = yade.qt.View()
    v.center()
    r = yade.qt.Renderer()   # YADE's one renderer: what is set here stays for later tests, so it is set back
    r.shape = False
    r.shape = True
    assert r.shape is True
    assert yade.Gl1_Sphere.stripes is True


def test_detached_bodies_share_one_store_that_is_dropped_when_empty(yade):
    """utils.sphere() bodies are rows of one shared store until appended: independent of each other;
    once every detached body was appended or dropped, the store's tables are freed when they are long, and
    kept for the next bodies when they are short (a script appending its spheres one at a time reuses them)."""
    from granum.yade.bodies import _NURSERY

    a, b = yade.sphere((0, 0, 0), 0.5), yade.sphere((1, 0, 0), 0.25)
    a.state.vel = (1, 2, 3)
    assert tuple(b.state.vel) == (0, 0, 0) and b.shape.radius == 0.25 and a.id == b.id == -1
    assert _NURSERY.live >= 2
    yade.O.bodies.append([a, b])
    assert _NURSERY.live == 0
    assert tuple(yade.O.bodies[0].state.vel) == (1, 2, 3) and yade.O.bodies[1].shape.radius == 0.25
    tables = _NURSERY.bodies
    for k in range(600):   # one at a time: the rows are reused, the tables kept (two blocks of rows at most)
        c = yade.sphere((k, 0, 0), 0.1, color=(0, 0, 1))
        assert tuple(c.state.vel) == (0, 0, 0) and tuple(c.shape.color) == (0, 0, 1)   # a reused row is reset
        c.state.vel = (k, 0, 0)
        yade.O.bodies.append(c)
    assert _NURSERY.bodies is tables and _NURSERY.bodies.count <= 2 * _NURSERY.BLOCK
    assert [tuple(yade.O.bodies[i].state.vel) for i in (2, 601)] == [(0, 0, 0), (599, 0, 0)]
    dropped = [yade.sphere((k, 0, 0), 0.1) for k in range(_NURSERY.KEEP_ROWS + 1)]
    assert _NURSERY.bodies.count > _NURSERY.KEEP_ROWS
    del dropped
    assert _NURSERY.live == 0 and _NURSERY.bodies.count == 0   # long tables: freed
