"""ViscElMat rolling resistance (mR, mRtype) and the per-material-pair values of the Ip2 functors (MatchMaker):
closed forms, real YADE's numbers (tests/reference/yade/viscel_pairs.py), refusals naming the bad value,
determinism across thread counts and save -> load -> continue."""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import reference

REF = reference("viscel_pairs")


def _rolling(y, mR1, mR2, mRtype1, mRtype2, w1, w2, ks=0.0, cn=0.0, fixed1=True, v2=(0, 0, 0)):
    """The reference script's rolling scene: a sphere (r .02) on a sphere (r .01), one step; returns
    (phys, torque on 1, torque on 2)."""
    O = y.O
    O.reset()
    m1 = O.materials.append(y.ViscElMat(kn=1e5, cn=cn, ks=ks, cs=0, mR=mR1, mRtype=mRtype1, frictionAngle=0.5,
                                        density=1000))
    m2 = O.materials.append(y.ViscElMat(kn=1e5, cn=cn, ks=ks, cs=0, mR=mR2, mRtype=mRtype2, frictionAngle=0.5,
                                        density=1000))
    a = O.bodies.append(y.sphere((0, 0, 0), 0.01, material=m1, fixed=fixed1))
    b = O.bodies.append(y.sphere((0, 0, 0.03 - 1e-4), 0.02, material=m2))
    O.bodies[a].state.angVel = w1
    O.bodies[b].state.angVel = w2
    O.bodies[b].state.vel = v2
    O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]),
                 y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom()], [y.Ip2_ViscElMat_ViscElMat_ViscElPhys()],
                                   [y.Law2_ScGeom_ViscElPhys_Basic()]),
                 y.NewtonIntegrator(damping=0, gravity=(0, 0, 0))]
    O.dt = 1e-9
    O.step()
    i = O.interactions[a, b]
    return i, np.array(O.forces.t(a)), np.array(O.forces.t(b))


@pytest.mark.parametrize("case", sorted(REF["rolling"]))
def test_rolling_moment_equals_yades(yade, case):
    ref = REF["rolling"][case]
    i, t1, t2 = _rolling(yade, **ref["args"])
    assert i.phys.mR == pytest.approx(ref["mR"], rel=1e-14)
    assert i.phys.mRtype == ref["mRtype"]
    for got, want in ((t1, ref["t1"]), (t2, ref["t2"]), (np.array(i.phys.normalForce), ref["normalForce"])):
        np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-15)


@pytest.mark.parametrize("mRtype", [1, 2])
def test_rolling_moment_closed_form(yade, mRtype):
    """M2 = -mR |Fn| s (w2 - w1) on body 2 (the opposite on body 1), s = 1 (type 1) or |c1 x w1 - c2 x w2|
    (type 2), with Fn = kn delta of one step (the two spheres do not move in 1e-9 s): no shear stiffness, so the
    torques are the rolling moment alone."""
    w1, w2 = np.array([2.0, 0.0, 0.5]), np.array([0.0, 3.0, -1.0])
    _, t1, t2 = _rolling(yade, 0.05, 0.05, mRtype, mRtype, tuple(w1), tuple(w2))
    fn = 1e5 / 2 * 1e-4   # two kn = 1e5 springs in series, overlap 1e-4
    point = np.array([0, 0, 0.01 - 0.5e-4])
    c1, c2 = point, point - np.array([0, 0, 0.03 - 1e-4])
    s = 1.0 if mRtype == 1 else np.linalg.norm(np.cross(c1, w1) - np.cross(c2, w2))
    expected = -0.05 * fn * s * (w2 - w1)
    np.testing.assert_allclose(t2, expected, rtol=1e-12)
    np.testing.assert_allclose(t1, -expected, rtol=1e-12)


def _pair(y, mats, ip2, law, geom=None, fixed=False):
    O = y.O
    O.reset()
    ids = [O.materials.append(m) for m in mats]
    a = O.bodies.append(y.sphere((0, 0, 0), 0.01, material=ids[0], fixed=fixed))
    b = O.bodies.append(y.sphere((0, 0, 0.03 - 1e-5), 0.02, material=ids[-1]))
    O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]),
                 y.InteractionLoop([geom or y.Ig2_Sphere_Sphere_ScGeom()], [ip2], [law]),
                 y.NewtonIntegrator(damping=0, gravity=(0, 0, 0))]
    O.dt = 1e-9
    O.step()
    return O.interactions[a, b].phys


def _cases(y):
    """The reference script's pair cases, built with granum's classes (same names and arguments)."""
    MM = y.MatchMaker

    def V(**k):
        return y.ViscElMat(**{"density": 2000, "frictionAngle": 0.4, **k})

    def F(**k):
        return y.FrictMat(**{"young": 1e7, "poisson": 0.3, "density": 2000, "frictionAngle": 0.4, **k})

    def C(**k):
        return y.CohFrictMat(**{"young": 1e7, "poisson": 0.3, "density": 2000, "isCohesive": True, **k})

    va, vb = dict(tc=1e-3, en=0.5, et=0.6), dict(tc=2e-3, en=0.8, et=0.3, frictionAngle=0.2)
    kk = dict(kn=1e5, cn=1.0, ks=2e4, cs=0.5)
    fb, fm = dict(frictionAngle=0.2, young=3e7, poisson=0.5), dict(frictionAngle=0.2, young=3e7, poisson=0.25)
    ca = dict(normalCohesion=1e5, shearCohesion=2e5, frictionAngle=0.4)
    cb = dict(normalCohesion=3e5, shearCohesion=1e5, frictionAngle=0.2)
    VI, VL = y.Ip2_ViscElMat_ViscElMat_ViscElPhys, y.Law2_ScGeom_ViscElPhys_Basic
    FI, CS = y.Ip2_FrictMat_FrictMat_FrictPhys, y.Law2_ScGeom_FrictPhys_CundallStrack
    MI, ML = y.Ip2_FrictMat_FrictMat_MindlinPhys, y.Law2_ScGeom_MindlinPhys_Mindlin

    def CI(**k):
        return y.Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(setCohesionOnNewContacts=True, **k)

    CL, G6 = y.Law2_ScGeom6D_CohFrictPhys_CohesionMoment, y.Ig2_Sphere_Sphere_ScGeom6D()
    cases = {
        "viscel_same": ([V(**va)], VI(), VL()),
        "viscel_mixed": ([V(**va), V(**vb)], VI(), VL()),
        "viscel_mixed_fixed": ([V(**va), V(**vb)], VI(), VL(), None, True),
        "viscel_en_zero_mixed": ([V(tc=1e-3, en=0.0, et=0.0), V(tc=1e-3, en=0.5, et=0.5)], VI(), VL()),
        "viscel_en_zero": ([V(tc=1e-3, en=0.0, et=0.0)], VI(), VL()),
        "viscel_mm_en_match": ([V(**va), V(**vb)], VI(en=MM(matches=((0, 1, 0.3),))), VL()),
        "viscel_mm_et_val": ([V(**va), V(**vb)], VI(et=MM(algo="val", val=0.9)), VL()),
        "viscel_mm_tc_match": ([V(**va), V(**vb)], VI(tc=MM(matches=((1, 0, 3e-3),))), VL()),
        "viscel_mm_numbers": ([V(**va), V(**vb)], VI(tc=1e-3, en=0.3, et=0.4), VL()),
        "viscel_mm_frict_val": ([V(**va), V(**vb)], VI(frictAngle=MM(algo="val", val=0.1)), VL()),
        "viscel_mm_frict_match": ([V(**va), V(**vb)], VI(frictAngle=MM(matches=((1, 0, 0.1),))), VL()),
        "viscel_kn_mm_en_only": ([V(**kk), V(**kk)], VI(en=0.5), VL()),
        "viscel_kn_mm_all": ([V(**kk), V(**kk)], VI(tc=1e-3, en=0.5, et=0.5), VL()),
        "frict_base": ([F(), F(**fb)], FI(), CS()),
        "frict_kn_avg": ([F(), F(**fb)], FI(kn=MM(algo="avg")), CS()),
        "frict_kn_match": ([F(), F(**fb)], FI(kn=MM(matches=((0, 1, 5e4),))), CS()),
        "frict_kn_number": ([F(), F(**fb)], FI(kn=5e4), CS()),
        "frict_ks_number": ([F(), F(**fb)], FI(ks=5e4), CS()),
        "frict_ks_avg": ([F(), F(**fb)], FI(ks=MM(algo="avg")), CS()),
        "frict_angle_number": ([F(), F(**fb)], FI(frictAngle=0.1), CS()),
        "cohfrict_base": ([C(**ca), C(**cb)], CI(), CL(), G6),
        "cohfrict_mm": ([C(**ca), C(**cb)], CI(normalCohesion=MM(matches=((0, 1, 7e5),)), shearCohesion=4e5,
                                                frictAngle=MM(algo="max")), CL(), G6),
        "mindlin_base": ([F(), F(**fm)], MI(), ML()),
        "mindlin_en_match": ([F(), F(**fm)], MI(en=MM(matches=((0, 1, 0.5),))), ML()),
        "mindlin_en_es_match": ([F(), F(**fm)], MI(en=MM(matches=((0, 1, 0.5),)), es=MM(matches=((0, 1, 0.7),))),
                                ML()),
        "mindlin_beta_match": ([F(), F(**fm)], MI(betan=MM(matches=((0, 1, 0.2),)),
                                                  betas=MM(matches=((0, 1, 0.1),))), ML()),
        "mindlin_angle_avg": ([F(), F(**fm)], MI(frictAngle=MM(algo="avg")), ML()),
        "mindlin_angle_match": ([F(), F(**fm)], MI(frictAngle=MM(matches=((0, 1, 0.1),))), ML()),
    }
    for algo in ("avg", "min", "max", "harmAvg", "zero"):
        cases["frict_angle_" + algo] = ([F(), F(**fb)], FI(frictAngle=MM(algo=algo)), CS())
    return cases


#: the constants an Ip2 sets, compared with YADE's
_COMPARED = ("kn", "ks", "cn", "cs", "tangensOfFrictionAngle", "mR", "normalAdhesion", "shearAdhesion", "kno",
             "kso", "betan", "betas")


@pytest.mark.parametrize("case", sorted(set(REF["pairs"]) - {"viscel_facet_same", "viscel_facet_mixed"}))
def test_pair_constants_equal_yades(yade, case):
    """Per-pair constants with and without MatchMakers: means of tc, en, et with the reduced mass (ViscEl),
    the algorithms' inputs (E_i r_i, E_i r_i nu_i, phi_i), strengths times min(r)^2, damping ratios."""
    args = _cases(yade)[case]
    phys = _pair(yade, *args)
    want = REF["pairs"][case]["phys"]
    compared = [k for k in _COMPARED if k in want]
    assert len(compared) >= 3
    for k in compared:
        assert getattr(phys, k) == pytest.approx(want[k], rel=1e-12, abs=1e-300), k


@pytest.mark.parametrize("case", ["viscel_facet_same", "viscel_facet_mixed"])
def test_a_massless_facet_counts_with_the_spheres_mass(yade, case):
    """YADE 2023.02a: a sphere on a facet gets the constants of two bodies of the sphere's mass (m/2)."""
    y = yade
    va, vb = dict(tc=1e-3, en=0.5, et=0.6), dict(tc=2e-3, en=0.8, et=0.3, frictionAngle=0.2)
    other = va if case.endswith("same") else vb
    m = y.O.materials.append(y.ViscElMat(density=2000, frictionAngle=0.4, **va))
    n = y.O.materials.append(y.ViscElMat(**{"density": 2000, "frictionAngle": 0.4, **other}))
    s = y.O.bodies.append(y.sphere((0, 0, 0.01 - 1e-5), 0.01, material=m))
    f = y.O.bodies.append(y.facet([(-1, -1, 0), (1, -1, 0), (0, 1, 0)], material=n))
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb(), y.Bo1_Facet_Aabb()]),
                   y.InteractionLoop([y.Ig2_Facet_Sphere_ScGeom()], [y.Ip2_ViscElMat_ViscElMat_ViscElPhys()],
                                     [y.Law2_ScGeom_ViscElPhys_Basic()]),
                   y.NewtonIntegrator(damping=0, gravity=(0, 0, 0))]
    y.O.dt = 1e-9
    y.O.step()
    phys = y.O.interactions[s, f].phys
    want = REF["pairs"][case]["phys"]
    for k in ("kn", "cn", "ks", "cs", "tangensOfFrictionAngle"):
        assert getattr(phys, k) == pytest.approx(want[k], rel=1e-12), k
    # the closed form: reduced mass m/2, tc and en the materials' means
    mass, tc, en = y.O.bodies[s].state.mass / 2, (va["tc"] + other["tc"]) / 2, (va["en"] + other["en"]) / 2
    assert phys.kn == pytest.approx(mass * (math.pi ** 2 + math.log(en) ** 2) / tc ** 2, rel=1e-12)


def test_matchmaker_called_from_python_as_yade(yade):
    M = REF["matchmaker"]
    m = yade.MatchMaker(matches=((0, 1, 0.3), (2, 1, 0.5)))
    assert [m(0, 1), m(1, 0), m(1, 2)] == M["matched"]
    with pytest.raises(ValueError, match=r"no match for \(0,2\), and values required for algo computation 'avg'"):
        m(0, 2)
    assert m(0, 2, 1.0, 3.0) == M["no_match_values"]
    for algo in ("avg", "min", "max", "harmAvg", "val", "zero"):
        mm = yade.MatchMaker(algo=algo, val=7.0)
        want = M["algo_" + algo]
        assert mm(0, 2, 1.0, 3.0) == want["call"]
        assert mm.computeFallback(1.0, 3.0) == want["fallback"]
        assert mm.computeFallback(0.0, 3.0) == want["fallback_zero"]
        if isinstance(want["no_values"], dict):
            with pytest.raises(ValueError):
                mm(0, 2)
        else:
            assert mm(0, 2) == want["no_values"]
    with pytest.raises(ValueError, match="algo 'foo' not recognized"):
        yade.MatchMaker(algo="foo")
    assert yade.Ip2_FrictMat_FrictMat_FrictPhys(frictAngle=0.3).frictAngle.dict() == M["from_number"]
    d = yade.MatchMaker().dict()
    assert d["matches"] == [] and d["algo"] == "avg" and math.isnan(d["val"])
    for name, attrs in M["ip2_defaults"].items():
        got = getattr(yade, name)().dict()
        assert {k: got[k] for k in attrs} == attrs


def _spheres(y, mats, ip2, law):
    for k, m in enumerate(mats):
        mats[k] = y.O.materials.append(m)
    y.O.bodies.append([y.sphere((0, 0, 0), 1, fixed=True, material=mats[0]),
                       y.sphere((0, 0, 1.99), 1, material=mats[-1])])
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom()], [ip2], [law]), y.NewtonIntegrator()]
    y.O.dt = 1e-6


def test_different_rolling_models_stop_the_run_naming_them(yade):
    """YADE aborts (an uncaught C++ exception) when two ViscElMats with different mRtype touch."""
    y = yade
    _spheres(y, [y.ViscElMat(tc=1e-3, en=0.5, et=0.5, mRtype=1), y.ViscElMat(tc=1e-3, en=0.5, et=0.5, mRtype=2)],
             y.Ip2_ViscElMat_ViscElMat_ViscElPhys(), y.Law2_ScGeom_ViscElPhys_Basic())
    with pytest.raises(y.SimulationError, match=r"mRtype=1 and mRtype=2"):
        y.O.step()


@pytest.mark.parametrize("ip2, attr", [("Ip2_ViscElMat_ViscElMat_ViscElPhys", "en"),
                                       ("Ip2_ViscElMat_ViscElMat_ViscElPhys", "frictAngle"),
                                       ("Ip2_FrictMat_FrictMat_MindlinPhys", "betan"),
                                       ("Ip2_CohFrictMat_CohFrictMat_CohFrictPhys", "normalCohesion")])
def test_a_matchmaker_without_a_value_for_a_pair_stops_the_run_naming_it(yade, ip2, attr):
    """These functors give their MatchMakers no values to combine (YADE aborts): a pair without a match stops
    the run, naming the parameter and the materials; a MatchMaker that cannot match anything is refused
    before the run."""
    y = yade
    mats = {"Ip2_ViscElMat_ViscElMat_ViscElPhys": lambda: y.ViscElMat(tc=1e-3, en=0.5, et=0.5),
            "Ip2_FrictMat_FrictMat_MindlinPhys": lambda: y.FrictMat(),
            "Ip2_CohFrictMat_CohFrictMat_CohFrictPhys": lambda: y.CohFrictMat()}[ip2]
    law = {"Ip2_ViscElMat_ViscElMat_ViscElPhys": y.Law2_ScGeom_ViscElPhys_Basic,
           "Ip2_FrictMat_FrictMat_MindlinPhys": y.Law2_ScGeom_MindlinPhys_Mindlin,
           "Ip2_CohFrictMat_CohFrictMat_CohFrictPhys": y.Law2_ScGeom6D_CohFrictPhys_CohesionMoment}[ip2]
    extra = {"setCohesionOnNewContacts": True} if "Coh" in ip2 else {}
    f = getattr(y, ip2)(**{attr: y.MatchMaker(matches=((5, 6, 0.1),)), **extra})
    _spheres(y, [mats(), mats()], f, law())
    if "Coh" in ip2:
        y.O.engines[2].geomDispatcher.functors = [y.Ig2_Sphere_Sphere_ScGeom6D()]
    with pytest.raises(y.SimulationError, match=rf"{ip2}.{attr}: its MatchMaker has no match for the materials 0 "
                                                rf"and 1"):
        y.O.step()
    y.O.reset()
    f = getattr(y, ip2)(**{attr: y.MatchMaker(algo="avg"), **extra})
    _spheres(y, [mats(), mats()], f, law())
    with pytest.raises(ValueError, match=rf"{ip2}.{attr}: MatchMaker\(algo='avg'\) without matches gives no value"):
        y.O.step()
    assert y.O.iter == 0


@pytest.mark.parametrize("ip2, attr, value, why", [
    ("Ip2_FrictMat_FrictMat_FrictPhys", "kn", -1e5, "kn"),
    ("Ip2_FrictMat_FrictMat_FrictPhys", "frictAngle", -0.1, "frictAngle"),
    ("Ip2_ViscElMat_ViscElMat_ViscElPhys", "en", 1.5, "en"),
    ("Ip2_ViscElMat_ViscElMat_ViscElPhys", "tc", 0.0, "tc"),
    ("Ip2_FrictMat_FrictMat_MindlinPhys", "en", 0.0, "en"),
    ("Ip2_FrictMat_FrictMat_MindlinPhys", "betas", -0.2, "betas"),
    ("Ip2_CohFrictMat_CohFrictMat_CohFrictPhys", "shearCohesion", -5.0, "shearCohesion"),
])
def test_bad_matchmaker_values_are_refused_before_the_run(yade, ip2, attr, value, why):
    """A value a MatchMaker may return is checked against the parameter's range (as a material's is), whether
    given as a number, in matches or as val."""
    y = yade
    for mm in (value, y.MatchMaker(matches=((0, 0, value),)), y.MatchMaker(algo="val", val=value)):
        y.O.reset()
        mat = {"Ip2_ViscElMat_ViscElMat_ViscElPhys": lambda: y.ViscElMat(tc=1e-3, en=0.5, et=0.5),
               "Ip2_CohFrictMat_CohFrictMat_CohFrictPhys": lambda: y.CohFrictMat()}.get(ip2, y.FrictMat)()
        law = {"Ip2_ViscElMat_ViscElMat_ViscElPhys": y.Law2_ScGeom_ViscElPhys_Basic(),
               "Ip2_FrictMat_FrictMat_MindlinPhys": y.Law2_ScGeom_MindlinPhys_Mindlin(),
               "Ip2_CohFrictMat_CohFrictMat_CohFrictPhys": y.Law2_ScGeom6D_CohFrictPhys_CohesionMoment()}.get(
            ip2, y.Law2_ScGeom_FrictPhys_CundallStrack())
        _spheres(y, [mat], getattr(y, ip2)(**{attr: mm}), law)
        with pytest.raises(ValueError, match=rf"{ip2}.{why} must be finite.*got {value!r}"):
            y.O.step()
        assert y.O.iter == 0 and y.O.interactions.countReal() == 0


def test_matchmaker_val_without_val_and_bad_arguments_are_refused(yade):
    y = yade
    _spheres(y, [y.FrictMat()], y.Ip2_FrictMat_FrictMat_FrictPhys(frictAngle=y.MatchMaker(algo="val")),
             y.Law2_ScGeom_FrictPhys_CundallStrack())
    with pytest.raises(ValueError, match=r"frictAngle: MatchMaker\(algo='val'\) needs val, got val=nan"):
        y.O.step()
    with pytest.raises(TypeError, match="frictAngle"):
        y.Ip2_FrictMat_FrictMat_FrictPhys(frictAngle="x")
    with pytest.raises(TypeError, match=r"each item must be \(id1, id2, value\)"):
        y.MatchMaker(matches=((0, 1),))
    with pytest.raises(ValueError, match="mR must be finite and >= 0"):
        y.ViscElMat(mR=-0.1)
    with pytest.raises(ValueError, match="mRtype must be one of"):
        y.ViscElMat(mRtype=3)


def _rolling_pile(y):
    """Two layers of ViscElMat spheres with rolling resistance (type 2) on a facet, touching their neighbours,
    set spinning and moving at random (seeded): contacts with rolling moments from the first step."""
    y.O.reset()
    m = y.O.materials.append(y.ViscElMat(tc=1e-3, en=0.5, et=0.5, density=2600, mR=0.05, mRtype=2,
                                         frictionAngle=0.5))
    r, s = 0.02, 0.04 * (1 - 1e-3)
    rng = np.random.default_rng(7)
    for k in range(2):
        for j in range(5):
            for i in range(5):
                b = y.O.bodies[y.O.bodies.append(y.sphere((i * s, j * s, r * (1 - 1e-3) + k * s), r, material=m))]
                b.state.angVel = tuple(rng.uniform(-3, 3, 3))
                b.state.vel = tuple(rng.uniform(-0.05, 0.05, 3))
    y.O.bodies.append(y.utils.facet([(-1, -1, 0), (3, -1, 0), (-1, 3, 0)], material=m))
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb(), y.Bo1_Facet_Aabb()]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom(), y.Ig2_Facet_Sphere_ScGeom()],
                                     [y.Ip2_ViscElMat_ViscElMat_ViscElPhys()], [y.Law2_ScGeom_ViscElPhys_Basic()]),
                   y.NewtonIntegrator(gravity=(0, 0, -9.81), damping=0.0)]
    y.O.dt = 1e-5


def test_save_load_continue_with_rolling_resistance_equals_the_uninterrupted_run(yade, tmp_path):
    y = yade

    def state():
        return np.array([list(b.state.pos) + list(b.state.vel) + list(b.state.angVel) for b in y.O.bodies])

    _rolling_pile(y)
    y.O.run(3000, True)
    whole = state()
    _rolling_pile(y)
    y.O.run(1500, True)
    path = str(tmp_path / "r.yade")
    y.O.save(path)
    y.O.reset()
    y.O.load(path)
    y.O.run(1500, True)
    np.testing.assert_array_equal(state(), whole)
    assert y.O.interactions.countReal() > 10 and all(i.phys.mR == 0.05 for i in y.O.interactions)
    assert np.abs(whole[:, 6:]).max() > 0, "nothing turned"


def test_threads_give_the_same_bits_with_rolling_resistance(tmp_path):
    """The visco-elastic lattice with rolling resistance above the parallel threshold: -j1 and -j2 give the
    same positions and angular velocities, bit for bit."""
    script = Path(__file__).parents[1] / "benchmarks" / "dense_lattice.py"
    states = {}
    for j in ("1", "2"):
        out = tmp_path / f"j{j}.txt"
        subprocess.run([sys.executable, "-m", "granum", "-j", j, str(script)], check=True, timeout=1800,
                       env={**os.environ, "BENCH_N": "12", "BENCH_STEPS": "200", "BENCH_LAW": "viscel_rolling",
                            "BENCH_DUMP": str(out)}, capture_output=True)
        states[j] = out.read_text()
    assert states["1"] == states["2"]
    w = np.loadtxt(tmp_path / "j1.txt")[:, 3:]
    assert np.abs(w).max() > 0, "nothing turned"
