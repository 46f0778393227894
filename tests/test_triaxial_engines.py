"""TriaxialCompressionEngine, ThreeDTriaxialEngine, UniaxialStrainer, TriaxialTest and the voxel/force utilities:
closed forms of the imposed strain rates and wall motions, the state machine's transitions as YADE makes them,
real YADE's numbers (tests/reference/yade/triaxial_engines.json), determinism, and bad input."""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import reference

REF = reference("triaxial_engines")
RATE_DAMPING = 0.9997   # YADE's factor of the loading's strain rate per step (measured, see the kernel)


def _cloud(y, n=150, seed=1, friction=30):
    """n spheres of a loose cloud in a 10 m box between the six frictionless boxes of aabbWalls (thickness 0)."""
    sp = y.pack.SpherePack()
    sp.makeCloud((0, 0, 0), (10, 10, 10), rRelFuzz=0.2, num=n, seed=seed)
    y.O.materials.append(y.FrictMat(young=15e6, poisson=0.4, frictionAngle=math.radians(friction), density=2600,
                                    label="spheres"))
    y.O.materials.append(y.FrictMat(young=15e6, poisson=0.4, frictionAngle=0, density=0, label="walls"))
    y.O.bodies.append(y.aabbWalls([(0, 0, 0), (10, 10, 10)], thickness=0, material="walls"))
    y.O.bodies.append([y.sphere(c, r, material="spheres") for c, r in sp])


def _engines(y, engine):
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb(), y.Bo1_Box_Aabb()]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom(), y.Ig2_Box_Sphere_ScGeom()],
                                     [y.Ip2_FrictMat_FrictMat_FrictPhys()], [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
                   y.GlobalStiffnessTimeStepper(timeStepUpdateInterval=100, timestepSafetyCoefficient=0.8), engine,
                   y.NewtonIntegrator(damping=0.4)]


def _compression(y, **kw):
    args = dict(internalCompaction=False, sigmaIsoCompaction=-50e3, sigmaLateralConfinement=-20e3, max_vel=10,
                strainRate=0.1, StabilityCriterion=0.05, frictionAngleDegree=20)
    args.update(kw)
    triax = y.TriaxialCompressionEngine(**args)
    _engines(y, triax)
    return triax


def _run_until_state(y, triax, state, limit=6000):
    """Run in chunks of testEquilibriumInterval that end right after a check step; the states seen."""
    seen = []
    if y.O.iter == 0:
        y.O.run(1, True)
    while triax.currentState != state and y.O.iter < limit:
        seen.append((y.O.iter, triax.currentState))
        y.O.run(triax.testEquilibriumInterval, True)
    assert triax.currentState == state, f"state {state} not reached in {limit} steps (seen {seen[-3:]})"
    return seen


@pytest.mark.fallback
def test_state_machine_compaction_unloading_loading(yade, tmp_path, monkeypatch):
    """1 -> 2 -> 3 as YADE: each stage ends at a check step with the unbalanced force below StabilityCriterion
    and the mean stress at σ_iso; the end of the compaction sets σ_iso to the lateral stress, the friction of the
    spheres' material and of their contacts (not the walls'), and writes Key_Compacted_<iter>_2.xml/.spheres;
    the loading frees the top and bottom walls and writes Key_Unloaded_<iter>_3."""
    monkeypatch.chdir(tmp_path)
    _cloud(yade)
    triax = _compression(yade, Key="T")
    seen = _run_until_state(yade, triax, 2)
    assert {s for _, s in seen} == {1}
    it = yade.O.iter - 1                  # the check step of the transition
    assert it % triax.testEquilibriumInterval == 0
    assert triax.UnbalancedForce <= triax.StabilityCriterion
    assert triax.sigma_iso == triax.previousSigmaIso == -20e3
    assert (triax.goal1, triax.goal2, triax.goal3) == (-20e3, -20e3, -20e3)
    assert os.path.exists(f"T_Compacted_{it}_2.xml")
    spheres = np.loadtxt(f"T_Compacted_{it}_2.spheres")
    assert spheres.shape == (150, 4)
    assert yade.O.materials[0].frictionAngle == pytest.approx(math.radians(20), rel=1e-15)
    assert yade.O.materials[1].frictionAngle == 0
    tans = {(i.id1 < 6 or i.id2 < 6): i.phys.tangensOfFrictionAngle for i in yade.O.interactions}
    assert tans[False] == pytest.approx(math.tan(math.radians(20)), rel=1e-15) and tans[True] == 0
    _run_until_state(yade, triax, 3)
    it = yade.O.iter - 1
    assert triax.UnbalancedForce <= triax.StabilityCriterion
    assert abs(triax.meanStress + 20e3) < 0.01 * 20e3
    assert not triax.wall_top_activated and not triax.wall_bottom_activated and triax.wall_left_activated
    assert os.path.exists(f"T_Unloaded_{it}_3.xml") and yade.O.filename == f"./T_Unloaded_{it}_3.xml"
    # the strain rate after the loading's first step and its wall motion (closed forms)
    assert triax.currentStrainRate == pytest.approx(0.1 * (1 - RATE_DAMPING), rel=1e-12)
    top, bottom = yade.O.bodies[3], yade.O.bodies[2]
    for _ in range(3):
        y0, h, r0 = top.state.pos[1], top.state.pos[1] - bottom.state.pos[1], triax.currentStrainRate
        yade.O.run(1, True)
        dt = yade.O.dt                    # the step's (the time stepper runs before the engine)
        r = r0 + (1 - RATE_DAMPING) * (0.1 - r0)
        assert triax.currentStrainRate == pytest.approx(r, rel=1e-12)
        assert top.state.pos[1] == pytest.approx(y0 - 0.5 * r * h * dt, rel=1e-14)
        assert tuple(top.state.vel) == (0, 0, 0)
    n = yade.O.iter - it
    assert triax.currentStrainRate == pytest.approx(0.1 * (1 - RATE_DAMPING ** n), rel=1e-10)
    for w in (0, 1, 4, 5):
        assert triax.stress(w)[w // 2] == pytest.approx(-20e3, rel=0.02)


def test_epsilon_max_stops_the_loading_walls(yade):
    """Once |ε_y| (updated every computeStressStrainInterval) reaches epsilonMax, the loading walls and the
    strain rate stay as they are (YADE 2023.02a: the state stays 3 and the run goes on)."""
    _cloud(yade)
    triax = _compression(yade, sigmaLateralConfinement=-50e3, epsilonMax=0.002, strainRate=0.3, noFiles=True)
    _run_until_state(yade, triax, 3)
    while abs(triax.strain[1]) < triax.epsilonMax:
        yade.O.run(10, True)
    yade.O.run(10, True)
    y_top, rate = yade.O.bodies[3].state.pos[1], triax.currentStrainRate
    yade.O.run(50, True)
    assert yade.O.bodies[3].state.pos[1] == y_top and triax.currentStrainRate == rate
    assert triax.currentState == 3


def test_no_unloading_when_auto_unload_is_off(yade):
    """autoUnload=False: the compaction goes straight to the loading, at sigmaLateralConfinement."""
    _cloud(yade)
    triax = _compression(yade, autoUnload=False, noFiles=True)
    seen = _run_until_state(yade, triax, 3)
    assert {s for _, s in seen} == {1}
    assert triax.sigma_iso == -20e3 and triax.goal2 == -20e3


def test_state_set_from_python_is_entered(yade):
    """currentState=3 set between runs starts the loading at the next step (previousState tells the change)."""
    _cloud(yade)
    triax = _compression(yade, noFiles=True, sigmaLateralConfinement=-50e3)
    yade.O.run(50, True)
    assert triax.currentState == triax.previousState == 1
    triax.currentState = 3
    yade.O.run(1, True)
    assert triax.previousState == 3 and not triax.wall_top_activated
    assert triax.currentStrainRate == pytest.approx(0.1 * (1 - RATE_DAMPING), rel=1e-12)


def test_save_load_continue_equals_the_uninterrupted_run(yade, tmp_path):
    """Through the compaction's end (the state machine's arrays and the synced attributes travel with the
    checkpoint): save -> load -> continue gives the bits of the uninterrupted run."""
    def scene():
        yade.O.reset()
        _cloud(yade, n=100)
        return _compression(yade, noFiles=True, StabilityCriterion=0.1)

    def state():
        return np.array([list(b.state.pos) + list(b.state.vel) for b in yade.O.bodies])

    triax = scene()
    yade.O.run(900, True)
    whole, whole_state = state(), (triax.currentState, triax.currentStrainRate, triax.maxStress)
    assert triax.currentState > 1, "no transition in the run: the test would not cover the state machine"
    scene()
    yade.O.run(450, True)
    path = str(tmp_path / "t.yade")
    yade.O.save(path)
    yade.O.load(path)
    yade.O.run(450, True)
    np.testing.assert_array_equal(state(), whole)
    t = yade.O.engines[4]
    assert (t.currentState, t.currentStrainRate, t.maxStress) == whole_state


def test_threads_give_the_same_bits(tmp_path):
    """benchmarks/triaxial_compression.py (1000 spheres, contacts above the parallel block) at -j1 and -j2: the
    same positions and velocities, bit for bit."""
    script = Path(__file__).parents[1] / "benchmarks" / "triaxial_compression.py"
    dumps = {}
    for j in ("1", "2"):
        out = tmp_path / f"j{j}.txt"
        subprocess.run([sys.executable, "-m", "granum", "-j", j, str(script)], check=True, timeout=1800, cwd=tmp_path,
                       env={**os.environ, "BENCH_N": "1000", "BENCH_STEPS": "400", "BENCH_DUMP": str(out)},
                       capture_output=True)
        dumps[j] = out.read_text()
    assert dumps["1"] == dumps["2"]
    assert np.abs(np.loadtxt(tmp_path / "j1.txt")[:, 3:]).max() > 0


def test_three_d_engine_strain_axis(yade):
    """stressControl_1=False: the x walls leave the servo and move by ½ r width dt each, r → strainRate1 with the
    engine's strainDamping (closed form); y and z are servoed to their goals."""
    _cloud(yade)
    t = yade.ThreeDTriaxialEngine(internalCompaction=False, max_vel=10, stressControl_1=False, strainRate1=0.1,
                                  goal1=-7, goal2=-50e3, goal3=-50e3)
    _engines(yade, t)
    left = yade.O.bodies[0]
    yade.O.run(1, True)
    assert t.currentStrainRate1 == pytest.approx(0.1 * (1 - 0.9997), rel=1e-12)
    assert not t.wall_left_activated and not t.wall_right_activated and t.wall_top_activated
    for _ in range(3):
        x0, w, r0 = left.state.pos[0], yade.O.bodies[1].state.pos[0] - left.state.pos[0], t.currentStrainRate1
        yade.O.run(1, True)
        dt = yade.O.dt
        r = r0 + (1 - t.strainDamping) * (0.1 - r0)
        assert t.currentStrainRate1 == pytest.approx(r, rel=1e-12)
        assert left.state.pos[0] == pytest.approx(x0 + 0.5 * r * w * dt, rel=1e-14)
    assert t.currentStrainRate2 == t.currentStrainRate3 == 0
    yade.O.run(1500, True)
    assert t.stress(2)[1] == pytest.approx(-50e3, rel=0.05)


def _strainer(y, forces=False, **kw):
    y.O.bodies.append([y.sphere((0, 0, 0), .5), y.sphere((3, 0, 0.2), .5), y.sphere((0, 0, 10), .5),
                       y.sphere((3, 0, 10.4), .5)])
    y.O.dt = 1e-3
    kw.setdefault("crossSectionArea", 2)
    s = y.UniaxialStrainer(negIds=[1, 0], posIds=[3, 2], **kw)
    engines = [y.ForceResetter(), s, y.NewtonIntegrator(damping=0)]
    if forces:
        command = ("O.forces.addF(0,(0,0,1.0)); O.forces.addF(1,(0,0,3.0)); O.forces.addF(2,(0,0,-10.0)); "
                   "O.forces.addF(3,(0,0,-30.0))")
        engines.insert(1, y.PyRunner(iterPeriod=1, command=command))
    y.O.engines = engines
    return s


@pytest.mark.parametrize("case, kw", [("rate", dict(strainRate=0.01)), ("abs", dict(absSpeed=0.1)),
                                      ("asym", dict(strainRate=0.01, asymmetry=1)),
                                      ("asymneg", dict(strainRate=0.01, asymmetry=-1)),
                                      ("block", dict(strainRate=0.01, blockDisplacements=True, blockRotations=True)),
                                      ("stop", dict(strainRate=1, stopStrain=0.0035)),
                                      ("stress", dict(strainRate=1, forces=True))])
def test_uniaxial_strainer_as_yade(yade, case, kw):
    """Per step, YADE's velocities, positions, strain, avgStress, active flag and blocked DOFs (the closed form:
    strain n·ε̇·dt, speeds ±ε̇L0/2, the last step landing exactly on stopStrain, avgStress (ΣF_neg − ΣF_pos)/2A)."""
    ref = REF["strainer"][case]
    s = _strainer(yade, **kw)
    for row in ref["rows"]:
        yade.O.run(1, True)
        b = yade.O.bodies
        assert yade.O.iter == row["iter"]
        np.testing.assert_allclose([x.state.vel[2] for x in b], row["vz"], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose([x.state.pos[2] for x in b], row["z"], rtol=1e-14, atol=1e-15)
        assert s.strain == pytest.approx(row["strain"], rel=1e-12, abs=1e-15)
        assert s.avgStress == pytest.approx(row["avgStress"], rel=1e-14)
        assert s.active == row["active"]
        assert [x.state.blockedDOFs for x in b] == row["blocked"]
    for name in ("originalLength", "absSpeed", "strainRate", "currentStrainRate"):
        assert getattr(s, name) == pytest.approx(ref[name], rel=1e-15), name


def test_triaxial_test_scene_as_yade(yade):
    """TriaxialTest(...).load(): the six boxes (positions, extents, massless), the radii (makeCloud at
    porosity .8, or radiusMean with the box scaled), O.dt = r_min √(ρ/E), the engine list and the spheres' mass
    as YADE's; the spheres' material as YADE's but for its density (YADE's material keeps 1000 while the masses
    use ``density``; granum's material holds ``density``)."""
    cases = {"default200": dict(numberOfGrains=200),
             "radiusMean": dict(numberOfGrains=100, radiusMean=0.1, upperCorner=(1, 2, 3), noFiles=True),
             "thin": dict(numberOfGrains=50, seed=3, radiusStdDev=0, thickness=0, wallOversizeFactor=1.5,
                          noFiles=True)}
    for name, kw in cases.items():
        ref = REF["triaxial_test"][name]
        yade.O.reset()
        yade.TriaxialTest(**kw).load()
        b = yade.O.bodies
        assert len(b) == ref["n"]
        for i, (pos, ext) in enumerate(ref["walls"]):
            np.testing.assert_allclose(list(b[i].state.pos), pos, rtol=1e-14, atol=1e-15)
            np.testing.assert_allclose(list(b[i].shape.extents), ext, rtol=1e-14, atol=1e-15)
            assert b[i].state.mass == ref["wall_mass"][i] and b[i].state.blockedDOFs == "xyzXYZ"
        radii = sorted(x.shape.radius for x in b if isinstance(x.shape, yade.Sphere))
        np.testing.assert_allclose(radii, ref["radii"], rtol=1e-13)
        assert yade.O.dt == pytest.approx(ref["dt"], rel=1e-13)
        assert [type(e).__name__ for e in yade.O.engines] == ref["engines"]
        m = b[6].material
        for k in ("frictionAngle", "young", "poisson"):
            assert getattr(m, k) == pytest.approx(ref["sphere_material"][k], rel=1e-15)
            assert getattr(b[0].material, k) == pytest.approx(ref["wall_material"][k], rel=1e-15)
        assert b[6].state.mass == pytest.approx(4 / 3 * math.pi * b[6].shape.radius ** 3 * 2600, rel=1e-14)


@pytest.mark.parametrize("cls", ["TriaxialCompressionEngine", "ThreeDTriaxialEngine", "UniaxialStrainer",
                                 "TriaxialTest"])
def test_defaults_as_yade(yade, cls):
    """Every attribute YADE's fresh instance has, with YADE's default (the outputs YADE leaves at their initial
    values too)."""
    ref = REF["defaults"][cls]
    obj = getattr(yade, cls)()
    for name, value in ref.items():
        if name in ("ompThreads", "dead", "label"):
            continue
        if cls == "ThreeDTriaxialEngine" and name == "strainDamping":
            # YADE has two members of this name: dict() shows the controller's (0.99), the attribute reads the
            # engine's (0.9997, the one its strain rates use: measured)
            assert obj.strainDamping == 0.9997
            continue
        got = getattr(obj, name)
        if isinstance(value, float) and math.isnan(value):
            assert math.isnan(got), name
        elif isinstance(value, list):
            assert list(got) == pytest.approx(value), name
        else:
            assert got == value, name


def test_voxel_porosity_and_total_force_as_yade(yade):
    """voxelPorosity: the count of grid points strictly inside a sphere, as YADE's (exactly where the points
    are not at the sphere's surface to rounding: resolutions 51, 64, the offset and anisotropic boxes; 4e-4 at
    50 and 100, where points lie on it); totalForceInVolume of three overlapping spheres."""
    yade.O.bodies.append(yade.sphere((0.5, 0.5, 0.5), 0.3))
    ref = REF["voxel"]
    for res in (51, 64):
        assert yade.utils.voxelPorosity(res, (0, 0, 0), (1, 1, 1)) == pytest.approx(ref[str(res)], rel=1e-15)
    for res in (50, 100):
        assert yade.utils.voxelPorosity(res, (0, 0, 0), (1, 1, 1)) == pytest.approx(ref[str(res)], abs=4e-4)
    assert yade.utils.voxelPorosity(50, (0.5, 0.5, 0.5), (1.5, 1.5, 1.5)) == pytest.approx(ref["offset"], rel=1e-15)
    assert yade.utils.voxelPorosity(50, (0, 0, 0), (1, 2, 0.8)) == pytest.approx(ref["aniso"], rel=1e-15)
    with pytest.raises(ValueError, match="below 50"):
        yade.utils.voxelPorosity(20, (0, 0, 0), (1, 1, 1))
    with pytest.raises(ValueError, match="start==end"):
        yade.utils.voxelPorosity(50)
    yade.O.reset()
    yade.O.bodies.append([yade.sphere((0, 0, 0), 1), yade.sphere((1.8, 0.1, 0), 1), yade.sphere((0.9, 1.7, 0.2), 1)])
    yade.O.engines = [yade.ForceResetter(), yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb()]),
                      yade.InteractionLoop([yade.Ig2_Sphere_Sphere_ScGeom()], [yade.Ip2_FrictMat_FrictMat_FrictPhys()],
                                           [yade.Law2_ScGeom_FrictPhys_CundallStrack()]), yade.NewtonIntegrator()]
    yade.O.dt = 1e-6
    yade.O.run(1, True)
    f, k = yade.utils.totalForceInVolume()
    np.testing.assert_allclose(list(f), REF["total_force"][0], rtol=1e-12)
    assert k == pytest.approx(REF["total_force"][1], rel=1e-15)


def test_bad_input_is_refused_naming_it(yade):
    """Unknown states, unimplemented options and missing parameters: errors naming them, the scene untouched."""
    t = yade.TriaxialCompressionEngine()
    with pytest.raises(ValueError, match="currentState"):
        t.currentState = 7
    with pytest.raises(TypeError, match="currentState"):
        t.currentState = 1.5
    _cloud(yade, n=20)
    _engines(yade, yade.TriaxialCompressionEngine(fixedPoroCompaction=1, sigmaIsoCompaction=-1e3))
    with pytest.raises(NotImplementedError, match="fixedPoroCompaction"):
        yade.O.run(1, True)
    assert yade.O.iter == 0
    _engines(yade, yade.TriaxialCompressionEngine(internalCompaction=True, sigmaIsoCompaction=5e3))
    with pytest.raises(ValueError, match="sigmaIsoCompaction"):
        yade.O.run(1, True)
    yade.O.reset()
    s = _strainer(yade, strainRate=1, crossSectionArea=float("nan"))
    with pytest.raises(RuntimeError, match="crossSectionArea must be specified"):
        yade.O.run(1, True)
    assert REF["strainer_no_area"]["message"].endswith("crossSectionArea must be specified.")
    s.crossSectionArea, s.limitStrain = 1, 0.01
    with pytest.raises(NotImplementedError, match="limitStrain"):
        yade.O.run(1, True)
    s.limitStrain, s.strainRate = 0, float("nan")
    with pytest.raises(ValueError, match="strainRate or absSpeed"):
        yade.O.run(1, True)
    assert yade.O.iter == 0 and yade.O.bodies[0].state.blockedDOFs == ""
    with pytest.raises(ValueError, match="axis"):
        yade.UniaxialStrainer(axis=3)
    with pytest.raises(ValueError, match="asymmetry"):
        yade.UniaxialStrainer(asymmetry=2)
    for kw, name in ((dict(facetWalls=True), "facetWalls"), (dict(wallWalls=True), "wallWalls"),
                     (dict(importFilename="a.spheres"), "importFilename"), (dict(fixedBoxDims="x"), "fixedBoxDims")):
        with pytest.raises(NotImplementedError, match=name):
            yade.TriaxialTest(**kw)
    with pytest.raises(ValueError, match="upperCorner"):
        yade.TriaxialTest(lowerCorner=(1, 1, 1), upperCorner=(1, 2, 3)).load()
