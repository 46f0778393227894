"""The pairs' detection state between steps: what the interaction loop's detection takes for granted
(granum.core.contacts, granum.kernels.interaction.detect_block).

The detection lists a pair for testing on its budget alone (a pair with a contact has an infinite one) and
reads the step's hits from ``pair_hit`` (zero outside the interaction loop). A pair with a contact listed again
would get a second contact; a hit left from an earlier step would make a contact of a pair that does not touch.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import frict_engines

from granum.core.contacts import C_CONTACTS, C_PAIRS, FLAG_ALIVE, I_FLAGS, I_ID1, I_ID2

HIT_TOUCH = 1   # granum.kernels.interaction.HIT_TOUCH


def _settling_box(yade, geoms=None) -> None:
    """A seeded cloud of spheres falling into a facet box: contacts begin and end at many steps."""
    O = yade.O
    O.bodies.append(yade.geom.facetBox((0.5, 0.5, 0.5), (0.5, 0.5, 0.5)))
    sp = yade.pack.SpherePack()
    sp.makeCloud((0, 0, 0), (1, 1, 0.8), rMean=0.05, rRelFuzz=0.3, seed=5)
    sp.toSimulation()
    O.engines = frict_engines(yade, gravity=(0, 0, -9.81), damping=0.1, geoms=geoms)
    O.dt = 0.5 * yade.PWaveTimeStep()


def _detection_state(scene) -> tuple[np.ndarray, np.ndarray]:
    """The hits left in ``pair_hit`` and the budgets of the pairs with a contact."""
    C = scene.contacts
    n = int(C.ctr[C_PAIRS])
    return C.pair_hit[:n].copy(), C.pair_gap[:n][C.pair_con[:n] >= 0]


def _contacts(O) -> list:
    """The live contacts as sorted (id1, id2): one per pair (no pair twice)."""
    C = O._scene.contacts
    con = C.con_i[:C.ctr[C_CONTACTS]]
    live = con[(con[:, I_FLAGS] & FLAG_ALIVE) != 0]
    return sorted(map(tuple, np.sort(live[:, [I_ID1, I_ID2]], axis=1).tolist()))


def test_no_hit_outlives_a_step_and_contact_pairs_are_never_listed(yade):
    """Every 10 steps of 600 in which the landing cloud's contacts begin and end, no pair holds a hit, every pair
    with a contact has an infinite budget, and no two contacts join the same bodies."""
    O = yade.O
    _settling_box(yade)
    O.run(2000, True)   # the first spheres have landed
    made = 0
    for _ in range(60):
        O.run(10, True)
        hits, budgets = _detection_state(O._scene)
        assert not hits.any()
        assert np.isposinf(budgets).all()
        pairs = _contacts(O)
        assert len(pairs) == len(set(pairs))
        made = max(made, len(pairs))
    assert made > 150


def test_a_step_stopped_by_a_missing_geometry_functor_leaves_no_hit(yade):
    """Spheres touching facets without Ig2_Facet_Sphere_ScGeom listed: the step stops with an error naming the
    functor as soon as their bounds overlap, and leaves no hit behind; listed then, the run goes on and makes the
    facet contacts (each pair once)."""
    O = yade.O
    _settling_box(yade, geoms=[yade.Ig2_Sphere_Sphere_ScGeom()])
    with pytest.raises(RuntimeError, match="no IGeom functor for .*Facet"):
        O.run(2000, True)
    hits, _ = _detection_state(O._scene)
    assert not hits.any()
    O.engines[2].geomDispatcher.functors = [yade.Ig2_Sphere_Sphere_ScGeom(), yade.Ig2_Facet_Sphere_ScGeom()]
    O.run(500, True)   # the error came when bounds met: the spheres reach the floor a little later
    pairs = _contacts(O)
    facet_ids = {b.id for b in O.bodies if isinstance(b.shape, yade.Facet)}
    assert any(a in facet_ids for a, _ in pairs)
    assert len(pairs) == len(set(pairs))


def test_a_checkpoint_with_stale_hits_resumes_exactly(yade, tmp_path):
    """A checkpoint whose pairs hold hits and finite budgets on pairs with contacts (what an earlier version could
    leave, or a damaged file) loads with both put right: the run goes on bit for bit as without them."""
    O = yade.O
    _settling_box(yade)
    O.run(1500, True)
    assert len(_contacts(O)) > 20
    path = tmp_path / "scene.yade"
    O.save(str(path))
    O.run(100, True)
    expected = O.bodies.arrays("pos", "vel", "angVel")
    O.reset()
    O.load(str(path))
    C = O._scene.contacts
    n = int(C.ctr[C_PAIRS])
    C.pair_hit[:n] = HIT_TOUCH
    C.pair_gap[:n][C.pair_con[:n] >= 0] = 0.0
    O.save(str(path))
    O.reset()
    O.load(str(path))
    hits, budgets = _detection_state(O._scene)
    assert not hits.any() and np.isposinf(budgets).all()
    O.run(100, True)
    got = O.bodies.arrays("pos", "vel", "angVel")
    for k in ("ids", "pos", "vel", "angVel"):
        assert np.array_equal(got[k], expected[k]), k


def _touching_sphere_pairs(O, n) -> set:
    """The pairs of the spheres 0..n-1 that overlap now (brute force over every two)."""
    b = O._scene.bodies
    pos = b.pos[:n]
    r = np.array([O.bodies[i].shape.radius for i in range(n)])
    d = np.linalg.norm(pos[:, None, :] - pos[None, :, :], axis=2)
    i, j = np.nonzero(np.triu(d < r[:, None] + r[None, :], 1))
    return set(zip(i.tolist(), j.tolist(), strict=True))


def _dropped_cluster(yade) -> int:
    """A cluster of 1,052 spheres (gaps of half a radius) above a facet floor 2 cm below: their count."""
    O = yade.O
    mat = O.materials.append(yade.ViscElMat(density=2300, frictionAngle=0.5, tc=0.001, en=0.3, et=0.3))
    ids = O.bodies.append(yade.pack.regularHexa(yade.pack.inSphere((0, 0.3, 0), 0.15), radius=0.01, gap=0.005,
                                                material=mat))
    assert ids == list(range(len(ids)))
    O.bodies.append(yade.geom.facetBox((0, 0.43, 0), (0.4, 0.3, 0.4), material=mat))
    O.engines = [
        yade.ForceResetter(),
        yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb(), yade.Bo1_Facet_Aabb()]),
        yade.InteractionLoop([yade.Ig2_Sphere_Sphere_ScGeom(), yade.Ig2_Facet_Sphere_ScGeom()],
                             [yade.Ip2_ViscElMat_ViscElMat_ViscElPhys()], [yade.Law2_ScGeom_ViscElPhys_Basic()]),
        yade.NewtonIntegrator(damping=0, gravity=(0, -9.81, 0)),
    ]
    O.dt = 1e-4
    return len(ids)


def test_budgets_carried_over_collider_runs_miss_no_touching_pair(yade):
    """The dropped cluster from its impact on: the collider runs because spheres left their bounds, and the pairs it
    finds again keep their budgets, measured from the present (granum.kernels.motion.carry_budgets). At every step
    every two spheres that overlap when the step begins are in contact after it, and every sphere reaching
    through the floor touches one of its facets: no carried budget let a touching pair go unevaluated."""
    O = yade.O
    n = _dropped_cluster(yade)
    floor = [b.id for b in O.bodies if isinstance(b.shape, yade.Facet) and  # the box's bottom, y = 0.43 - 0.3
             max(abs(b.state.pos[1] + v[1] - 0.13) for v in b.shape.vertices) < 1e-9]
    assert len(floor) == 2
    O.run(620, True)   # just before the impact
    runs = O.engines[1].numAction
    checked = through = carried = 0
    radius = np.array([O.bodies[i].shape.radius for i in range(n)])
    for _ in range(400):
        touching = _touching_sphere_pairs(O, n)
        pos = O._scene.bodies.pos[:n].copy()
        low = set(np.flatnonzero(pos[:, 1] - radius < 0.13).tolist())
        before = O.engines[1].numAction
        O.step()
        pairs = set(_contacts(O))
        checked += len(touching)
        through += len(low)
        assert touching <= pairs
        assert low <= {a for a, b in pairs if b in floor} | {b for a, b in pairs if a in floor}
        if O.engines[1].numAction > before:
            carried += _carried_budgets(O._scene.contacts, pos, radius)
    assert checked > 1000 and through > 50 and O.engines[1].numAction - runs >= 3
    assert carried > 100


def _carried_budgets(C, pos, radius) -> int:
    """How many sphere pairs without a contact have, after a step whose collider ran, a budget below their
    separation when the step began: carried over the run. A pair evaluated in that step (every pair, without
    carrying) has its separation then, less the float32 rounding: the collider ran before the detection, and the
    motions since are zero."""
    m = int(C.ctr[C_PAIRS])
    ids, gap = C.pair_ids[:m], C.pair_gap[:m].astype(float)
    spheres = (ids < len(pos)).all(axis=1) & (C.pair_con[:m] < 0) & np.isfinite(gap)
    i, j = ids[spheres, 0], ids[spheres, 1]
    sep = np.linalg.norm(pos[j] - pos[i], axis=1) - radius[i] - radius[j]
    return int((gap[spheres] < sep - 1e-7).sum())


def test_a_wall_turned_to_a_sphere_on_its_ignored_side_touches_it_at_the_next_step(yade):
    """A sphere overlapping a wall from the side the wall ignores (sense +1, the sphere below) has no contact, and
    the detection's budget of the pair holds the distance to the plane; ``sense = 0`` (both sides) makes the pair
    touch, so the scene must bound and pair again (a collider run that carries budgets over would keep the old
    one): the contact exists after the next step."""
    O = yade.O
    O.bodies.append(yade.utils.wall(0, axis=2, sense=1))
    O.bodies.append(yade.sphere((0, 0, -0.5), 1, fixed=True))
    O.bodies.append(yade.sphere((5, 0, 3), 1))   # moves: the collider runs because bodies moved
    O.bodies[2].state.vel = (0, 0, 30)
    O.engines = frict_engines(yade, gravity=(0, 0, 0))
    O.dt = 1e-3
    O.run(100, True)
    assert O.engines[1].numAction > 2
    assert not _contacts(O)
    O.bodies[0].shape.sense = 0
    O.step()
    assert _contacts(O) == [(0, 1)]


DROPPED_CLUSTER = """
import numpy
import granum.yade as yade
from test_detection_state import _dropped_cluster
n = _dropped_cluster(yade)
moved = 0
for _ in range(120):   # the impact at step 640, the first re-origins from about step 900
    O.run(10, True)
    moved += bool(O._scene.bodies.detect_shift[:n].any())
numpy.save('state.npy', numpy.array([list(b.state.pos) + list(b.state.vel) + list(b.state.angVel) for b in O.bodies]))
numpy.save('moved.npy', numpy.array([moved]))
"""


def test_threads_give_the_same_bits_through_moved_origins(tmp_path):
    """The dropped cluster over its impact with one and two threads (its pairs' detection, re-origin included, in
    parallel at -j2): the same bits, and the detection moved its origin in both."""
    import os
    import subprocess
    import sys

    (tmp_path / "cluster.py").write_text(DROPPED_CLUSTER)
    states = {}
    for threads in ("1", "2"):
        run = tmp_path / threads
        run.mkdir()
        env = {**os.environ, "PYTHONPATH": os.pathsep.join([os.path.dirname(__file__),
                                                            os.environ.get("PYTHONPATH", "")])}
        subprocess.run([sys.executable, "-m", "granum", "-j", threads, str(tmp_path / "cluster.py")], cwd=run,
                       check=True, timeout=1800, env=env)
        states[threads] = np.load(run / "state.npy")
        assert np.load(run / "moved.npy")[0] > 0, "the detection never moved its origin"
    assert np.abs(states["1"][:, 3:6]).max() > 0, "nothing moved"
    assert (states["1"] == states["2"]).all()


def test_a_moved_detection_origin_misses_no_touching_pair(yade):
    """A cluster of spheres dropped onto a facet spreads and bounces: the box of the displacements since the
    collider ran outgrows the pairs' budgets, and the detection moves its origin (granum.kernels.interaction.
    reorigin: some body's detect_shift is set). At every step every two spheres that overlap when the step
    begins (brute force) are in contact after it: the detection evaluated every pair that could touch."""
    O = yade.O
    n = _dropped_cluster(yade)
    O.run(600, True)   # just before the impact
    shifted = checked = 0
    for _ in range(300):
        touching = _touching_sphere_pairs(O, n)
        O.step()
        checked += len(touching)
        assert touching <= {tuple(p) for p in _contacts(O)}
        O.run(2, True)
        shifted += bool(O._scene.bodies.detect_shift[:n].any())
    assert checked > 1000 and shifted > 0


def test_the_motions_the_collider_leaves_are_those_the_interaction_loop_computes(yade):
    """The collider's check computes every body's motion; the interaction loop right after it reads them instead of
    computing them again. The dropped cluster with the standard engine order, and with the ForceResetter between
    the collider and the loop (the same physics, the loop computes its own motions): the same bits after its
    impact, where contacts began and ended and the collider ran again."""
    O = yade.O
    states = []
    for order in ((0, 1, 2, 3), (1, 0, 2, 3)):
        O.reset()
        _dropped_cluster(yade)
        O.engines = [O.engines[k] for k in order]
        O.run(900, True)
        b = O._scene.bodies
        n = b.count
        states.append((b.pos[:n].copy(), b.vel[:n].copy(), b.ang_vel[:n].copy(), _contacts(O),
                       O.engines[order.index(1)].numAction))
    fed, own = states
    assert fed[4] == own[4] >= 3 and len(fed[3]) >= 20
    for a, b in zip(fed[:3], own[:3], strict=True):
        assert np.array_equal(a.view(np.int64), b.view(np.int64))
    assert fed[3] == own[3]


@pytest.mark.parametrize("next_stage", [True, False])
def test_the_interaction_loop_takes_the_collider_s_motions_only_as_the_next_stage(yade, next_stage):
    """The stages called one by one from Python, as the step loop numbers them (``C_STAGE``): two spheres whose
    bounds overlap, the second moved into the first after a step, by less than the Verlet distance (no collider
    run). Its check leaves the motions with its stage's number; they are then replaced by zeros (as if nothing had
    moved). The loop called as the next stage takes them, sees no motion and leaves the pair untested; called as
    a later one (another stage between), it computes the motions itself and the spheres touch."""
    from granum._jit import call
    from granum.core.contacts import C_COLLIDER_RUNS, C_MOTIONS_STAGE, C_STAGE, CONTACTS
    from granum.kernels.collider import collider_stage
    from granum.kernels.interaction import interaction_stage
    from granum.kernels.motion import motion_words

    O = yade.O
    O.bodies.append([yade.sphere((0, 0, 0), 1.0), yade.sphere((2.4, 0, 0), 1.0)])   # bounds: 1.5 + 1.5 > 2.4
    O.engines = frict_engines(yade)
    O.dt = 1e-6
    O.step()
    assert not O.interactions[0, 1].isReal and O.engines[1].numAction == 1
    O.bodies[1].state.pos = (1.95, 0, 0)   # 0.45 from its bound's position: within the Verlet distance, 0.5
    scene = O._scene
    engines = list(O.engines)
    S, C = scene.arrays(), scene.contacts_record()
    ctr = scene.contacts.ctr
    ctr[C_STAGE] = 2
    call(collider_stage, S, C, engines[1].params(scene, engines))
    assert ctr[C_MOTIONS_STAGE] == 2 and ctr[C_COLLIDER_RUNS] == 1
    work = CONTACTS.from_record(C).scratch   # the work area: the motions (2, 4) at its start
    assert work[4:8].tolist() == [1.95 - 2.4, 0.0, 0.0, 0.0]   # sphere 1's row
    work[:call(motion_words, 2)] = 0.0
    ctr[C_STAGE] = 3 if next_stage else 4
    call(interaction_stage, S, C, engines[2].params(scene, engines))
    scene.take_contacts(C)
    assert ctr[C_MOTIONS_STAGE] == 0
    assert O.interactions[0, 1].isReal != next_stage
