"""The layers of granum: a module imports only modules of its own layer or of lower ones.

Bottom to top (ARCHITECTURE.md, "Layout"): the Numba set-up and the math types, ``core``,
``physics``, ``kernels``, ``engines``, ``io``, ``batch`` and ``idem``, ``yade``, the launcher.
Every import statement counts, also one inside a function, and so does a ``"module:function"``
string (how engines name their compiled stage, imported by the runner).
"""

from __future__ import annotations

import ast
import pathlib
import re

import pytest

SRC = pathlib.Path(__file__).resolve().parent.parent / "src"

#: Layers from the bottom: the names of granum's top-level modules and packages in each.
LAYERS = (
    ("bottom", ("__init__", "mathtypes", "_jit", "_linking", "_compile", "_codegen")),
    ("core", ("core",)),
    ("physics", ("physics",)),
    ("kernels", ("kernels",)),
    ("engines", ("engines",)),
    ("io", ("io",)),
    ("batch/idem", ("batch", "idem")),
    ("yade", ("yade",)),
    ("cli", ("cli", "__main__")),
)
_LEVEL = {name: (k, layer) for k, (layer, names) in enumerate(LAYERS) for name in names}
#: a compiled stage's reference, ``"granum.kernels.forces:reset_stage"``
_REF = re.compile(r"(granum(?:\.\w+)+):\w+")


def layer_of(module: str) -> tuple[int, str] | None:
    """``(rank, name)`` of the layer of the granum module ``module``; None outside granum."""
    parts = module.split(".")
    if parts[0] != "granum":
        return None
    top = parts[1] if len(parts) > 1 else "__init__"
    if top == "__version__":    # from granum import __version__
        top = "__init__"
    if top not in _LEVEL:
        raise AssertionError(f"granum.{top} is in no layer: add it to LAYERS in tests/test_layers.py and to "
                             f"ARCHITECTURE.md")
    return _LEVEL[top]


def module_name(path: pathlib.Path) -> str:
    parts = list(path.relative_to(SRC).with_suffix("").parts)
    if parts[-1] == "__init__" and len(parts) > 1:
        parts.pop()
    return ".".join(parts)


def imported(path: pathlib.Path, tree: ast.AST):
    """``(line, module)`` for every granum module the file imports or names as ``"module:function"``."""
    package = module_name(path).split(".")
    if path.name != "__init__.py":
        package.pop()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield node.lineno, alias.name
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(package[: len(package) - node.level + 1] + ([base] if base else []))
            if base == "granum":    # from granum import physics
                for alias in node.names:
                    yield node.lineno, f"granum.{alias.name}"
            else:
                yield node.lineno, base
        elif isinstance(node, ast.Constant) and isinstance(node.value, str):
            m = _REF.fullmatch(node.value)
            if m:
                yield node.lineno, m.group(1)


def upward_imports(path: pathlib.Path, source: str) -> list[str]:
    """One message per import of ``path`` (whose text is ``source``) from a higher layer."""
    me = module_name(path)
    rank, layer = layer_of(me)
    out = []
    for line, target in sorted(imported(path, ast.parse(source, str(path)))):
        theirs = layer_of(target)
        if theirs is not None and theirs[0] > rank:
            out.append(f"{path.relative_to(SRC.parent)}:{line}: {me} (layer {layer}) imports {target} "
                       f"(layer {theirs[1]}, higher)")
    return out


FILES = sorted((SRC / "granum").rglob("*.py"))


@pytest.mark.parametrize("path", FILES, ids=lambda p: module_name(p))
def test_imports_only_own_or_lower_layers(path):
    bad = upward_imports(path, path.read_text())
    assert not bad, "upward imports (see the layers in ARCHITECTURE.md, 'Layout'):\n" + "\n".join(bad)


def test_an_upward_import_is_found():
    """The check sees a function-local import, a relative one and a stage reference going up."""
    path = SRC / "granum" / "core" / "scene.py"
    source = ("def f():\n"
              "    from ..physics import registry\n"
              "    import granum.yade\n"
              "S = 'granum.kernels.forces:reset_stage'\n")
    assert upward_imports(path, source) == [
        "src/granum/core/scene.py:2: granum.core.scene (layer core) imports granum.physics (layer physics, higher)",
        "src/granum/core/scene.py:3: granum.core.scene (layer core) imports granum.yade (layer yade, higher)",
        "src/granum/core/scene.py:4: granum.core.scene (layer core) imports granum.kernels.forces "
        "(layer kernels, higher)"]
    assert upward_imports(SRC / "granum" / "yade" / "omega.py", source) == []
