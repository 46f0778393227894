"""Which bodies the periodic collider refuses as wider than half the cell, against real YADE 2023.02a
(tests/reference/yade/periodic_span.py): a lone wide sphere and the smaller id of a pair are accepted, the
larger id of a pair that meets is refused, allowBiggerThanPeriod accepts all; in sheared cells the span is
measured along the cell's frame (a sphere's exact extent: cellFlipping.py's 45-degree shear no longer refused).
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import reference

from granum.kernels.collider_periodic import HALF_CELL

REF = reference("periodic_span")
CASES = {c["name"]: c for c in REF["cases"]}


def _run(y, case):
    y.O.periodic = True
    y.O.cell.hSize = y.Matrix3(*[x for row in case["hSize"] for x in row])
    y.O.bodies.append([y.sphere(tuple(c), r) for c, r in case["spheres"]])
    y.O.engines = [y.ForceResetter(),
                   y.InsertionSortCollider([y.Bo1_Sphere_Aabb()], verletDist=case["verletDist"],
                                           allowBiggerThanPeriod=case["allowBiggerThanPeriod"]),
                   y.InteractionLoop([y.Ig2_Sphere_Sphere_ScGeom()], [y.Ip2_FrictMat_FrictMat_FrictPhys()],
                                     [y.Law2_ScGeom_FrictPhys_CundallStrack()]),
                   y.NewtonIntegrator(gravity=(0, 0, 0))]
    y.O.dt = 1e-6
    try:
        for _ in range(5):
            y.O.step()
    except y.SimulationError as e:
        return str(e)
    return None


@pytest.mark.parametrize("name", list(CASES))
def test_refused_as_yade(yade, name):
    """Refused where YADE raised (naming the wider body of larger id), else the same real interactions
    (ids, cellDist) after five steps."""
    case = CASES[name]
    error = _run(yade, case)
    assert (error is not None) == case["raised"], error
    if error is not None:
        assert "body 1 (Sphere" in error  # in every refused case, the wide body of larger id
        assert "spans over half of the periodic cell" in error
        assert yade.O.iter == 0
    else:
        assert yade.O.iter == case["iter"]
        got = [[i.id1, i.id2, list(i.cellDist), i.isReal] for i in yade.O.interactions]
        assert got == case["interactions"]


def test_sheared_span_is_the_exact_extent(yade):
    """In a cell sheared by g = 1 (cellFlipping.py's flip point) a sphere of radius r spans 2 r sqrt(2) / L
    cells along x: accepted just below half a cell and refused just above, whatever the verlet distance adds."""
    limit = HALF_CELL / (2 * np.sqrt(2))  # the radius of a sphere spanning half the cell [m] (L = 1)
    for r, refused in ((0.99 * limit, False), (1.01 * limit, True)):
        yade.O.reset()
        case = dict(CASES["sheared_narrow"], spheres=[[[.3, .4, .5], .05], [[.3, .4, .5 + r], r]])
        assert (_run(yade, case) is not None) == refused, r
