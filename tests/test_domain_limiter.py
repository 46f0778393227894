"""DomainLimiter against real YADE 2023.02a (tests/reference/yade/domain_limiter.json)."""

from __future__ import annotations

import pytest
from conftest import frict_engines, reference

REF = reference("domain_limiter")


def test_defaults(yade):
    d = yade.DomainLimiter()
    for name, value in REF["defaults"].items():
        if name in ("ompThreads",):
            continue
        got = getattr(d, name)
        assert (list(got) if name in ("lo", "hi") else got) == value, name


def test_erases_what_left_the_box(yade):
    """Spheres outside (a fixed one too), a clump with its centre outside (with its members); a clump
    centred on a face stays; nDeleted counts a clump once, vDeleted only spheres; the mask selects."""
    O, s = yade.O, yade.sphere
    engines = frict_engines(yade, bounds=[yade.Bo1_Sphere_Aabb()], geoms=[yade.Ig2_Sphere_Sphere_ScGeom()])
    dl = yade.DomainLimiter(lo=(-1, -1, -1), hi=(1, 1, 1), iterPeriod=1, label="dl")
    O.engines = engines[:3] + [dl] + engines[3:]
    O.dt = 1e-6
    O.bodies.append([s((0, 0, 0), .1), s((2, 0, 0), .1, mask=2), s((0, 0, 5), .2), s((0, 0, -5), .1, fixed=True)])
    O.bodies.appendClumped([s((0.9, 0, 0), .1), s((1.1, 0, 0), .1)])
    O.bodies.appendClumped([s((1.05, 0, 0.5), .1), s((1.25, 0, 0.5), .1)])
    O.bodies.appendClumped([s((0.5, 0.5, 0.5), .1), s((0.7, 0.5, 0.5), .1)])
    for k, ref in enumerate(REF["steps"]):
        if k == 2:
            dl.mask = 2
            O.bodies.append([s((3, 0, 0), .1, mask=1), s((3, 3, 0), .1, mask=3)])
        O.step()
        assert O.iter == ref["iter"]
        assert [b.id for b in O.bodies] == ref["bodies"]
        assert dl.nDeleted == ref["nDeleted"]
        assert dl.mDeleted == pytest.approx(ref["mDeleted"], rel=1e-12)
        assert dl.vDeleted == pytest.approx(ref["vDeleted"], rel=1e-12)


def test_a_facet_outside_stays(yade):
    """YADE erases the spheres outside the box (a fixed one too) but keeps a facet there."""
    O, s = yade.O, yade.sphere
    O.bodies.append([yade.facet([(0, 3, 0), (1, 3, 0), (0, 4, 0)]), s((0, 3, 0), .1, fixed=True), s((0, -3, 0), .1)])
    dl = yade.DomainLimiter(lo=(-1, -1, -1), hi=(1, 1, 1), iterPeriod=1)
    O.engines = [yade.ForceResetter(), yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb(), yade.Bo1_Facet_Aabb()]),
                 dl, yade.NewtonIntegrator()]
    O.dt = 1e-4
    O.run(3, True)
    assert [b.id for b in O.bodies] == REF["facet"]["bodies"] and dl.nDeleted == REF["facet"]["nDeleted"]
