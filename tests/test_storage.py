"""Storage: growable tables, lazy columns, the width of the contact pool."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import frict_engines

from granum.core.table import Column, Table

COLUMNS = (
    Column("x", (3,), "f8", 0.0),
    Column("q", (4,), "f8", (1.0, 0.0, 0.0, 0.0)),
    Column("extra", (2,), "f8", (7.0, 8.0), lazy=True),
)


def test_appended_rows_hold_the_defaults_after_growth_and_clear():
    t = Table(COLUMNS, capacity=2)
    t.append_rows(2)
    t.q[:2] = 5.0
    t.append_rows(3)                      # grows past the capacity
    assert (t.q[:2] == 5.0).all() and (t.q[2:5] == (1.0, 0.0, 0.0, 0.0)).all()
    t.clear()
    t.append_rows(4)                      # reused rows get their defaults again
    assert (t.q[:4] == (1.0, 0.0, 0.0, 0.0)).all() and (t.x[:4] == 0.0).all()


def test_rows_appended_in_one_go_leave_room_for_a_few_more():
    """A list of bodies appended at once grows the table to a power of two, not to the rows alone: the few bodies
    appended next (a facet box) must not copy every column into arrays twice as long."""
    t = Table(COLUMNS, capacity=8)
    t.append_rows(1000)
    assert t.x.shape[0] == 1024
    t.append_rows(12)
    assert t.x.shape[0] == 1024 and (t.q[1000:1012] == (1.0, 0.0, 0.0, 0.0)).all()


def test_a_lazy_column_is_allocated_on_first_use_with_defaults_in_the_rows_so_far():
    t = Table(COLUMNS)
    t.append_rows(3)
    assert not t.allocated("extra") and t.stored("extra").shape == (0, 2)
    t.extra[1] = (1.0, 2.0)
    assert t.allocated("extra")
    assert t.extra[:3].tolist() == [[7.0, 8.0], [1.0, 2.0], [7.0, 8.0]]
    t.append_rows(20)                     # grows with the table
    assert t.extra.shape[0] == t.x.shape[0] and (t.extra[3:23] == (7.0, 8.0)).all()
    with pytest.raises(AttributeError, match="no column 'extar'"):
        t.extar  # noqa: B018


def test_copy_rows_carries_a_lazy_column_only_where_it_exists():
    src, dst = Table(COLUMNS), Table(COLUMNS)
    src.append_rows(2)
    dst.append_rows(2)
    dst.copy_rows(src, 0, 1)
    assert not dst.allocated("extra")     # nothing to carry: stays unallocated
    src.extra[1] = (3.0, 4.0)
    dst.copy_rows(src, 1, 0)
    assert dst.extra[:2].tolist() == [[3.0, 4.0], [7.0, 8.0]]
    src2 = Table(COLUMNS)
    src2.append_rows(1)
    dst.copy_rows(src2, 0, 0)              # the source never used it: the destination row gets the default
    assert dst.extra[0].tolist() == [7.0, 8.0]


def test_a_sphere_packing_run_allocates_none_of_the_rarely_used_body_columns(yade):
    """Permanent forces, clump offsets, reference orientations and angular momenta cost nothing until used."""
    O = yade.O
    O.bodies.append([yade.sphere((0, 0, 0.0099 * 2 * k), 0.01) for k in range(5)])
    O.engines = frict_engines(yade, gravity=(0, 0, -9.81))
    O.dt = 1e-5
    O.run(20, True)
    b = O._scene.bodies
    lazy = [c.name for c in b.columns if c.lazy]
    assert set(lazy) >= {"perm_force", "perm_torque", "clump_rel_pos", "clump_rel_ori", "ang_mom", "ref_ori"}
    assert not any(b.allocated(n) for n in lazy)
    assert O.forces.permF(0) == yade.Vector3(0, 0, 0)
    O.forces.setPermF(4, (0, 0, 3.0))     # now used: takes effect in ForceResetter
    O.run(1, True)
    assert b.allocated("perm_force") and not b.allocated("perm_torque")
    assert O.forces.permF(4)[2] == 3.0


def test_detached_bodies_that_used_a_rarely_used_column_do_not_allocate_it_for_later_spheres(yade):
    """Detached bodies share one table: a box made earlier with an angular velocity and a reference orientation
    allocates its angular momenta and reference orientations there, which the spheres appended later must not
    bring into the scene (each sphere's rows hold the defaults); the box's own values still arrive with it."""
    O = yade.O
    box = yade.box((0, 0, 0), (0.1, 0.2, 0.3))
    box.state.angVel = (1.0, 2.0, 3.0)
    box.state.refOri = yade.Quaternion((0, 0, 1), 0.5)
    O.bodies.append([yade.sphere((0, 0, 0.0099 * 2 * k), 0.01) for k in range(5)])
    b = O._scene.bodies
    assert not b.allocated("ang_mom") and not b.allocated("ref_ori")
    O.bodies.append(box)
    assert b.allocated("ang_mom") and b.allocated("ref_ori")
    assert np.allclose(np.asarray(O.bodies[5].state.angMom), np.asarray(box.state.inertia) * (1.0, 2.0, 3.0))
    assert O.bodies[5].state.refOri == yade.Quaternion((0, 0, 1), 0.5)
    assert O.bodies[0].state.refOri == yade.Quaternion(1, 0, 0, 0)


def test_an_aspherical_body_gets_its_angular_momentum_from_its_angular_velocity(yade):
    O = yade.O
    box = yade.box((0, 0, 0), (0.1, 0.2, 0.3))
    box.state.angVel = (1.0, 2.0, 3.0)
    O.bodies.append(box)
    inertia = np.asarray(box.state.inertia)
    assert np.allclose(np.asarray(box.state.angMom), inertia * (1.0, 2.0, 3.0), rtol=1e-14)
    s = yade.sphere((1, 0, 0), 0.1)
    s.state.angVel = (1.0, 0.0, 0.0)
    O.bodies.append(s)
    s.aspherical = True                   # turned aspherical later: L = I w from then on
    assert np.allclose(np.asarray(s.state.angMom), np.asarray(s.state.inertia) * (1.0, 0.0, 0.0), rtol=1e-14)


def _pile(y, n=6):
    """A column of slightly overlapping spheres on a wall: contacts from the first step on."""
    O = y.O
    O.bodies.append(y.wall((0, 0, 0), 2))
    O.bodies.append([y.sphere((0.001 * k, 0, 0.0099 + 0.0198 * k), 0.01) for k in range(n)])
    return O


def test_the_contact_pool_stores_only_the_columns_its_laws_use(yade):
    from granum.core.contacts import F_E_DISSIP, NF_CORE, NI, NI_CORE, nf

    O = _pile(yade)
    O.engines = frict_engines(yade, gravity=(0, 0, -9.81))
    O.dt = 1e-6
    O.run(5, True)
    C = O._scene.contacts
    assert O.interactions.countReal() > 0
    assert C.con_f.shape[1] == NF_CORE and C.con_i.shape[1] == NI_CORE
    O.trackEnergy = True
    O.run(5, True)
    assert O._scene.contacts.con_f.shape[1] == F_E_DISSIP + 1 and O.energy["elastPotential"] > 0
    O.periodic = True
    assert O._scene.contacts.con_i.shape[1] == NI and O.interactions.all()[0].cellDist == yade.Vector3i(0, 0, 0)

    yade.O.reset()
    O = _pile(yade)
    mat = O.materials.append(yade.ViscElMat(tc=1e-3, en=0.5, et=0.5, frictionAngle=0.3, density=2600))
    for b in O.bodies:
        b.material = O.materials[mat]
    O.engines = [yade.ForceResetter(), yade.InsertionSortCollider([yade.Bo1_Sphere_Aabb(), yade.Bo1_Wall_Aabb()]),
                 yade.InteractionLoop([yade.Ig2_Sphere_Sphere_ScGeom(), yade.Ig2_Wall_Sphere_ScGeom()],
                                      [yade.Ip2_ViscElMat_ViscElMat_ViscElPhys()],
                                      [yade.Law2_ScGeom_ViscElPhys_Basic()]),
                 yade.NewtonIntegrator(gravity=(0, 0, -9.81))]
    O.dt = 1e-6
    O.run(5, True)
    # the core columns, the energies' place, the visco-elastic damping and elastic shear, the contact moment
    # (rolling resistance, 3) and mR, mRtype (2): none of the other laws' groups (Mindlin's, L3Geom's, the
    # cohesion's share these columns)
    assert O._scene.contacts.con_f.shape[1] == NF_CORE + 2 + 2 + 3 + 3 + 2 < nf()
    assert O.interactions.all()[0].phys.cn > 0


def test_tracking_energy_does_not_change_the_motion(yade):
    """The energy columns are bookkeeping: positions are bitwise the same with and without them."""
    runs = []
    for track in (False, True):
        yade.O.reset()
        O = _pile(yade)
        O.engines = frict_engines(yade, gravity=(0, 0, -9.81), damping=0.1)
        O.dt = 1e-5
        O.trackEnergy = track
        O.run(300, True)
        runs.append(np.array([tuple(b.state.pos) for b in O.bodies]))
    assert np.array_equal(runs[0], runs[1])


def _mixed_bodies(y, frict, cpm):
    """Bodies of every factory, several materials (the default one too), a CpmState, a bare body and a body made
    from a shape object, not listed in the order they were made; explicit colours, so that two calls make the same
    bodies."""
    Sphere, Body = y.Sphere, y.Body
    made_first = y.sphere((5, 5, 5), 0.5, material=cpm, fixed=True, color=(1, 0, 1))   # listed after others
    out = [y.sphere((0, 0, 0.02 * k), 0.01 + 0.001 * k, material=frict if k % 3 else -1, color=(0.1 * k, 0, 0))
           for k in range(5)]
    out += y.geom.facetBox((0, 0, 0), (1, 1, 1), material=frict, color=(0, 1, 0))
    out += [y.box((1, 2, 3), (0.1, 0.2, 0.3), material=frict, color=(0, 0, 1)),
            y.wall(0.5, 2, material=frict, color=(1, 1, 0)),
            made_first,
            Body(),
            Body(shape=Sphere(radius=0.3, color=(0.5, 0.5, 0.5)), material=frict),
            y.sphere((6, 6, 6), 0.2, material=frict, color=(0, 0.5, 0))]
    return out


def _scene_snapshot(y):
    scene = y.O._scene
    columns = {name: scene.bodies.stored(name)[:scene.body_count].copy() for name in scene.bodies.__dict__
               if isinstance(getattr(scene.bodies, name), np.ndarray)}
    shapes = {int(kind): {c.name: t.stored(c.name)[:t.count].copy() for c in t.columns}
              for kind, t in scene.shapes.items()}
    materials = [(type(m).__name__, m.density) for m in scene.materials]
    born = (scene.born.iter[:scene.body_count].copy(), scene.born.time[:scene.body_count].copy())
    return columns, shapes, materials, born


def test_appending_a_list_of_bodies_stores_what_appending_them_one_by_one_stores(yade):
    """``O.bodies.append(list)`` copies the columns of all the bodies at once; appending them one at a time is the
    reference: the same ids, body columns, shape rows, materials (in the order they first appear), birth steps."""
    stored = []
    for one_by_one in (False, True):
        yade.O.reset()
        yade.O._scene.iter = 7   # (read-only in YADE)
        frict = yade.FrictMat(density=2000)
        cpm = yade.CpmMat(density=2500)
        yade.O.bodies.append(yade.sphere((9, 9, 9), 1.0, material=frict, color=(1, 1, 1)))  # a scene not empty
        bodies = _mixed_bodies(yade, frict, cpm)
        yade.O.materials.append(yade.FrictMat(density=3000))   # the default material of the bare body, appended
        ids = [yade.O.bodies.append(b) for b in bodies] if one_by_one else yade.O.bodies.append(bodies)
        assert ids == list(range(1, 1 + len(bodies)))
        assert [b.id for b in bodies] == ids                       # the handles now look into the scene
        assert all(type(b) is yade.Body for b in bodies)             # and have no row of the nursery to give back
        assert yade.O.bodies[3].shape.radius == pytest.approx(0.012)   # the third of the list
        assert type(yade.O.bodies[ids[-4]].state).__name__ == "CpmState"
        stored.append(_scene_snapshot(yade))
    (cols, shapes, materials, born), (cols1, shapes1, materials1, born1) = stored
    assert cols.keys() == cols1.keys()
    for name in cols:
        np.testing.assert_array_equal(cols[name], cols1[name], err_msg=name)
    assert shapes.keys() == shapes1.keys()
    for kind in shapes:
        for name in shapes[kind]:
            np.testing.assert_array_equal(shapes[kind][name], shapes1[kind][name], err_msg=f"{kind} {name}")
    assert materials == materials1 == [("FrictMat", 2000), ("FrictMat", 1000), ("CpmMat", 2500),
                                            ("FrictMat", 3000)]
    np.testing.assert_array_equal(born[0], born1[0])
    assert (born[0] == 7).all()


def test_a_list_with_a_body_already_appended_appends_the_bodies_before_it_and_stops(yade):
    a, b, c = (yade.sphere((0, 0, k), 0.1) for k in range(3))
    yade.O.bodies.append(b)
    with pytest.raises(ValueError, match="already in a simulation"):
        yade.O.bodies.append([a, b, c])
    assert (a.id, b.id, c.id) == (1, 0, -1) and len(yade.O.bodies) == 2
    d = yade.sphere((0, 0, 5), 0.1)
    with pytest.raises(ValueError, match="already in a simulation"):
        yade.O.bodies.append([d, d])                              # the same body twice
    assert d.id == 2 and len(yade.O.bodies) == 3


def test_bodies_made_and_dropped_reuse_the_rows_of_the_storage_of_detached_bodies(yade):
    """A script making and dropping bodies in a loop while another one is kept must not grow the storage of the
    detached bodies without end."""
    from granum.yade.bodies import _NURSERY

    start = _NURSERY.bodies.count   # rows used by earlier tests' scenes are kept: measured from here
    kept = yade.sphere((0, 0, 0), 1.0)
    assert isinstance(kept, yade.Body) and type(kept).__name__ == "Body"
    for k in range(5000):
        yade.sphere((0, 0, k), 0.1)
        yade.Sphere(radius=0.1)
    assert kept.id == -1 and _NURSERY.bodies.count <= start + 2 * _NURSERY.BLOCK
