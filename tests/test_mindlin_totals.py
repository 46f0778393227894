"""Law2_ScGeom_MindlinPhys_Mindlin's energy accumulators keep the share of contacts that ended (by the law or
erased from Python), as YADE 2023.02a's do (tests/reference/yade/mindlin_ended.py), and survive a checkpoint."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import reference

REF = reference("mindlin_ended")


def _run(y, erase_at=None, path=None):
    """The reference script's run; with ``path``, saved there and loaded again once the contact has ended."""
    O = y.O
    O.reset()
    m = O.materials.append(y.FrictMat(young=1e7, poisson=0.3, density=2000, frictionAngle=0.3))
    a = O.bodies.append(y.sphere((0, 0, 0), 0.01, material=m, fixed=True))
    b = O.bodies.append(y.sphere((0, 0, 0.0201), 0.01, material=m))
    O.bodies[b].state.vel = (0.3, 0, -0.5)
    O.engines = [y.ForceResetter(), y.InsertionSortCollider([y.Bo1_Sphere_Aabb()]),
                 y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom()],
                                   [y.Ip2_FrictMat_FrictMat_MindlinPhys(betan=0.3, betas=0.2)],
                                   [y.Law2_ScGeom_MindlinPhys_Mindlin(calcEnergy=True, label="law")]),
                 y.NewtonIntegrator(damping=0, gravity=(0, 0, 0))]
    O.dt = 1e-6

    def values():
        law = O.engines[2].lawDispatcher.functors[0]
        return [getattr(law, k) for k in REF["names"]]

    out = {"every_200": []}
    seen = False
    for _ in range(20000):
        O.step()
        if O.iter == erase_at:
            out["before_erase"] = values()
            O.interactions.erase(a, b)
            out["after_erase"] = values()
        real = O.interactions.has(a, b) and O.interactions[a, b].isReal
        seen = seen or real
        if O.iter % 200 == 0:
            out["every_200"].append([O.iter, real] + values())
        if seen and not real and O.iter > (erase_at or 0) + 1:
            out["ended_at"] = O.iter
            out["at_end"] = values()
            break
    if path:
        O.save(path)
        O.reset()
        O.load(path)
    for _ in range(3):
        O.step()
    out["after"] = values()
    return out


@pytest.mark.parametrize("case", ["plain", "erase"])
def test_accumulators_keep_ended_contacts_as_yade(yade, case):
    ref = REF[case]
    got = _run(yade, erase_at=ref["erased_at"])
    assert got["ended_at"] == ref["ended_at"]
    assert [r[:2] for r in got["every_200"]] == [r[:2] for r in ref["every_200"]]
    np.testing.assert_allclose([r[2:] for r in got["every_200"]], [r[2:] for r in ref["every_200"]], rtol=1e-6,
                               atol=1e-12)
    # after the contact ended (and some steps without contact) the totals stay, as in YADE
    np.testing.assert_allclose(got["at_end"], ref["at_end"], rtol=1e-6)
    np.testing.assert_allclose(got["after"], ref["after"], rtol=1e-6)
    assert got["after"] == got["at_end"] and min(abs(v) for v in got["after"]) > 0
    if case == "erase":
        assert got["after_erase"] == got["before_erase"]


def test_accumulators_survive_save_and_load(yade, tmp_path):
    """The ended contact's totals travel with the checkpoint (saved and loaded once no contact is left): the
    same numbers as the uninterrupted run."""
    whole = _run(yade)
    again = _run(yade, path=str(tmp_path / "m.yade"))
    assert yade.O.interactions.countReal() == 0
    assert again["after"] == whole["after"] and min(abs(v) for v in whole["after"]) > 0
