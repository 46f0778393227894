"""Generated kernel modules.

Some compiled code depends on run-time configuration: the conversions of a record kind
(its fields, :mod:`granum.core.records`), the dispatch from functor codes to registered
physics functions and the collider's branch to the registered shape reaches (they depend
on the registry), and the fused step loop (it depends on the engine list). All are
rendered as Python source, written to the cache directory and imported like ordinary
modules, so that Numba can cache their compiled code on disk like any other kernel.
The file name carries a hash of the source: a configuration seen before loads without
recompiling. The module sits in the bottom layer, beside :mod:`granum._jit`, because
the records of ``core`` use it.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
import sys
import tempfile

from granum._jit import CACHE_DIR

GENERATED_DIR = CACHE_DIR / "generated"


def load_module(stem: str, source: str):
    """Import ``source`` as module ``granum_generated.<stem>_<hash>`` (written once to disk)."""
    digest = hashlib.sha256(source.encode()).hexdigest()[:16]
    name = f"granum_generated_{stem}_{digest}"
    if name in sys.modules:
        return sys.modules[name]
    GENERATED_DIR.mkdir(parents=True, exist_ok=True)
    path = GENERATED_DIR / f"{name}.py"
    if not path.exists() or path.read_text() != source:
        # atomic write: concurrent processes never import a half-written file
        fd, tmp = tempfile.mkstemp(dir=GENERATED_DIR, suffix=".tmp")
        with os.fdopen(fd, "w") as fh:
            fh.write(source)
        os.replace(tmp, path)
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def import_line(ref: str, alias: str) -> str:
    """``from module import function as alias`` for a ``"module:function"`` reference."""
    module, func = ref.split(":")
    return f"from {module} import {func} as {alias}"
