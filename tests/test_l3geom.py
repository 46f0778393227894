"""L3Geom and Law2_L3Geom_FrictPhys_ElPerfPl against real YADE (tests/reference/yade/l3geom.py) and closed forms.

The scenes are those of the reference script: two kinematic spheres (fixed, velocities set) in contact,
recorded after every step.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import reference

DIRECTION = np.array([0.6, 0.3, 0.74]) / np.linalg.norm([0.6, 0.3, 0.74])
SHEAR = np.array([0.74, 0.0, -0.6]) / np.linalg.norm([0.74, 0.0, -0.6]) * 0.6 - 0.01 * DIRECTION


def _scene(y, geom, law, dist, vel, ang_vel1, ang_vel2, steps, energy=False):
    """The reference script's ``scene``: the records of ``steps`` steps, as lists."""
    m1 = y.O.materials.append(y.FrictMat(young=1e7, poisson=0.3, density=1000, frictionAngle=0.5))
    m2 = y.O.materials.append(y.FrictMat(young=2e7, poisson=0.2, density=1000, frictionAngle=0.3))
    y.O.bodies.append([y.sphere((0, 0, 0), 0.5, material=m1, fixed=True),
                       y.sphere(tuple(dist * DIRECTION), 0.4, material=m2, fixed=True)])
    y.O.bodies[0].state.angVel = ang_vel1
    y.O.bodies[1].state.vel = tuple(vel)
    y.O.bodies[1].state.angVel = ang_vel2
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb(aabbEnlargeFactor=1.5)]),
                   y.InteractionLoop([geom], [y.Ip2_FrictMat_FrictMat_FrictPhys()], [law]),
                   y.NewtonIntegrator(damping=0)]
    y.O.dt = 1e-3
    y.O.trackEnergy = energy
    out = []
    for _ in range(steps):
        y.O.step()
        rec = {"iter": y.O.iter, "real": y.O.interactions.has(0, 1) and y.O.interactions[0, 1].isReal,
               "f": [list(y.O.forces.f(k)) for k in (0, 1)], "t": [list(y.O.forces.t(k)) for k in (0, 1)],
               "pos2": list(y.O.bodies[1].state.pos)}
        if rec["real"]:
            i = y.O.interactions[0, 1]
            g, p = i.geom, i.phys
            rec.update({"geom_class": type(g).__name__, "u": list(g.u), "u0": list(g.u0),
                        "trsf": [list(g.trsf[k]) for k in range(3)], "F": list(g.F), "normal": list(g.normal),
                        "contactPoint": list(g.contactPoint), "refR1": g.refR1, "refR2": g.refR2, "kn": p.kn,
                        "ks": p.ks, "tangensOfFrictionAngle": p.tangensOfFrictionAngle,
                        # YADE's L3Geom reports the force on body 1; granum's FrictPhys, on body 2
                        "normalForce": list(-np.array(p.normalForce)), "shearForce": list(-np.array(p.shearForce))})
        if energy:
            rec["energy"] = {k: y.O.energy[k] for k in y.O.energy.keys()}
        out.append(rec)
    return out


RUNS = {
    "default": lambda y: _scene(y, y.Ig2_Sphere_Sphere_L3Geom(), y.Law2_L3Geom_FrictPhys_ElPerfPl(), 0.88, SHEAR,
                                (0, 0, 1), (1, 0, 2), 60, energy=True),
    "options": lambda y: _scene(y, y.Ig2_Sphere_Sphere_L3Geom(noRatch=False, approxMask=3, trsfRenorm=3,
                                                              distFactor=-1.2),
                                y.Law2_L3Geom_FrictPhys_ElPerfPl(noSlip=True), 0.91, SHEAR - 0.3 * DIRECTION,
                                (0, 0, 1), (1, 0, 2), 60),
    "mask4": lambda y: _scene(y, y.Ig2_Sphere_Sphere_L3Geom(approxMask=4), y.Law2_L3Geom_FrictPhys_ElPerfPl(), 0.88,
                              SHEAR, (0, 0, 1), (1, 0, 2), 60),
    "separate": lambda y: _scene(y, y.Ig2_Sphere_Sphere_L3Geom(), y.Law2_L3Geom_FrictPhys_ElPerfPl(), 0.895,
                                 0.19 * DIRECTION, (0, 0, 0), (0, 0, 0), 30),
    "separate_noBreak": lambda y: _scene(y, y.Ig2_Sphere_Sphere_L3Geom(),
                                         y.Law2_L3Geom_FrictPhys_ElPerfPl(noBreak=True), 0.895,
                                         0.2 * DIRECTION + np.array([0.05, 0, 0]), (0, 0, 0), (0, 0, 0), 30),
}
VECTORS = ("u", "u0", "F", "normal", "contactPoint", "normalForce", "shearForce", "f", "t", "pos2", "trsf")
SCALARS = ("refR1", "refR2", "kn", "ks", "tangensOfFrictionAngle")


@pytest.mark.parametrize("run", sorted(RUNS))
def test_two_sphere_contact_step_by_step_as_yade(yade, run):
    ref = reference("l3geom")[run]
    got = RUNS[run](yade)
    for r, g in zip(ref, got, strict=True):
        where = f"{run}, iter {r['iter']}"
        assert g["real"] == r["real"], where
        if r["real"]:
            assert g["geom_class"] == r["geom_class"] == "L3Geom"
            for k in SCALARS:
                assert g[k] == pytest.approx(r[k], rel=1e-12), f"{where}: {k}"
        for k in VECTORS:
            if k in r:
                want = np.array(r[k])
                scale = max(1.0, float(np.abs(want).max()))
                np.testing.assert_allclose(g[k], want, rtol=0, atol=1e-9 * scale, err_msg=f"{where}: {k}")
        if "energy" in r:
            for k, v in r["energy"].items():
                assert g["energy"].get(k, 0.0) == pytest.approx(v, rel=1e-9, abs=1e-9), f"{where}: energy {k}"


def test_the_reference_runs_exercise_sliding_breaking_and_pulling():
    """What the reference runs are meant to show (so that a change of the script cannot hollow them out)."""
    ref = reference("l3geom")
    assert any(r["u0"][1] != 0 for r in ref["default"]), "default: no plastic slip"
    assert not ref["separate"][-1]["real"] and ref["separate"][0]["real"], "separate: no break"
    assert ref["separate_noBreak"][-1]["F"][0] > 0, "noBreak: no tension"
    assert all(r["u0"][1] == 0 for r in ref["options"]), "noSlip: slipped"


def test_static_overlap_gives_kn_times_overlap_and_no_shear(yade):
    """Closed form: two fixed spheres overlapping by delta: F = (-kn delta, 0, 0) in the local frame, the force on
    body 2 is kn delta n, torques vanish, kn = 2 E1 r1 E2 r2/(E1 r1 + E2 r2)."""
    got = _scene(yade, yade.Ig2_Sphere_Sphere_L3Geom(), yade.Law2_L3Geom_FrictPhys_ElPerfPl(), 0.88, (0, 0, 0),
                 (0, 0, 0), (0, 0, 0), 5)
    kn = 2 * 1e7 * 0.5 * 2e7 * 0.4 / (1e7 * 0.5 + 2e7 * 0.4)
    delta = 0.9 - 0.88
    for r in got:
        assert r["kn"] == pytest.approx(kn, rel=1e-14)
        np.testing.assert_allclose(r["F"], (-kn * delta, 0, 0), atol=1e-9 * kn * delta)
        np.testing.assert_allclose(r["f"][1], kn * delta * DIRECTION, rtol=1e-12)
        np.testing.assert_allclose(r["f"][0], -kn * delta * DIRECTION, rtol=1e-12)
        np.testing.assert_allclose(r["t"], 0, atol=1e-9)
        trsf = np.array(r["trsf"])
        np.testing.assert_allclose(trsf @ trsf.T, np.eye(3), atol=1e-15)
        np.testing.assert_allclose(trsf[0], DIRECTION, atol=1e-15)


def test_shear_force_never_exceeds_the_coulomb_limit_and_slip_dissipates(yade):
    """|F_t| <= -F_n tan(phi) at every step of a sliding contact; once sliding, |F_t| = -F_n tan(phi) and the
    plastic dissipation grows."""
    got = RUNS["default"](yade)
    sliding = 0
    for r in got:
        fn, ft = r["F"][0], math.hypot(r["F"][1], r["F"][2])
        limit = -fn * r["tangensOfFrictionAngle"]
        assert ft <= limit * (1 + 1e-12)
        if r["u0"][1] != 0 and ft == pytest.approx(limit, rel=1e-12):
            sliding += 1
    assert sliding > 20
    assert got[-1]["energy"]["plastDissip"] > got[-2]["energy"]["plastDissip"] > 0


def test_l3geom_fields_read_and_write_as_yade(yade):
    """The L3Geom attributes are views of the contact row: trsf is a Matrix3 (rows: normal, tangents),
    u/u0/F are Vector3, refR1/refR2 floats; assigning u0 changes the force of the next step."""
    _scene(yade, yade.Ig2_Sphere_Sphere_L3Geom(), yade.Law2_L3Geom_FrictPhys_ElPerfPl(), 0.88, (0, 0, 0),
           (0, 0, 0), (0, 0, 0), 1)
    g = yade.O.interactions[0, 1].geom
    assert type(g.trsf).__name__ == "Matrix3" and type(g.u).__name__ == "Vector3"
    assert set(dir(g)) >= {"u", "u0", "trsf", "F", "normal", "contactPoint", "refR1", "refR2"}
    g.u0 = (g.u[0], 0, 0)
    yade.O.step()
    assert g.F[0] == pytest.approx(0, abs=1e-6)


def test_unsupported_values_refused_by_name(yade):
    """Every attribute of the functors is implemented; a wrong keyword is refused by name."""
    with pytest.raises(TypeError, match="noSuch"):
        yade.Ig2_Sphere_Sphere_L3Geom(noSuch=1)
    assert yade.Ig2_Sphere_Sphere_L3Geom().trsfRenorm == 100
    assert isinstance(yade.Ig2_Sphere_Sphere_L3Geom(approxMask=3).approxMask, int)
