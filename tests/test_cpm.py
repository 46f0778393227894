"""The concrete particle model: CpmMat, CpmPhys, Ip2_CpmMat_CpmMat_CpmPhys, Ip2_FrictMat_CpmMat_FrictPhys,
Law2_ScGeom_CpmPhys_Cpm, CpmState and CpmStateUpdater.

Step by step against real YADE 2023.02a: the reference script tests/reference/yade/cpm.py runs unmodified under
granum and every record (the CpmPhys, forces, torques, the CpmStates and the updater's outputs) is compared with
YADE's. Also the damage law in closed form, determinism across thread counts, save -> load -> continue, refused
input and the values YADE's concrete examples use.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import granum_reference_run, reference

RUNS = ("tension", "tension_linear", "linear_default", "shear", "compression", "prestress", "noncohesive",
        "neverDamage", "frict_cpm")
#: a quantity is compared to 1e-9 of the largest magnitude it takes in the run, or of the largest magnitude of
#: its companion: a shear strain or stress that is rounding noise (pure tension: about 1e-17) is measured
#: against the normal one
COMPANION = {"epsT": "epsN", "sigmaT": "sigmaN", "epsTPl": "epsN", "Fs": "f", "t": "f", "normalForce": "f",
             "shearForce": "f", "Fn": "f"}


@pytest.fixture(scope="module")
def granum_runs():
    """The reference script's records, produced by granum."""
    return granum_reference_run("cpm.py")


def _flat(record: dict) -> dict:
    out = {}
    for k, v in record.items():
        if isinstance(v, dict):
            out.update({f"{k}.{kk}": vv for kk, vv in v.items()})
        else:
            out[k] = v
    return out


def _magnitude(records, key) -> float:
    values = [np.abs(np.array(r[key], float)) for r in records if key in r]
    return max((float(np.nanmax(v)) for v in values if v.size and not np.isnan(v).all()), default=0.0)


@pytest.mark.parametrize("run", RUNS)
def test_two_spheres_step_by_step_as_yade(granum_runs, run):
    """Every recorded value equals YADE's to 1e-9 of its scale (see COMPANION); NaN where YADE has NaN;
    booleans, ints, classes and the steps at which a contact is real exactly."""
    ref = [_flat(r) for r in reference("cpm")[run]]
    got = [_flat(r) for r in granum_runs[run]]
    assert len(got) == len(ref)
    keys = {k for r in ref for k, v in r.items() if isinstance(v, list | float) and k != "iter"}
    scale = {k: max(_magnitude(ref, k), _magnitude(ref, COMPANION.get(k, k))) for k in keys}
    for a, b in zip(ref, got, strict=True):
        assert set(a) == set(b), (run, a["iter"])
        for k, va in a.items():
            if k in keys:
                x, y = np.array(va, float), np.array(b[k], float)
                np.testing.assert_array_equal(np.isnan(y), np.isnan(x), err_msg=f"{run} {k} iter {a['iter']}")
                ok = ~np.isnan(x)
                np.testing.assert_allclose(y[ok], x[ok], rtol=0, atol=1e-9 * max(scale[k], 1e-300),
                                           err_msg=f"{run} {k} iter {a['iter']}")
            else:
                assert b[k] == va, (run, k, a["iter"])


def test_the_reference_runs_exercise_what_they_are_named_after():
    """So that a change of the script cannot hollow them out."""
    ref = reference("cpm")
    assert max(r["omega"] for r in ref["tension"] if r["real"]) > 0.98
    assert min(r["relResidualStrength"] for r in ref["tension"] if r["real"]) < 0.4
    assert max(r["state0"]["numBrokenCohesive"] for r in ref["tension_linear"]) > 100
    assert np.linalg.norm(ref["shear"][-1]["epsTPl"]) > 1e-3
    assert min(r.get("epsNPl", 0) for r in ref["compression"]) < -5e-4
    last = ref["noncohesive"][-1]["state0"]
    assert last["normDmg"] == 1.0 and last["numBrokenCohesive"] > 100   # made and ended every other step
    assert ref["frict_cpm"][-1]["phys_class"] == "FrictPhys"
    assert ref["rate_equals_tension"] is True   # YADE ignores the rate dependence: granum refuses it
    assert ref["prestress"][0]["epsN"] == pytest.approx(-1.5e6 / 24e9)


def test_damage_follows_the_exponential_softening_law():
    """YADE's records of the tension run against the closed form: omega = 1 - (eps0/kappa) exp(-(kappa - eps0)
    / epsf) past the crack onset, sigma_N = (1 - omega) E eps_N, the residual strength (1 - omega) kappa / eps0
    (granum follows the records to 1e-9: test_two_spheres_step_by_step_as_yade)."""
    for r in reference("cpm")["tension"]:
        if not r["real"]:
            continue
        k, e0, ef = r["kappaD"], r["epsCrackOnset"], r["epsFracture"]
        omega = 1 - e0 / k * math.exp(-(k - e0) / ef) if k > e0 else 0.0
        assert r["omega"] == pytest.approx(omega, rel=1e-12, abs=1e-15)
        assert r["sigmaN"] == pytest.approx((1 - omega) * r["E"] * r["epsN"], rel=1e-9, abs=1e-6)
        assert r["relResidualStrength"] == pytest.approx((1 - omega) * k / e0 if k > e0 else 1.0, rel=1e-9)


def test_elastic_energy_as_yade(granum_runs):
    """Law2_ScGeom_CpmPhys_Cpm.elasticEnergy() of a damaged contact (omega 0.66): YADE's sum, whose normal term
    divides by the damaged stiffness."""
    ref = reference("cpm")["elasticEnergy"]
    got = granum_runs["elasticEnergy"]
    assert got[0] == ref[0] and ref[2] > 0.5
    assert got[1] == pytest.approx(ref[1], rel=1e-9)


def test_damage_law_and_its_inverse_as_yade(granum_runs):
    """CpmPhys.funcG (the linear law above 1 past epsFracture, as YADE's) and funcGInv (YADE solves the exponential
    law's inverse iteratively: to 1e-9)."""
    ref = reference("cpm")
    for (args, want), (_, got) in zip(ref["funcG"], granum_runs["funcG"], strict=True):
        assert got == pytest.approx(want, rel=1e-14, abs=1e-300), args
    for (args, want), (_, got) in zip(ref["funcGInv"], granum_runs["funcGInv"], strict=True):
        assert got == pytest.approx(want, rel=1e-9, abs=1e-300), args
    assert any(r["real"] and not r["isCohesive"] for r in ref["linear_default"])   # the link broke past omega 1


def test_updater_and_states_of_the_reference(granum_runs):
    """The CpmStateUpdater's and CpmState's defaults and the class associations, as YADE's."""
    ref = reference("cpm")
    assert granum_runs["newAssocState"] == ref["newAssocState"] == "CpmState"
    assert granum_runs["sphere_state"] == ref["sphere_state"] == "CpmState"
    assert granum_runs["yieldSigmaTMagnitude"] == ref["yieldSigmaTMagnitude"]
    assert granum_runs["rate_equals_tension"]["exception"] == "NotImplementedError"
    for cls in ("CpmMat", "Ip2_CpmMat_CpmMat_CpmPhys", "Law2_ScGeom_CpmPhys_Cpm", "CpmStateUpdater"):
        expected, got = ref["defaults"][cls], granum_runs["defaults"][cls]
        for k, v in expected.items():
            if k in ("id", "label", "E", "nDone", "virtLast", "iterLast", "realLast"):
                continue
            assert k in got, (cls, k)
            assert (math.isnan(got[k]) if isinstance(v, float) and math.isnan(v) else got[k] == v), (cls, k)


def _packing(y, steps_cohesive=10, eps_crack=2e-3):
    """A small CPM packing: a cloud of spheres (cohesive links within 1.5 times the radii) falling under gravity
    onto a FrictMat facet; links break as it lands."""
    y.O.reset()
    m = y.O.materials.append(y.CpmMat(young=1e7, poisson=0.2, frictionAngle=0.6, density=2600, sigmaT=1e4,
                                      epsCrackOnset=eps_crack, relDuctility=5))
    wall = y.O.materials.append(y.FrictMat(young=1e7, poisson=0.2, frictionAngle=0.5))
    sp = y.pack.SpherePack()
    sp.makeCloud((0, 0, 0), (0.5, 0.5, 0.4), rMean=0.04, rRelFuzz=0.3, seed=5)
    sp.toSimulation(material=m)
    y.O.bodies.append(y.utils.facet([(-1, -1, 0), (2, -1, 0), (-1, 2, 0)], material=wall))
    bo1 = y.Bo1_Sphere_Aabb(aabbEnlargeFactor=1.5)
    ig2 = y.Ig2_Sphere_Sphere_ScGeom(interactionDetectionFactor=1.5)
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([bo1, y.Bo1_Facet_Aabb()]),
                   y.InteractionLoop([ig2, y.Ig2_Facet_Sphere_ScGeom()],
                                     [y.Ip2_CpmMat_CpmMat_CpmPhys(cohesiveThresholdIter=steps_cohesive),
                                      y.Ip2_FrictMat_CpmMat_FrictPhys()],
                                     [y.Law2_ScGeom_CpmPhys_Cpm(omegaThreshold=0.9),
                                      y.Law2_ScGeom_FrictPhys_CundallStrack()]),
                   y.NewtonIntegrator(gravity=(0, 0, -9.81), damping=0.1),
                   y.CpmStateUpdater(iterPeriod=100)]
    y.O.dt = 1e-4
    return bo1, ig2


def _state(y):
    rows = []
    for b in y.O.bodies:
        s = b.state
        row = list(s.pos) + list(s.vel) + list(s.angVel)
        if type(s).__name__ == "CpmState":
            row += [s.normDmg, s.numBrokenCohesive] + [s.stress[i, j] for i in range(3) for j in range(3)]
        rows.append(row + [0.0] * (29 - len(row)))
    return np.array(rows)


def test_save_load_continue_equals_the_uninterrupted_run(yade, tmp_path):
    """A CPM packing whose links break as it lands: save -> load -> continue gives the bits of the uninterrupted
    run (the CpmPhys columns, the CpmStates and their broken-link counts travel with it)."""
    def run(split):
        bo1, ig2 = _packing(yade)
        yade.O.step()
        bo1.aabbEnlargeFactor = ig2.interactionDetectionFactor = 1.0   # as YADE's concrete examples do
        if split:
            yade.O.run(1499, True)
            path = str(tmp_path / "cpm.yade")
            yade.O.save(path)
            yade.O.load(path)
            yade.O.run(1500, True)
        else:
            yade.O.run(2999, True)
        return _state(yade)

    whole = run(False)
    np.testing.assert_array_equal(run(True), whole)
    assert whole[:, 10].max() > 0, "no link broke"
    omegas = [i.phys.omega for i in yade.O.interactions if type(i.phys).__name__ == "CpmPhys"]
    assert len(omegas) > 20 and max(omegas) > 0


def test_threads_give_the_same_bits(tmp_path):
    """The CPM lattice benchmark above the parallel threshold: -j1 and -j2 give the same positions and angular
    velocities, bit for bit."""
    script = Path(__file__).parents[1] / "benchmarks" / "dense_lattice.py"
    states = {}
    for j in ("1", "2"):
        out = tmp_path / f"j{j}.txt"
        subprocess.run([sys.executable, "-m", "granum", "-j", j, str(script)], check=True, timeout=1800,
                       env={**os.environ, "BENCH_N": "12", "BENCH_STEPS": "200", "BENCH_LAW": "cpm",
                            "BENCH_DUMP": str(out)},
                       capture_output=True)
        states[j] = out.read_text()
    assert states["1"] == states["2"]


@pytest.mark.parametrize("kw, bad", [(dict(sigmaT=-3e6), "sigmaT"), (dict(epsCrackOnset=-1e-4), "epsCrackOnset"),
                                     (dict(relDuctility=-30.0), "relDuctility"),
                                     (dict(equivStrainShearContrib=-0.1), "equivStrainShearContrib"),
                                     (dict(damLaw=2), "damLaw"), (dict(damLaw=-1), "damLaw"),
                                     (dict(sigmaT=float("inf")), "sigmaT"), (dict(young=-1.0), "young"),
                                     (dict(isoPrestress=float("nan")), "isoPrestress")])
def test_bad_material_values_are_refused_naming_them(yade, kw, bad):
    with pytest.raises(ValueError, match=bad):
        yade.CpmMat(**kw)


@pytest.mark.parametrize("cls, kw", [("CpmMat", dict(dmgTau=1e-3)), ("CpmMat", dict(plTau=1e-3)),
                                     ("CpmMat", dict(dmgRateExp=2.0)), ("CpmMat", dict(plRateExp=2.0))])
def test_the_rate_dependence_yades_build_ignores_is_refused(yade, cls, kw):
    with pytest.raises(NotImplementedError, match=next(iter(kw))):
        getattr(yade, cls)(**kw)


def _pair(y, ip2=None, law=None, mats=None):
    mats = mats or [y.CpmMat(sigmaT=3e6, epsCrackOnset=1e-4, relDuctility=30)]
    ids = [y.O.materials.append(m) for m in mats] * (3 - len(mats))
    y.O.bodies.append([y.sphere((0, 0, 0), 0.1, material=ids[0]), y.sphere((0.19, 0, 0), 0.1, material=ids[1])])
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom()], [ip2 or y.Ip2_CpmMat_CpmMat_CpmPhys()],
                                     [law or y.Law2_ScGeom_CpmPhys_Cpm()]),
                   y.NewtonIntegrator()]


@pytest.mark.parametrize("kw", [dict(yieldSurfType=0), dict(yieldLogSpeed=0.5), dict(yieldEllipseShift=1.0)])
def test_the_full_models_yield_surfaces_are_refused_at_the_run(yade, kw):
    _pair(yade, law=yade.Law2_ScGeom_CpmPhys_Cpm(**kw))
    with pytest.raises(NotImplementedError, match=next(iter(kw))):
        yade.O.step()


@pytest.mark.parametrize("kw", [dict(epsSoft=float("nan")), dict(relKnSoft=float("inf")),
                                dict(omegaThreshold=float("nan"))])
def test_non_finite_law_parameters_are_refused_at_the_run(yade, kw):
    _pair(yade, law=yade.Law2_ScGeom_CpmPhys_Cpm(**kw))
    with pytest.raises(ValueError, match=next(iter(kw))):
        yade.O.step()


def test_materials_of_two_damage_laws_are_refused_naming_both(yade):
    """A contact between a linear-softening and an exponential CpmMat has no law of its own."""
    _pair(yade, mats=[yade.CpmMat(sigmaT=3e6, epsCrackOnset=1e-4, relDuctility=30, damLaw=0),
                      yade.CpmMat(sigmaT=3e6, epsCrackOnset=1e-4, relDuctility=30, damLaw=1)])
    with pytest.raises(ValueError, match="damLaw=0.*damLaw=1"):
        yade.O.step()
    assert yade.O.iter == 0


def test_a_cpm_body_with_a_plain_state_is_refused(yade):
    """YADE's testThrowsAtBadCombination: a CpmMat body with a plain State stops the step (RuntimeError)."""
    b = yade.Body()
    b.mat = yade.CpmMat()
    b.state = yade.State()
    yade.O.bodies.append(b)
    with pytest.raises(RuntimeError, match="CpmState"):
        yade.O.step()
    b.state = yade.CpmState()
    assert b.mat.stateTypeOk(b.state) and type(b.state).__name__ == "CpmState"


def test_the_law_adds_nothing_to_the_energies(yade):
    """As YADE's (checked with O.trackEnergy on the oblique pull of 'elasticEnergy'): a damaged, sliding CPM contact
    adds no plastic dissipation and no elastic energy to O.energy."""
    _pair(yade)
    yade.O.trackEnergy = True
    for b in yade.O.bodies:
        b.state.blockedDOFs = "xyzXYZ"
    yade.O.bodies[1].state.vel = (1.0, 0.5, 0.0)
    yade.O.dt = 1e-6
    yade.O.run(2000, True)
    phys = yade.O.interactions[0, 1].phys
    assert phys.omega > 0.5 and np.linalg.norm(list(phys.epsTPl)) > 0
    energy = dict(yade.O.energy.items())
    assert "plastDissip" not in energy and energy.get("elastPotential", 0.0) == 0.0


def test_damage_tensor_is_refused(yade):
    with pytest.raises(NotImplementedError, match="damageTensor"):
        _ = yade.CpmState().damageTensor


def test_every_value_of_yades_examples_is_accepted(yade):
    """The CpmMat, Ip2, Law2 and CpmStateUpdater arguments of YADE 2023.02a's examples (concrete/uniax.py,
    brazilian.py, periodic.py, triax.py, PeriodicBoundaries/peri3dController_*.py, agglomerate/simulation.py,
    test/test_Ip2_FrictMat_CpmMat_FrictPhys.py), NaN strengths (the defaults) included."""
    yade.CpmMat(young=24e9, frictionAngle=math.atan(0.8), poisson=0.2, density=4800, sigmaT=3.5e6, relDuctility=30,
                epsCrackOnset=1e-4, isoPrestress=0)
    yade.CpmMat(young=25e9, poisson=0.2, sigmaT=3e6, epsCrackOnset=1e-4, relDuctility=1e-6)
    yade.CpmMat(neverDamage=True, young=25e9, frictionAngle=0.7, poisson=0.2, sigmaT=3e6, epsCrackOnset=1e-4,
                relDuctility=30)
    yade.CpmMat(neverDamage=True, frictionAngle=0)
    yade.CpmMat(young=30e9, poisson=0.2, density=4800, sigmaT=3e6, relDuctility=30, epsCrackOnset=1e-4,
                neverDamage=False, isoPrestress=-1e6)
    yade.Ip2_CpmMat_CpmMat_CpmPhys(cohesiveThresholdIter=1)
    yade.Ip2_CpmMat_CpmMat_CpmPhys(cohesiveThresholdIter=-1)
    yade.Ip2_FrictMat_CpmMat_FrictPhys()
    yade.Law2_ScGeom_CpmPhys_Cpm(epsSoft=0)
    yade.CpmStateUpdater(realPeriod=0.5)
    yade.CpmStateUpdater(iterPeriod=50, label="cpmStateUpdater")


def test_a_cpm_contact_without_the_cpm_law_stops_naming_the_types(yade):
    _pair(yade, law=yade.Law2_ScGeom_FrictPhys_CundallStrack())
    with pytest.raises(RuntimeError, match="no Law2 functor.*CpmMat"):
        yade.O.step()
