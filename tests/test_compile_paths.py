"""granum's two compile paths (granum._jit): the fast one over Numba internals, the plain one when an internal
is missing or GRANUM_COMPILE=fallback; the probe that chooses; what granum leaves of Numba to a user's own
functions."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from granum import _linking

ROOT = Path(__file__).parents[1]


def _granum(args: list[str], cwd, **env) -> subprocess.CompletedProcess:
    """Run ``python args`` in ``cwd`` with granum's environment plus ``env``."""
    return subprocess.run([sys.executable, *args], cwd=cwd, env={**os.environ, **env}, capture_output=True,
                          text=True, timeout=1800)


@pytest.mark.fallback
def test_the_plain_path_gives_the_fast_paths_bits_on_the_dense_lattice(tmp_path):
    """The dense-lattice benchmark above the parallel threshold (4913 spheres in a facet box, friction, damping,
    gravity): the positions and angular velocities after the run are the same bits on both paths."""
    if _linking.missing_internal() is not None:
        pytest.skip("this Numba has no fast path to compare with")
    dumps = {}
    for mode in ("auto", "fallback"):
        dumps[mode] = tmp_path / f"{mode}.txt"
        run = _granum(["-m", "granum", "-j", "2", str(ROOT / "benchmarks" / "dense_lattice.py")], tmp_path,
                      GRANUM_COMPILE=mode, BENCH_N="17", BENCH_STEPS="20", BENCH_DUMP=str(dumps[mode]))
        assert run.returncode == 0, run.stderr
    fast, plain = dumps["auto"].read_text(), dumps["fallback"].read_text()
    assert len(fast.splitlines()) == 17 ** 3
    assert fast == plain


# A scene with every way the step loop hands control back: a PyRunner every few steps, a periodic engine in
# simulated time, O.timingEnabled; first with user_function removed from numba.core.imputils (granum imports it;
# Numba bound its own copy at import, so Numba itself still works).
_WITHOUT_AN_INTERNAL = """
import warnings
import numba
from numba.core.registry import cpu_target
cpu_target.target_context                       # Numba's own modules hold their names already
import numba.core.imputils
del numba.core.imputils.user_function
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    from granum.yade import *
    from granum import _jit
    O.bodies.append([sphere((0, 0, 0), .5, fixed=True), sphere((0, 0, 1.2), .5)])
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [Law2_ScGeom_FrictPhys_CundallStrack()]),
                 NewtonIntegrator(gravity=(0, 0, -9.81), damping=.1),
                 PyRunner(command='zs.append(O.bodies[1].state.pos[2])', iterPeriod=50),
                 PyRunner(command='ts.append(O.time)', virtPeriod=0.002)]
    zs, ts = [], []
    O.dt = 1e-5
    O.timingEnabled = True
    O.run(1000, True)
print("PLAIN", _jit.PLAIN, "CACHE", _jit.CACHE_DIR.name.endswith("-plain"))
print("RESULT", O.iter, len(zs), len(ts), repr(O.bodies[1].state.pos[2]), O.engines[3].execCount)
for w in caught:
    print("WARNING", w.category.__name__, w.message)
"""


def test_a_missing_internal_selects_the_plain_path_with_one_warning_naming_it(tmp_path):
    out = _granum(["-c", _WITHOUT_AN_INTERNAL], tmp_path, GRANUM_COMPILE="auto")  # the choice made by the probe
    assert out.returncode == 0, out.stderr
    assert "PLAIN True CACHE True" in out.stdout
    warnings = [line for line in out.stdout.splitlines() if line.startswith("WARNING")]
    assert len(warnings) == 1, warnings
    assert "CompileFallbackWarning" in warnings[0] and "lacks numba.core.imputils.user_function," in warnings[0]
    # the same scene with the internal present: the fast path, no warning, the same numbers
    fast = _granum(["-c", _WITHOUT_AN_INTERNAL.replace("del numba.core.imputils.user_function", "")], tmp_path,
                   GRANUM_COMPILE="auto")
    assert fast.returncode == 0, fast.stderr
    if _linking.missing_internal() is None:
        assert "PLAIN False CACHE False" in fast.stdout
        assert "WARNING" not in fast.stdout
    result = [line for line in out.stdout.splitlines() if line.startswith("RESULT")]
    assert result == [line for line in fast.stdout.splitlines() if line.startswith("RESULT")]
    assert result[0].startswith("RESULT 1000 ") and result[0].endswith(" 1000")


def test_the_probe_names_the_first_internal_missing_from_a_module_a_dispatcher_or_a_library():
    assert _linking.missing_internal(("numba.core.codegen.JITCodeLibrary", "dispatcher.overloads",
                                      "library._final_module")) is None
    for missing in ("numba.core.codegen.NoSuchLibrary", "numba.no_such_module.thing",
                    "numba.core.compiler.Flags.no_such_option", "dispatcher._compiler.no_such_method",
                    "library.no_such_field"):
        assert _linking.missing_internal(("numba.core.compiler.compile_extra", missing, "library.nor_this")) \
            == missing


def test_a_bad_compile_setting_is_refused_naming_it(tmp_path):
    out = _granum(["-c", "import granum.yade"], tmp_path, GRANUM_COMPILE="fastest")
    assert out.returncode != 0
    assert "GRANUM_COMPILE must be 'auto' (the default) or 'fallback', not 'fastest'" in out.stderr


_USER_KERNEL = """
import numba


@numba.njit(cache=True)
def user_function(x):
    return x + 1
"""


def test_a_users_cached_function_is_cached_where_numba_puts_it_and_other_overloads_are_untouched(tmp_path):
    """granum points Numba's cache folder at its own only while it decorates its functions, and changes only
    the templates of its own ``@overload`` functions."""
    (tmp_path / "userkern.py").write_text(_USER_KERNEL)
    script = ("from granum.yade import *\nimport userkern\nprint('VALUE', userkern.user_function(41))\n"
              "from numba.core.typing.templates import _OverloadFunctionTemplate as T\n"
              "print('TEMPLATE', T._get_jit_decorator.__module__)\n")
    out = _granum(["-c", script], tmp_path, GRANUM_CACHE_DIR=str(tmp_path / "granum-cache"))
    assert out.returncode == 0, out.stderr
    assert "VALUE 42" in out.stdout
    assert "TEMPLATE numba.core.typing.templates" in out.stdout
    assert list((tmp_path / "__pycache__").glob("userkern.user_function-*.nbi"))
    assert not [p for p in (tmp_path / "granum-cache").rglob("*") if "userkern" in p.name]
