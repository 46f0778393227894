"""The extended Hertz-Mindlin law (physics/mindlin_cdm.py: conical damage model, pressure-dependent friction)
against closed forms, real YADE (tests/reference/yade/cdm.py, cdm_check.py) and YADE's own check script."""

from __future__ import annotations

import functools
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import granum_reference_run, reference, resumed_run_matches

CHECK = "/usr/share/doc/yade/scripts/checks-and-tests/checks/checkHertzExtended.py"


@functools.lru_cache(maxsize=1)
def granum_runs() -> dict:
    """What the reference script cdm.py records when granum runs it."""
    return granum_reference_run("cdm.py")


def assert_close(got, want, where: str, rtol: float, atol: float = 0.0) -> None:
    """Records compared field by field: booleans and None exactly, NaN as NaN, numbers to ``rtol`` (an absolute
    floor of rtol times the largest magnitude of a vector, for components that cancel, and of ``atol``)."""
    if isinstance(want, dict):
        assert set(got) == set(want), f"{where}: fields {sorted(set(got) ^ set(want))}"
        for k in want:
            assert_close(got[k], want[k], f"{where}.{k}", rtol, atol)
    elif isinstance(want, list):
        assert len(got) == len(want), f"{where}: {len(got)} items, YADE {len(want)}"
        scale = max((abs(x) for x in want if isinstance(x, float)), default=0.0)
        for k, (g, w) in enumerate(zip(got, want, strict=True)):
            if isinstance(w, float) and isinstance(g, float):
                assert g == pytest.approx(w, rel=rtol, abs=max(rtol * scale, atol), nan_ok=True), \
                    f"{where}[{k}]: {g} vs {w}"
            else:
                assert_close(g, w, f"{where}[{k}]", rtol, atol)
    elif isinstance(want, float) and not isinstance(want, bool):
        assert got == pytest.approx(want, rel=rtol, abs=1e-300, nan_ok=True), f"{where}: {got} vs {want}"
    else:
        assert got == want, f"{where}: {got!r} vs {want!r}"


@pytest.mark.parametrize("run", ["load_unload", "never_erase", "frictmat", "slide", "hertzian"])
def test_contacts_step_by_step_as_yade(run):
    """Every recorded step of the reference runs (yielding, unloading with the damaged radius, the overlap that
    became all plastic, separation, neverErase, FrictMat with FrictMatCDM, sliding with the pressure-dependent
    friction, hertzian facet and wall): forces, torques, the MindlinPhysCDM fields and the law's ratios. Measured
    agreement 1e-10 (summation order in the shear increment); 1e-8 leaves room for that round-off to grow."""
    assert_close(granum_runs()[run], reference("cdm")[run], run, rtol=1e-8)


def test_the_reference_runs_exercise_every_regime():
    """The reference data holds what the comparison above should cover (else it would compare little)."""
    ref = reference("cdm")
    real = [r for r in ref["load_unload"] if r["real"]]
    assert any(r["isYielding"] for r in real) and any(not r["isYielding"] and r["kn"] > 0 for r in real)
    assert any(r["kn"] == 0.0 for r in real), "no step with an all-plastic overlap"
    assert not ref["load_unload"][-1]["real"], "the contact never ended"
    assert ref["never_erase"][-1]["real"] and ref["never_erase"][-1]["pen"] < 0
    assert any(r.get("isSliding") for r in ref["slide"]) and any(r.get("isYielding") for r in ref["slide"])
    mu = {r["tangensOfFrictionAngle"] for r in real}
    assert len(mu) > 10, "the friction coefficient did not depend on the pressure"
    assert ref["hertzian"][-1]["facet"]["refR1"] == 1e7 and ref["hertzian"][-1]["wall"]["refR1"] == 1e7


def test_yade_defaults(yade):
    for name, want in reference("cdm")["dicts"].items():
        assert_close(getattr(yade, name)().dict(), want, name, rtol=0.0)


@pytest.mark.skipif(not os.path.exists(CHECK), reason="YADE's check scripts are not installed")
def test_yades_check_script_passes_and_agrees_with_yade(yade):
    """YADE's checkHertzExtended.py, its text unmodified, as YADE's checkList.py runs it (with YadeCheckError
    defined): it raises unless its 40 steps give its precomputed overlaps, forces, contact radii and stresses
    (to 1e-5). The script is gated on YADE's CGAL feature, for the polyhedra bound functor it lists in the
    collider (no polyhedron is created): granum has neither, so here ``features`` names CGAL and
    ``Bo1_Polyhedra_Aabb`` is another bound functor the list already holds. Then its contacts against what YADE
    recorded after the same script (cdm_check.py)."""
    class YadeCheckError(Exception):
        pass

    ns: dict = {}
    exec("from granum.yade import *", ns)
    ns.update(YadeCheckError=YadeCheckError, features=[*ns["features"], "CGAL"],
              Bo1_Polyhedra_Aabb=ns["Bo1_Sphere_Aabb"])
    exec(compile(Path(CHECK).read_text(), CHECK, "exec"), ns)
    ref = reference("cdm_check")
    assert (yade.O.iter, yade.O.dt) == (ref["iter"], ref["dt"])
    for want in ref["contacts"]:
        i = yade.O.interactions[want["ids"][0], want["ids"][1]]
        assert [i.id1, i.id2] == want["ids"]
        got = {"ids": want["ids"], "refR1": i.geom.refR1, "refR2": i.geom.refR2, "pen": i.geom.penetrationDepth,
               "R": i.phys.R, "isYielding": i.phys.isYielding, "kn": i.phys.kn, "ks": i.phys.ks, "kno": i.phys.kno,
               "normalForce": list(i.phys.normalForce), "shearForce": list(i.phys.shearForce),
               "f": list(yade.O.forces.f(min(want["ids"])))}
        # the facet's normal has a round-off component (1e-16) that gives its shear force 1e-13 N (YADE: 0)
        assert_close(got, want, f"contact {want['ids']}", rtol=1e-10, atol=1e-12 * abs(want["normalForce"][2]))


def _pair(y, mat1, mat2, delta, r1=0.1, r2=0.15, geom=None):
    """Two fixed spheres (radii r1, r2) overlapping by delta, the CDM functors (``geom``: the geometry functor,
    default Ig2_Sphere_Sphere_ScGeom), dt 1e-6; one step."""
    m1 = y.O.materials.append(mat1)
    m2 = m1 if mat2 is mat1 else y.O.materials.append(mat2)
    y.O.bodies.append([y.sphere((0, 0, 0), r1, material=m1, fixed=True),
                       y.sphere((r1 + r2 - delta, 0, 0), r2, material=m2, fixed=True)])
    y.O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]),
                   y.InteractionLoop([geom or y.Ig2_Sphere_Sphere_ScGeom()],
                                     [y.Ip2_FrictMatCDM_FrictMatCDM_MindlinPhysCDM(),
                                      y.Ip2_FrictMat_FrictMatCDM_MindlinPhysCDM()],
                                     [y.Law2_ScGeom_MindlinPhysCDM_HertzMindlinCDM()]),
                   y.NewtonIntegrator(damping=0)]
    y.O.dt = 1e-6
    y.O.step()
    return y.O.interactions[0, 1]


def _press(y, delta, r1=0.1, r2=0.15):
    """Move sphere 2 so that the overlap is delta, then one step."""
    y.O.bodies[1].state.pos = (r1 + r2 - delta, 0, 0)
    y.O.step()


E1, E2, NU1, NU2, R1, R2 = 1e8, 2e8, 0.25, 0.15, 0.1, 0.15
E_STAR = 1 / ((1 - NU1 ** 2) / E1 + (1 - NU2 ** 2) / E2)
R0 = R1 * R2 / (R1 + R2)


def _peak_pressure(delta_el, r):
    return 2 * E_STAR / math.pi * math.sqrt(delta_el / r)


def test_hertz_before_damage(yade):
    """Below the strength: F_n = 4/3 E* sqrt(R*) delta^(3/2), k_n = F_n / delta, k_s = 8 G* sqrt(R* delta),
    R stays R*, and the friction coefficient is mu0 + c1/(1 + c2 sigma) with sigma = F_n / (pi R* delta)."""
    mats = [yade.FrictMatCDM(young=E1, poisson=NU1, frictionAngle=0.4, sigmaMax=4e7, alpha=1.0, c1=0.3, c2=2e-6),
            yade.FrictMatCDM(young=E2, poisson=NU2, frictionAngle=0.3, sigmaMax=5e7, alpha=1.2, c1=0.5, c2=1e-6)]
    g_star = 1 / (2 * (2 - NU1) * (1 + NU1) / E1 + 2 * (2 - NU2) * (1 + NU2) / E2)
    i = _pair(yade, *mats, delta=1e-4)
    for delta in (1e-4, 3e-4, 2e-4):
        _press(yade, delta)
        fn = 4 / 3 * E_STAR * math.sqrt(R0) * delta ** 1.5
        assert _peak_pressure(delta, R0) < 4e7
        assert i.phys.normalForce[0] == pytest.approx(fn, rel=1e-12)
        assert i.phys.kn == pytest.approx(fn / delta, rel=1e-12)
        assert i.phys.ks == pytest.approx(8 * g_star * math.sqrt(R0 * delta), rel=1e-12)
        assert i.phys.R == i.phys.radius == pytest.approx(R0, rel=1e-15) and not i.phys.isYielding
        sigma = fn / (math.pi * R0 * delta)
        assert i.phys.tangensOfFrictionAngle == pytest.approx(math.tan(0.3) + 0.3 / (1 + 1e-6 * sigma), rel=1e-12)
    assert (i.phys.sigmaMax, i.phys.c1, i.phys.c2, i.phys.mu0) == (4e7, 0.3, 1e-6, pytest.approx(math.tan(0.3)))
    assert i.phys.alphaFac == pytest.approx((1 - math.sin(1.0)) / math.sin(1.0), rel=1e-15)


def test_conical_damage_loading_and_unloading(yade):
    """Loading past the strength: the peak pressure 2E*/pi sqrt(delta_el/R) stays at sigmaMax as R grows, with the
    plastic overlap (R - R0)(1 - sin alpha)/sin alpha; unloading keeps R (elastic with the damaged radius) and the
    force vanishes once the overlap is all plastic; reloading is elastic until the last peak."""
    sigma_max, alpha = 2e6, 1.0
    a_f = (1 - math.sin(alpha)) / math.sin(alpha)
    mats = [yade.FrictMatCDM(young=E1, poisson=NU1, sigmaMax=sigma_max, alpha=alpha),
            yade.FrictMatCDM(young=E2, poisson=NU2, sigmaMax=5e6, alpha=1.2)]
    i = _pair(yade, *mats, delta=1e-4)
    radii = []
    for delta in np.linspace(2e-4, 2e-3, 9):
        _press(yade, delta)
        r = i.phys.R
        d_el = delta - (r - R0) * a_f
        k = (math.pi * sigma_max / (2 * E_STAR)) ** 2
        assert i.phys.isYielding
        assert r == pytest.approx((delta + R0 * a_f) / (k + a_f), rel=1e-12)
        assert _peak_pressure(d_el, r) == pytest.approx(sigma_max, rel=1e-12)
        assert i.phys.normalForce[0] == pytest.approx(4 / 3 * E_STAR * math.sqrt(r) * d_el ** 1.5, rel=1e-12)
        radii.append(r)
    assert np.all(np.diff(radii) > 0)
    r, plastic = radii[-1], (radii[-1] - R0) * a_f
    for delta in plastic + (2e-3 - plastic) * np.array([0.5, 0.01, 0.9]):   # unloading, reloading below the peak
        _press(yade, delta)
        assert not i.phys.isYielding and i.phys.R == r
        assert i.phys.normalForce[0] == pytest.approx(4 / 3 * E_STAR * math.sqrt(r) * (delta - plastic) ** 1.5,
                                                      rel=1e-9)
    _press(yade, plastic - 1e-6)
    assert (i.phys.normalForce[0], i.phys.kn, i.phys.ks) == (0.0, 0.0, 0.0) and yade.O.interactions[0, 1].isReal
    _press(yade, -1e-6)
    assert not yade.O.interactions.has(0, 1) or not yade.O.interactions[0, 1].isReal


def test_sliding_limit_follows_the_pressure(yade):
    """A sliding contact pressed further (yielding): |F_s| = mu F_n with mu = mu0 + c1/(1 + c2 sigma),
    sigma = F_n/(pi R delta_el)."""
    mat = yade.FrictMatCDM(young=E1, poisson=NU1, frictionAngle=0.2, sigmaMax=2e6, alpha=1.3, c1=0.4, c2=3e-6)
    i = _pair(yade, mat, mat, delta=1e-3, r2=R1)
    yade.O.bodies[1].state.vel = (-0.5, 5, 0)
    for _ in range(30):
        yade.O.step()
    assert i.phys.isSliding and i.phys.isYielding
    fn = i.phys.normalForce.norm()
    d_el = i.geom.penetrationDepth - (i.phys.R - i.phys.radius) * i.phys.alphaFac
    mu = math.tan(0.2) + 0.4 / (1 + 3e-6 * fn / (math.pi * i.phys.R * d_el))
    assert i.phys.shearForce.norm() == pytest.approx(mu * fn, rel=1e-12)
    assert i.phys.tangensOfFrictionAngle == pytest.approx(mu, rel=1e-14)
    law = yade.O.engines[2].lawDispatcher.functors[0]
    assert (law.ratioSlidingContacts(), law.ratioYieldingContacts()) == (1.0, 1.0)


def test_frictmat_with_frictmatcdm_in_either_order(yade):
    """Ip2_FrictMat_FrictMatCDM_MindlinPhysCDM takes the FrictMatCDM's strength and angle and a constant friction,
    whichever body is id1 (YADE aborts when the FrictMatCDM body is id1)."""
    plain = yade.FrictMat(young=E1, poisson=NU1, frictionAngle=0.4)
    cdm = yade.FrictMatCDM(young=E2, poisson=NU2, frictionAngle=0.3, sigmaMax=5e6, alpha=1.0, c1=0.1, c2=0.4)
    phys = []
    for mats in ((plain, cdm), (cdm, plain)):
        yade.O.reset()
        i = _pair(yade, *mats, delta=1e-3)
        phys.append((i.phys.sigmaMax, i.phys.alphaFac, i.phys.c1, i.phys.c2, i.phys.E, i.phys.R,
                     i.phys.normalForce.norm()))
    assert phys[0] == pytest.approx(phys[1], rel=1e-15)
    assert phys[0][:4] == (5e6, pytest.approx((1 - math.sin(1.0)) / math.sin(1.0)), 0.0, 0.0)


def test_threads_give_the_same_bits(tmp_path):
    """The CDM lattice benchmark above the parallel threshold, contacts crushed from the first step: -j1 and -j2
    give the same positions and angular velocities, bit for bit."""
    script = Path(__file__).parents[1] / "benchmarks" / "dense_lattice.py"
    states = {}
    for j in ("1", "2"):
        out = tmp_path / f"j{j}.txt"
        subprocess.run([sys.executable, "-m", "granum", "-j", j, str(script)], check=True, timeout=1800,
                       env={**os.environ, "BENCH_N": "12", "BENCH_STEPS": "200", "BENCH_LAW": "cdm",
                            "BENCH_DUMP": str(out)},
                       capture_output=True)
        states[j] = out.read_text()
    assert states["1"] == states["2"]


def test_save_load_continue_equals_the_uninterrupted_run(yade, tmp_path):
    """Spheres falling onto a hertzian wall and crushing: save -> load -> continue gives the bits of the
    uninterrupted run (R, the friction coefficient and the shear force travel with the checkpoint)."""
    def scene():
        yade.O.reset()
        yade.O.materials.append(yade.FrictMatCDM(young=1e7, poisson=0.3, density=2600, frictionAngle=0.5,
                                                 sigmaMax=2e5, alpha=1.2, c1=0.2, c2=1e-5))
        sp = yade.pack.SpherePack()
        sp.makeCloud((0, 0, 0), (1, 1, 0.2), rMean=0.04, rRelFuzz=0.3, seed=3)
        sp.toSimulation()
        yade.O.bodies.append(yade.utils.wall(0, axis=2))
        yade.O.engines = [yade.ForceResetter(),
                          yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb(), yade.Bo1_Wall_Aabb()]),
                          yade.InteractionLoop([yade.Ig2_Sphere_Sphere_ScGeom(),
                                                yade.Ig2_Wall_Sphere_ScGeom(hertzian=True)],
                                               [yade.Ip2_FrictMatCDM_FrictMatCDM_MindlinPhysCDM()],
                                               [yade.Law2_ScGeom_MindlinPhysCDM_HertzMindlinCDM()]),
                          yade.NewtonIntegrator(gravity=(0, 0, -9.81), damping=0.1)]
        yade.O.dt = 2e-5

    resumed_run_matches(yade, scene, 3000, tmp_path / "cdm.yade")
    law = yade.O.engines[2].lawDispatcher.functors[0]
    assert yade.O.interactions.countReal() > 10 and law.ratioYieldingContacts() > 0


@pytest.mark.parametrize("kw, bad", [(dict(sigmaMax=0.0), "sigmaMax.*0.0"), (dict(sigmaMax=-2e6), "sigmaMax.*-2"),
                                     (dict(alpha=0.0), "alpha.*0.0"), (dict(alpha=math.pi / 2), "alpha.*1.57"),
                                     (dict(alpha=2.0), "alpha.*2.0"), (dict(c1=-0.1), "c1.*-0.1"),
                                     (dict(c2=-1e-6), "c2.*-1e-06"), (dict(c2=math.nan), "c2.*nan")])
def test_bad_material_values_are_refused_naming_them(yade, kw, bad):
    with pytest.raises(ValueError, match=bad):
        yade.FrictMatCDM(**kw)
    mat = yade.FrictMatCDM(sigmaMax=1e6)
    with pytest.raises(ValueError, match=bad):
        setattr(mat, *next(iter(kw.items())))


@pytest.mark.parametrize("sigma_max", [None, 5.4e7])
def test_a_strength_not_below_e_star_is_refused_before_the_run(yade, sigma_max):
    """sigmaMax must stay below the pair's E* (here 5.33e7 Pa; YADE aborts the contact): the default 1e99 and
    5.4e7 are refused before the first step, naming the value and the materials; nothing ran."""
    kw = {} if sigma_max is None else {"sigmaMax": sigma_max}
    mat = yade.FrictMatCDM(young=1e8, poisson=0.25, label="grain", **kw)
    with pytest.raises(ValueError, match=r"material 0 'grain' \(FrictMatCDM\).*sigmaMax=(1e\+99|54000000).*E\* = "):
        _pair(yade, mat, mat, delta=1e-4, r2=R1)
    assert yade.O.iter == 0


def test_ratios_without_contacts_are_nan(yade):
    law = yade.Law2_ScGeom_MindlinPhysCDM_HertzMindlinCDM()
    assert math.isnan(law.ratioYieldingContacts()) and math.isnan(law.ratioSlidingContacts())


def test_the_law_on_an_scgeom6d_is_refused_naming_the_histories(yade):
    """MindlinPhysCDM's columns are those ScGeom6D's share (no cohesive pool widens for this law): the
    combination is refused before the run, naming both."""
    mat = yade.FrictMatCDM(young=E1, poisson=NU1, sigmaMax=2e6)
    with pytest.raises(ValueError, match="'cdm'.*'scgeom6d'|'scgeom6d'.*'cdm'"):
        _pair(yade, mat, mat, delta=1e-4, r2=R1, geom=yade.Ig2_Sphere_Sphere_ScGeom6D())
    assert yade.O.iter == 0
