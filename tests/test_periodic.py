"""Periodic cells: broad phase across images, momentum, homogeneous deformation, stress, controller."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from conftest import frict_engines

from granum.core.contacts import C_PAIRS


def _cloud(yade, h, n, rmin, rmax, seed):
    rng = np.random.default_rng(seed)
    yade.O.periodic = True
    yade.O.cell.hSize = h
    H = np.asarray(yade.O.cell.hSize)
    for _ in range(n):
        s = rng.uniform(-0.3, 1.3, 3)  # unwrapped positions, also outside the cell
        yade.O.bodies.append(yade.sphere(tuple(H @ s), rng.uniform(rmin, rmax)))


def _fractional_boxes(yade, verlet):
    H = np.asarray(yade.O.cell.hSize)
    hinv = np.linalg.inv(H)
    pos = np.array([b.state.pos for b in yade.O.bodies])
    r = np.array([b.shape.radius for b in yade.O.bodies]) + verlet
    s = pos @ hinv.T
    hw = r[:, None] * np.linalg.norm(hinv, axis=1)[None, :]  # a ball's exact extent along each cell axis
    return H, pos, r - verlet, s, hw


@pytest.mark.parametrize("shear", [0.0, 0.3, -0.45])
def test_periodic_pairs_equal_brute_force_over_images(yade, shear):
    """Pairs and cellDist equal a brute-force search of the 27 nearest images, orthogonal and sheared cells
    (each sphere's bound, radius plus Verlet distance, spans r |row k of H^-1| on either side along axis k)."""
    h = ((1.0, shear, 0.2 * shear), (0.0, 1.1, 0.0), (0.0, 0.0, 0.9))
    _cloud(yade, h, 400, 0.02, 0.05, seed=4)
    yade.O.engines = [yade.ForceResetter(), yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb()])]
    yade.O.step()
    v = 0.5 * min(b.shape.radius for b in yade.O.bodies)  # default verletDist = -0.5: half the smallest radius
    H, pos, r, s, hw = _fractional_boxes(yade, v)
    want = {}
    images = np.array(list(itertools.product((-2, -1, 0, 1, 2), repeat=3)))
    for i in range(len(pos) - 1):
        d = s[i][None, None, :] - (s[i + 1:][:, None, :] + images[None, :, :])   # (j, image, 3)
        hit = np.all(np.abs(d) <= (hw[i] + hw[i + 1:])[:, None, :], axis=2)
        for jj, kk in zip(*np.nonzero(hit), strict=True):
            want[(i, i + 1 + int(jj))] = tuple(int(x) for x in images[kk])
    C = yade.O._scene.contacts
    n = int(C.ctr[C_PAIRS])
    got = {(int(a), int(b)): tuple(int(x) for x in k)
           for (a, b), k in zip(C.pair_ids[:n], C.pair_cell[:n], strict=True)}
    assert got == want
    # and every geometric contact (over images) is one of them
    near = images[np.all(np.abs(images) <= 1, axis=1)]
    for i in range(len(pos) - 1):
        dist = np.linalg.norm(pos[i][None, None, :] - pos[i + 1:][:, None, :] - (near @ H.T)[None, :, :], axis=2)
        for jj, kk in zip(*np.nonzero(dist <= (r[i] + r[i + 1:])[:, None]), strict=True):
            assert got.get((i, i + 1 + int(jj))) == tuple(int(x) for x in near[kk])


def test_contacts_across_the_boundary_have_the_right_geometry(yade):
    """Two spheres touching through the boundary interact with cellDist and the image's normal."""
    yade.O.periodic = True
    yade.O.cell.setBox(2, 2, 2)
    yade.O.bodies.append([yade.sphere((0.05, 1, 1), 0.1), yade.sphere((1.9, 1, 1), 0.1)])
    yade.O.engines = frict_engines(yade)
    yade.O.step()
    i = yade.O.interactions[0, 1]
    assert i.isReal
    assert i.geom.penetrationDepth == pytest.approx(0.05)
    # body 2's image at 1.9 - 2 = -0.1 lies below body 1 along x
    assert np.asarray(i.cellDist).tolist() == [-1, 0, 0]
    np.testing.assert_allclose(np.asarray(i.geom.normal), [-1, 0, 0])
    assert yade.O.forces.f(0)[0] > 0 and yade.O.forces.f(1)[0] < 0


def test_no_contact_is_missed_in_a_deforming_cell(yade):
    """A periodic gas in a cell that shrinks and shears: at every step the geometric contacts over the
    images are exactly the real interactions, though the collider seldom runs (pair budgets include the
    motion of the images with the cell)."""
    from granum.core.contacts import C_COLLIDER_RUNS

    O = yade.O
    O.periodic = True
    O.cell.setBox(1, 1, 1)
    sp = yade.pack.SpherePack()
    sp.makeCloud((0, 0, 0), (1, 1, 1), rMean=0.045, rRelFuzz=0.3, num=200, periodic=True, seed=3)
    sp.toSimulation()
    rng = np.random.default_rng(5)
    for b in O.bodies:
        b.state.vel = tuple(rng.normal(0, 1, 3))
    O.engines = frict_engines(yade, bounds=[yade.Bo1_Sphere_Aabb()], geoms=[yade.Ig2_Sphere_Sphere_ScGeom()])
    O.cell.velGrad = ((-1, 0.5, 0), (0, -1, 0), (0, 0, -1))
    O.dt = 0.5 * yade.PWaveTimeStep()
    rad = np.array([b.shape.radius for b in O.bodies])
    iu, ju = np.triu_indices(len(rad), 1)
    near = np.array(list(itertools.product((-1, 0, 1), repeat=3)), float)
    checked = crossing = 0
    steps = 300
    for _ in range(steps):
        pos = np.array([b.state.pos for b in O.bodies])  # what the collider and InteractionLoop see
        O.step()
        H = np.asarray(O.cell.hSize)  # deformed at the start of the step, before the collider ran
        d = pos[iu] - pos[ju]
        k0 = np.round(d @ np.linalg.inv(H).T)  # nearest image of body j, then its neighbours
        dist = np.linalg.norm(d[:, None, :] - (k0[:, None, :] + near[None, :, :]) @ H.T, axis=2).min(axis=1)
        touch = dist < rad[iu] + rad[ju]
        for a, b in zip(iu[touch], ju[touch], strict=True):
            assert O.interactions.has(int(a), int(b), onlyReal=True), \
                f"iter {O.iter}: spheres {a} and {b} overlap (over the images) but do not interact"
        checked += int(touch.sum())
        crossing += int((touch & np.any(k0 != 0, axis=1)).sum())
        gap = {(a, b): g for a, b, g in zip(iu.tolist(), ju.tolist(), (dist - rad[iu] - rad[ju]).tolist(), strict=True)}
        for i in O.interactions:
            assert gap[(min(i.id1, i.id2), max(i.id1, i.id2))] <= 1e-12, f"iter {O.iter}: {i.id1, i.id2} real but apart"
    runs = int(O._scene.contacts.ctr[C_COLLIDER_RUNS])
    assert checked > 300 and crossing > 20, "the test must see many contacts, some through the boundary"
    assert 3 <= runs <= steps // 5, f"the collider ran {runs} times in {steps} steps"


def test_image_brought_by_the_shrinking_cell_touches_in_its_step(yade):
    """Two fixed spheres (homoDeform 0: they do not follow the flow) meet only through the boundary, as
    the cell shrinks: no body moves, yet the interaction is real exactly from the step in which the image
    overlaps (the image moves with the cell, so the bound of the motions must not be zero)."""
    O = yade.O
    O.periodic = True
    O.cell.setBox(1, 1, 1)
    r = 0.1
    O.bodies.append([yade.sphere((0.15, 0.5, 0.5), r, fixed=True), yade.sphere((0.85, 0.5, 0.5), r, fixed=True)])
    O.engines = frict_engines(yade, bounds=[yade.Bo1_Sphere_Aabb()], geoms=[yade.Ig2_Sphere_Sphere_ScGeom()])
    O.cell.homoDeform = 0
    O.cell.velGrad = ((-1, 0, 0), (0, 0, 0), (0, 0, 0))
    O.dt = 1e-4
    seen = []
    for _ in range(1500):
        length = O.cell.hSize[0][0]  # the cell this step's detection sees (deformed at its start)
        O.step()
        gap = O.cell.hSize[0][0] - 0.7 - 2 * r  # distance of sphere 1 to the image of sphere 0, less 2r
        real = O.interactions.has(0, 1, onlyReal=True)
        assert real == (gap < 0), f"iter {O.iter}: gap {gap}, interaction real: {real} (cell {length})"
        seen.append(real)
    assert any(seen) and not seen[0]


def test_momentum_is_conserved_across_the_boundary(yade):
    """A periodic gas of colliding spheres without damping keeps its total momentum to rounding."""
    _cloud(yade, ((1, 0.2, 0), (0, 1, 0), (0, 0, 1)), 150, 0.04, 0.06, seed=7)
    rng = np.random.default_rng(8)
    for b in yade.O.bodies:
        b.state.vel = tuple(rng.normal(0, 1, 3))
    yade.O.engines = frict_engines(yade, damping=0.0)
    yade.O.dt = 0.3 * yade.PWaveTimeStep()
    p0 = sum(b.state.mass * np.asarray(b.state.vel) for b in yade.O.bodies)
    crossings = 0
    for _ in range(20):
        yade.O.run(100, True)
        crossings += sum(1 for i in yade.O.interactions if np.any(np.asarray(i.cellDist) != 0))
    p = sum(b.state.mass * np.asarray(b.state.vel) for b in yade.O.bodies)
    scale = sum(b.state.mass * np.linalg.norm(b.state.vel) for b in yade.O.bodies)
    assert crossings > 0
    np.testing.assert_allclose(p, p0, atol=1e-13 * scale)


def test_free_body_follows_the_homogeneous_flow(yade):
    """With homoDeform the velocity jumps to L x and the cell base vectors follow (1 + L dt) H each step."""
    yade.O.periodic = True
    yade.O.cell.setBox(2, 2, 2)
    yade.O.bodies.append(yade.sphere((0.5, 1, 1), 0.1))
    yade.O.engines = [yade.ForceResetter(), yade.NewtonIntegrator(damping=0.3)]
    yade.O.dt = 1e-2
    L = np.array([[-0.1, 0, 0], [0, 0, 0], [0.2, 0, 0]])
    yade.O.cell.velGrad = L
    yade.O.step()
    b = yade.O.bodies[0]
    np.testing.assert_allclose(np.asarray(b.state.vel), L @ [0.5, 1, 1])  # jump, undamped
    h = np.eye(3) * 2
    for _ in range(5):
        yade.O.step()
        h = h + 1e-2 * L @ h  # updated from the second step on (the gradient of the previous step)
    np.testing.assert_allclose(np.asarray(yade.O.cell.hSize), h, rtol=1e-14)
    np.testing.assert_allclose(np.asarray(yade.O.cell.trsf), h / 2, rtol=1e-14)


def test_stress_of_a_compressed_cubic_lattice_is_analytic(yade):
    """Simple cubic lattice, spacing a = 2r(1 - eps): sigma = -kn (2 r eps) / a^2 on the diagonal."""
    r, eps, n = 0.05, 1e-3, 4
    a = 2 * r * (1 - eps)
    young = 1e7
    yade.O.periodic = True
    yade.O.cell.setBox(n * a, n * a, n * a)
    yade.O.materials.append(yade.FrictMat(young=young, poisson=0.3, density=1000))
    for ijk in itertools.product(range(n), repeat=3):
        yade.O.bodies.append(yade.sphere(tuple(a * (np.array(ijk) + 0.5)), r))
    yade.O.engines = frict_engines(yade)
    yade.O.step()
    assert yade.O.interactions.countReal() == 3 * n ** 3
    sigma = -young * r * (2 * r * eps) / a ** 2  # kn = E r for equal spheres
    np.testing.assert_allclose(np.asarray(yade.getStress()), np.diag([sigma] * 3), rtol=1e-12, atol=1e-9 * abs(sigma))
    sn, st = yade.normalShearStressTensors()
    # YADE's convention for this function: compression positive by default, radii sum 2r as the branch
    np.testing.assert_allclose(np.asarray(sn), np.diag([-sigma * 2 * r / a] * 3), rtol=1e-12, atol=1e-6)
    np.testing.assert_allclose(np.asarray(yade.fabricTensor()), np.eye(3) / 3, atol=1e-15)


def test_peri_triax_controller_reaches_an_isotropic_goal(yade):
    """PeriTriaxController compresses a loose periodic cloud to -1e5 Pa and calls doneHook within tolerance."""
    sp = yade.pack.SpherePack()
    sp.makeCloud((0, 0, 0), (1, 1, 1), rMean=0.08, rRelFuzz=0.3, periodic=True, seed=2)
    sp.toSimulation()
    goal = -1e5
    yade.O.engines = frict_engines(yade, damping=0.4)[:3] + [
        yade.PeriTriaxController(goal=(goal, goal, goal), stressMask=7, dynCell=True, maxStrainRate=(1, 1, 1),
                                 maxUnbalanced=0.05, relStressTol=1e-2, doneHook="O.pause()", label="triax"),
        yade.NewtonIntegrator(damping=0.4)]
    yade.O.dt = 0.5 * yade.PWaveTimeStep()
    yade.O.run(200000, True)
    triax = yade.O.engines[3]
    assert yade.O.iter < 200000, "the goal was never reached"
    np.testing.assert_allclose(np.asarray(triax.stress), [goal] * 3, rtol=1e-2)
    np.testing.assert_allclose(np.diag(np.asarray(yade.getStress())), [goal] * 3, rtol=2e-2)
    assert triax.currUnbalanced < 0.05


def test_bad_cell_and_controller_input(yade):
    """Non-positive cell volume, stressMask outside 0..7 and a raising doneHook give clear errors."""
    yade.O.periodic = True
    with pytest.raises(ValueError, match="volume"):
        yade.O.cell.hSize = ((1, 0, 0), (0, 1, 0), (0, 0, -1))
    with pytest.raises(ValueError, match="volume"):
        yade.O.cell.hSize = ((1, 1, 0), (1, 1, 0), (0, 0, 1))
    assert np.asarray(yade.O.cell.hSize).tolist() == np.eye(3).tolist()
    with pytest.raises(ValueError, match="stressMask"):
        yade.PeriTriaxController(stressMask=8)
    yade.O.cell.setBox(1, 1, 1)
    yade.O.bodies.append([yade.sphere((0.5, 0.5, 0.5), 0.1), yade.sphere((0.5, 0.5, 0.69), 0.1)])
    yade.O.engines = frict_engines(yade)[:3] + [
        yade.PeriTriaxController(goal=(0, 0, 0), maxUnbalanced=math.inf, doneHook="raise ValueError('hook failed')"),
        yade.NewtonIntegrator()]
    with pytest.raises(ValueError, match="hook failed"):
        yade.O.run(10, True)
    assert yade.O.iter == 1 and len(yade.O.bodies) == 2
    yade.O.periodic = False
    with pytest.raises(RuntimeError, match="periodic"):
        yade.O.step()


@pytest.mark.parametrize("glob_update, rows", [(1, "rows"), (5, "rows_glob5")])
def test_peri_triax_dyn_cell_follows_yade_step_by_step(yade, glob_update, rows):
    """dynCell: the strain rate gains dt (goal - sigma) / mass, damped by growDamping when it keeps its sign
    (tests/reference/yade/peritriax_dyncell.py): rates and sizes equal YADE's to 1e-9 for 8 steps. With YADE's
    default globUpdate 5 the stress is still the current step's (only the unbalanced force waits for the update;
    a stress 4 steps old had kept the example scripts' compressions short of their goal), and with dynCell the
    stiffness reads 0, as in YADE."""
    from conftest import REFERENCE, reference

    O = yade.O
    O.periodic = True
    O.cell.setBox(1, 1.2, 0.9)
    sp = yade.pack.SpherePack()
    sp.load(str(REFERENCE / "periiso_pack.txt"))
    for c, r in sp:
        O.bodies.append(yade.sphere(c, r * 1.0004))
    triax = yade.PeriTriaxController(dynCell=True, mass=0.2, maxUnbalanced=0.01, relStressTol=0.01,
                                     goal=(-1e4, -1e4, -1e4), stressMask=7, globUpdate=glob_update,
                                     maxStrainRate=(100., 100., 100.))
    O.engines = frict_engines(yade, damping=0.2)
    O.engines = O.engines[:3] + [triax] + O.engines[3:]
    O.dt = 1e-5
    for row in reference("peritriax_dyncell")[rows]:
        O.step()
        assert [O.cell.velGrad[k, k] for k in range(3)] == pytest.approx(row["rate"], rel=1e-9)
        assert list(O.cell.size) == pytest.approx(row["size"], rel=1e-12)
        assert list(triax.stress) == pytest.approx(row["stress"], rel=1e-6)
        assert list(triax.stiff) == row["stiff"]
