"""The browser view's inspector and engine list without a browser: rows of attributes, values typed back,
edits through the YADE setters (same errors as a script's assignment)."""

from __future__ import annotations

import math

import pytest

from granum.mathtypes import Quaternion, Vector3
from granum.yade import (
    ForceResetter,
    InsertionSortCollider,
    InteractionLoop,
    NewtonIntegrator,
    O,
    utils,
)
from granum.yade.snapshot import RENDERER
from granum.yade.view import inspector
from granum.yade.view.session import Session


@pytest.fixture
def touching():
    """Two spheres in contact after one step, FrictPhys between them."""
    from granum.yade import (
        Bo1_Sphere_Aabb,
        Ig2_Sphere_Sphere_ScGeom,
        Ip2_FrictMat_FrictMat_FrictPhys,
        Law2_ScGeom_FrictPhys_CundallStrack,
    )

    O.reset()
    O.bodies.append([utils.sphere((0, 0, 0), 1.0), utils.sphere((0, 0, 1.9), 1.0)])
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [Law2_ScGeom_FrictPhys_CundallStrack()]),
                 NewtonIntegrator(damping=0.2)]
    O.dt = 1e-6
    O.step()
    yield O
    O.reset()


@pytest.mark.parametrize("text, value", [
    ("0.25", 0.25), ("-3e-2", -0.03), ("'xyz'", "xyz"), ("True", True), ("(1, 2, 3)", (1, 2, 3)),
    ("Vector3(0,0,-9.81)", Vector3(0, 0, -9.81)), ("inf", math.inf),
])
def test_values_typed_are_read_as_literals(text, value):
    assert inspector.parse_value(text) == value


def test_quaternion_reads_back_from_its_repr():
    q = Quaternion((0, 0, 1), 0.5)
    back = inspector.parse_value(repr(q))
    assert isinstance(back, Quaternion) and (back.toAxisAngle()[1] == pytest.approx(0.5))


@pytest.mark.parametrize("text, refused", [
    ("__import__('os')", "calls of Vector2"), ("Vector3(1,2,3).norm()", "calls of"), ("O", "unknown name 'O'"),
    ("1 +", "cannot read"), ("1 + 2", "BinOp"), ("[i for i in ()]", "ListComp"), ("Vector3(x=1)", "calls of"),
])
def test_anything_but_a_value_is_refused(text, refused):
    with pytest.raises(ValueError, match=refused):
        inspector.parse_value(text)


def test_body_sections_list_state_shape_material_and_interactions(touching):
    sections = {s["key"]: s for s in inspector.body_sections(O, 0)}
    assert list(sections) == ["state", "shape", "mat", "intr 0 1"]
    state = {r["name"]: r for r in sections["state"]["rows"]}
    assert state["vel"]["editable"] and state["vel"]["value"] == repr(O.bodies[0].state.vel)
    assert not state["se3"]["editable"]          # a property without a setter is shown, not edited
    shape = {r["name"]: r for r in sections["shape"]["rows"]}
    assert shape["radius"]["value"] == "1.0"
    mat = {r["name"]: r for r in sections["mat"]["rows"]}
    assert float(mat["young"]["value"]) == O.bodies[0].mat.young
    phys = {r["name"]: r for r in sections["intr 0 1"]["rows"]}
    assert float(phys["kn"]["value"]) == O.interactions[0, 1].phys.kn > 0


def test_an_edit_goes_through_the_setter(touching):
    s = Session(O, RENDERER)
    s.picked_id = 1
    s._run_command("edit_body", "state", "vel", "Vector3(1,2,3)")
    assert s.message == "" and O.bodies[1].state.vel == Vector3(1, 2, 3)
    s._run_command("edit_body", "intr 0 1", "kn", "5e6")
    assert O.interactions[0, 1].phys.kn == 5e6
    s._run_command("edit_engine", 3, "damping", "0.35")
    assert O.engines[3].damping == 0.35
    assert {r["name"]: r["value"] for r in s.panel_state()["engines"][3]["rows"]}["damping"] == "0.35"


def test_a_bad_value_gives_the_scripts_error_and_changes_nothing(touching):
    s = Session(O, RENDERER)
    s.picked_id = 0
    vel, pos = O.bodies[0].state.vel, O.bodies[0].state.pos
    with pytest.raises(ValueError) as script:
        O.bodies[0].state.vel = (1, 2)
    s._run_command("edit_body", "state", "vel", "(1, 2)")
    assert s.message == f"O.bodies[0].state.vel = (1, 2): {script.value}"
    assert O.bodies[0].state.vel == vel
    s._run_command("edit_engine", 3, "damping", "'much'")
    assert "NewtonIntegrator.damping must be a number" in s.message and O.engines[3].damping == 0.2
    s._run_command("edit_body", "state", "vel", "Vector3(nan,0,0)")
    assert "must be finite" in s.message
    s._run_command("edit_body", "state", "pos", "os.system('x')")
    assert "cannot read" in s.message and O.bodies[0].state.pos == pos


def test_the_inspector_follows_the_picked_body(touching):
    s = Session(O, RENDERER)
    assert s.inspected() == {"picked": "", "inspected": []}
    s.picked_id = 1
    head = s.panel_state()["picked"]
    assert head.startswith("id 1: Sphere, FrictMat") and head.endswith("1 contacts")
    O.bodies.erase(1)
    assert s.inspected() == {"picked": "", "inspected": []} and s.picked_id == -1


def test_an_attribute_that_cannot_be_read_is_shown_with_its_error():
    class Odd:
        @property
        def broken(self):
            raise NotImplementedError("granum has no broken")

        @property
        def fine(self):
            return 1.5

    assert inspector.property_rows(Odd()) == [
        {"name": "broken", "value": "<NotImplementedError: granum has no broken>", "editable": False},
        {"name": "fine", "value": "1.5", "editable": False}]
