"""GlobalStiffnessTimeStepper and O.dynDt against real YADE (tests/reference/yade/timestepper.py, and
timestepper_rot.py for contacts with rolling and twisting stiffness), and the step against the critical step of
the linearised contact network (closed form: the largest eigenvalue).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import reference

REF = reference("timestepper")
REF_ROT = reference("timestepper_rot")
CHAIN = [((0, 0, 0), .5), ((.75, .2, 0), .3), ((1.3, .2, .3), .4), ((1.8, .55, .45), .35), ((2.4, .6, .1), .45),
         ((2.9, .9, .1), .3)]


def _engines(y, ts, damping=0.2, viscel=False):
    ip2, law = ((y.Ip2_ViscElMat_ViscElMat_ViscElPhys(), y.Law2_ScGeom_ViscElPhys_Basic()) if viscel else
                (y.Ip2_FrictMat_FrictMat_FrictPhys(), y.Law2_ScGeom_FrictPhys_CundallStrack()))
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom()], [ip2], [law]),
                   ts, y.NewtonIntegrator(damping=damping, gravity=(0, 0, 0))]


def _record(y, ts, n):
    out = []
    for _ in range(n):
        y.O.step()
        out.append((y.O.dt, ts.previousDt))
    return out


def _chain(y, **kw):
    m1 = y.O.materials.append(y.FrictMat(young=1e7, poisson=.3, density=2600, frictionAngle=.5))
    m2 = y.O.materials.append(y.FrictMat(young=3e7, poisson=.8, density=1500, frictionAngle=.5))
    y.O.bodies.append([y.sphere(c, r, material=(m1 if k % 2 == 0 else m2), fixed=(k == 0))
                       for k, (c, r) in enumerate(CHAIN)])
    ts = y.GlobalStiffnessTimeStepper(**kw)
    _engines(y, ts)
    y.O.dt = 1e-3
    return ts


@pytest.mark.parametrize("case", ["chain_1", "chain_3", "chain_maxDt"])
def test_chain_steps_as_yade(yade, case):
    """Every step's O.dt as YADE's over 40 steps of a moving chain: the formula, the update interval, the x1.05
    growth cap (chain_1, step 8) and maxDt."""
    ref = REF[case]
    ts = _chain(yade, **ref["kw"])
    got = _record(yade, ts, 40)
    for k, (s, (dt, prev)) in enumerate(zip(ref["steps"], got, strict=True)):
        assert dt == pytest.approx(s["dt"], rel=1e-9), f"step {k + 1}"
        assert prev == pytest.approx(s["previousDt"], rel=1e-9)
    pos = np.array([list(b.state.pos) for b in yade.O.bodies])
    np.testing.assert_allclose(pos, ref["final_pos"], rtol=0, atol=1e-9)


@pytest.mark.parametrize("interval", [1, 3])
def test_growth_cap_when_a_contact_ends(yade, interval):
    """A sphere between two fixed ones; one leaves: K halves, the step grows by 1.05 only (at an update)."""
    ref = REF[f"release_{interval}"]
    m = yade.O.materials.append(yade.FrictMat(young=1e7, poisson=.3, density=2600, frictionAngle=.5))
    yade.O.bodies.append([yade.sphere((0, 0, 0), .5, material=m), yade.sphere((.95, 0, 0), .5, material=m, fixed=True),
                          yade.sphere((-.95, 0, 0), .5, material=m, fixed=True)])
    yade.O.bodies[1].state.vel = (1, 0, 0)
    ts = yade.GlobalStiffnessTimeStepper(timeStepUpdateInterval=interval)
    _engines(yade, ts, damping=0)
    yade.O.dt = 1e-3
    got = _record(yade, ts, 12)
    assert [dt for dt, _ in got] == pytest.approx([s["dt"] for s in ref["steps"]], rel=1e-12)
    # closed form: two contacts along x, K_x = 2 kn, kn = E r = 5e6 N/m
    assert got[0][0] == pytest.approx(1.41044 * 0.8 * math.sqrt(ref["mass"] / 1e7), rel=1e-14)


@pytest.mark.parametrize("default", [-1, 1e-4])
def test_no_contact_default_step(yade, default):
    ref = REF[f"apart_{'default' if default < 0 else '1e-4'}"]
    m = yade.O.materials.append(yade.FrictMat(young=1e7, poisson=.3, density=2600, frictionAngle=.5))
    yade.O.bodies.append([yade.sphere((0, 0, 0), .5, material=m), yade.sphere((1.1, 0, 0), .3, material=m)])
    ts = yade.GlobalStiffnessTimeStepper(defaultDt=default, timestepSafetyCoefficient=.7)
    _engines(yade, ts)
    yade.O.dt = 1e-3
    got = _record(yade, ts, 2)
    assert [dt for dt, _ in got] == pytest.approx([s["dt"] for s in ref["steps"]], rel=1e-12)
    assert ts.previousDt == ref["steps"][-1]["previousDt"]  # nothing computed yet: the largest double


@pytest.mark.parametrize("k", range(10))
def test_viscel_dashpots(yade, k):
    ref = REF["viscel"][k]
    m = yade.O.materials.append(yade.ViscElMat(density=2600, kn=5e6, ks=2e6, cn=ref["cn"], cs=ref["cs"],
                                               frictionAngle=.5))
    yade.O.bodies.append([yade.sphere((0, 0, 0), .5, material=m), yade.sphere((.9, 0, 0), .5, material=m)])
    _engines(yade, yade.GlobalStiffnessTimeStepper(viscEl=ref["viscEl"]), damping=0, viscel=True)
    yade.O.dt = 1e-3
    yade.O.step()
    assert yade.O.dt == pytest.approx(ref["dt"], rel=1e-12)


def test_dyn_dt(yade):
    ref = REF["dynDt"]
    assert yade.O.dynDt == ref["fresh_engines_dynDt"] and not yade.O.dynDtAvailable
    ts = yade.GlobalStiffnessTimeStepper()
    _engines(yade, ts)
    assert [yade.O.dynDt, ts.active] == ref["with_stepper"] and yade.O.dynDtAvailable
    yade.O.dynDt = False
    assert [yade.O.dynDt, ts.active] == ref["after_dynDt_False"]
    ts.active = True
    assert [yade.O.dynDt, ts.active] == ref["after_active_True"]
    yade.O.engines = yade.O.engines[:3] + yade.O.engines[4:]
    assert yade.O.dynDt == ref["without_stepper"]
    with pytest.raises(RuntimeError, match="No TimeStepper found in O.engines"):
        yade.O.dynDt = True


def _critical_step(y):
    """2/sqrt(lambda_max(M^-1 K)) of the free bodies' 6 DOFs, K the linearised contact stiffness: for a
    contact of normal n between arms a1 = r1 n (body 1) and a2 = -r2 n (body 2), the relative displacement
    at the contact point is u = (x2 + th2 x a2) - (x1 + th1 x a1) and the energy 1/2 u.Kc.u,
    Kc = kn n n^T + ks (1 - n n^T); a contact with rolling and twisting stiffness (kr, ktw) adds
    1/2 w.Kw.w, w = th2 - th1 its relative rotation, Kw = kr (1 - n n^T) + ktw n n^T."""
    free = [b.id for b in y.O.bodies if b.dynamic]
    col = {i: 6 * k for k, i in enumerate(free)}
    K = np.zeros((6 * len(free),) * 2)
    for i in y.O.interactions:
        n = np.array(list(i.geom.normal))
        kc = i.phys.kn * np.outer(n, n) + i.phys.ks * (np.eye(3) - np.outer(n, n))
        cross = lambda a: np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])  # noqa: E731
        blocks = {i.id1: np.hstack([-np.eye(3), cross(i.geom.refR1 * n)]),
                  i.id2: np.hstack([np.eye(3), -cross(-i.geom.refR2 * n)])}
        B = np.zeros((3, K.shape[0]))
        for body, blk in blocks.items():
            if body in col:
                B[:, col[body]:col[body] + 6] = blk
        K += B.T @ kc @ B
        kr, ktw = getattr(i.phys, "kr", 0.0), getattr(i.phys, "ktw", 0.0)
        kw = kr * (np.eye(3) - np.outer(n, n)) + ktw * np.outer(n, n)
        R = np.zeros((3, K.shape[0]))
        for body, sign in ((i.id1, -1.0), (i.id2, 1.0)):
            if body in col:
                R[:, col[body] + 3:col[body] + 6] = sign * np.eye(3)
        K += R.T @ kw @ R
    minv = np.concatenate([[1 / y.O.bodies[i].state.mass] * 3 + list(1 / np.array(list(y.O.bodies[i].state.inertia)))
                           for i in free])
    lam = np.linalg.eigvals(np.sqrt(minv)[:, None] * K * np.sqrt(minv)[None, :]).real.max()
    return 2 / math.sqrt(lam)


@pytest.mark.parametrize("safety", [0.8, 1.0])
def test_below_the_critical_step(yade, safety):
    """On the chain, the step (safety 0.8, and even 1) is below the critical step of the linearised network,
    and not far below (the diagonal estimate is within a factor 2 here)."""
    _chain(yade, timestepSafetyCoefficient=safety)
    yade.O.step()
    crit = _critical_step(yade)
    assert 0.5 * crit < yade.O.dt < crit


def test_bad_attributes(yade):
    with pytest.raises(ValueError, match="timeStepUpdateInterval must be at least 1.*got 0"):
        yade.GlobalStiffnessTimeStepper(timeStepUpdateInterval=0)
    with pytest.raises(ValueError, match="timestepSafetyCoefficient must be positive, got -0.5"):
        yade.GlobalStiffnessTimeStepper(timestepSafetyCoefficient=-.5)
    with pytest.raises(ValueError, match="maxDt must be positive"):
        yade.GlobalStiffnessTimeStepper(maxDt=0)
    with pytest.raises(NotImplementedError, match="densityScaling"):
        yade.GlobalStiffnessTimeStepper(densityScaling=True)


# ---- rolling and twisting stiffness (RotStiffFrictPhys: CohFrictPhys, MindlinPhys) -------------------------

COH = ("Ig2_Sphere_Sphere_ScGeom6D", "Ip2_CohFrictMat_CohFrictMat_CohFrictPhys",
       "Law2_ScGeom6D_CohFrictPhys_CohesionMoment")


def _rot_engines(y, ts, ip2, law):
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom6D()], [ip2], [law]), ts,
                   y.NewtonIntegrator(damping=.2, gravity=(0, 0, 0))]


def _coh_chain(y, safety):
    m1 = y.O.materials.append(y.CohFrictMat(young=1e7, poisson=.3, density=2600, frictionAngle=.5, alphaKr=3,
                                            alphaKtw=1, momentRotationLaw=True, isCohesive=False))
    m2 = y.O.materials.append(y.CohFrictMat(young=3e7, poisson=.8, density=1500, frictionAngle=.5, alphaKr=20,
                                            alphaKtw=8, momentRotationLaw=True, isCohesive=False))
    y.O.bodies.append([y.sphere(c, r, material=(m1 if k % 2 == 0 else m2), fixed=(k == 0))
                       for k, (c, r) in enumerate(CHAIN)])
    y.O.bodies[5].state.angVel = (0, 0, 3)
    ts = y.GlobalStiffnessTimeStepper(timeStepUpdateInterval=1, timestepSafetyCoefficient=safety)
    _rot_engines(y, ts, getattr(y, COH[1])(), getattr(y, COH[2])())
    y.O.dt = 1e-3
    return ts


@pytest.mark.parametrize("case", ["chain", "chain_safety_.5"])
def test_cohfrict_chain_steps_as_yade(yade, case):
    """The chain with CohFrictPhys contacts (rolling and twisting stiffness, one sphere spinning): every step's
    O.dt as YADE's over 30 steps; without kr and ktw the first step would be 3.0 times larger."""
    ref = REF_ROT[case]
    ts = _coh_chain(yade, ref["safety"])
    got = _record(yade, ts, 30)
    for k, (s, (dt, prev)) in enumerate(zip(ref["steps"], got, strict=True)):
        assert dt == pytest.approx(s["dt"], rel=1e-9), f"step {k + 1}"
        assert prev == pytest.approx(s["previousDt"], rel=1e-9)


def _pair(y, ref, ip2, law, mat):
    m = y.O.materials.append(mat)
    n = np.array(ref["normal"], float) / np.linalg.norm(ref["normal"])
    y.O.bodies.append([y.sphere((0, 0, 0), .5, material=m, fixed=True), y.sphere(tuple(n * .89), .4, material=m)])
    _rot_engines(y, y.GlobalStiffnessTimeStepper(timeStepUpdateInterval=1), ip2, law)
    y.O.dt = 1e-3
    y.O.step()
    i = y.O.interactions[0, 1]
    c = ref["contacts"][0]
    assert [i.phys.kn, i.phys.ks, i.phys.kr, i.phys.ktw] == pytest.approx([c[k] for k in ("kn", "ks", "kr", "ktw")],
                                                                          rel=1e-12)
    assert y.O.dt == pytest.approx(ref["dt"], rel=1e-12)


@pytest.mark.parametrize("k", range(len(REF_ROT["pair_cohfrict"])))
def test_cohfrict_pair_step_as_yade(yade, k):
    """A sphere on a fixed one, oblique and axial normals: kr counts for the rotations about the axes normal
    to n and ktw for the rotation about n, with or without momentRotationLaw (YADE's steps to 1e-12)."""
    ref = REF_ROT["pair_cohfrict"][k]
    mat = yade.CohFrictMat(young=1e7, poisson=.3, density=2600, frictionAngle=.5, alphaKr=ref["alphaKr"],
                           alphaKtw=ref["alphaKtw"], momentRotationLaw=ref["momentRotationLaw"], isCohesive=False)
    _pair(yade, ref, getattr(yade, COH[1])(), getattr(yade, COH[2])(), mat)


@pytest.mark.parametrize("k", range(len(REF_ROT["pair_mindlin"])))
def test_mindlin_pair_step_as_yade(yade, k):
    """The same pair with Hertz-Mindlin's krot and ktwist (with or without includeMoment)."""
    ref = REF_ROT["pair_mindlin"][k]
    mat = yade.FrictMat(young=1e7, poisson=.3, density=2600, frictionAngle=.5)
    _pair(yade, ref, yade.Ip2_FrictMat_FrictMat_MindlinPhys(krot=ref["krot"], ktwist=ref["ktwist"]),
          yade.Law2_ScGeom_MindlinPhys_Mindlin(includeMoment=ref["includeMoment"]), mat)


def test_rolling_stiffness_closed_form(yade):
    """Normal along x, alphaKtw 2: about x only the twisting spring acts, K^R_x = ktw, and that rotation is the
    stiffest (I/ktw is the smallest ratio): dt = q s sqrt(I / ktw)."""
    ref = next(r for r in REF_ROT["pair_cohfrict"] if r["normal"] == [1, 0, 0] and r["alphaKtw"] == 2)
    mat = yade.CohFrictMat(young=1e7, poisson=.3, density=2600, frictionAngle=.5, alphaKr=0, alphaKtw=2,
                           momentRotationLaw=True, isCohesive=False)
    _pair(yade, ref, getattr(yade, COH[1])(), getattr(yade, COH[2])(), mat)
    ktw = yade.O.interactions[0, 1].phys.ktw
    assert yade.O.dt == pytest.approx(1.41044 * 0.8 * math.sqrt(yade.O.bodies[1].state.inertia[0] / ktw), rel=1e-14)


@pytest.mark.parametrize("safety", [0.8, 1.0])
def test_cohfrict_below_the_critical_step(yade, safety):
    """With rolling and twisting springs the step stays below the critical step of the linearised network
    (its rotational blocks included) and within a factor 2 of it."""
    _coh_chain(yade, safety)
    yade.O.step()
    crit = _critical_step(yade)
    assert 0.5 * crit < yade.O.dt < crit
