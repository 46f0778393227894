"""How compiled code calls compiled code: canonical argument types and link-only callees.

Numba compiles a function into its own *library*. It optimises the function, links into it
the libraries of everything it calls, optimises the linked module as a whole and generates
machine code for it. A callee is therefore optimised and translated again in every library
above it: the step loop contains the stages, which contain the loops over blocks, which
contain the per-item functions... On a first run, three quarters of the time spent in LLVM
went into code it had already optimised or translated once.

A granum function called from compiled code gets two changes (:func:`install`):

* **Canonical argument types.** Numba compiles a callee once per tuple of argument types: a
  constant argument (``load3_row(a, c, F_FN)``) types as its literal value, a ``prange``
  index as ``uint64``, an index read from ``con_i`` as ``int32``, and the same function was
  compiled up to five times over. Integer scalars are therefore passed as ``int64`` (Numba
  converts them at the call: granum's integer arguments are indices, codes and flags, far
  inside that range) and constants as their plain type. Integers inside tuples keep their
  types (no kernel passes them between compiled functions with varying widths).
* **Link-only compilation.** The callee's library is optimised function by function and
  linked with the libraries it calls, and nothing more (:class:`LinkOnlyLibrary`): no
  optimisation as a whole, no machine code, no entry point callable from Python, no disk
  cache. The library of the *entry point* that finally links it (a function called from
  Python: the step loop, a stage, a record conversion) optimises the whole and translates
  it, once, and its cached machine code contains the callee.

A function declared ``inline="always"`` is compiled so too, with Numba's ``forceinline`` option instead
(:func:`granum._jit.jit`): its function is marked ``alwaysinline``, and LLVM inlines it into each caller
when the entry point is optimised. Numba's own inlining copies the function's IR into every call site and
types and lowers each copy again; this way it is typed and lowered once for its argument types.

A callee that already has an ordinary compilation for the same types (it was called from
Python, or is in the disk cache) is linked from that one instead. Recursion is not supported
on the link-only path: a function that calls itself is compiled as usual.

**Shared callees.** A function that several stages call (the bodies' motions, the sort of the
pairs) is declared ``shared`` (:func:`install`): it gets an ordinary compilation, an entry point
in the disk cache, the first time compiled code calls it, and its callers link that one. While a
first run's stages are compiled on two processes, it is compiled by one of them only
(:func:`granum._compile.compile_once`); the other loads it from the cache (Numba keeps a cached
function's LLVM module with its machine code, for callers to link), or compiles it link-only when
the types it needs are not there.

**Calls by symbol.** :func:`entry_call` calls an entry point without linking its library: the
caller only declares the function, and the JIT resolves the symbol to the machine code already
loaded. The step loop calls its stages so, and compiles in a fraction of a second instead of
optimising and translating the whole program once more. The entry point must be loaded before
the caller's machine code (the runner loads a plan's stages first), under the symbol the caller
was compiled against (:func:`entry_symbol`; the step loop's source names the symbols it uses, so
a recompiled stage gets a new step loop). A cached caller whose callees are not loaded would
crash the process: only the runner creates such callers, and it always loads the callees first.

Link-only compilation also applies to the implementations of granum's own ``@overload`` functions
(:func:`overload`): they are only ever called from compiled code. Other packages' overloads (NumPy's
in Numba) compile as Numba compiles them.

**Numba's internals.** All this relies on Numba internals outside its documented extension API
(:data:`INTERNALS`). :func:`missing_internal` probes them; when one is gone (a newer Numba),
:mod:`granum._jit` compiles on its plain path instead, which uses none of this module. Nothing here
changes Numba's behaviour until :func:`enable` is called.
"""

from __future__ import annotations

from numba import types
from numba.core import cgutils, compiler, entrypoints, errors, sigutils, typing
from numba.core import event as numba_event
from numba.core.caching import FunctionCache
from numba.core.codegen import JITCodeLibrary
from numba.core.compiler_lock import global_compiler_lock
from numba.core.imputils import user_function
from numba.core.registry import CPUDispatcher
from numba.core.runtime.nrt import rtsys
from numba.cpython import hashing  # noqa: F401  (its import adds the hash secret's symbols: _load_from_cache)
from numba.extending import intrinsic

from granum import _compile


def canonical(t):
    """The type a callee is compiled for when called with an argument of type ``t``."""
    t = types.unliteral(t)
    return types.int64 if isinstance(t, types.Integer) else t


class LinkOnlyLibrary(JITCodeLibrary):
    """The library of a function that only compiled code calls: finalising it links its callees'
    libraries into it and stops there. Whoever links this library optimises and translates it."""

    def finalize(self):
        self._raise_if_finalized()
        seen = set()
        for library in self._linking_libraries:
            if library not in seen:
                seen.add(library)
                self._reload_init.update(library._reload_init)
                self._final_module.link_in(library._get_module_for_linking(), preserve=True)
        self._finalized = True


class _LinkOnlyKey:
    """Implementation key of a link-only compilation (Numba keys ordinary ones by their entry point)."""

    __slots__ = ("name",)

    def __init__(self, name: str):
        self.name = name

    def __repr__(self):
        return f"<link-only {self.name}>"


#: Environments of link-only functions by symbol name. Kept alive here: the entry point that links
#: such a function sets its environment pointer when it is translated (:func:`_set_environments`), and
#: Numba's cache stores the environments an entry point refers to only while they are alive. One per
#: link-only compilation of the process (a few hundred), each small.
_ENVIRONMENTS: dict = {}


def _compile_link_only(dispatcher, args: tuple):
    """Compile ``dispatcher`` for ``args`` into a :class:`LinkOnlyLibrary`; register it for callers."""
    target = dispatcher.targetdescr
    flags = compiler.Flags()
    target.options.parse_as_flags(flags, dispatcher.targetoptions)
    flags = dispatcher._compiler._customize_flags(flags)
    flags.no_compile = True            # no machine code, hence no entry point
    flags.no_cpython_wrapper = True
    flags.no_cfunc_wrapper = True
    library = LinkOnlyLibrary(target.target_context.codegen(), dispatcher.py_func.__qualname__)
    with numba_event.trigger_event("numba:compile", data=dict(dispatcher=dispatcher, args=args, return_type=None)):
        cres = compiler.compile_extra(target.typing_context, target.target_context, dispatcher.py_func, args=args,
                                      return_type=None, flags=flags, locals=dispatcher.locals, library=library,
                                      pipeline_class=dispatcher._compiler.pipeline_class)
    key = _LinkOnlyKey(dispatcher.py_func.__qualname__)
    target.target_context.insert_user_function(key, cres.fndesc, [cres.library])
    _ENVIRONMENTS[cres.fndesc.env_name] = cres.environment
    return key, cres


def load_cached(dispatcher, args: tuple) -> bool:
    """Whether ``dispatcher`` has an ordinary compilation for argument types ``args``, in memory or, loaded
    now, from its disk cache (an entry point compiled by an earlier run or another process)."""
    with global_compiler_lock:
        if args in dispatcher.overloads:
            return True
        cres = _load_from_cache(dispatcher, args)
        if cres is None:
            return False
        dispatcher._cache_hits[args] += 1
        dispatcher.targetctx.insert_user_function(cres.entry_point, cres.fndesc, [cres.library])
        dispatcher.add_overload(cres)
        return True


def _load_from_cache(dispatcher, args: tuple):
    """``dispatcher``'s compilation for argument types ``args`` from its disk cache, or None.

    Numba's ``FunctionCache.load_overload`` refreshes the target context first: the first time in a process it
    imports all of Numba's lowering modules and installs their registries, 0.24-0.30 s of a cached start's
    1 s (2-core AMD EPYC, 2026-12-08), which only compiling needs (Numba's compiler refreshes the context itself).
    Machine code loaded from the cache needs the symbols it refers to: the runtime's (NRT, initialised here),
    those of Numba's extensions (a user's law may call one: their init hooks run here, as Numba runs them before
    it compiles), the hash secret's (added to LLVM's table when ``numba.cpython.hashing`` is imported: at this
    module's import), Numba's C helpers and math functions (added when the target context is made) and the
    parallel loops' (when the thread pool starts, at :mod:`granum._jit`'s import).

    Numba writes an entry's index before its data: a reader between the two, while a writer replaces a stale
    index, can find the data file of an older entry. One compiled for other argument types is a miss here; the
    callers read without the compile lock only the entries that are never replaced so
    (:func:`granum._jit._read_unlocked`)."""
    context = dispatcher.targetctx
    rtsys.initialize(context)
    entrypoints.init_all()
    cache = dispatcher._cache
    if not isinstance(cache, FunctionCache):   # a function compiled without a disk cache
        return None
    cres = None
    with cache._guard_against_spurious_io_errors():   # as Numba reads it (Windows: a file being replaced)
        cres = cache._load_overload(args, context)
    return cres if cres is not None and tuple(cres.signature.args) == tuple(args) else None


def entry_symbol(dispatcher, args: tuple) -> str:
    """The symbol of ``dispatcher``'s entry point for argument types ``args`` (which must exist)."""
    return dispatcher.overloads[tuple(args)].fndesc.mangled_name


@intrinsic
def entry_call(typingctx, fn, args):
    """``fn(*args)`` through the symbol of ``fn``'s entry point for the types of ``args`` (a tuple), which
    must be loaded already (:func:`granum._jit.entry_points`): it is never compiled here, so that the caller
    refers only to symbols its creator loaded first. Compiled code only."""
    if not isinstance(fn, types.Dispatcher) or not isinstance(args, types.BaseTuple):
        return None
    argtypes = tuple(args.types)
    dispatcher = fn.dispatcher
    if argtypes not in dispatcher.overloads:
        raise errors.TypingError(f"entry_call: {dispatcher.py_func.__qualname__} has no entry point loaded for "
                                 f"{argtypes}; load it first (granum._jit.entry_points)")
    fndesc = dispatcher.overloads[argtypes].fndesc

    def codegen(context, builder, sig, llargs):
        values = cgutils.unpack_tuple(builder, llargs[1], len(argtypes))
        return user_function(fndesc, ())(context, builder, fndesc.restype(*argtypes), values)

    return fndesc.restype(fn, args), codegen


def install(dispatcher, canonical_types: bool = True, shared: bool = False):
    """Give ``dispatcher`` link-only compilation when compiled code calls it, and canonical argument types
    unless ``canonical_types`` is false; with ``shared``, an ordinary compilation instead, once for both processes
    of a first run (see "Shared callees" above), and the attribute ``granum_shared`` that says so."""
    link_only: dict = {}      # argument types -> (implementation key, compile result)
    compiling: set = set()
    qualified = f"{dispatcher.py_func.__module__}.{dispatcher.py_func.__qualname__}"   # a shared function's claim
    generic_template = dispatcher.get_call_template
    generic_overload = dispatcher.get_overload

    def get_call_template(args, kws):
        if canonical_types:
            args = tuple(canonical(a) for a in args)
            kws = {k: canonical(v) for k, v in kws.items()}
        pysig, folded = dispatcher._compiler.fold_argument_types(args, kws)
        folded = tuple(folded)
        with global_compiler_lock:
            if folded in compiling:   # recursion: Numba's own path handles it
                return generic_template(args, kws)
            if folded not in link_only and not load_cached(dispatcher, folded):
                if not (shared and _compile.compile_once(qualified, lambda: dispatcher.compile(folded),
                                                         lambda: load_cached(dispatcher, folded))):
                    compiling.add(folded)
                    try:
                        link_only[folded] = _compile_link_only(dispatcher, folded)
                    finally:
                        compiling.discard(folded)
            signatures = list(dispatcher.nopython_signatures)
            signatures += [cres.signature for a, (_, cres) in link_only.items() if a not in dispatcher.overloads]
        name = dispatcher.py_func.__name__
        template = typing.make_concrete_template(f"CallTemplate({name})", key=name, signatures=signatures)
        return template, pysig, folded, {}

    def get_overload(sig):
        args = tuple(sigutils.normalize_signature(sig)[0])
        if args not in dispatcher.overloads and args in link_only:
            return link_only[args][0]
        return generic_overload(sig)

    dispatcher.get_call_template = get_call_template
    dispatcher.get_overload = get_overload
    dispatcher.granum_shared = shared
    return dispatcher


def _set_environments(library) -> None:
    """Point the environment globals of the link-only functions inside ``library`` at their environments."""
    for gv in library._final_module.global_variables:
        if gv.name in _ENVIRONMENTS:
            library.codegen.set_env(gv.name, _ENVIRONMENTS[gv.name])


class _TranslatedLibraries(numba_event.Listener):
    """After every compilation of an entry point, set the environments of the link-only code it holds."""

    def on_start(self, event):
        pass   # (required by the Listener interface) the environments exist only once a compilation ends

    def on_end(self, event):
        data = event.data or {}
        cres = getattr(data.get("dispatcher"), "overloads", {}).get(tuple(data.get("args") or ()))
        if cres is not None and cres.entry_point is not None and not isinstance(cres.library, LinkOnlyLibrary):
            _set_environments(cres.library)


def enable() -> None:
    """Switch link-only compilation on for this process (:mod:`granum._jit`, once, when the probe passed):
    from now on, compiling an entry point sets the environments of the link-only code it holds."""
    numba_event.register("numba:compile", _TranslatedLibraries())


def overload(func, **options):
    """``numba.extending.overload(func, **options)`` whose implementations compile link-only, and nothing else
    changed: only the template made here for ``func`` gets link-only compilation. Their argument types are
    kept (an overload may depend on them)."""
    from numba.core.extending import _overload_default_jit_options
    from numba.core.typing.templates import infer, infer_global, make_overload_template

    jit_options = {**_overload_default_jit_options, **options.pop("jit_options", {})}
    strict = options.pop("strict", True)
    inline = options.pop("inline", "never")
    prefer_literal = options.pop("prefer_literal", False)

    def decorate(definition):
        template = make_overload_template(func, definition, jit_options, strict, inline, prefer_literal, **options)
        generic = template._get_jit_decorator

        def _get_jit_decorator(self):
            jitter = generic(self)

            def decorator(**jit_kw):
                make = jitter(**jit_kw)

                def decorate_implementation(pyfunc):
                    d = make(pyfunc)
                    return install(d, canonical_types=False) if isinstance(d, CPUDispatcher) else d

                return decorate_implementation

            return decorator

        template._get_jit_decorator = _get_jit_decorator
        infer(template)
        infer_global(func, types.Function(template))
        return definition

    return decorate


#: The Numba internals this module relies on beyond Numba's documented extension API, as attribute paths:
#: from a module (``numba...``), from a sample CPU dispatcher (``dispatcher.``) or from a sample code library
#: (``library.``). :func:`missing_internal` checks them all.
INTERNALS = (
    "numba.core.codegen.JITCodeLibrary",
    "numba.core.compiler.compile_extra",
    "numba.core.compiler.Flags.no_compile",
    "numba.core.compiler.Flags.no_cpython_wrapper",
    "numba.core.compiler.Flags.no_cfunc_wrapper",
    "numba.core.compiler.Flags.forceinline",
    "numba.core.compiler.CompileResult.fndesc",
    "numba.core.compiler.CompileResult.library",
    "numba.core.compiler.CompileResult.environment",
    "numba.core.compiler.CompileResult.entry_point",
    "numba.core.compiler.CompileResult.signature",
    "numba.core.funcdesc.FunctionDescriptor.env_name",
    "numba.core.funcdesc.FunctionDescriptor.mangled_name",
    "numba.core.funcdesc.FunctionDescriptor.restype",
    "numba.core.compiler_lock.global_compiler_lock",
    "numba.core.event.trigger_event",
    "numba.core.event.register",
    "numba.core.event.Listener",
    "numba.core.imputils.user_function",
    "numba.core.cgutils.unpack_tuple",
    "numba.core.sigutils.normalize_signature",
    "numba.core.typing.make_concrete_template",
    "numba.core.typing.templates.make_overload_template",
    "numba.core.typing.templates._OverloadFunctionTemplate._get_jit_decorator",
    "numba.core.extending._overload_default_jit_options",
    "numba.core.registry.CPUDispatcher",
    "dispatcher.targetdescr.options.parse_as_flags",
    "dispatcher.targetdescr.target_context.insert_user_function",
    "dispatcher.targetdescr.typing_context",
    "dispatcher.targetctx",
    "dispatcher.targetoptions",
    "dispatcher._compiler._customize_flags",
    "dispatcher._compiler.pipeline_class",
    "dispatcher._compiler.fold_argument_types",
    "numba.core.caching.FunctionCache._load_overload",
    "numba.core.caching.FunctionCache._guard_against_spurious_io_errors",
    "numba.core.runtime.nrt.rtsys.initialize",
    "numba.cpython.hashing",
    "numba.core.entrypoints.init_all",
    "dispatcher._cache",
    "dispatcher._cache_hits",
    "dispatcher.add_overload",
    "dispatcher.get_call_template",
    "dispatcher.get_overload",
    "dispatcher.nopython_signatures",
    "dispatcher.overloads",
    "dispatcher.locals",
    "library._raise_if_finalized",
    "library._linking_libraries",
    "library._reload_init",
    "library._final_module",
    "library._get_module_for_linking",
    "library._finalized",
    "library.codegen.set_env",
)


def _resolve(path: str, samples: dict) -> bool:
    """Whether attribute path ``path`` (see :data:`INTERNALS`) resolves."""
    import importlib

    parts = path.split(".")
    if parts[0] in samples:
        value, rest = samples[parts[0]], parts[1:]
    else:   # the longest importable module prefix, then attributes
        for k in range(len(parts), 0, -1):
            try:
                value = importlib.import_module(".".join(parts[:k]))
            except ImportError:
                continue
            rest = parts[k:]
            break
        else:
            return False
    for name in rest:
        if not hasattr(value, name):
            return False
        value = getattr(value, name)
    return True


def missing_internal(internals=INTERNALS) -> str | None:
    """The first of ``internals`` (attribute paths, see :data:`INTERNALS`) this process's Numba lacks, or None.
    Cheap (no compilation): the samples are a dispatcher that is never compiled and an empty code library."""
    import numba
    from numba.core.registry import cpu_target

    samples = {"dispatcher": numba.njit(_probe_sample),
               "library": cpu_target.target_context.codegen().create_library("granum-probe")}
    return next((path for path in internals if not _resolve(path, samples)), None)


def _probe_sample(x):
    """The function of the sample dispatcher :func:`missing_internal` inspects (never compiled)."""
    return x
