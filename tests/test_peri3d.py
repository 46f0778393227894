"""Peri3dController against YADE 2023.02a (tests/reference/yade/peri3d.py): strain paths step by step (the
strain vector, the cell's trsf and velocity gradient), a path with intermediate points, the first steps of a
stress-controlled compression of a shared packing, the defaults and refused input."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import REFERENCE, frict_engines, reference


def M(m):
    return np.asarray(m, dtype=float)


def _one_sphere(y, **kw):
    y.O.periodic = True
    y.O.cell.setBox(1, 1, 1)
    y.O.bodies.append(y.sphere((0.5, 0.5, 0.5), 0.1))
    p3d = y.Peri3dController(label="p3d", **kw)
    y.O.engines = frict_engines(y, damping=0.2) + [p3d]   # YADE NewtonIntegrator()'s damping
    y.O.dt = 1e-3
    return p3d


@pytest.mark.parametrize("case, kw", [
    ("strain", dict(goal=(0.01, -0.02, 0, 0.004, 0, 0.002), stressMask=0, nSteps=10, doneHook="done.append(O.iter)")),
    ("path", dict(goal=(0.3, 0, 0, 0, 0, 0), stressMask=0, nSteps=10, xxPath=[(2, 3), (4, 1), (5, 2)]))])
def test_strain_paths_equal_yades_step_by_step(yade, case, kw):
    """Strain, rate, trsf and velGrad at each of 13 steps (nSteps 10, so 3 beyond the goal, along the last segment)
    to rounding; without doneHook the engine is dead after the goal; the hook runs in each step after it."""
    ref = reference("peri3d")
    yade.O._namespace = {"done": [], "O": yade.O}
    p3d = _one_sphere(yade, **kw)
    for row in ref[case]:
        yade.O.step()
        assert p3d.progress == pytest.approx(row["progress"], rel=1e-14)
        np.testing.assert_allclose(M(p3d.strain), row["strain"], rtol=1e-12, atol=1e-17)
        np.testing.assert_allclose(M(p3d.strainRate), row["strainRate"], rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(M(yade.O.cell.trsf), row["trsf"], rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(M(yade.O.cell.velGrad), row["velGrad"], rtol=1e-9, atol=1e-9)
        assert p3d.dead == row["dead"]
    if case == "strain":   # YADE runs the hook at the start of the step: O.iter one less than granum's after it
        assert [i - 1 for i in yade.O._namespace["done"]] == ref["strain_done_iters"]


def test_strain_path_is_followed_exactly(yade):
    """Closed form: with every component a strain, after n steps the strain vector is (n/nSteps) goal and the cell's
    trsf (one step behind) is 1 + the strain tensor of step n - 1 (shears gamma/2), for a path of 400 steps."""
    goal = np.array([0.02, -0.01, 0.005, 0.006, -0.004, 0.002])
    p3d = _one_sphere(yade, goal=tuple(goal), nSteps=400)
    for n in range(1, 401):
        yade.O.step()
        np.testing.assert_allclose(M(p3d.strain), n / 400 * goal, rtol=1e-12, atol=1e-16)
    e = 399 / 400 * goal
    tensor = np.array([[e[0], e[5] / 2, e[4] / 2], [e[5] / 2, e[1], e[3] / 2], [e[4] / 2, e[3] / 2, e[2]]])
    np.testing.assert_allclose(M(yade.O.cell.trsf), np.eye(3) + tensor, rtol=0, atol=1e-12)


def test_stress_control_follows_yade_on_a_shared_packing(yade):
    """Hydrostatic stress path to -20 MPa on YADE's packing: the first step's rate (YADE's compliance estimate),
    the predictor's rates and the strains equal YADE's to 1e-6 for 60 steps (the packing's dynamics then
    separates the two runs, as any two codes' would)."""
    ref = [r for r in reference("peri3d")["stress"] if r["iter"] <= 60]
    y = yade
    y.O.periodic = True
    y.O.cell.setBox(1, 1.2, 0.9)
    sp = y.pack.SpherePack()
    sp.load(str(REFERENCE / "periiso_pack.txt"))
    y.O.materials.append(y.FrictMat(young=30e9, frictionAngle=0.1, poisson=0.3, density=1e3))
    for c, r in sp:
        y.O.bodies.append(y.sphere(c, r * 1.25))
    p3d = y.Peri3dController(goal=(-2e7, -2e7, -2e7, 0, 0, 0), stressMask=0b000111, nSteps=300, maxStrain=.5,
                             youngEstimation=.5e9, doneHook="O.pause()")
    y.O.engines = frict_engines(y, damping=0.2) + [p3d]   # YADE NewtonIntegrator()'s damping
    y.O.dt = y.PWaveTimeStep() / 2
    for row in ref:
        y.O.run(row["iter"] - y.O.iter, True)
        np.testing.assert_allclose(M(p3d.strainRate), row["strainRate"], rtol=1e-6, atol=1e-9)
        np.testing.assert_allclose(M(p3d.strain), row["strain"], rtol=1e-6, atol=1e-12)
        np.testing.assert_allclose(M(p3d.stressIdeal), row["stressIdeal"], rtol=1e-12)
        np.testing.assert_allclose(M(p3d.stress)[:3], row["stress"][:3], rtol=0.05)   # contact dynamics: 2 %


def test_defaults_equal_yades(yade):
    ref = reference("peri3d")["defaults"]
    p3d = yade.Peri3dController()
    for name in ("goal", "stressMask", "nSteps", "progress", "mod", "doneHook", "maxStrainRate", "maxStrain",
                 "youngEstimation", "poissonEstimation", "stress", "strain", "strainRate", "stressRate",
                 "stressIdeal", "xxPath", "xyPath"):
        got = getattr(p3d, name)
        got = [list(M(v)) for v in got] if name.endswith("Path") else got
        want = ref[name]
        assert (np.asarray(got, dtype=float) == np.asarray(want, dtype=float)).all() if not isinstance(want, str) \
            else got == want, name


def test_bad_input_is_refused(yade):
    with pytest.raises(ValueError, match="stressMask"):
        yade.Peri3dController(stressMask=64)
    with pytest.raises(ValueError, match="nSteps"):
        yade.Peri3dController(nSteps=0)
    with pytest.raises(ValueError, match="xxPath"):
        yade.Peri3dController(xxPath=[(2, 1), (1, 1)])
    with pytest.raises(ValueError, match="yyPath"):
        yade.Peri3dController(yyPath=[(1, 0)])
    with pytest.raises(TypeError, match="6-vector"):
        yade.Peri3dController(goal=(1, 2, "x", 0, 0, 0))
    yade.O.bodies.append(yade.sphere((0, 0, 0), 0.1))
    yade.O.engines = [yade.Peri3dController()]
    with pytest.raises(RuntimeError, match="periodic"):
        yade.O.run(1, True)
