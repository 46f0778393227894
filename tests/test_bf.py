"""yade.bf (breakage functions) against real YADE 2023.02a (tests/reference/yade/bf.json), the
failure criterion against its formula, and conservation of mass and momentum in breakage."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import reference

from granum.mathtypes import as_quat_wxyz
from granum.yade.clumps import rotation

REF = reference("bf")


@pytest.fixture
def bf(yade):
    from granum.yade import bf

    yade.O.engines = [yade.ForceResetter(), yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb()]),
                      yade.InteractionLoop([yade.Ig2_Sphere_Sphere_ScGeom()], [yade.Ip2_FrictMat_FrictMat_FrictPhys()],
                                           [yade.Law2_ScGeom_FrictPhys_CundallStrack()]),
                      yade.NewtonIntegrator(damping=0)]
    yade.O.dt = 1e-6
    return bf


def _failure(bf, O, i, ref):
    weib = [{}, {"wei_V0": 1.0}, {"wei_V0": 1.0, "wei_P": 0.9}, {"wei_V0": 1.0, "wei_m": 5}]
    for key, values in ref.items():
        st, sc = (float(x) for x in key.split(","))
        got = [bf.checkFailure(O.bodies[i], st, sc, **w) for w in weib]
        np.testing.assert_allclose(got, values["weibull"], rtol=1e-5, err_msg=key)
        assert bf.checkFailure(O.bodies[i], st, sc, weibull=False) == pytest.approx(values["plain"], rel=1e-5)
        assert bf.checkFailure(O.bodies[i], st, sc, weibull=False, stress_correction=False) == pytest.approx(
            values["plain_nocorr"], rel=1e-5)


def _stress(bf, O, i, ref):
    # YADE computes the tensor in float32: agreement to its precision, relative to the largest entry
    scale = np.abs(ref["stress_nocorr"]).max()
    np.testing.assert_allclose(bf.stressTensor(O.bodies[i]), ref["stress"], atol=3e-6 * scale)
    np.testing.assert_allclose(bf.stressTensor(O.bodies[i], stress_correction=False), ref["stress_nocorr"],
                               atol=3e-6 * scale)
    np.testing.assert_allclose(np.asarray(O.forces.f(i)), ref["force"], rtol=1e-9, atol=1e-6)
    _failure(bf, O, i, ref["failure"])


def test_stress_and_failure_of_a_sphere_with_three_contacts(yade, bf):
    O, s = yade.O, yade.sphere
    i = O.bodies.append(s((0, 0, 0), 1))
    O.bodies.append([s((1.9, 0, 0), 1, fixed=True), s((-1.9, 0, 0), 1, fixed=True), s((0, 1.95, 0), 1, fixed=True)])
    O.step()
    _stress(bf, O, i, REF["stress"]["three_contacts"])


def test_stress_with_shear(yade, bf):
    O, s = yade.O, yade.sphere
    i = O.bodies.append(s((0, 0, 0), .5))
    O.bodies.append(s((0.6, 0.5, 0.2), .4, fixed=True))
    O.bodies[i].state.vel, O.bodies[i].state.angVel = (0, 0, 1), (0, 3, 0)
    O.step()
    O.step()
    _stress(bf, O, i, REF["stress"]["oblique_shear"])


def test_stress_of_clump_members(yade, bf):
    O, s = yade.O, yade.sphere
    _, ids = O.bodies.appendClumped([s((0, 0, 0), .5), s((0.6, 0, 0), .4)])
    O.bodies.append(s((-0.3, 0.8, 0.1), .4, fixed=True))
    O.step()
    _stress(bf, O, ids[0], REF["stress"]["clump_member"])
    _stress(bf, O, ids[1], REF["stress"]["clump_member_without_contact"])


def test_love_weber_closed_form(yade, bf):
    """Two equal opposite contacts along x on a sphere of radius r: sigma_xx = -2 F (r - d/2) / V, all
    else 0; a third unbalanced contact along y adds -F_y (r - d/2) / V without and a further
    -r F_y / V with the correction."""
    O, s = yade.O, yade.sphere
    r, d = 0.3, 0.02
    i = O.bodies.append(s((0, 0, 0), r, fixed=True))  # fixed: the overlaps stay as built
    O.bodies.append([s((2 * r - d, 0, 0), r, fixed=True), s((-(2 * r - d), 0, 0), r, fixed=True)])
    O.step()
    V = 4 / 3 * math.pi * r ** 3
    F = abs(O.interactions[0, 1].phys.normalForce[0])
    expect = np.zeros((3, 3))
    expect[0, 0] = -2 * F * (r - d / 2) / V
    np.testing.assert_allclose(bf.stressTensor(O.bodies[i]), expect, atol=1e-12 * F / V)
    O.bodies.append(s((0, 2 * r - d, 0), r, fixed=True))
    O.step()
    Fy = abs(O.interactions[0, 3].phys.normalForce[1])
    plain = bf.stressTensor(O.bodies[i], stress_correction=False)
    assert plain[1, 1] == pytest.approx(-Fy * (r - d / 2) / V, rel=1e-12)
    assert bf.stressTensor(O.bodies[i])[1, 1] == pytest.approx(plain[1, 1] - r * Fy / V, rel=1e-12)


@pytest.mark.parametrize("case", range(len(REF["criterion"]["cases"])))
def test_failure_criterion_on_given_tensors(yade, bf, monkeypatch, case):
    """YADE's effort for given stress tensors (stressTensor replaced), and the formula written out."""
    c = REF["criterion"]["cases"][case]
    M = np.array(c["tensor"])
    monkeypatch.setattr(bf.bf, "_stress", lambda *a: M.copy())
    r = REF["criterion"]["radius"]
    i = yade.O.bodies.append(yade.sphere((0, 0, 0), r))
    _failure(bf, yade.O, i, c["failure"])
    # the formula: s1/st - s3/sc across zero, else the larger of |s1|/st and |s3|/sc; Weibull size effect
    s = np.sort(np.linalg.eigvals(M).real)
    V = 4 / 3 * math.pi * r ** 3
    for st, sc in [(1.0, 1.0), (1.0, 2.0), (2.0, 1.0)]:
        e = s[2] / st - s[0] / sc if s[2] > 0 > s[0] else max(abs(s[2]) / st, abs(s[0]) / sc)
        w = (V / (0.01 * math.log(1 / (1 - 0.63)))) ** (1 / 3)
        assert bf.checkFailure(yade.O.bodies[i], st, sc, weibull=False) == pytest.approx(e if e > 1 else 0.0)
        assert bf.checkFailure(yade.O.bodies[i], st, sc) == pytest.approx(e * w if e * w > 1 else 0.0)


def _new_spheres(O, first):
    return sorted((b for b in O.bodies if b.id >= first), key=lambda b: b.id)


@pytest.mark.parametrize("name", list(REF["replace"]))
def test_replace_sphere_matches_yade(yade, bf, name):
    """Same number, radius and mass of subparticles, at the same places (as a set: equidistant lattice
    points may come in another order), total mass kept; YADE leaves them at rest, granum gives them
    the sphere's momentum."""
    O = yade.O
    ref = REF["replace"][name]
    kw = dict(ref["kw"])
    if "outer_predicate" in kw:
        kw["outer_predicate"] = yade.pack.inAlignedBox((-5, -5, -0.2 if name == "outer_predicate" else 0.7),
                                                        (5, 5, 5))
    i = O.bodies.append(yade.sphere((0, 0, 0), 1))
    O.bodies[i].state.vel, O.bodies[i].state.angVel = (1, 2, 3), (0, 0, 5)
    if name.startswith("neighbour"):
        O.bodies.append(yade.sphere((1.5, 0, 0), 1))
    P0, L0 = _momenta(O)
    ids = bf.replaceSphere(i, **kw)
    assert (O.bodies[i] is None) == ref["erased"] and len(O.bodies) == ref["len"]
    new = [b for b in ref["bodies"] if b["id"] >= (2 if name.startswith("neighbour") else 1)]
    assert ids == [b["id"] for b in new]
    got = sorted(tuple(np.round(O.bodies[k].state.pos, 9)) for k in ids)
    np.testing.assert_allclose(got, sorted(tuple(np.round(b["pos"], 9)) for b in new), atol=1e-9)
    for k, b in zip(ids, new, strict=True):
        assert O.bodies[k].shape.radius == pytest.approx(b["radius"], rel=1e-12)
        assert O.bodies[k].state.mass == pytest.approx(b["mass"], rel=1e-12)
    total = sum(b.state.mass for b in O.bodies)
    assert total == pytest.approx(ref["mass_after"], rel=1e-12)
    if "subparticles_mass" not in kw:  # the whole mass is kept: so is the momentum
        P1, L1 = _momenta(O)
        np.testing.assert_allclose(P1, P0, rtol=1e-12)
        np.testing.assert_allclose(L1, L0, rtol=1e-12, atol=1e-9)


def _momenta(O):
    P, L = np.zeros(3), np.zeros(3)
    for b in O.bodies:
        if b.isClumpMember or not b.dynamic:
            continue
        m, x, v = b.state.mass, np.asarray(b.state.pos), np.asarray(b.state.vel)
        R = rotation(as_quat_wxyz(b.state.ori))
        P += m * v
        L += np.cross(x, m * v) + R @ (np.asarray(b.state.inertia) * (R.T @ np.asarray(b.state.angVel)))
    return P, L


SCENES = {
    "line_middle": ([((0, 0, 0), 1), ((1.5, 0, 0), 1), ((3, 0, 0), 1)], [((1.5, 1.9, 0), 1), ((1.5, -1.9, 0), 1)]),
    "two_members": ([((0, 0, 0), 1), ((1.5, 0, 0), 1)], [((1.5, 1.9, 0), 1), ((1.5, -1.9, 0), 1)]),
    "triangle": ([((0, 0, 0), 1), ((1.5, 0, 0), 1), ((0.75, 1.2, 0), 1)], [((-1.9, 0, 0), 1), ((0, 0, 1.9), 1)]),
}


@pytest.mark.parametrize("name", list(SCENES))
def test_eval_clump_matches_yade_and_conserves_mass_and_momentum(yade, bf, name):
    """The bodies left (ids, shapes, clumps, radii, masses) are YADE's; positions of the remaining
    members too, subparticles as a set. Total mass and linear and angular momentum are conserved
    exactly (YADE: the mass to 1e-12 here, and every new body at rest)."""
    O = yade.O
    members, pressers = SCENES[name]
    ref = REF["clumps"][name]
    cid, ids = O.bodies.appendClumped([yade.sphere(c, r) for c, r in members], discretization=20)
    O.bodies.append([yade.sphere(c, r, fixed=True) for c, r in pressers])
    O.bodies[cid].state.vel = (1, 0, 0)
    O.step()
    np.testing.assert_allclose([bf.checkFailure(O.bodies[i], 1e3, 5e3, wei_V0=0.001) for i in ids],
                               ref["before"]["efforts"], rtol=1e-5)
    mass0 = _dynamic_mass(O)
    assert mass0 == pytest.approx(ref["before"]["mass"], rel=1e-12)
    P0, L0 = _momenta(O)
    assert bf.evalClump(cid, 2, 1e3, 5e3) is ref["returned"] is True
    assert len(O.bodies) == ref["len"]
    got = {b.id: b for b in O.bodies}
    assert sorted(got) == [b["id"] for b in ref["bodies"]]
    subs = []
    for b in ref["bodies"]:
        mine = got[b["id"]]
        assert type(mine.shape).__name__ == b["shape"] and mine.clumpId == b["clumpId"]
        assert mine.state.mass == pytest.approx(b["mass"], rel=1e-6)
        if b["shape"] == "Sphere":
            assert mine.shape.radius == pytest.approx(b["radius"], rel=1e-6)
            if mine.shape.radius < 1:
                subs.append((np.round(mine.state.pos, 6), np.round(b["pos"], 6)))
            else:
                np.testing.assert_allclose(np.asarray(mine.state.pos), b["pos"], atol=1e-9)
    np.testing.assert_allclose(sorted(map(tuple, (s[0] for s in subs))), sorted(map(tuple, (s[1] for s in subs))),
                               atol=1e-5)
    assert _dynamic_mass(O) == pytest.approx(mass0, rel=1e-13)
    assert ref["mass"] == pytest.approx(mass0, rel=1e-9)
    P1, L1 = _momenta(O)
    np.testing.assert_allclose(P1, P0, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(L1, L0, rtol=1e-11, atol=1e-8)


def _dynamic_mass(O):
    return sum(b.state.mass for b in O.bodies if b.dynamic and not b.isClumpMember)


def test_eval_clump_without_failure_changes_nothing(yade, bf):
    O = yade.O
    cid, _ = O.bodies.appendClumped([yade.sphere((0, 0, 0), 1), yade.sphere((1.5, 0, 0), 1)], discretization=20)
    O.step()
    assert bf.evalClump(cid, 2, 1e3, 5e3) is REF["clumps"]["unbroken"]["returned"] is False
    assert len(O.bodies) == REF["clumps"]["unbroken"]["len"]


def test_grow_particle(yade, bf):
    i = yade.O.bodies.append(yade.sphere((0, 0, 0), 1))
    bf.growParticle(i, 1.5)
    b = yade.O.bodies[i]
    r, m, inertia = REF["growParticle"]["grown"]
    assert (b.shape.radius, b.state.mass) == (pytest.approx(r), pytest.approx(m))
    np.testing.assert_allclose(np.asarray(b.state.inertia), inertia)
    bf.growParticle(i, 0.5, False)
    r, m, inertia = REF["growParticle"]["shrunk_same_mass"]
    assert (b.shape.radius, b.state.mass) == (pytest.approx(r), pytest.approx(m))


def test_bad_input(yade, bf):
    O = yade.O
    cid, ids = O.bodies.appendClumped([yade.sphere((0, 0, 0), 1), yade.sphere((1.5, 0, 0), 1)])
    w = O.bodies.append(yade.wall(0, axis=2))
    with pytest.raises(TypeError, match="is not a sphere"):
        bf.stressTensor(O.bodies[w])
    with pytest.raises(ValueError, match="strengths must be positive"):
        bf.checkFailure(O.bodies[ids[0]], 0, 1)
    with pytest.raises(ValueError, match="wei_P"):
        bf.checkFailure(O.bodies[ids[0]], 1, 1, wei_P=1.0)
    with pytest.raises(ValueError, match="release it first"):
        bf.replaceSphere(ids[0])
    with pytest.raises(TypeError, match="is not a clump"):
        bf.evalClump(ids[0], 2, 1, 1)
    with pytest.raises(IndexError, match="no body"):
        bf.evalClump(99, 2, 1, 1)
    n = len(O.bodies)
    with pytest.raises(ValueError, match="grow_radius"):
        bf.replaceSphere(O.bodies.append(yade.sphere((5, 0, 0), 1)), grow_radius=3)
    assert len(O.bodies) == n + 1 and O.bodies[n] is not None
