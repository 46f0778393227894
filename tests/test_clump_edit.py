"""Clump editing (addToClump, releaseFromClump, updateClumpProperties, deleteClumpMember,
deleteClumpBody, erase, getRoundness) against real YADE 2023.02a (tests/reference/yade/clump_edit.json)
and closed forms; momentum through the edits; misuse; save -> load of an edited clump."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import reference

from granum.mathtypes import as_quat_wxyz
from granum.yade.clumps import rotation

REF = reference("clump_edit")


def _rot(b):
    return rotation(as_quat_wxyz(b.state.ori))


def _tensor(b):
    """Inertia tensor about the centre, global frame (independent of the choice of principal axes)."""
    R = _rot(b)
    return R @ np.diag(np.asarray(b.state.inertia)) @ R.T


def _check(O, cid, ref, rtol=1e-9):
    """Clump ``cid`` matches YADE's record: mass, centre, inertia tensor, members and their positions."""
    if ref is None:
        assert O.bodies[cid] is None
        return
    b = O.bodies[cid]
    assert b is not None and b.isClump
    assert b.state.mass == pytest.approx(ref["mass"], rel=rtol)
    scale = max(ref["inertia"])
    np.testing.assert_allclose(np.asarray(b.state.pos), ref["pos"], rtol=rtol, atol=rtol * 10)
    np.testing.assert_allclose(np.sort(np.asarray(b.state.inertia)), np.sort(ref["inertia"]), rtol=rtol)
    np.testing.assert_allclose(_tensor(b), ref["tensor"], rtol=rtol, atol=rtol * scale)
    assert sorted(b.shape.members) == ref["members"]
    for i, x in zip(ref["members"], ref["member_pos"], strict=True):
        np.testing.assert_allclose(np.asarray(O.bodies[i].state.pos), x, atol=1e-12)


@pytest.mark.parametrize("d", [0, 1, 2, 5, 10, 20])
def test_grid_integration_of_two_overlapping_spheres_matches_yade(yade, d):
    cid, _ = yade.O.bodies.appendClumped([yade.sphere((0, 0, 0), 1), yade.sphere((1, 0, 0), 1)], discretization=d)
    _check(yade.O, cid, REF["grid"][f"two_overlapping_d{d}"])


def test_grid_cases_match_yade(yade):
    """Touching and apart spheres (no overlap: the sum), three overlapping and unequal spheres,
    two densities (the lower id owns a shared cell), an edited member mass (spheres are weighed
    from radius and density)."""
    O, s = yade.O, yade.sphere
    g = REF["grid"]
    cid, _ = O.bodies.appendClumped([s((0, 0, 0), 1), s((2, 0, 0), 1)], discretization=2)
    _check(O, cid, g["two_touching_d2"])
    for d in [0, 10]:
        O.reset()
        cid, _ = O.bodies.appendClumped([s((0, 0, 0), 1), s((1.5, .3, 0), .5), s((0, 2.5, 0), .4)], discretization=d)
        _check(O, cid, g[f"three_apart_d{d}"])
    O.reset()
    cid, ids = O.bodies.appendClumped([s((0, 0, 0), 1), s((1, 0, 0), 1), s((0, 1, 0), 1)], 10)
    _check(O, cid, g["three_overlapping_d10"])
    O.bodies.releaseFromClump(ids[2], cid, 5)
    _check(O, cid, g["three_overlapping_d10_release_d5"])
    O.reset()
    cid, _ = O.bodies.appendClumped([s((0, 0, 0), .3), s((.2, .1, -.05), .25), s((.1, -.2, .1), .2)], 7)
    _check(O, cid, g["three_unequal_d7"])
    for order in ["light_first", "heavy_first"]:
        O.reset()
        m1 = O.materials.append(yade.FrictMat(density=1000))
        m2 = O.materials.append(yade.FrictMat(density=3000))
        a, b = (m1, m2) if order == "light_first" else (m2, m1)
        cid, _ = O.bodies.appendClumped([s((0, 0, 0), 1, material=a), s((1, 0, 0), 1, material=b)], 2)
        _check(O, cid, g[f"densities_{order}_d2"])
    O.reset()
    a, b = O.bodies.append(s((0, 0, 0), 1)), O.bodies.append(s((3, 0, 0), 1))
    O.bodies[a].state.mass = 100.0
    O.bodies[a].state.inertia = (5, 5, 5)
    _check(O, O.bodies.clump([a, b]), g["edited_member_mass_d0"])


def test_add_and_release_match_yade(yade):
    O, s = yade.O, yade.sphere
    e = REF["edit"]
    cid, ids = O.bodies.appendClumped([s((0, 0, 0), 1), s((2, 0, 0), 1)])
    k = O.bodies.append(s((0, 2, 0), 1))
    _check(O, cid, e["before_add"])
    O.bodies.addToClump([k], cid)
    _check(O, cid, e["add_sphere"])
    assert O.bodies[k].clumpId == cid and O.bodies[k].isClumpMember
    O.bodies.releaseFromClump(k, cid)
    _check(O, cid, e["release_it_again"])
    assert O.bodies[k].isStandalone and O.bodies[k].clumpId == -1
    with pytest.warns(UserWarning, match="not released from clump"):
        O.bodies.releaseFromClump(ids[0], cid)
    assert e["release_from_two_members"]["warnings"]
    _check(O, cid, e["release_from_two_members"]["clump"])
    for d in [0, 10]:
        O.reset()
        cid, ids = O.bodies.appendClumped([s((0, 0, 0), 1), s((2, 0, 0), 1)])
        k = O.bodies.append(s((1, 1, 0), 1))
        O.bodies.addToClump([k], cid, d)
        _check(O, cid, e[f"add_overlapping_d{d}"])
    O.bodies.releaseFromClump(k, cid, 10)
    _check(O, cid, e["release_overlapping_d10"])


@pytest.mark.parametrize("what", ["clump", "member"])
def test_adding_a_clump_or_its_member_merges_the_whole_clump(yade, what):
    """YADE: all members of the other clump join and it is erased (granum also gives the moved
    members the clump's id, which YADE forgets)."""
    O, s = yade.O, yade.sphere
    c1, _ = O.bodies.appendClumped([s((0, 0, 0), 1), s((2, 0, 0), 1)])
    c2, i2 = O.bodies.appendClumped([s((0, 3, 0), 1), s((2, 3, 0), 1)])
    O.bodies.addToClump([c2 if what == "clump" else i2[0]], c1)
    ref = REF["edit"][f"add_{what}_of_other_clump"]
    _check(O, c1, ref["clump"])
    assert O.bodies[c2] is None and ref["other_clump"] is None and len(O.bodies) == ref["len"]
    assert all(O.bodies[i].clumpId == c1 for i in i2)


def test_erase_delete_and_update_match_yade(yade):
    O, s = yade.O, yade.sphere
    u = REF["update"]
    c1, i1 = O.bodies.appendClumped([s((0, 0, 0), 1), s((2, 0, 0), 1), s((0, 2, 0), .5)])
    O.bodies.erase(i1[2])
    _check(O, c1, u["erase_member"]["clump"])
    assert O.bodies[i1[2]] is None and len(O.bodies) == u["erase_member"]["len"]
    O.bodies.erase(c1)
    assert O.bodies[c1] is None
    assert [{"clumpId": O.bodies[i].clumpId, "isStandalone": O.bodies[i].isStandalone} for i in i1[:2]] \
        == u["erase_clump"]["members"]
    O.reset()
    c1, i1 = O.bodies.appendClumped([s((0, 0, 0), 1), s((2, 0, 0), 1), s((0, 2, 0), .5)])
    O.bodies.deleteClumpMember(O.bodies[c1], O.bodies[i1[2]])
    _check(O, c1, u["deleteClumpMember"]["clump"])
    assert O.bodies[i1[2]] is None
    O.bodies.deleteClumpBody(O.bodies[c1])
    assert O.bodies[c1] is None and all(O.bodies[i] is None for i in i1)
    O.reset()
    c1, i1 = O.bodies.appendClumped([s((0, 0, 0), 1), s((1, 0, 0), 1), s((0, 2, 0), .5)])
    c2, _ = O.bodies.appendClumped([s((5, 0, 0), 1), s((6, 0, 0), 1)])
    O.bodies.updateClumpProperties()
    for k, ref in zip([c1, c2], u["default"], strict=True):
        _check(O, k, ref)
    O.bodies.updateClumpProperties([c2], 20)
    for k, ref in zip([c1, c2], u["exclude_c2_d20"], strict=True):
        _check(O, k, ref)
    O.bodies.updateClumpProperties(discretization=0)
    for k, ref in zip([c1, c2], u["d0"], strict=True):
        _check(O, k, ref)
    O.bodies[i1[0]].shape.radius = 1.5
    O.bodies.updateClumpProperties(discretization=0)
    for k, ref in zip([c1, c2], u["d0_after_radius_1.5"], strict=True):
        _check(O, k, ref)
    rc = REF["roundness"]
    assert O.bodies.getRoundness() == pytest.approx(rc["clumps"]["none"], rel=1e-12)
    assert O.bodies.getRoundness([c1]) == pytest.approx(rc["clumps"]["exclude_c1"], rel=1e-12)
    assert O.bodies.getRoundness(i1) == pytest.approx(rc["clumps"]["exclude_members_of_c1"], rel=1e-12)
    assert O.bodies.getRoundness([c1, c2]) == rc["clumps"]["exclude_both"]
    O.bodies.append(s((10, 0, 0), 1))
    assert O.bodies.getRoundness() == pytest.approx(rc["with_sphere"]["none"], rel=1e-12)
    assert O.bodies.getRoundness([c1, c2]) == rc["with_sphere"]["exclude_clumps"]
    O.bodies.append(yade.box((0, 0, -5), (1, 1, 1)))
    assert O.bodies.getRoundness() == pytest.approx(rc["with_box"], rel=1e-12)
    O.reset()
    assert O.bodies.getRoundness() == rc["empty"]
    cid = O.bodies.clump([O.bodies.append(yade.box((0, 0, -5), (1, 1, 1))), O.bodies.append(s((0, 0, -7), 1))])
    _check(O, cid, rc["box_sphere_clump"]["clump"])
    assert O.bodies.getRoundness() == pytest.approx(rc["box_sphere_clump"]["rc"], rel=1e-12)


def test_two_touching_equal_spheres_closed_form(yade):
    """Two spheres of radius r touching: M = 2 m, I_axis = 2 * 2/5 m r^2, I_perp = 2 (2/5 m r^2 + m r^2);
    the same with discretization (they do not overlap), and the grid converges to the union's
    volume for overlapping ones (lens: pi (4 r + d)(2 r - d)^2 / 12)."""
    r, rho = 0.1, 1000.0
    m = rho * 4 / 3 * math.pi * r ** 3
    for d in [0, 20]:
        yade.O.reset()
        cid, _ = yade.O.bodies.appendClumped([yade.sphere((0, 0, 0), r), yade.sphere((2 * r, 0, 0), r)], d)
        b = yade.O.bodies[cid]
        assert b.state.mass == pytest.approx(2 * m, rel=1e-14)
        np.testing.assert_allclose(np.sort(np.asarray(b.state.inertia)),
                                   [0.8 * m * r * r, 2 * (0.4 + 1) * m * r * r, 2 * (0.4 + 1) * m * r * r], rtol=1e-12)
    yade.O.reset()
    cid, _ = yade.O.bodies.appendClumped([yade.sphere((0, 0, 0), r), yade.sphere((r, 0, 0), r)], 60)
    vol = 2 * 4 / 3 * math.pi * r ** 3 - math.pi * (4 * r + r) * r ** 2 / 12
    assert yade.O.bodies[cid].state.mass == pytest.approx(rho * vol, rel=5e-3)


def test_edits_conserve_momentum_and_rigid_motion(yade):
    """With discretization 0, adding a moving sphere to a spinning clump conserves linear and
    angular momentum exactly; releasing it again leaves the released body on the clump's rigid
    velocity field and the rest keeps the same rigid motion."""
    O, s = yade.O, yade.sphere
    cid, ids = O.bodies.appendClumped([s((0, 0, 0), .1), s((.2, 0, 0), .1), s((0, .25, .05), .08)])
    c = O.bodies[cid]
    c.state.vel, c.state.angVel = (1, -2, .5), (3, 1, -2)
    k = O.bodies.append(s((.1, -.3, 0), .12))
    O.bodies[k].state.vel, O.bodies[k].state.angVel = (0, 4, 0), (0, 0, 7)

    def momenta():
        P = np.zeros(3)
        L = np.zeros(3)
        for b in O.bodies:
            if b.isClumpMember:
                continue
            m, x, v = b.state.mass, np.asarray(b.state.pos), np.asarray(b.state.vel)
            R = _rot(b)
            P += m * v
            L += np.cross(x, m * v) + R @ (np.asarray(b.state.inertia) * (R.T @ np.asarray(b.state.angVel)))
        return P, L

    P0, L0 = momenta()
    O.bodies.addToClump([k], cid)
    P1, L1 = momenta()
    np.testing.assert_allclose(P1, P0, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(L1, L0, rtol=1e-12, atol=1e-13)
    v, w, x = np.asarray(c.state.vel), np.asarray(c.state.angVel), np.asarray(c.state.pos)
    xk = np.asarray(O.bodies[k].state.pos)
    O.bodies.releaseFromClump(k, cid)
    np.testing.assert_allclose(np.asarray(O.bodies[k].state.vel), v + np.cross(w, xk - x), rtol=1e-13)
    np.testing.assert_allclose(np.asarray(O.bodies[k].state.angVel), w, rtol=1e-13)
    np.testing.assert_allclose(np.asarray(c.state.angVel), w, rtol=1e-12)
    np.testing.assert_allclose(np.asarray(c.state.vel), v + np.cross(w, np.asarray(c.state.pos) - x), rtol=1e-12)
    P2, L2 = momenta()
    np.testing.assert_allclose(P2, P0, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(L2, L0, rtol=1e-12, atol=1e-13)


def _snapshot(O):
    b = O._scene.bodies
    n = O._scene.body_count
    return {c: np.array(getattr(b, c)[:n]) for c in ("alive", "clump_id", "mass", "pos", "inertia", "ori", "vel")}


@pytest.mark.parametrize("call, exc, match", [
    ("O.bodies.addToClump([i1[0]], c1)", ValueError, "already a member of clump"),
    ("O.bodies.addToClump([c1], c1)", ValueError, "is clump"),
    ("O.bodies.addToClump([999], c1)", IndexError, "no body with id 999"),
    ("O.bodies.addToClump([s, 999], c1)", IndexError, "no body with id 999"),
    ("O.bodies.addToClump([s], i2[0])", TypeError, "is not a clump"),
    ("O.bodies.addToClump([s], 999)", IndexError, "no body with id 999"),
    ("O.bodies.addToClump(s, c1)", TypeError, "list of body ids"),
    ("O.bodies.addToClump([s, b], c1, 5)", ValueError, "integrates spheres only"),
    ("O.bodies.releaseFromClump(s, c1)", ValueError, "not a member of clump"),
    ("O.bodies.releaseFromClump(i2[0], c1)", ValueError, "not a member of clump"),
    ("O.bodies.releaseFromClump(i1[0], 999)", IndexError, "no body with id 999"),
    ("O.bodies.releaseFromClump(999, c1)", IndexError, "no body with id 999"),
    ("O.bodies.deleteClumpMember(O.bodies[c1], O.bodies[s])", ValueError, "not a member of clump"),
    ("O.bodies.updateClumpProperties([999])", IndexError, "999"),
    ("O.bodies.getRoundness([999])", IndexError, "999"),
])
def test_misuse_raises_and_changes_nothing(yade, call, exc, match):
    """YADE warns, crashes (-11) or raises a misleading message for these (clump_edit.json 'errors');
    granum raises an error naming the value, before anything changes."""
    O = yade.O
    c1, i1 = O.bodies.appendClumped([yade.sphere((0, 0, 0), 1), yade.sphere((2, 0, 0), 1), yade.sphere((0, 2, 0), .5)])
    c2, i2 = O.bodies.appendClumped([yade.sphere((5, 0, 0), 1), yade.sphere((7, 0, 0), 1)])
    s = O.bodies.append(yade.sphere((0, -1.5, 0), 1))  # overlaps member 0: discretization integrates
    b = O.bodies.append(yade.box((0, -3, 0), (1, 1, 1)))  # a body the grid cannot integrate
    before = _snapshot(O)
    with pytest.raises(exc, match=match):
        eval(call, {"O": O, "c1": c1, "i1": i1, "c2": c2, "i2": i2, "s": s, "b": b})
    after = _snapshot(O)
    for name in before:
        np.testing.assert_array_equal(after[name], before[name], err_msg=name)
    assert sorted(O.bodies[c1].shape.members) == i1 and sorted(O.bodies[c2].shape.members) == i2


def test_save_load_of_an_edited_clump_continues_identically(yade, tmp_path):
    """An edited clump (sphere added, member released, a second clump merged) saved and loaded runs
    on with the same bits as the uninterrupted run."""
    from conftest import frict_engines

    O, s = yade.O, yade.sphere
    O.bodies.append(yade.wall(0, axis=2))
    c1, i1 = O.bodies.appendClumped([s((0, 0, .3), .1), s((.15, 0, .3), .1), s((0, .15, .35), .07)])
    c2, _ = O.bodies.appendClumped([s((.5, 0, .3), .1), s((.6, 0, .3), .1)])
    k = O.bodies.append(s((-.1, -.1, .3), .08))
    O.bodies.addToClump([k], c1, 10)
    O.bodies.releaseFromClump(i1[2], c1)
    O.bodies.addToClump([c2], c1)
    O.engines = frict_engines(yade, gravity=(0, 0, -9.81), damping=0.2)
    O.dt = 0.2 * yade.PWaveTimeStep()
    O.run(200, True)
    path = str(tmp_path / "edited.yade")
    O.save(path)
    O.run(300, True)
    ref = _snapshot(O)
    members = sorted(O.bodies[c1].shape.members)
    O.load(path)
    assert sorted(O.bodies[c1].shape.members) == members
    O.run(300, True)
    for name, value in _snapshot(O).items():
        np.testing.assert_array_equal(value, ref[name], err_msg=name)


def test_text_clumps_round_trip(yade, tmp_path):
    """export.textClumps writes YADE's lines (%g, clumps and members by id, mask, comment) and returns
    (clumps, spheres); ymport.textClumps reads them back scaled, turned and shifted, one clump per id
    in order of first appearance (as YADE 2023.02a: a 90 degree turn about z of (0.2, 0, 1) scaled by 2
    gives (0, 0.4, 2))."""
    O, s = yade.O, yade.sphere
    O.bodies.append(s((5, 5, 5), 1))
    O.bodies.appendClumped([s((0.123456789, 1e-7, -3.5), 0.333333333, mask=3), s((1, 2, 12345.678), 0.25)])
    path = str(tmp_path / "c.txt")
    assert yade.export.textClumps(path, comment="hello\n#second") == (1, 2)
    assert open(path).read() == ("#format x_y_z_r_clumpId\n# hello\n#second\n0.123457\t1e-07\t-3.5\t0.333333\t3\n"
                                 "1\t2\t12345.7\t0.25\t3\n")
    assert yade.export.textClumps(path, mask=2) == (1, 1)
    with pytest.raises(ValueError, match="format"):
        yade.export.textClumps(path, format="x_y_z_r")
    O.reset()
    with open(path, "w") as f:
        f.write("#x\n1 2 3 0.5 7\n1.5 2 3 0.5 7\n5 5 5 1 2\n5 6 5 1 2\n9 9 9 1 4\n")
    assert yade.ymport.textClumps(path) == [(2, [0, 1]), (5, [3, 4]), (7, [6])]
    with open(path, "w") as f:
        f.write("0 0 1 0.5 3\n0.2 0 1 0.5 3\n")
    cid, ids = yade.ymport.textClumps(path, scale=2.0, orientation=yade.Quaternion((0, 0, 1), math.pi / 2),
                                      shift=(0, 0, 1))[0]
    np.testing.assert_allclose(np.asarray(O.bodies[ids[1]].state.pos), (0, 0.4, 3), atol=1e-15)
    assert O.bodies[ids[1]].shape.radius == 1.0
