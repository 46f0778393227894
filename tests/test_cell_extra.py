"""Cell attributes added for YADE's periodic examples: prevHSize, shearTrsf/unshearTrsf, velGradChanged,
flipCell (its integer matrix on YADE's cases, and contacts unchanged by a flip), utils.flipCell,
stressTensorOfPeriodicCell and totalForceInVolume (tests/reference/yade/cell_extra.py)."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import REFERENCE, frict_engines, reference


def M(m):
    return np.asarray(m, dtype=float)


def test_step_attributes_equal_yades(yade):
    ref = reference("cell_extra")["steps"]
    O = yade.O
    O.periodic = True
    O.cell.hSize = yade.Matrix3(1, 0.2, 0, 0, 1, 0, 0, 0, 1)
    O.bodies.append(yade.sphere((0.5, 0.5, 0.5), 0.1))
    O.engines = frict_engines(yade)
    O.dt = 1e-3
    O.cell.velGrad = yade.Matrix3(0, 1, 0, 0, -.5, 0, 0, 0, 0)
    for row in ref:
        assert O.iter == row["iter"]
        for name in ("hSize", "prevHSize", "shearTrsf", "unshearTrsf", "trsf"):
            np.testing.assert_allclose(M(getattr(O.cell, name)), row[name], rtol=1e-14, atol=1e-16, err_msg=name)
        assert O.cell.velGradChanged == row["velGradChanged"]
        O.step()


@pytest.mark.parametrize("case", range(10))
def test_flip_matrices_equal_yades(yade, case):
    """The flip matrix and the cell after, on YADE's cases (ties at 1/2 included: .5 flips, -.5 does not)."""
    ref = reference("cell_extra")["flips"][case]
    O = yade.O
    O.periodic = True
    O.bodies.append(yade.sphere((0.5, 0.5, 0.5), 0.1))
    O.cell.hSize = yade.Matrix3(*ref["hSize0"])
    flip = M(O.cell.flipCell())
    np.testing.assert_array_equal(flip, ref["flip"])
    np.testing.assert_allclose(M(O.cell.hSize), ref["hSize"], rtol=1e-15, atol=1e-15)
    np.testing.assert_allclose(M(O.cell.prevHSize), ref["prevHSize"], rtol=1e-15, atol=1e-15)
    assert M(O.cell.refHSize).ravel().tolist() == ref["hSize0"] and M(O.cell.trsf).tolist() == ref["trsf"]
    assert round(abs(np.linalg.det(flip))) == 1


def test_flip_keeps_every_contact_and_the_dynamics(yade):
    """A sheared dense periodic packing: after flipCell positions and hSize @ cellDist (each contact's branch) are
    the same, hSize changed by an integer matrix of determinant 1, and the next 50 steps give the same
    positions as without the flip, to rounding (the images are the same points)."""
    def scene():
        O = yade.O
        O.reset()
        O.periodic = True
        O.cell.hSize = yade.Matrix3(1, 0.6, 0, 0, 1, 0, 0, 0, 1)
        sp = yade.pack.SpherePack()
        sp.load(str(REFERENCE / "periiso_pack.txt"))
        for c, r in sp:
            O.bodies.append(yade.sphere(O.cell.hSize * yade.Vector3(c[0], c[1] / 1.2, c[2] / 0.9), r))
        O.engines = frict_engines(yade, damping=0.2)
        O.dt = 1e-6
        O.cell.velGrad = yade.Matrix3(0, 1, 0, 0, 0, 0, 0, 0, 0)
        O.run(5, True)

    def branches():
        O = yade.O
        h = M(O.cell.hSize)
        return {(i.id1, i.id2): M(O.bodies[i.id2].state.pos) + h @ M(i.cellDist) - M(O.bodies[i.id1].state.pos)
                for i in O.interactions if i.isReal}

    scene()
    yade.O.run(50, True)
    straight = np.array([M(b.state.pos) for b in yade.O.bodies])
    scene()
    before, h0 = branches(), M(yade.O.cell.hSize)
    flip = M(yade.O.cell.flipCell())
    assert not np.array_equal(flip, np.eye(3)) and round(abs(np.linalg.det(flip))) == 1
    np.testing.assert_allclose(M(yade.O.cell.hSize), h0 @ flip, rtol=1e-15)
    after = branches()
    assert len(before) > 20 and before.keys() == after.keys()
    for key, v in before.items():
        np.testing.assert_allclose(after[key], v, rtol=0, atol=1e-14)
    yade.O.run(50, True)
    np.testing.assert_allclose(np.array([M(b.state.pos) for b in yade.O.bodies]), straight, rtol=0, atol=1e-12)


def test_utils_functions_equal_yades(yade):
    ref = reference("cell_extra")
    O = yade.O
    O.periodic = True
    O.cell.hSize = yade.Matrix3(1, 1.7, 0, 0, 1, 0, 0, 0, 1)
    with pytest.warns(DeprecationWarning):
        assert M(yade.utils.flipCell()).tolist() == ref["utils_flipCell"]
    np.testing.assert_allclose(M(O.cell.hSize), ref["utils_flipCell_hSize"], rtol=1e-15)
    O.reset()
    O.periodic = True
    O.cell.setBox(1, 1.2, 0.9)
    sp = yade.pack.SpherePack()
    sp.load(str(REFERENCE / "periiso_pack.txt"))
    for c, r in sp:
        O.bodies.append(yade.sphere(c, r * 1.6))
    O.engines = frict_engines(yade)
    O.dt = 1e-6
    O.step()
    assert len([i for i in O.interactions if i.isReal]) == ref["nReal"]
    # getStress's branch vectors are the positions after the step (YADE's: the contact geometry of the step),
    # which moved by the step's motion: 5e-5 of the stress
    for got, want in ((yade.stressTensorOfPeriodicCell(), ref["getStress"]),
                      (yade.stressTensorOfPeriodicCell(), ref["stressTensorOfPeriodicCell"]),
                      (yade.stressTensorOfPeriodicCell(2.0), ref["stressTensorOfPeriodicCell_v2"])):
        np.testing.assert_allclose(M(got), want, rtol=1e-4, atol=1e-4 * np.abs(want).max())
    np.testing.assert_array_equal(M(yade.stressTensorOfPeriodicCell()), M(yade.getStress()))
    force, stiff = yade.totalForceInVolume()
    np.testing.assert_allclose(M(force), ref["totalForceInVolume"][0], rtol=1e-10)
    assert stiff == pytest.approx(ref["totalForceInVolume"][1], rel=1e-12)


def test_flip_flippable_is_refused_by_name(yade):
    assert yade.O.cell.flipFlippable is False
    yade.O.cell.flipFlippable = False
    with pytest.raises(NotImplementedError, match="flipFlippable"):
        yade.O.cell.flipFlippable = True
