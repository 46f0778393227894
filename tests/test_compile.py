"""How granum compiles: link-only callees and calls by symbol (granum._linking), and a first run's parts on
two processes (granum._compile). Each test runs a small module of its own in a fresh process and cache
directory."""

from __future__ import annotations

import math
import os
import subprocess
import sys
import textwrap
from types import SimpleNamespace

import numpy as np
import pytest

KERNELS = '''
import numpy as np
from granum._jit import jit
from granum._linking import entry_call


@jit
def inner(x):
    if x > 5:
        raise ValueError("too big", x)
    print("inner", x)
    return 2 * x


@jit
def outer(a):
    s = 0
    for v in a:
        s += inner(v)          # an int64 from the array
    s += inner(np.int32(1))    # other integer types: the same compilation
    s += inner(np.uint8(1))
    return s


@jit
def part_a(a):   # NumPy's median and sort: seconds of compilation, so that each process takes a part
    return np.median(a) + np.sort(a)[-1]


@jit
def part_b(a):
    return float(np.argsort(a, kind="mergesort")[0]) + np.cumsum(a)[-1]


@jit
def whole(a):   # calls its parts by symbol: their code stays in their own entry points
    return entry_call(part_a, (a,)) + entry_call(part_b, (a,))


@jit(shared=True)
def common(a):   # both parts of the next entry points call it: compiled once, by either process
    return np.sort(a)[-2] + np.cumsum(a)[1]


@jit
def part_c(a):
    return np.median(a) + common(a)


@jit
def part_d(a):
    return float(np.argsort(a, kind="mergesort")[0]) + common(a)


@jit(shared=True)
def typed(a):   # called with floats by one part, integers by the other
    return a.sum()


@jit
def part_e(a):
    return typed(a) + np.sort(a).sum()


@jit
def part_f(a):
    return typed(a) + np.cumsum(a)[-1] + 1
'''


def _run(folder, script: str, module: str = KERNELS, timeout: float = 600, **env) -> str:
    """Run ``script`` in ``folder`` (created) with ``module`` (the one above unless said) importable as ``kern``
    and a cache directory of its own, on the fast compile path whatever the suite's (these tests are the fast
    path's: the suite also runs with GRANUM_COMPILE=fallback); its standard output."""
    folder.mkdir(exist_ok=True)
    if not (folder / "kern.py").exists():   # rewriting it would change its time stamp: Numba's cache key
        (folder / "kern.py").write_text(module)
    environ = {**os.environ, "GRANUM_COMPILE": "auto", "GRANUM_CACHE_DIR": str(folder / "cache"), **env}
    out = subprocess.run([sys.executable, "-c", textwrap.dedent(script)], cwd=folder, env=environ, check=True,
                         capture_output=True, text=True, timeout=timeout)
    return out.stdout


LINK_ONLY = '''
import numpy as np
import kern
from granum._linking import LinkOnlyLibrary
print("sum", kern.outer(np.arange(3)))
try:
    kern.outer(np.arange(8))
except ValueError as e:
    print("raised", e.args)
print("entry points of inner:", len(kern.inner.overloads))
print("outer compiled:", len(kern.outer.overloads), "loaded from the cache:", sum(kern.outer.stats.cache_hits.values()))
print("link-only:", isinstance(kern.outer.overloads[next(iter(kern.outer.overloads))].library, LinkOnlyLibrary))
'''


def test_link_only_callees_print_raise_and_are_cached_inside_their_entry_point(tmp_path):
    """A callee compiled link-only has its environment (print, exceptions with values), is compiled once for
    all integer types, is not an entry point of its own, and its code comes back with the entry point's cache."""
    first = _run(tmp_path, LINK_ONLY)
    second = _run(tmp_path, LINK_ONLY)
    for out in (first, second):
        assert "inner 0\ninner 1\ninner 2\ninner 1\ninner 1\nsum 10\n" in out
        assert "raised ('too big', 6)" in out
        assert "entry points of inner: 0" in out
        assert "link-only: False" in out
    assert "outer compiled: 1 loaded from the cache: 0" in first
    assert "outer compiled: 1 loaded from the cache: 1" in second


RUNTIME_NEEDS = '''
import math
import numpy as np
from granum._jit import jit, prange


@jit(parallel=True)
def runtime_needs(a, word):
    # what machine code calls into: the runtime's allocation (NRT), a maths function, a parallel loop (the thread
    # pool's scheduler), a string's hash (the hash secret's symbols), an exception with values (Numba's helpers)
    if a.shape[0] == 0:
        raise ValueError("empty", a.shape[0])
    out = np.empty(a.shape[0])
    for k in prange(a.shape[0]):
        out[k] = math.sqrt(a[k])
    return out.sum(), hash(word)
'''

CACHED_CALL = '''
import numpy as np
from numba.core.registry import cpu_target
import kern
from granum import _jit
refreshes = []
context = cpu_target.target_context
refresh = context.refresh
context.refresh = lambda: (refreshes.append(1), refresh())[1]
total, word_hash = _jit.call(kern.runtime_needs, np.arange(1.0, 5.0), "granum")
print("sum", repr(total), "hash as Python's:", word_hash == hash("granum"))
try:
    _jit.call(kern.runtime_needs, np.empty(0), "granum")
except ValueError as e:
    print("raised", e.args)
print("loaded from the cache:", sum(kern.runtime_needs.stats.cache_hits.values()))
print("context refreshed:", bool(refreshes))
'''


def test_code_loaded_from_the_cache_runs_without_refreshing_numbas_context(tmp_path):
    """granum loads cached machine code without refreshing Numba's target context (importing Numba's lowering
    modules, which only compiling needs: a quarter of a cached start). The code loaded so still finds what it
    calls into: the runtime's allocation, a maths function, a parallel loop, a string's hash, an exception's
    values; the same values as when it was compiled, and a missing symbol would have ended the process."""
    first = _run(tmp_path, CACHED_CALL, module=RUNTIME_NEEDS)
    second = _run(tmp_path, CACHED_CALL, module=RUNTIME_NEEDS)
    expected = f"sum {sum(math.sqrt(k) for k in range(1, 5))!r} hash as Python's: True\nraised ('empty', 0)\n"
    for out in (first, second):
        assert expected in out
    assert "loaded from the cache: 0\ncontext refreshed: True" in first
    assert "loaded from the cache: 1\ncontext refreshed: False" in second


SPREAD = '''

@jit{options}
def {name}(a, i, w):   # three loops, two of them with calls to the maths library: more than LLVM inlines on its own
    s = 0.0
    for k in range(max(i - w, 0), min(i + w + 1, a.shape[0])):
        s += a[k] * (1.0 + k - i)
    for k in range(a.shape[0]):
        s += math.sin(a[k]) * math.exp(-a[k]) + math.atan2(a[k], 1.0 + k)
    for k in range(a.shape[0]):
        s -= math.log1p(a[k]) * math.tanh(a[k] - i) + math.hypot(a[k], w)
    return s
'''

#: ``spread`` declared inline="always", and the same function as an ordinary callee (``kept``), each called at three
#: sites in two entry points with two integer types
INLINED = ("import math\nimport numpy as np\nfrom granum._jit import jit\n"
           + SPREAD.format(options='(inline="always")', name="spread") + SPREAD.format(options="", name="kept")
           + '''

@jit
def left(a):
    return spread(a, 0, 2) + spread(a, a.shape[0] - 1, np.int32(3)) + kept(a, 0, 2) + kept(a, 8, np.int32(3))


@jit
def right(a):
    return spread(a, 1, 1) + kept(a, 1, 1)
''')


INLINE_BY_LLVM = '''
import numpy as np
from numba.core import event
import kern
compiled = []
class Count(event.Listener):
    def on_start(self, ev):
        pass
    def on_end(self, ev):
        compiled.append(ev.data["dispatcher"].py_func.__name__)
event.register("numba:compile", Count())
a = np.linspace(0.5, 2.0, 9) ** 2
print("values:", repr(kern.left(a)), repr(kern.right(a)))
print("spread compiled:", compiled.count("spread"), "entry points:", len(kern.spread.overloads))
for name in ("spread", "kept"):
    calls = [line for f in (kern.left, kern.right) for ir in f.inspect_llvm().values() for line in ir.splitlines()
             if " call " in line and name in line]
    print(name, "called:", len(calls))
'''


def _python(name: str, source: str):
    """Function ``name`` of ``source`` (written for ``jit``) as plain Python."""
    namespace = {"math": math, "jit": lambda f: f}
    exec(source.format(options="", name=name), namespace)
    return namespace[name]


def test_a_function_inlined_always_is_compiled_once_and_inlined_by_llvm(tmp_path):
    """On the fast path ``inline="always"`` compiles the function once, link-only, for its three call sites and
    both integer types (Numba's own inlining would type a copy at each site and never compile it), and LLVM
    inlines it into both entry points, where the same function declared without it stays a call."""
    out = _run(tmp_path, INLINE_BY_LLVM, module=INLINED)
    spread = _python("spread", SPREAD)
    a = np.linspace(0.5, 2.0, 9) ** 2
    left = 2 * (spread(a, 0, 2) + spread(a, 8, 3))
    right = 2 * spread(a, 1, 1)
    values = out.split("values: ")[1].split("\n")[0].split()
    assert float(values[0]) == pytest.approx(left, rel=1e-13)   # the maths library's last bits may differ
    assert float(values[1]) == pytest.approx(right, rel=1e-13)
    assert "spread compiled: 1 entry points: 0" in out
    calls = {line.split()[0]: int(line.split()[-1]) for line in out.splitlines() if " called: " in line}
    assert calls["spread"] == 0
    assert calls["kept"] > 0


PARTS = '''
import os, time
import numpy as np
import kern
from granum import _compile, _jit
a = np.linspace(0.0, 1.0, 7)
parent = os.getpid()
CHILD = None
if CHILD is not None:   # the child process misbehaves when it takes a part
    compile_here = _compile.compile_each
    def _compile_part(d, sigs):
        if os.getpid() != parent:
            exec(CHILD)
        compile_here(d, sigs)
    _compile.compile_each = _compile_part
    _compile.MIN_WAIT = 1.0
    _compile.PATIENCE = 1.0
symbols = _jit.entry_points([(kern.part_a, [(a,)]), (kern.part_b, [(a,)])])
value = kern.whole(a)
print("parts from the cache:", sum(sum(d.stats.cache_hits.values()) for d in (kern.part_a, kern.part_b)))
ir = next(iter(kern.whole.inspect_llvm().values())).splitlines()
print("parts declared:", sum(line.startswith("declare") and any(s in line for s in symbols) for line in ir),
      "defined:", sum(line.startswith("define") and any(s in line for s in symbols) for line in ir))
reference = np.median(a) + a.max() + np.cumsum(a)[-1]
print("value equals NumPy's:", value == reference)
'''


@pytest.mark.skipif(sys.platform != "linux", reason="parts are compiled on two processes on Linux only")
def test_parts_compiled_by_a_second_process_are_loaded_from_the_cache(tmp_path):
    two = _run(tmp_path / "two", PARTS, GRANUM_COMPILE_JOBS="2")
    assert "parts from the cache: 1" in two     # the child compiled one part, the parent loaded it
    assert "value equals NumPy's: True" in two
    assert "parts declared: 2 defined: 0" in two
    one = _run(tmp_path / "one", PARTS, GRANUM_COMPILE_JOBS="1")
    assert "parts from the cache: 0" in one
    assert "value equals NumPy's: True" in one


#: A Numba extension (found through its ``numba_extensions`` entry point) whose init hook adds the symbol of a C
#: function its overload calls, and a kernel that calls it.
EXTENSION = {
    "target_mod.py": "def special(x):\n    return abs(x)\n",
    "fakeext.py": '''
import ctypes
import llvmlite.binding as ll
from llvmlite import ir
from numba.core import cgutils, types
from numba.extending import intrinsic, overload
import target_mod


@intrinsic
def _c_labs(typingctx, x):
    def codegen(context, builder, sig, args):
        fnty = ir.FunctionType(ir.IntType(64), [ir.IntType(64)])
        return builder.call(cgutils.get_or_insert_function(builder.module, fnty, "fakeext_labs"), args)
    return types.int64(types.int64), codegen


@overload(target_mod.special)
def _special(x):
    return lambda x: _c_labs(x)


def init():
    ll.add_symbol("fakeext_labs", ctypes.cast(ctypes.CDLL(None).labs, ctypes.c_void_p).value)
''',
    "fakeext-0.1.dist-info/METADATA": "Metadata-Version: 2.1\nName: fakeext\nVersion: 0.1\n",
    "fakeext-0.1.dist-info/entry_points.txt": "[numba_extensions]\ninit = fakeext:init\n",
}

EXTENDED = '''
import target_mod
from granum._jit import jit


@jit
def extended(x):
    return target_mod.special(x)
'''


def test_code_loaded_from_the_cache_finds_the_symbols_of_numbas_extensions(tmp_path):
    """A kernel calling a Numba extension's C function (a user's law may) runs again from the cache: the
    extensions' init hooks, which add their symbols, run before granum loads cached code (Numba runs them before
    it compiles; without them the second process ended on an unresolved symbol)."""
    site = tmp_path / "site"
    for name, text in EXTENSION.items():
        (site / name).parent.mkdir(parents=True, exist_ok=True)
        (site / name).write_text(text)
    script = "import kern\nfrom granum import _jit\nprint('value', _jit.call(kern.extended, -7))\n"
    for _ in range(2):   # compiled, then loaded from the cache
        assert "value 7" in _run(tmp_path / "run", script, module=EXTENDED, PYTHONPATH=str(site))


KERNEL_PARTS = '''
import numpy as np
from granum import _jit
from granum.kernels.copy import copy_items, copy_rows
a, b = np.zeros(4), np.arange(4.0)
m, n = np.zeros((2, 3)), np.ones((2, 3))
_jit.entry_points([(copy_items, [(a, b, 4)]), (copy_rows, [(m, n, 2)])])
print("parts from the cache:", sum(sum(d.stats.cache_hits.values()) for d in (copy_items, copy_rows)))
_jit.call(copy_items, a, b, 4)
_jit.call(copy_rows, m, n, 2)
print("copied:", a.tolist(), m.sum())
'''


def test_kernel_parts_in_the_cache_load_while_another_process_holds_the_compile_lock(tmp_path):
    """A process whose parts (granum's kernels, cached in a folder keyed by their sources) are all in the disk
    cache reads them without the compile lock, which another process holds while it compiles (a job of a batch, a
    test run beside a script); it waited for that compiling before."""
    import filelock

    _run(tmp_path, KERNEL_PARTS)   # the parts compiled into the cache
    (lock,) = tmp_path.glob("cache/*/compile.lock")
    with filelock.FileLock(lock):   # held until the process ends: one that waited for it would time out
        again = _run(tmp_path, KERNEL_PARTS, timeout=180)
    assert "parts from the cache: 2" in again
    assert "copied: [0.0, 1.0, 2.0, 3.0] 6.0" in again


@pytest.mark.skipif(sys.platform != "linux", reason="parts are compiled on two processes on Linux only")
@pytest.mark.parametrize("child", ["os._exit(3)", "time.sleep(600)"], ids=["dies", "hangs"])
def test_a_failing_second_process_only_costs_time(tmp_path, child):
    """A child that dies, or stops making progress, leaves its parts to the parent: same result."""
    out = _run(tmp_path, PARTS.replace("CHILD = None", f"CHILD = {child!r}"), GRANUM_COMPILE_JOBS="2")
    assert "parts from the cache: 0" in out
    assert "value equals NumPy's: True" in out


SHARED = '''
import os, time
import numpy as np
from numba.core import event
import kern
from granum import _compile, _jit
a = np.linspace(0.0, 1.0, 7)
ints = np.arange(7)
parent = os.getpid()

class Log(event.Listener):   # one line per compiling of a shared function, in either process (at once: the child
    def on_start(self, ev):  # leaves without Python's exit handlers)
        pass
    def on_end(self, ev):
        name = ev.data["dispatcher"].py_func.__name__
        if name in ("common", "typed"):
            with open("compiled.txt", "a") as f:
                f.write(f"{name} {os.getpid()}\\n")
event.register("numba:compile", Log())
CHILD_DIES = False
if CHILD_DIES:   # the child claims the shared function and dies; the parent begins once it has claimed it
    _compile.MIN_WAIT = 600.0
    compile_each = _compile.compile_each
    def late(d, sigs):
        if os.getpid() == parent:
            deadline = time.monotonic() + 120.0
            while not os.path.exists("claimed") and time.monotonic() < deadline:
                time.sleep(0.01)
        compile_each(d, sigs)
    _compile.compile_each = late
    once = _compile.compile_once
    def dying(name, compile_here, load_cached):
        def here():
            if os.getpid() != parent:
                open("claimed", "w").close()
                os._exit(3)
            compile_here()
        return once(name, here, load_cached)
    _compile.compile_once = dying
    parts = [(kern.part_c, [(a,)]), (kern.part_d, [(a,)])]
else:   # and two parts that call another shared function with other types each
    parts = [(kern.part_c, [(a,)]), (kern.part_d, [(a,)]), (kern.part_e, [(a,)]), (kern.part_f, [(ints,)])]
start = time.monotonic()
_jit.entry_points(parts)
print("seconds:", time.monotonic() - start)
print("parts from the cache:", sum(sum(d.stats.cache_hits.values()) for d, _ in parts))
lines = [line.split() for line in open("compiled.txt").read().splitlines()] if os.path.exists("compiled.txt") else []
print("compilings of the shared function:", sum(name == "common" for name, _ in lines),
      "by the parent:", all(int(pid) == parent for name, pid in lines if name == "common"),
      "entry points:", len(kern.common.overloads))
os.remove("compiled.txt") if os.path.exists("compiled.txt") else None
reference = np.sort(a)[-2] + np.cumsum(a)[1]
print("values equal NumPy's:", kern.part_c(a) == np.median(a) + reference, kern.part_d(a) == reference)
if not CHILD_DIES:
    print("other types:", kern.part_e(a) == 2.0 * a.sum(), kern.part_f(ints) == 2 * ints.sum() + 1)
'''


@pytest.mark.skipif(sys.platform != "linux", reason="parts are compiled on two processes on Linux only")
def test_a_shared_function_is_compiled_once_for_both_processes(tmp_path):
    """Parts that call the same shared function, compiled on two processes: one of them compiles it (an entry
    point in the disk cache), the other loads it, and the parts compute with it; on one process it is an entry
    point, compiled once, too. Another shared function called with other types in each process (one compiles it
    link-only, writing nothing to the disk cache) gives the right values, also when loaded again from the cache."""
    for jobs in ("2", "1"):
        out = _run(tmp_path / jobs, SHARED, GRANUM_COMPILE_JOBS=jobs)
        from_child = int(out.split("parts from the cache: ")[1].split()[0])   # what the parent loaded, the child made
        assert from_child >= 1 if jobs == "2" else from_child == 0
        assert "compilings of the shared function: 1" in out
        assert "entry points: 1" in out
        assert "values equal NumPy's: True True" in out
        assert "other types: True True" in out
        again = _run(tmp_path / jobs, SHARED, GRANUM_COMPILE_JOBS=jobs)   # everything from the disk cache
        assert "parts from the cache: 4" in again
        assert "compilings of the shared function: 0" in again
        assert "values equal NumPy's: True True" in again
        assert "other types: True True" in again


@pytest.mark.skipif(sys.platform != "linux", reason="parts are compiled on two processes on Linux only")
def test_a_process_that_dies_compiling_a_shared_function_leaves_it_to_the_other(tmp_path):
    """The child claims the shared function and dies: the parent, which waits for it, sees the child gone and
    compiles the function itself (link-only: the types it needs are not in the cache), long before its patience
    (600 s here) runs out."""
    out = _run(tmp_path, SHARED.replace("CHILD_DIES = False", "CHILD_DIES = True"), GRANUM_COMPILE_JOBS="2")
    assert "compilings of the shared function: 1 by the parent: True entry points: 0" in out
    assert "values equal NumPy's: True True" in out
    assert float(out.split("seconds: ")[1].split()[0]) < 300


def test_a_shared_function_is_compiled_by_its_claimer_only(tmp_path, monkeypatch):
    """compile_once on two processes, each side played here with its own set of claims: the claimer compiles every
    types it needs; the other loads them when they are in the disk cache, else is told to compile them link-only
    (False), without waiting once the claimer is done, has gone, or after MIN_WAIT."""
    import time

    from granum import _compile

    compiled = []
    folder = str(tmp_path)
    monkeypatch.setattr(_compile, "_sharing", (folder, lambda: True, set()))   # the claimer
    assert _compile.compile_once("f", lambda: compiled.append("f floats"), lambda: False)
    assert _compile.compile_once("f", lambda: compiled.append("f ints"), lambda: False)
    monkeypatch.setattr(_compile, "_sharing", (folder, lambda: True, set()))   # the other process
    assert _compile.compile_once("f", lambda: compiled.append("f again"), lambda: True)
    assert not _compile.compile_once("f", lambda: compiled.append("f again"), lambda: False)
    assert compiled == ["f floats", "f ints"]
    _compile._claim(folder, _compile.claim_name("g"))   # claimed by a process that never finishes it
    start = time.monotonic()
    monkeypatch.setattr(_compile, "_sharing", (folder, lambda: False, set()))   # ... and has gone
    assert not _compile.compile_once("g", lambda: compiled.append("g"), lambda: False)
    monkeypatch.setattr(_compile, "_sharing", (folder, lambda: True, set()))    # ... and still runs
    monkeypatch.setattr(_compile, "MIN_WAIT", 0.3)
    assert not _compile.compile_once("g", lambda: compiled.append("g"), lambda: False)
    assert 0.3 <= time.monotonic() - start < 30 and compiled == ["f floats", "f ints"]
    monkeypatch.setattr(_compile, "_sharing", None)   # one process: compiled here
    assert _compile.compile_once("g", lambda: compiled.append("g"), lambda: False)
    assert compiled[-1] == "g"


def test_a_shared_function_is_never_inlined():
    from granum._jit import jit

    for inline in ("always", lambda *args: True):
        with pytest.raises(ValueError, match="a shared function is an entry point of its own, never inlined"):
            jit(shared=True, inline=inline)(lambda x: x)


def test_the_second_part_is_one_that_needs_no_shared_function_of_the_first():
    """compile_parts orders the parts largest first, but puts second the largest part that reaches no shared
    function the first one reaches (which the other process compiles meanwhile)."""
    from granum import _compile

    def function(name, calls, shared=False):
        namespace = {c.py_func.__name__: c for c in calls}
        exec(f"def {name}():\n    " + ("; ".join(f"{c.py_func.__name__}()" for c in calls) or "pass"), namespace)
        namespace[name].__module__ = "granum.example"
        return SimpleNamespace(py_func=namespace[name], granum_shared=shared)

    for shared in (True, False):
        motions = function("motions", [], shared)
        helpers = [function(f"helper{k}", []) for k in range(5)]
        interaction = function("interaction", [motions, *helpers[:4]])
        collider = function("collider", [motions, *helpers[2:5]])
        newton = function("newton", helpers[:2])
        reset = function("reset", [])
        parts = [(p, [()]) for p in (reset, newton, collider, interaction)]
        names = [p.py_func.__name__ for p, _ in _compile.ordered(parts)]
        assert names == (["interaction", "newton", "collider", "reset"] if shared else
                         ["interaction", "collider", "newton", "reset"])


def test_compile_jobs_setting_is_checked(tmp_path):
    with pytest.raises(subprocess.CalledProcessError) as err:
        _run(tmp_path, PARTS, GRANUM_COMPILE_JOBS="two")
    assert "GRANUM_COMPILE_JOBS must be a whole number" in err.value.stderr


def test_dispatch_is_generated_for_the_functors_a_table_lists():
    from granum.kernels import dispatch
    from granum.kernels.static import Static, StaticType, static_value
    from granum.physics import registry

    sphere = dispatch.code_of("Ig2_Sphere_Sphere_ScGeom")
    source = dispatch.render("geom", (sphere,))
    assert registry.FUNCTORS["Ig2_Sphere_Sphere_ScGeom"].func.split(":")[1] in source
    for other in ("Ig2_Facet_Sphere_ScGeom", "Ig2_Wall_Sphere_ScGeom", "Ig2_Box_Sphere_ScGeom"):
        assert registry.FUNCTORS[other].func.split(":")[1] not in source
    table = dispatch.functor_set("geom", [sphere, sphere])
    assert table.value == ("functors", "geom", (sphere,))
    assert static_value(StaticType(table.value), "functors") == table.value
    assert static_value(StaticType(table.value), "cell") is None
    with pytest.raises(ValueError, match="unknown functor role"):
        dispatch.functor_set("shape", [0])
    with pytest.raises(TypeError, match="a static value is a tuple"):
        Static(["functors"])


def test_the_step_loops_type_key_separates_what_numba_types_apart():
    """The runner keeps one compiled step loop per key of its arguments: values of different Numba types
    must get different keys, values of the same type the same key."""
    import numba
    import numpy as np

    from granum.engines.runner import _type_key
    from granum.kernels.static import Static

    readonly = np.zeros(3)
    readonly.flags.writeable = False
    values = [np.zeros(3), np.zeros(3, np.float32), np.zeros((3, 2))[:, 0], np.zeros((2, 3)), readonly,
              np.zeros((2, 3), order="F"), Static(("cell", False)), Static(("cell", True)), [1, 2], [1.0, 2.0],
              1, 1.0, True, None, (np.zeros(3), 1), (np.zeros(3), 1.0)]
    for a in values:
        for b in values:
            assert (_type_key(a) == _type_key(b)) == (numba.typeof(a) == numba.typeof(b)), (a, b)
    assert _type_key(np.ones(5)) == _type_key(np.zeros(7))


def test_cache_directories_in_use_are_not_pruned(tmp_path, monkeypatch):
    """Only the newest cache directories of other granum versions are kept, and any used within
    CACHE_IN_USE_S (a process of another version may be compiling into it: pruning it under that
    process made its compile lock vanish)."""
    import time

    from granum import _jit

    monkeypatch.setenv("GRANUM_CACHE_DIR", str(tmp_path))
    now = time.time()
    ages = {"recent": 3600.0, "old1": 3 * 86400, "old2": 4 * 86400, "old3": 5 * 86400, "old4": 6 * 86400,
            "old5": 7 * 86400}
    for name, age in ages.items():
        (tmp_path / name).mkdir()
        os.utime(tmp_path / name, (now - age, now - age))
    _jit._prune_old_caches(keep=3)
    # the three newest stay; with none to keep, the one used recently still stays
    assert sorted(p.name for p in tmp_path.iterdir()) == ["old1", "old2", "recent"]
    _jit._prune_old_caches(keep=0)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["recent"]


def _part(name):
    """A stand-in for a compiled entry point: what compile_parts reads of one (its Python function)."""
    def func():
        return None
    func.__name__ = name
    return SimpleNamespace(py_func=func)


def test_the_notice_is_given_only_for_parts_missing_from_the_cache(monkeypatch):
    """compile_parts calls granum._compile.NOTICE with the count of parts it must compile, and what it returned
    once they are compiled (also when compiling fails), or at the end of the enclosing ``announced`` block; not at
    all when every part came from the cache."""
    from granum import _compile

    events, compiled = [], []
    monkeypatch.setenv("GRANUM_COMPILE_JOBS", "1")
    monkeypatch.setattr(_compile, "NOTICE", lambda count: events.append(count) or (lambda: events.append("done")))
    monkeypatch.setattr(_compile, "compile_each", lambda d, sigs: compiled.append((d, sigs)))
    a, b = _part("a"), _part("b")
    _compile.compile_parts([(a, [(1,)]), (b, [(1,), (2,)])], lambda d, sig: True)
    assert events == [] and compiled == []
    _compile.compile_parts([(a, [(1,)]), (b, [(1,), (2,)])], lambda d, sig: d is a or sig == (1,))
    assert events == [1, "done"] and compiled == [(b, [(2,)])]

    def failing(d, sigs):
        raise RuntimeError("compile failed")

    monkeypatch.setattr(_compile, "compile_each", failing)
    with pytest.raises(RuntimeError, match="compile failed"):
        _compile.compile_parts([(a, [(1,)])], lambda d, sig: False)
    assert events == [1, "done", 1, "done"]

    # inside an announced block (a step loop: its stages, then the loop) the line ends with the block
    monkeypatch.setattr(_compile, "compile_each", lambda d, sigs: compiled.append((d, sigs)))
    events.clear()
    with _compile.announced():
        _compile.compile_parts([(a, [(1,)])], lambda d, sig: False)
        assert events == [1]
        events.append("loop compiled")
    assert events == [1, "loop compiled", "done"]
