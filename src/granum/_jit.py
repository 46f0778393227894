"""Numba set-up shared by every compiled kernel.

* Compiled code is cached on disk. Numba's cache only notices edits to the file of
  the cached function itself, not to the functions it calls in other modules, so the
  cache directory is keyed by a hash of all granum sources: any edit to granum starts
  a fresh cache and a stale kernel can never be loaded.
  Only granum's own functions are cached there: Numba's cache folder is set while
  granum decorates a function, and restored (a user's ``@njit(cache=True)`` keeps
  Numba's own rules).
* :func:`kernel` compiles one Python function twice, serially and with ``prange``
  parallelism. Callers pick the variant by problem size, and both give the same bits,
  so results are bitwise independent of the number of threads. A step loop of small
  scenes, or on one thread, calls :func:`serial_variant` of its stages, which compile
  no parallel code; one of mid-sized scenes, their variants without the parallel
  kernels over bodies.
* Two compile paths. The *fast* path links compiled functions into their callers
  once (:mod:`granum._linking`), compiles a first run's stages on two processes
  (:mod:`granum._compile`) and fuses the stages of a step into one compiled loop
  that calls them by symbol. It relies on Numba internals, which
  :func:`granum._linking.missing_internal` probes at import. When one is missing
  (with one :class:`CompileFallbackWarning` naming it), or with
  ``GRANUM_COMPILE=fallback``, kernels compile on the *plain* path: ordinary
  ``@njit`` functions, compiled in one process, and a step loop in Python that calls
  the stages' entry points (:class:`granum.kernels.steploop.PlainLoop`). Same
  results, bit for bit; slower first runs, and a few microseconds more per step.
  Its code is cached apart.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import os
import pathlib
import re
import shutil
import threading
import time
import types
import warnings

import filelock
import numba
from numba import njit, prange

from granum import _compile

_PKG = pathlib.Path(__file__).resolve().parent


#: Packages whose code can end up inside compiled kernels (the YADE layer, the engines
#: and the launcher never do, so editing them keeps the cache).
KERNEL_SOURCES = ("_jit.py", "_linking.py", "core", "kernels", "physics", "idem")


def source_hash() -> str:
    """Hash of the text of the granum sources that compiled kernels are made of (16 hex digits)."""
    h = hashlib.sha256()
    files = []
    for name in KERNEL_SOURCES:
        files += [_PKG / name] if name.endswith(".py") else list((_PKG / name).rglob("*.py"))
    for p in sorted(files):
        h.update(p.relative_to(_PKG).as_posix().encode())
        h.update(p.read_bytes())
    return h.hexdigest()[:16]


def cache_root() -> pathlib.Path:
    """Directory that holds granum's caches (``$GRANUM_CACHE_DIR`` or ``~/.cache/granum``)."""
    base = os.environ.get("GRANUM_CACHE_DIR") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "granum")
    return pathlib.Path(base)


class CompileFallbackWarning(RuntimeWarning):
    """Granum compiles on its plain path because the installed Numba lacks an internal the fast path uses."""


def _choose_path() -> tuple[bool, str | None]:
    """Whether kernels compile on the plain path (see the module docstring), and the Numba internal whose
    absence chose it (None when the environment did, or on the fast path)."""
    setting = os.environ.get("GRANUM_COMPILE", "").strip()
    if setting not in ("", "auto", "fallback"):
        raise ValueError(f"GRANUM_COMPILE must be 'auto' (the default) or 'fallback', not {setting!r}")
    if setting == "fallback":
        return True, None
    try:
        from granum import _linking
    except (ImportError, AttributeError) as e:   # a name _linking imports, or a base class it extends, is gone
        name = re.search(r"cannot import name '(\w+)'", str(e)) if isinstance(e, ImportError) else None
        return True, f"{e.name}.{name[1]}" if name and e.name else str(e)
    missing = _linking.missing_internal()
    return missing is not None, missing


#: Whether kernels compile on the plain path (``GRANUM_COMPILE=fallback``, or a Numba without the fast path's
#: internals); see the module docstring.
PLAIN, _MISSING = _choose_path()
if _MISSING is not None:
    warnings.warn(f"granum: Numba {numba.__version__} lacks {_MISSING}, which granum's fast compile path uses; "
                  f"kernels compile on the plain path instead (same results, slower first runs; "
                  f"GRANUM_COMPILE=fallback chooses it without this warning)", CompileFallbackWarning, stacklevel=2)
if not PLAIN:
    from granum import _linking

    _linking.enable()

#: ``GRANUM_NOPAR=1`` compiles the parallel variants of the kernels as plain loops, to check them
#: against the parallel ones; such code is cached apart.
SERIAL_ONLY = os.environ.get("GRANUM_NOPAR", "") not in ("", "0")
SOURCE_HASH = source_hash()
CACHE_DIR = cache_root() / (SOURCE_HASH + ("-nopar" if SERIAL_ONLY else "") + ("-plain" if PLAIN else ""))


#: A cache directory used within this time is kept even when it is not among the newest [s]: a process of
#: another granum version (another environment, a job still running) may be using it.
CACHE_IN_USE_S = 2 * 86400


def _prune_old_caches(keep: int = 3) -> None:
    """Remove cache directories of older granum sources, keeping the newest few and those used recently
    (each process marks its own directory as used when it starts and when it compiles)."""
    root = cache_root()
    now = time.time()
    try:
        dirs = sorted((d for d in root.iterdir() if d.is_dir() and d.name != CACHE_DIR.name),
                      key=lambda d: d.stat().st_mtime, reverse=True)
        old = [d for d in dirs[keep:] if now - d.stat().st_mtime > CACHE_IN_USE_S]
    except OSError:
        return
    for d in old:
        shutil.rmtree(d, ignore_errors=True)


def _mark_cache_used() -> None:
    """Create this version's cache directory if needed and mark it as used now (its modification time)."""
    CACHE_DIR.mkdir(parents=True, exist_ok=True)
    os.utime(CACHE_DIR)


_mark_cache_used()
_prune_old_caches()
_DECORATING = threading.Lock()


@contextlib.contextmanager
def _granum_cache():
    """Numba's cache folder set to granum's (:data:`CACHE_DIR`) while functions are decorated: Numba reads it
    when a dispatcher is made, so the functions made meanwhile are cached there, and no other."""
    with _DECORATING:
        saved = numba.config.CACHE_DIR
        numba.config.CACHE_DIR = str(CACHE_DIR / "numba")
        try:
            yield
        finally:
            numba.config.CACHE_DIR = saved

# Threading layer: OpenMP first. A step launches several short parallel loops, and TBB's launch
# overhead made the falling-ball benchmark 2.5x slower with two threads than with one (OpenMP:
# 1.6x faster). NUMBA_THREADING_LAYER, if the user sets it, still decides.
numba.config.THREADING_LAYER_PRIORITY = ["omp", "tbb", "workqueue"]
# Start numba's thread pool now. Compiling a parallel kernel starts it as a side effect,
# but loading one from the cache does not, and calling a cached parallel kernel before
# the pool exists crashes the process.
numba.get_num_threads()

#: Loops shorter than this run serially: below it, waking the thread pool costs more
#: than the loop. The choice depends on the size only, so it never changes results.
PARALLEL_THRESHOLD = 4096
#: Items (bodies, pairs, contacts) per iteration of block-wise parallel loops. Fixed, so that
#: results never depend on the number of threads.
BLOCK = 512

#: Contact updates (geometry, physics, law: ~50-100 ns per contact, ten times the work per body or
#: per pair) pay for waking the pool from three blocks on. Two blocks, the second mostly partial, left one
#: thread with most of the work: on a 2-core Xeon, dense lattices of 792 and 1,218 contacts, `-j2` against `-j1`,
#: the interaction stage took 67.0 against 60.4 us and 98.2 against 118.8; the falling ball's 677 contacts were
#: updated in 41.8 us on two threads, 38.5 on one. Below it the update also adds the forces itself
#: (:func:`granum.kernels.interaction.update_scatter`), which spares the force gather.
PARALLEL_THRESHOLD_CONTACTS = 2 * BLOCK + 1

#: Items from which a block's loops take their vectorized variants where they have one (ForceResetter, the
#: collider's test): the flat views those loops run over cost a call into Numba's run time each (about 50 ns).
VECTOR_MIN_ITEMS = 64


def jit(fn=None, **kw):
    """``numba.njit`` with granum's defaults (on-disk cache, no Python fallback); called from compiled
    code, the function is compiled for canonical argument types and link-only (:mod:`granum._linking`).
    ``inline="always"``: on the fast path, Numba's ``forceinline`` instead, so that LLVM inlines the
    function into its callers (:mod:`granum._linking`); on the plain path, Numba's inlining. ``shared=True``: a
    function several stages call, compiled as an entry point of its own, once for both processes of a first run
    (:mod:`granum._linking`, "Shared callees"; on the plain path, an ordinary function as every other).

    Division follows IEEE 754 (``error_model="numpy"``: x/0 is inf or NaN, as in C and YADE) instead of
    testing every divisor for zero to raise ZeroDivisionError: 2-4 % of a dense-lattice step. Most
    inputs that would divide by zero are refused before a run (a free body without mass, a zero radius,
    a facet with collinear vertices); a non-finite state that still arises in a free body (zero inertia,
    coincident sphere centres) stops the run with the body named (NewtonIntegrator's check).
    """
    opts = dict(cache=True, nogil=True, error_model="numpy")
    opts.update(kw)
    shared = opts.pop("shared", False)
    if shared and (opts.get("inline", "never") != "never" or opts.get("forceinline")):
        raise ValueError(f"jit: a shared function is an entry point of its own, never inlined (shared=True with "
                         f"inline={opts.get('inline')!r})")
    if not PLAIN and opts.get("inline") == "always":
        # LLVM inlines it where it is linked: typed and lowered once for its argument types instead of once at
        # every call site, as Numba's own inlining does (the plain path keeps Numba's)
        del opts["inline"]
        opts["forceinline"] = True

    def make(f):
        with _granum_cache():
            dispatcher = njit(**opts)(f)
        return dispatcher if PLAIN else _linking.install(dispatcher, shared=shared)

    return make if fn is None else make(fn)


#: granum's overloaded functions, function -> (typing function, overload options): :func:`serial_variant` makes
#: serial variants of them.
_OVERLOADS: dict = {}


def overload(func, **options):
    """``numba.extending.overload`` for granum's own overloads: on the fast path their implementations compile
    link-only (:func:`granum._linking.overload`)."""
    if PLAIN:
        from numba.extending import overload as numba_overload

        declare = numba_overload(func, **dict(options))
    else:
        declare = _linking.overload(func, **dict(options))

    def decorate(definition):
        _OVERLOADS[func] = (definition, options)
        return declare(definition)

    return decorate


#: Globals that the serial variant of a kernel resolves to other functions, name -> function (registered by
#: :mod:`granum.kernels.schedule`: the serial variant takes its blocks in order, without a queue).
SERIAL_GLOBALS: dict = {}


def _renamed_copy(fn, replaced: dict, suffix: str):
    """A copy of Python function ``fn`` named with ``suffix`` (so that its compiled code has a cache file of its
    own) that sees the globals ``replaced`` in place of its module's, and the others as they are now."""
    copy = types.FunctionType(fn.__code__, {**fn.__globals__, **replaced}, fn.__name__ + suffix,
                              fn.__defaults__, fn.__closure__)
    copy.__qualname__ = fn.__qualname__ + suffix
    copy.__module__ = fn.__module__
    return copy


#: What a kernel's items are (:func:`kernel`'s ``over``): its callers run it in parallel once those items reach
#: their threshold (the scene's bodies, its potential pairs, its contact rows; iDEM's particles).
ITEMS = frozenset({"bodies", "pairs", "contacts", "particles"})
#: The serial dispatcher and the items of each parallel one that :func:`kernel` makes.
_KERNELS: dict = {}
#: Variants made by :func:`serial_variant`, (granum function, items) -> the variant (the function itself when it
#: reaches no parallel kernel over those items).
_VARIANTS: dict = {}
#: Held while variants are made (a re-entrant lock: a variant's callees are made first), so that two threads never
#: make two copies of one function, which would share its cache files.
_MAKING_VARIANTS = threading.RLock()


def kernel(fn, over: str):
    """Compile ``fn`` (which loops with ``prange``) serially and in parallel; ``over``: what its items are (one
    of :data:`ITEMS`, the count its callers compare with their threshold).

    Returns ``(serial, parallel)`` dispatchers. Both compute identical results as
    long as every item (a block, where the loop takes blocks from a queue) writes only
    its own outputs (no reductions across items), which granum's kernels guarantee. The parallel variant is
    compiled from a renamed copy of ``fn`` so that the two never share a cache file.
    The serial variant is a copy of ``fn`` that sees the names of ``SERIAL_GLOBALS``
    replaced, and the other globals of its module as they are when ``kernel`` is called.
    """
    if over not in ITEMS:
        raise ValueError(f"kernel {fn.__qualname__}: over must be one of {sorted(ITEMS)}, not {over!r}")
    serial = jit(_renamed_copy(fn, SERIAL_GLOBALS, ""))
    parallel = jit(_renamed_copy(fn, {}, "_parallel"), parallel=not SERIAL_ONLY)
    _KERNELS[parallel] = serial, over
    return serial, parallel


def serial_variant(dispatcher, over: frozenset = ITEMS):
    """``dispatcher`` (a granum function) compiled to call the serial variant of every :func:`kernel` over the
    items ``over`` that it reaches through its globals and granum's overloads: itself when it reaches none, else a
    renamed copy (made once).

    A step loop made of such variants compiles no parallel code over those items (``examples/bouncing_sphere.py``'s
    first run on one process, all items serial: 37 s of compiling before, 30 s with them) and computes what the
    stages compute, bit for bit: it only runs, in those kernels, the variant that the stages pick below their
    size thresholds. The runner uses it when the scene is below those thresholds, or runs on one thread
    (:meth:`granum.engines.runner.Runner.serial`)."""
    over = frozenset(over)
    with _MAKING_VARIANTS:
        key = dispatcher, over
        if key not in _VARIANTS:
            if dispatcher in _KERNELS:
                serial, items = _KERNELS[dispatcher]
                _VARIANTS[key] = serial if items in over else dispatcher
                return _VARIANTS[key]
            _VARIANTS[key] = dispatcher  # while its callees are looked at (a recursive function calls itself)
            replaced = _serial_globals(dispatcher.py_func, over)
            if replaced:
                options = {k: v for k, v in dispatcher.targetoptions.items() if k != "nopython"}
                copy = _renamed_copy(dispatcher.py_func, replaced, _variant_suffix(over))
                _VARIANTS[key] = jit(copy, shared=getattr(dispatcher, "granum_shared", False), **options)
        return _VARIANTS[key]


def _variant_suffix(over: frozenset) -> str:
    """The name suffix of the variants over the items ``over`` (a cache file of their own)."""
    return "_serial" if over == ITEMS else "_serial_" + "_".join(sorted(over))


def _serial_overload(func, over: frozenset):
    """The overloaded function ``func`` (:func:`overload`) whose implementations call the serial variants over the
    items ``over``: itself when they reach no such :func:`kernel`, else a renamed copy overloaded by a copy of its
    typing function that sees the variants (the implementations it defines inherit its globals)."""
    with _MAKING_VARIANTS:
        key = func, over
        if key not in _VARIANTS:
            _VARIANTS[key] = func
            definition, options = _OVERLOADS[func]
            replaced = _serial_globals(definition, over)
            if replaced:
                variant = _renamed_copy(func, {}, _variant_suffix(over))
                overload(variant, **options)(_renamed_copy(definition, replaced, _variant_suffix(over)))
                _VARIANTS[key] = variant
        return _VARIANTS[key]


def _serial_globals(fn, over: frozenset) -> dict:
    """The globals of Python function ``fn`` (its nested functions included) that have serial variants over the
    items ``over``, name -> variant (:func:`serial_variant`)."""
    replaced = {}
    for name, value in granum_callees(fn):
        if _compile.is_granum_dispatcher(value):
            variant = serial_variant(value, over)
        else:
            variant = _serial_overload(value, over)
        if variant is not value:
            replaced[name] = variant
    return replaced


def granum_callees(fn):
    """``(name, value)`` of the globals Python function ``fn`` (its nested functions included) reads that are
    granum's compiled functions or overloaded functions (:func:`overload`)."""
    for name in _compile.global_names(fn.__code__):
        value = fn.__globals__.get(name)
        if _compile.is_granum_dispatcher(value) or (callable(value) and value in _OVERLOADS):
            yield name, value


@contextlib.contextmanager
def compile_lock():
    """Hold the cache directory's lock (blocks while another process compiles into it).

    Numba numbers the cached variants of a function per process; two processes
    compiling the same function at once can pair an index entry of one with the code
    of the other. Compiling under this lock serialises first runs; the waiting
    processes then load the freshly cached code instead of compiling it again.
    The lock is a portable file lock (:mod:`filelock`: ``fcntl`` on POSIX, ``msvcrt`` on Windows).
    """
    _mark_cache_used()
    with filelock.FileLock(CACHE_DIR / "compile.lock"):
        yield


_warm: set[int] = set()


@functools.cache
def _source_keyed(filename: str) -> bool:
    """Whether the compiled functions of source file ``filename`` are cached in a folder keyed by their source:
    one of :data:`KERNEL_SOURCES`, or a module generated in :data:`CACHE_DIR`. Their cache entries are never
    replaced while another process may read them (an edited kernel source gets a new folder; a generated module's
    file is named by the hash of its text), so they are read without the compile lock. Numba writes an entry's
    index before its data: an edited file of another function (YADE's packing helpers, a user's module) can
    leave an index pointing at old data for a moment, so those are read under the lock."""
    path = pathlib.Path(filename).resolve()
    if path.is_relative_to(CACHE_DIR.resolve()):
        return True
    return path.is_relative_to(_PKG) and path.relative_to(_PKG).parts[0] in KERNEL_SOURCES


def _read_unlocked(fn, sig) -> bool:
    """Whether ``fn`` for argument types ``sig`` is in memory, or was read now from its disk cache without the
    compile lock (:func:`_source_keyed`; the fast path only)."""
    return sig in fn.overloads or (not PLAIN and _source_keyed(fn.py_func.__code__.co_filename)
                                   and _linking.load_cached(fn, sig))


def _compiled(fn, args) -> tuple:
    """Load ``fn`` for the types of ``args`` from the cache, or compile it under :func:`compile_lock`, unless it
    is compiled already; the argument types. Where an entry may be read without the lock, only compiling holds
    it (:func:`_read_unlocked`): a long first call must not keep other processes (the jobs of a batch, a cached
    start) from reading their own kernels. On the fast path the cache is read without the context refresh only
    compiling needs (:func:`granum._linking.load_cached`)."""
    sig = tuple(fn.typeof_pyval(a) for a in args)
    if not _read_unlocked(fn, sig):
        with compile_lock():
            if PLAIN or not _linking.load_cached(fn, sig):
                fn.compile(sig)
    return sig


def call(fn, *args):
    """Call compiled ``fn`` from Python, compiled (or loaded from the cache) the first time."""
    if id(fn) not in _warm:
        _compiled(fn, args)
        _warm.add(id(fn))
    return fn(*args)


def entry(fn, *args):
    """The entry point of compiled ``fn`` for the types of ``args`` (compiled if new): a C function that
    converts such arguments without typing them. Numba's dispatcher types an argument it cannot fingerprint
    in C (a tuple holding a static value, as a plan's parameters do) in Python at every call, which cost
    milliseconds per call."""
    return fn.overloads[_compiled(fn, args)].entry_point


def entry_points(calls) -> list[str]:
    """Load or compile the entry points ``calls`` (``(dispatcher, [argument values, ...])``), those missing from
    the disk cache on two processes (:mod:`granum._compile`); their symbols, for callers that call them by
    symbol (:func:`granum._linking.entry_call`). On the plain path, this process compiles them one by one
    (their callees are cached with each of them: two processes would write the same cache files), and there
    are no symbols to call them by (an empty list). Parts all found in memory or read from the cache without the
    compile lock (:func:`_read_unlocked`) need no lock: a cached start does not wait for another process's
    compiling."""
    parts = [(d, [tuple(d.typeof_pyval(a) for a in values) for values in argument_lists])
             for d, argument_lists in calls]
    if PLAIN:
        with compile_lock():
            for d, sigs in parts:
                _compile.compile_each(d, sigs)
        return []
    if not all(_read_unlocked(d, sig) for d, sigs in parts for sig in sigs):
        with compile_lock():
            _compile.compile_parts(parts, _linking.load_cached)
    return [_linking.entry_symbol(d, sig) for d, sigs in parts for sig in sigs]


__all__ = ["call", "compile_lock", "entry", "entry_points", "jit", "kernel", "njit", "overload", "prange", "BLOCK",
           "PARALLEL_THRESHOLD", "CACHE_DIR", "PLAIN", "SOURCE_HASH", "ITEMS", "serial_variant"]
