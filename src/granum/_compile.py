"""A first run compiles an entry point's parts on two processes.

Numba compiles on one thread. When an entry point (the step loop) is not in the disk
cache, its caller can name the entry points it is made of (the stages), which are
compiled first, each on its own and cached: the process forks, and parent and child
take the parts one at a time, largest first, until none is left. The parent then loads
the child's parts from the disk cache and compiles the entry point, which only links
them. A later run with another engine list finds the parts in the cache.

The child only compiles and writes the cache; it runs no kernel and exits without
running Python's exit handlers. If it fails or stops making progress, the parent
compiles what is missing itself, so the outcome never depends on the child. The two
never write the same cache file: each part is compiled by one of them, and the
functions below the parts are link-only, never cached on their own
(:mod:`granum._linking`), but for the few that several stages call (the bodies'
motions, the sort): each of those is compiled, for whatever types, only by whichever
process needs it first, as an entry point of its own in the disk cache, and the other
process loads it (or compiles other types link-only: :func:`compile_once`). So that
the other process does not need them at the same moment, it begins with the largest
part that calls none of those the first part calls (NewtonIntegrator's stage, while
the first compiles the interaction loop's). Forking is used on Linux only, with two or
more cores, when no other thread runs Python, and can be switched off with
``GRANUM_COMPILE_JOBS=1`` (larger values mean 2).
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import signal
import sys
import tempfile
import threading
import time
import types
import warnings

#: Called as ``done = NOTICE(count)`` before a first run compiles ``count`` entry points that are not in the disk
#: cache (a few seconds to half a minute), and ``done()`` once they are compiled; None: nothing is said. Set by
#: the layer that talks to the user (:mod:`granum.yade.progress`): this module prints nothing itself.
NOTICE = None

#: Per thread, the ends of the compilings announced inside the innermost :func:`announced` block (None: none open).
_held = threading.local()

#: A child that has not finished this long after the parent finished its own parts (and at least
#: :data:`PATIENCE` times as long as the parent took) is taken as stuck: the parent compiles the rest [s].
MIN_WAIT = 60.0
PATIENCE = 3.0

#: While a first run's parts are compiled on two processes: the folder of their claims, a function that says
#: whether the other process still runs, and the shared functions this process claimed; None otherwise
#: (:func:`compile_once`).
_sharing: tuple | None = None


def processes() -> int:
    """How many processes compile a first run's parts."""
    setting = os.environ.get("GRANUM_COMPILE_JOBS", "")
    if setting.strip():
        try:
            return max(1, int(setting))
        except ValueError:
            raise ValueError(f"GRANUM_COMPILE_JOBS must be a whole number, not {setting!r}") from None
    if sys.platform != "linux":
        return 1
    return min(2, len(os.sched_getaffinity(0)))


def is_granum_dispatcher(value) -> bool:
    """Whether ``value`` is a compiled granum function (a dispatcher of a function in a granum module)."""
    return getattr(value, "py_func", None) is not None and value.py_func.__module__.startswith("granum")


def reached(dispatcher, found: dict | None = None) -> dict:
    """The granum functions ``dispatcher`` reaches through its globals (its nested functions' too), itself
    included (id -> dispatcher)."""
    found = {} if found is None else found
    if id(dispatcher) not in found:
        found[id(dispatcher)] = dispatcher
        func = dispatcher.py_func
        for name in global_names(func.__code__):
            value = func.__globals__.get(name)
            if is_granum_dispatcher(value):
                reached(value, found)
    return found


def global_names(code) -> set[str]:
    """The names ``code`` and the functions defined in it may read as globals."""
    names = set(code.co_names)
    for const in code.co_consts:
        if isinstance(const, types.CodeType):
            names |= global_names(const)
    return names


def reach(dispatcher) -> int:
    """How many granum functions ``dispatcher`` reaches through its globals: how much compiling it costs."""
    return len(reached(dispatcher))


def shared_reached(dispatcher) -> set:
    """The ids of the functions compiled once for both processes (:func:`compile_once`: those declared
    ``shared``, :func:`granum._jit.jit`) that ``dispatcher`` reaches through its globals."""
    return {k for k, d in reached(dispatcher).items() if getattr(d, "granum_shared", False)}


def ordered(todo: list) -> list:
    """The parts ``todo`` in the order the processes take them: largest first, but second the largest part that
    reaches none of the shared functions the first reaches, when there is one. The two processes begin with those
    two: while one compiles the shared functions (early in a stage: the bodies' motions), the other compiles a
    part that does not need them, and it finds them in the disk cache when its next part does."""
    todo = sorted(todo, key=lambda p: -reach(p[0]))
    if len(todo) > 2:
        first = shared_reached(todo[0][0])
        apart = next((k for k in range(1, len(todo)) if not shared_reached(todo[k][0]) & first), None)
        if first and apart is not None:
            todo.insert(1, todo.pop(apart))
    return todo


def compile_once(name: str, compile_here, load_cached) -> bool:
    """Compile a shared function (``name``: the same in both processes) as an entry point in the disk cache
    (``compile_here()``) for the types at hand, unless the other process of a first run's parts compiles it:
    whether it is compiled or loaded now. Outside of a two-process compile, ``compile_here()``.

    While parts are compiled on two processes, the first process to ask for a function claims it, and only it
    compiles that function, for whatever types it needs (the two never write the same cache file). The other
    waits until the first is done with its first compilation (or has gone, or :data:`MIN_WAIT` seconds have
    passed), then loads the types at hand from the disk cache (``load_cached()``: whether they are there, loaded
    now); when they are not there (other types), False: the caller compiles them link-only, which writes nothing
    to disk. A process waits only while compiling a caller of the function; the other one, compiling the
    function, waits in turn only for the functions it calls: no deadlock while shared functions do not call one
    another in a cycle (granum's do not)."""
    sharing = _sharing
    if sharing is None:
        compile_here()
        return True
    folder, other_runs, mine = sharing
    claim = claim_name(name)
    done = os.path.join(folder, claim + ".done")
    if claim in mine:   # more types of a function this process claimed
        compile_here()
        return True
    if _claim(folder, claim):
        mine.add(claim)
        try:
            compile_here()
        finally:
            os.close(os.open(done, os.O_CREAT | os.O_WRONLY))
        return True
    deadline = time.monotonic() + MIN_WAIT
    while not os.path.exists(done) and time.monotonic() < deadline and other_runs():
        time.sleep(0.005)
    return load_cached()


def claim_name(name: str) -> str:
    """The claim file of shared function ``name`` (:func:`compile_once`)."""
    return "once-" + hashlib.sha256(name.encode()).hexdigest()[:32]


def _claim(folder: str, k: int | str) -> bool:
    """Take part ``k`` or shared function ``k`` (:func:`compile_once`): True once, for whichever process asks
    first."""
    try:
        os.close(os.open(os.path.join(folder, str(k)), os.O_CREAT | os.O_EXCL | os.O_WRONLY))
        return True
    except FileExistsError:
        return False


def compile_each(dispatcher, signatures) -> None:
    """Compile ``dispatcher`` for each argument-type tuple of ``signatures`` (or load it from the cache)."""
    for sig in signatures:
        dispatcher.compile(sig)


def compile_parts(parts: list[tuple[object, list[tuple]]], load_cached) -> None:
    """Compile the entry points ``parts`` (``(dispatcher, [argument types, ...])``), each cached on disk,
    on up to :func:`processes` processes. ``load_cached(dispatcher, argument types)`` loads a part from the
    disk cache if it is there and says whether it was (:func:`granum._linking.load_cached`). The caller holds
    the compile lock (:func:`granum._jit.compile_lock`)."""
    todo = [(d, [s for s in sigs if not load_cached(d, s)]) for d, sigs in parts]
    todo = ordered([(d, s) for d, s in todo if s])
    if not todo:
        return
    done = NOTICE(len(todo)) if NOTICE is not None else None
    held = getattr(_held, "ends", None)
    if done is not None and held is not None:   # the enclosing block ends the line
        held.append(done)
        done = None
    try:
        _compile_todo(todo)
    finally:
        if done is not None:
            done()


@contextlib.contextmanager
def announced():
    """A block whose compiling is announced as one: the line :func:`compile_parts` begins ends with the block, not
    with the parts (a step loop: its stages, then the loop that calls them, which links them)."""
    outer = getattr(_held, "ends", None)
    _held.ends = []
    try:
        yield
    finally:
        ends, _held.ends = _held.ends, outer
        for done in ends:
            done()


def _compile_todo(todo: list[tuple[object, list[tuple]]]) -> None:
    """Compile the entry points ``todo`` (none in the disk cache, :func:`ordered`) as :func:`compile_parts` says."""
    if processes() < 2 or len(todo) < 2 or not _fork_is_safe():
        for d, sigs in todo:
            compile_each(d, sigs)
        return
    global _sharing
    outer, parent = _sharing, os.getpid()
    with tempfile.TemporaryDirectory(prefix="granum-claims-") as folder:
        with warnings.catch_warnings():   # Python >= 3.12 warns about forking with threads: the child only compiles
            warnings.simplefilter("ignore", DeprecationWarning)
            pid = os.fork()
        if pid == 0:
            _sharing = folder, lambda: os.getppid() == parent, set()
            status = 1
            try:
                for k, (d, sigs) in enumerate(todo):
                    if _claim(folder, k):
                        compile_each(d, sigs)
                status = 0
            finally:
                os._exit(status)
        _sharing = folder, lambda: _running(pid), set()
        start = time.monotonic()
        try:
            for k, (d, sigs) in enumerate(todo):
                if _claim(folder, k):
                    compile_each(d, sigs)
            _wait(pid, max(MIN_WAIT, PATIENCE * (time.monotonic() - start)))
        finally:
            _sharing = outer
            _stop(pid)
    for d, sigs in todo:   # the child's parts come from the disk cache (compiled here if it failed)
        compile_each(d, sigs)


def _fork_is_safe() -> bool:
    """Whether no thread but this one and the main one runs Python: a lock another thread held when the
    process forked would stay locked in the child (Jupyter's kernel threads, a user's). The main thread
    waiting for a background ``O.run`` holds none."""
    others = threading.active_count() - 1
    return others == 0 or (others == 1 and threading.current_thread() is not threading.main_thread())


def _running(pid: int) -> bool:
    """Whether child ``pid`` has not exited (an exited child is reaped here: :func:`_wait` and :func:`_stop`
    allow for that)."""
    try:
        return os.waitpid(pid, os.WNOHANG)[0] == 0
    except ChildProcessError:
        return False


def _wait(pid: int, limit: float) -> None:
    """Wait up to ``limit`` seconds for child ``pid`` to exit."""
    deadline = time.monotonic() + limit
    try:
        while time.monotonic() < deadline:
            if os.waitpid(pid, os.WNOHANG)[0]:
                return
            time.sleep(0.02)
    except ChildProcessError:   # reaped already (by _running, or SIGCHLD ignored)
        return


def _stop(pid: int) -> None:
    """End child ``pid`` if it still runs, and reap it. Killing it never corrupts the cache: Numba writes
    each cache file to a temporary name and renames it, and an index entry without its data file is a
    miss."""
    try:
        if os.waitpid(pid, os.WNOHANG)[0] == 0:
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
    except ChildProcessError:
        pass
