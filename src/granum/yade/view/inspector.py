"""The page's editable inspector and engine list: an object's attributes as rows of text, and an edited row
assigned back through the object's own YADE attribute setter.

A row is ``{"name", "value", "editable"}``: ``value`` is the attribute's ``repr`` (``Vector3(0,0,-9.81)``,
``Quaternion((1,0,0),0)``, ``0.4``, ``'xyz'``), which is also what the user types back. The text typed is
read by :func:`parse_value`, which accepts Python literals and calls of the math types only (no other
names, no attribute access: the page never runs code), then assigned with ``setattr``: the same setter a
script's ``O.bodies[3].state.vel = ...`` goes through, so a bad value raises the same error, which the page
shows.
"""

from __future__ import annotations

import ast
import math

from granum import mathtypes

#: the calls a typed value may contain (the math types' constructors, as scripts write them)
CONSTRUCTORS = {name: getattr(mathtypes, name) for name in ("Vector2", "Vector3", "Vector6", "Quaternion",
                                                            "Matrix3", "Matrix6") if hasattr(mathtypes, name)}
#: types whose values are shown in rows that can be edited (their repr reads back through parse_value)
EDITABLE_TYPES = (bool, int, float, str, *CONSTRUCTORS.values())
#: interactions listed in the inspector for one body (a body in a dense packing has a dozen)
MAX_INTERACTIONS = 24


def parse_value(text: str):
    """The value typed in an inspector row: a Python literal (number, string, tuple, list, True/False/None)
    or a call of a math type (``Vector3(0,0,1)``, ``Quaternion((0,0,1),0.5)``) whose arguments are such
    values. Anything else raises ValueError naming what is refused."""
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as e:
        raise ValueError(f"cannot read {text!r}: {e.msg}") from None
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            if not (isinstance(node.func, ast.Name) and node.func.id in CONSTRUCTORS) or node.keywords:
                raise ValueError(f"cannot read {text!r}: only literals and calls of "
                                 f"{', '.join(CONSTRUCTORS)} are accepted")
        elif isinstance(node, ast.Name):
            if node.id not in CONSTRUCTORS and node.id not in ("inf", "nan"):
                raise ValueError(f"cannot read {text!r}: unknown name {node.id!r}")
        elif not isinstance(node, (ast.Expression, ast.Constant, ast.Tuple, ast.List, ast.UnaryOp, ast.USub,
                                   ast.UAdd, ast.Load)):
            raise ValueError(f"cannot read {text!r}: {type(node).__name__} is not a value")
    return eval(compile(tree, "<inspector>", "eval"), {"__builtins__": {}},   # noqa: S307 - AST checked above
                {**CONSTRUCTORS, "inf": math.inf, "nan": math.nan})


def _row(obj, name: str, settable: bool) -> dict:
    try:
        value = getattr(obj, name)
    except Exception as e:  # noqa: BLE001 - an attribute that cannot be read here: its error is the row's text
        return {"name": name, "value": f"<{type(e).__name__}: {e}>", "editable": False}
    editable = settable and isinstance(value, EDITABLE_TYPES)
    text = repr(value)
    if not editable and len(text) > 60:   # functor lists, id lists: shown cut, not edited
        text = text[:57] + "..."
    return {"name": name, "value": text, "editable": editable}


def declared_rows(obj) -> list[dict]:
    """Rows of an object whose attributes are declared in ``_attrs`` (engines, materials)."""
    return [_row(obj, name, not spec.readonly) for name, spec in type(obj)._attrs.items()]


def property_rows(obj) -> list[dict]:
    """Rows of a view whose attributes are properties (State, shapes, interaction physics); those without a
    setter are shown, not edited."""
    cls = type(obj)
    props = [(n, getattr(cls, n)) for n in dir(cls) if not n.startswith("_")]
    return [_row(obj, n, p.fset is not None) for n, p in props if isinstance(p, property)]


def body_sections(omega, i: int) -> list[dict]:
    """The inspector's sections for body ``i``: ``{"key", "title", "rows"}`` for its state, shape, material
    and each of its interactions' physics (``key`` names the object for :func:`resolve`)."""
    b = omega.bodies[i]
    sections = [{"key": "state", "title": f"state ({type(b.state).__name__})", "rows": property_rows(b.state)},
                {"key": "shape", "title": f"shape ({type(b.shape).__name__})", "rows": property_rows(b.shape)},
                {"key": "mat", "title": f"material ({type(b.mat).__name__} {b.mat.label or b.mat.id})",
                 "rows": declared_rows(b.mat)}]
    for intr in b.intrs()[:MAX_INTERACTIONS]:
        if intr.phys is None:
            continue
        pair = f"{intr.id1} {intr.id2}"
        sections.append({"key": f"intr {pair}", "title": f"interaction {intr.id1}-{intr.id2} "
                         f"({type(intr.phys).__name__})", "rows": property_rows(intr.phys)})
    return sections


def path(i: int, key: str) -> str:
    """How a script names the object of section ``key`` of body ``i`` (for messages)."""
    if key.startswith("intr "):
        return "O.interactions[{}, {}].phys".format(*key.split()[1:])
    return f"O.bodies[{i}].{key}"


def resolve(omega, i: int, key: str):
    """The object a section ``key`` of body ``i`` names (see :func:`body_sections`)."""
    b = omega.bodies[i]
    if b is None:
        raise ValueError(f"body {i} was erased")
    if key in ("state", "shape", "mat"):
        return getattr(b, key)
    kind, *ids = key.split()
    if kind == "intr" and len(ids) == 2:
        return omega.interactions[int(ids[0]), int(ids[1])].phys
    raise ValueError(f"the inspector has no section {key!r}")


def assign(obj, name: str, text: str) -> None:
    """``obj.name = value of text`` through the object's setter (its errors are the script's errors)."""
    setattr(obj, name, parse_value(text))
