"""ScGeom6D, the contact moments and the cohesive-frictional law (CohFrictMat, CohFrictPhys,
Ip2_CohFrictMat_CohFrictMat_CohFrictPhys, Law2_ScGeom6D_CohFrictPhys_CohesionMoment).

Step by step against real YADE 2023.02a: the reference script tests/reference/yade/cohfrict.py runs unmodified
under granum (its scenes, its records) and every record is compared with YADE's. Closed forms on one contact
(the rolling moment's elastic slope and bound, the strengths at which cohesion breaks), determinism across
thread counts, save -> load -> continue, moments reaching clumps and across periodic boundaries, refused input.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import granum_reference_run, reference, resumed_run_matches

N = np.array([0.6, 0.3, 0.74]) / np.linalg.norm([0.6, 0.3, 0.74])


@pytest.fixture(scope="module")
def granum_runs():
    """The reference script's records, produced by granum."""
    return granum_reference_run("cohfrict.py")


RUNS = sorted(k for k in reference("cohfrict") if k != "defaults")


def _numbers(v):
    return np.array(v, float)


@pytest.mark.parametrize("run", RUNS)
def test_two_body_contacts_step_by_step_as_yade(granum_runs, run):
    """Every recorded value of every step equals YADE's: to 1e-9 of the largest magnitude the quantity takes in
    the run, forces, torques and moments to 1e-9 of the largest force (in N, with radii near 1 m: a torque that
    is only rounding noise, as in a pure tension, differs by rounding), booleans, classes and the step at which
    each contact ends exactly."""
    ref, got = reference("cohfrict")[run], granum_runs[run]
    assert len(got) == len(ref)
    keys = {k for r in ref for k, v in r.items() if isinstance(v, (list, float)) and k != "iter"}
    scale = {k: max(np.abs(_numbers(r[k])).max() for r in ref if k in r) for k in keys}
    for k in ("t", "normalForce", "shearForce", "moment_twist", "moment_bending"):
        if k in scale:
            scale[k] = max(scale[k], scale.get("f", 0.0))
    for a, b in zip(ref, got, strict=True):
        assert set(a) == set(b), (run, a.get("iter"))
        for k, va in a.items():
            if k in keys:
                np.testing.assert_allclose(_numbers(b[k]), _numbers(va), rtol=0,
                                           atol=1e-9 * max(scale[k], 1e-300), err_msg=f"{run} {k} iter {a['iter']}")
            else:
                assert b[k] == va, (run, k, a.get("iter"))


def test_the_reference_runs_exercise_what_they_are_named_after():
    """So that a change of the script cannot hollow them out."""
    ref = reference("cohfrict")
    assert any(r.get("real") is False for r in ref["tension_fragile"])
    assert any(r.get("cohesionBroken") is True for r in ref["shear_fragile"])
    assert all(r.get("cohesionBroken") is False for r in ref["shear_plastic"])
    assert all(r["real"] for r in ref["roll_large"]) and max(abs(r["twist"]) for r in ref["roll_large"]) > 0.2
    assert max(np.linalg.norm(r["moment_bending"]) for r in ref["roll_plastic"]) > 1000
    assert ref["mixed"][0]["phys_class"] == "FrictPhys"
    assert [r["cohesionBroken"] for r in ref["now"] if "iter" in r][2:4] == [True, False]


VIEWS = ("CohFrictPhys", "ScGeom6D")


def test_geometry_and_physics_have_yades_attributes(yade):
    """i.geom and i.phys views of the contact columns (read and written in the step-by-step runs); ScGeom's
    shearInc and the creep quaternion twistCreep (creep is refused) are not stored."""
    for cls in VIEWS:
        missing = set(reference("cohfrict")["defaults"][cls]) - set(dir(getattr(yade, cls)()))
        assert missing <= {"shearInc", "twistCreep"}, (cls, missing)


@pytest.mark.parametrize("cls", sorted(set(reference("cohfrict")["defaults"]) - set(VIEWS)))
def test_yade_defaults(yade, cls):
    expected = reference("cohfrict")["defaults"][cls]
    got = getattr(yade, cls)().dict()
    for k, v in expected.items():
        if k in ("id", "label"):
            continue
        assert got[k] == pytest.approx(v) if isinstance(v, float) else got[k] == v, (cls, k)


def _pair(y, law=None, ip2=None, dist=0.88, vel=(0, 0, 0), ang_vel2=(0, 0, 0), **mat):
    """Two spheres (r 0.5 and 0.4, CohFrictMat) whose motion is imposed, cohesive from the first step."""
    kw = dict(young=1e7, poisson=0.3, density=1000, frictionAngle=0.5, normalCohesion=1e5, shearCohesion=2e5,
              momentRotationLaw=True)
    kw.update(mat)
    m = y.O.materials.append(y.CohFrictMat(**kw))
    y.O.bodies.append([y.sphere((0, 0, 0), 0.5, material=m), y.sphere(tuple(dist * N), 0.4, material=m)])
    for b in y.O.bodies:
        b.state.blockedDOFs = "xyzXYZ"
    y.O.bodies[1].state.vel = vel
    y.O.bodies[1].state.angVel = ang_vel2
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb(aabbEnlargeFactor=1.5)]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom6D(interactionDetectionFactor=1.5)],
                                     [ip2 or y.Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionOnNewContacts=True)],
                                     [law or y.Law2_ScGeom6D_CohFrictPhys_CohesionMoment()]),
                   y.NewtonIntegrator(damping=0)]
    y.O.dt = 1e-4


def test_rolling_moment_elastic_slope_and_its_bound(yade):
    """Sphere 2 rolls at omega about an axis normal to the contact: M_b = -k_r theta, theta = omega t,
    k_r = k_s r1 r2 alphaKr (total form); with etaRoll the incremental moment stops at etaRoll min(r) |F_n|."""
    axis = np.cross(N, [0, 0, 1])
    axis /= np.linalg.norm(axis)
    omega = 3.0
    _pair(yade, ang_vel2=tuple(omega * axis))
    yade.O.run(20, True)
    p, g = yade.O.interactions[0, 1].phys, yade.O.interactions[0, 1].geom
    r1, r2 = 0.5, 0.4
    kn = 1e7 * r1 * 1e7 * r2 * 2 / (1e7 * r1 + 1e7 * r2)
    assert p.kn == pytest.approx(kn, rel=1e-14) and p.ks == pytest.approx(0.3 * kn, rel=1e-14)
    assert p.kr == pytest.approx(p.ks * r1 * r2 * 2.0, rel=1e-14)
    theta = -omega * yade.O.dt * 19   # the rotation of body 1 relative to body 2, before the 20th step moves it
    np.testing.assert_allclose(list(g.bending), theta * axis, atol=1e-12)
    np.testing.assert_allclose(list(p.moment_bending), p.kr * theta * axis, rtol=0, atol=1e-9 * p.kr * abs(theta))
    assert abs(g.twist) < 1e-12 and np.abs(list(p.moment_twist)).max() < 1e-6
    # the moment acts on body 2 and its opposite on body 1, on top of the forces' arms
    f = np.array(p.normalForce) + np.array(p.shearForce)
    t2 = np.cross(-(r2 - g.penetrationDepth / 2) * N, f) + np.array(p.moment_bending)
    np.testing.assert_allclose(list(yade.O.forces.t(1)), t2, rtol=1e-9, atol=1e-9)

    yade.O.reset()
    _pair(yade, law=yade.Law2_ScGeom6D_CohFrictPhys_CohesionMoment(useIncrementalForm=True), ang_vel2=tuple(
        omega * 3 * axis), etaRoll=0.1)
    moments = []
    for _ in range(80):
        yade.O.step()
        moments.append(np.linalg.norm(list(yade.O.interactions[0, 1].phys.moment_bending)))
    p = yade.O.interactions[0, 1].phys
    bound = 0.1 * min(r1, r2) * np.linalg.norm(list(p.normalForce))
    assert p.maxRollPl == pytest.approx(0.1 * 0.4)
    assert moments[0] == pytest.approx(p.kr * omega * 3 * yade.O.dt, rel=1e-9)   # elastic slope, first step
    assert max(moments) == pytest.approx(bound, rel=1e-12) and moments[-1] == pytest.approx(bound, rel=1e-12)


def test_cohesion_breaks_at_the_normal_strength(yade):
    """Pulled apart at v: F_n = k_n (pen0 - v t) while -F_n <= a_n = min(C_n) min(r)^2; the contact ends at the
    first step where the tension would exceed it (fragile)."""
    v, pen0 = 1.0, 0.001
    _pair(yade, dist=0.9 - pen0, vel=tuple(v * N), normalCohesion=3e3)
    adhesion = 3e3 * 0.4 ** 2
    kn = 1e7 * 0.5 * 1e7 * 0.4 * 2 / (1e7 * 0.5 + 1e7 * 0.4)
    tensions = []
    for _ in range(100):
        yade.O.step()
        if not yade.O.interactions.countReal():
            break
        p = yade.O.interactions[0, 1].phys
        assert p.normalAdhesion == pytest.approx(adhesion)
        tensions.append(-np.dot(list(p.normalForce), N))
    # geometry at step k (before the step's motion): pen = pen0 - v dt (k - 1)
    k_break = next(k for k in range(1, 100) if kn * (v * yade.O.dt * (k - 1) - pen0) > adhesion)
    assert yade.O.iter == k_break and max(tensions) <= adhesion and max(tensions) > 0.5 * adhesion


def test_cohesion_breaks_at_the_shear_strength_then_friction_remains(yade):
    """Sheared: |F_s| grows by k_s du until it exceeds a_s + F_n tan(phi); then the cohesion is gone and
    |F_s| = F_n tan(phi) (fragile); with fragile=False it stays at a_s + F_n tan(phi), cohesive."""
    t = np.cross(N, [0, 0, 1])
    t /= np.linalg.norm(t)
    for fragile in (True, False):
        yade.O.reset()
        _pair(yade, dist=0.899, vel=tuple(t), shearCohesion=2e3, fragile=fragile)
        a_s = 2e3 * 0.4 ** 2
        for _ in range(40):
            yade.O.step()
            p = yade.O.interactions[0, 1].phys
            fn = np.linalg.norm(list(p.normalForce))
            fs = np.linalg.norm(list(p.shearForce))
            if p.cohesionBroken:
                assert fragile and fs == pytest.approx(fn * math.tan(0.5), rel=1e-12)
                break
            assert fs <= a_s + fn * math.tan(0.5) * (1 + 1e-12)
        else:
            assert not fragile and fs == pytest.approx(a_s + fn * math.tan(0.5), rel=1e-12)
        assert p.cohesionBroken == fragile


def test_no_moment_without_cohesion_unless_always(yade):
    """A frictional (non-cohesive) CohFrictPhys contact carries moments only with always_use_moment_law."""
    for always in (False, True):
        yade.O.reset()
        _pair(yade, ip2=yade.Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(),
              law=yade.Law2_ScGeom6D_CohFrictPhys_CohesionMoment(always_use_moment_law=always),
              ang_vel2=(0.0, 0.0, 5.0))
        yade.O.run(10, True)
        p = yade.O.interactions[0, 1].phys
        assert p.cohesionBroken and (np.linalg.norm(list(p.moment_bending)) > 0) == always


def test_set_cohesion_now_acts_once_on_existing_and_new_contacts(yade):
    ip2 = yade.Ip2_CohFrictMat_CohFrictMat_CohFrictPhys()
    _pair(yade, ip2=ip2, ang_vel2=(1.0, 2.0, 3.0))
    yade.O.run(3, True)
    assert yade.O.interactions[0, 1].phys.cohesionBroken and abs(yade.O.interactions[0, 1].geom.twist) > 0
    ip2.setCohesionNow = True
    before = list(yade.O.bodies[1].state.ori)
    yade.O.step()
    i = yade.O.interactions[0, 1]
    assert not i.phys.cohesionBroken and i.phys.normalAdhesion == pytest.approx(1e5 * 0.16)
    # the rotations start from the step cohesion began
    assert i.geom.twist == 0 and list(i.geom.bending) == [0, 0, 0]
    np.testing.assert_array_equal(list(i.geom.initialOrientation2), before)
    yade.O.step()
    assert ip2.setCohesionNow is False and abs(i.geom.twist) > 0
    # initCohesion on one contact, set from Python
    yade.O.reset()
    _pair(yade, ip2=yade.Ip2_CohFrictMat_CohFrictMat_CohFrictPhys())
    yade.O.run(2, True)
    yade.O.interactions[0, 1].phys.initCohesion = True
    yade.O.step()
    assert not yade.O.interactions[0, 1].phys.cohesionBroken and not yade.O.interactions[0, 1].phys.initCohesion


def _spinning_pair(y, periodic_shift=None):
    """A cohesive pair, sphere 2 spinning; with ``periodic_shift`` in a periodic cell, sphere 2 across the
    boundary (its centre shifted by one cell)."""
    m = y.O.materials.append(y.CohFrictMat(young=1e7, poisson=0.3, density=1000, normalCohesion=1e6,
                                           shearCohesion=1e6, momentRotationLaw=True))
    x2 = 0.88 * N + (periodic_shift if periodic_shift is not None else 0)
    y.O.bodies.append([y.sphere((0.5, 0.5, 0.5), 0.5, material=m), y.sphere(tuple(x2 + 0.5), 0.4, material=m)])
    for b in y.O.bodies:
        b.state.blockedDOFs = "xyzXYZ"
    y.O.bodies[1].state.angVel = (2.0, -1.0, 0.5)
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom6D()],
                                     [y.Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionNow=True)],
                                     [y.Law2_ScGeom6D_CohFrictPhys_CohesionMoment()]),
                   y.NewtonIntegrator(damping=0)]
    y.O.dt = 1e-4
    y.O.run(30, True)
    return np.array(y.O.interactions[0, 1].phys.moment_bending), [np.array(y.O.forces.t(k)) for k in (0, 1)]


def test_moments_across_a_periodic_boundary_equal_the_aperiodic_ones(yade):
    moment, torques = _spinning_pair(yade)
    yade.O.reset()
    yade.O.periodic = True
    yade.O.cell.setBox(3, 3, 3)
    moment_p, torques_p = _spinning_pair(yade, periodic_shift=np.array([3.0, 0, 0]))
    assert np.linalg.norm(moment) > 1
    np.testing.assert_allclose(moment_p, moment, rtol=1e-12)
    for a, b in zip(torques, torques_p, strict=True):
        np.testing.assert_allclose(b, a, rtol=1e-9, atol=1e-9 * np.linalg.norm(a))


def test_a_moment_on_a_clump_member_turns_the_clump(granum_runs):
    """The reference run 'clump' (compared step by step above): only the twisting moment acts on the member
    (no friction, the contact on the spin axis), and the clump turns with it about the normal."""
    last = granum_runs["clump"][-1]
    assert last["moment_twist"][2] > 1 and last["clump_angVel"][2] > 0
    assert abs(last["clump_angVel"][2]) > 100 * max(abs(last["clump_angVel"][0]), abs(last["clump_angVel"][1]))


def test_save_load_continue_equals_the_uninterrupted_run(yade, tmp_path):
    """A cohesive packing with moments (incremental form) falling on a cohesive facet: save -> load -> continue
    gives the bits of the uninterrupted run (the ScGeom6D, cohesion and moment columns travel with it)."""
    def scene():
        yade.O.reset()
        m = yade.O.materials.append(yade.CohFrictMat(young=1e6, poisson=0.3, density=2600, normalCohesion=1e4,
                                                     shearCohesion=1e4, momentRotationLaw=True, etaRoll=0.1))
        sp = yade.pack.SpherePack()
        sp.makeCloud((0, 0, 0), (1, 1, 0.6), rMean=0.07, rRelFuzz=0.3, seed=3)
        sp.toSimulation(material=m)
        yade.O.bodies.append(yade.utils.facet([(-1, -1, 0), (3, -1, 0), (-1, 3, 0)], material=m))
        yade.O.engines = [yade.ForceResetter(), yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb(),
                                                                             yade.Bo1_Facet_Aabb()]),
                          yade.InteractionLoop([yade.Ig2_Sphere_Sphere_ScGeom6D(), yade.Ig2_Facet_Sphere_ScGeom6D()],
                                               [yade.Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(
                                                   setCohesionOnNewContacts=True)],
                                               [yade.Law2_ScGeom6D_CohFrictPhys_CohesionMoment(
                                                   useIncrementalForm=True)]),
                          yade.NewtonIntegrator(gravity=(0, 0, -9.81), damping=0.1)]
        yade.O.dt = 1e-4
        yade.O.trackEnergy = True

    resumed_run_matches(yade, scene, 3000, tmp_path / "c.yade")
    moments = [np.linalg.norm(list(i.phys.moment_bending)) for i in yade.O.interactions
               if type(i.phys).__name__ == "CohFrictPhys"]
    assert len(moments) > 10 and max(moments) > 0


def test_threads_give_the_same_bits(tmp_path):
    """The cohesive lattice benchmark above the parallel threshold: -j1 and -j2 give the same positions and
    angular velocities, bit for bit (moments gathered per body in a fixed order)."""
    script = Path(__file__).parents[1] / "benchmarks" / "dense_lattice.py"
    states = {}
    for j in ("1", "2"):
        out = tmp_path / f"j{j}.txt"
        subprocess.run([sys.executable, "-m", "granum", "-j", j, str(script)], check=True, timeout=1800,
                       env={**os.environ, "BENCH_N": "12", "BENCH_STEPS": "200", "BENCH_LAW": "cohesive",
                            "BENCH_DUMP": str(out)},
                       capture_output=True)
        states[j] = out.read_text()
    assert states["1"] == states["2"]
    w = np.loadtxt(tmp_path / "j1.txt")[:, 3:]
    assert np.abs(w).max() > 0, "nothing turned"


@pytest.mark.parametrize("kw, bad", [(dict(normalCohesion=-5.0), "normalCohesion"),
                                     (dict(shearCohesion=-0.5), "shearCohesion"),
                                     (dict(alphaKr=-1.0), "alphaKr"), (dict(alphaKtw=-2.0), "alphaKtw"),
                                     (dict(etaRoll=float("nan")), "etaRoll"), (dict(young=-1.0), "young")])
def test_bad_material_values_are_refused_naming_them(yade, kw, bad):
    with pytest.raises(ValueError, match=bad):
        yade.CohFrictMat(**kw)


def test_every_value_of_yades_examples_is_accepted(yade):
    """The CohFrictMat, Ip2 and Law2 arguments of YADE 2023.02a's examples (test/triax-cohesive.py,
    simple-scene-energy-tracking.py, the chained-cylinder and grid examples) and the defaults (-1 strengths)."""
    yade.CohFrictMat(young=15e6, poisson=0.4, density=2600, frictionAngle=math.radians(30), normalCohesion=1e6,
                     shearCohesion=1e6, momentRotationLaw=True, etaRoll=0.1, label="spheres")
    yade.CohFrictMat(young=1.0e5, poisson=0.03, density=2.60e2, frictionAngle=0.5, isCohesive=False,
                     alphaKr=0.5, alphaKtw=0.0, normalCohesion=-1, shearCohesion=-1, fragile=False)
    yade.Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionNow=True, setCohesionOnNewContacts=True, label="ipf")
    yade.Law2_ScGeom6D_CohFrictPhys_CohesionMoment(useIncrementalForm=True, always_use_moment_law=False,
                                                   label="cohesiveLaw")


@pytest.mark.parametrize("functor, kw", [("Law2_ScGeom6D_CohFrictPhys_CohesionMoment", dict(twist_creep=True)),
                                         ("Ig2_Sphere_Sphere_ScGeom6D", dict(creep=True))])
def test_unimplemented_values_are_refused_naming_them(yade, functor, kw):
    funcs = {"geom": [yade.Ig2_Sphere_Sphere_ScGeom6D()], "phys": [yade.Ip2_CohFrictMat_CohFrictMat_CohFrictPhys()],
             "law": [yade.Law2_ScGeom6D_CohFrictPhys_CohesionMoment()]}
    f = getattr(yade, functor)(**kw)
    funcs[{"Ig2": "geom", "Ip2": "phys", "Law": "law"}[functor[:3]]] = [f]
    m = yade.O.materials.append(yade.CohFrictMat())
    yade.O.bodies.append([yade.sphere((0, 0, 0), 0.1, material=m), yade.sphere((0.19, 0, 0), 0.1, material=m)])
    yade.O.engines = [yade.ForceResetter(), yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb()]),
                      yade.InteractionLoop(funcs["geom"], funcs["phys"], funcs["law"]), yade.NewtonIntegrator()]
    with pytest.raises(NotImplementedError, match=next(iter(kw))):
        yade.O.step()


def test_a_cohesive_contact_without_its_law_stops_naming_the_types(yade):
    m = yade.O.materials.append(yade.CohFrictMat())
    yade.O.bodies.append([yade.sphere((0, 0, 0), 0.1, material=m), yade.sphere((0.19, 0, 0), 0.1, material=m)])
    yade.O.engines = [yade.ForceResetter(), yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb()]),
                      yade.InteractionLoop([yade.Ig2_Sphere_Sphere_ScGeom6D()],
                                           [yade.Ip2_CohFrictMat_CohFrictMat_CohFrictPhys()],
                                           [yade.Law2_L3Geom_FrictPhys_ElPerfPl()]),
                      yade.NewtonIntegrator()]
    with pytest.raises(Exception, match="ScGeom6D.*CohFrictPhys|CohFrictPhys.*ScGeom6D|Law2"):
        yade.O.step()


def test_functors_whose_histories_share_columns_on_one_contact_are_refused(yade):
    """The cohesion's columns are shared with other laws' histories and ScGeom6D's with L3Geom's (the pools
    stay narrow); a plan in which one contact would use two sharing groups, here the cohesive Ip2 on an L3Geom,
    is refused naming them, while ScGeom6D under another law (visco-elastic) is fine."""
    m = yade.O.materials.append(yade.CohFrictMat())
    yade.O.bodies.append([yade.sphere((0, 0, 0), 0.1, material=m), yade.sphere((0.19, 0, 0), 0.1, material=m)])
    yade.O.engines = [yade.ForceResetter(), yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb()]),
                      yade.InteractionLoop([yade.Ig2_Sphere_Sphere_L3Geom()],
                                           [yade.Ip2_CohFrictMat_CohFrictMat_CohFrictPhys()],
                                           [yade.Law2_L3Geom_FrictPhys_ElPerfPl()]),
                      yade.NewtonIntegrator()]
    with pytest.raises(ValueError, match="histories .*'l3geom'.*share contact columns"):
        yade.O.step()
    yade.O.reset()
    m = yade.O.materials.append(yade.ViscElMat(kn=1e5, ks=1e5, cn=1.0, cs=1.0, density=1000))
    yade.O.bodies.append([yade.sphere((0, 0, 0), 0.1, material=m), yade.sphere((0.19, 0, 0), 0.1, material=m)])
    yade.O.engines = [yade.ForceResetter(), yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb()]),
                      yade.InteractionLoop([yade.Ig2_Sphere_Sphere_ScGeom6D()],
                                           [yade.Ip2_ViscElMat_ViscElMat_ViscElPhys()],
                                           [yade.Law2_ScGeom_ViscElPhys_Basic()]),
                      yade.NewtonIntegrator()]
    yade.O.run(5, True)
    assert yade.O.interactions[0, 1].phys.cn == 1.0 / 2 and yade.O.forces.f(1)[0] > 0
