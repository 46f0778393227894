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


def test_copy_row_carries_a_lazy_column_only_where_it_exists():
    src, dst = Table(COLUMNS), Table(COLUMNS)
    src.append_rows(2)
    dst.append_rows(2)
    dst.copy_row(src, 0, 1)
    assert not dst.allocated("extra")     # nothing to carry: stays unallocated
    src.extra[1] = (3.0, 4.0)
    dst.copy_row(src, 1, 0)
    assert dst.extra[:2].tolist() == [[3.0, 4.0], [7.0, 8.0]]
    src2 = Table(COLUMNS)
    src2.append_rows(1)
    dst.copy_row(src2, 0, 0)              # the source never used it: the destination row gets the default
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
