"""``O``: the YADE ``Omega`` object, the scripting entry to the current scene.

``O.run(n)`` runs in a background thread as in YADE (``O.run(n, True)`` runs in the
calling thread and returns when done); ``O.pause()`` stops after the current step,
also when called from inside an engine. Assigning ``O.engines`` from inside a
running engine takes effect at the next step. Errors raised inside a background run
are re-raised by ``O.wait()``.
"""

from __future__ import annotations

import atexit
import builtins
import contextlib
import keyword
import sys
import threading
import time

import numpy as np

from granum.core.arrays import ENERGY_NAMES
from granum.core.scene import Scene
from granum.engines import interrupts
from granum.engines.base import Engine
from granum.engines.functors import Functor
from granum.engines.runner import Runner
from granum.engines.timestepper import TimeStepper
from granum.io import checkpoint
from granum.mathtypes import Vector3, as_vec3
from granum.yade.bodies import BodyContainer
from granum.yade.cell import Cell
from granum.yade.interactions import InteractionContainer
from granum.yade.materials import MaterialContainer, default_material
from granum.yade.progress import Progress, progress_wanted

#: prefix of :attr:`Omega.filename` for a scene kept in memory by ``O.saveTmp``
_MEMORY = ":memory:"


def _namespace() -> dict:
    """What checkpoint objects are saved as and rebuilt from: the classes of the YADE namespace, by name."""
    import granum.yade

    return granum.yade.namespace()


class EnergyTracker:
    """``O.energy``: named energy terms (dict-like; a term appears once it was computed)."""

    __slots__ = ("_omega",)

    def __init__(self, omega):
        self._omega = omega

    def keys(self) -> list:
        s = self._omega._scene
        return [n for k, n in enumerate(ENERGY_NAMES) if s.energy_set[k]]

    def __getitem__(self, name: str) -> float:
        s = self._omega._scene
        try:
            k = ENERGY_NAMES.index(name)
        except ValueError:
            raise KeyError(f"no energy term {name!r}; known terms: {self.keys()}") from None
        return float(s.energy[k])

    def __contains__(self, name) -> bool:
        return name in self.keys()

    def __iter__(self):
        return iter(self.keys())

    def __len__(self):
        return len(self.keys())

    def items(self) -> list:
        return [(k, self[k]) for k in self.keys()]

    def total(self) -> float:
        """Sum of all terms (constant when energy is conserved)."""
        return sum(self[k] for k in self.keys())

    def clear(self) -> None:
        s = self._omega._scene
        s.energy[:] = 0.0
        s.energy_set[:] = 0


class ForceContainer:
    """``O.forces``: forces and torques of the last step, and permanent forces."""

    __slots__ = ("_omega",)

    def __init__(self, omega):
        self._omega = omega

    def _id(self, i: int) -> int:
        n = self._omega._scene.body_count
        if not 0 <= int(i) < n:
            raise IndexError(f"Body id out of range: {i} (there are {n} bodies)")
        return int(i)

    def _get(self, column: str, i: int):
        a = self._omega._scene.bodies.stored(column)  # permanent forces: a lazy column, maybe not used yet
        i = self._id(i)
        # a copy of the row (float64 (3,): no conversion to check): 2.8 -> 1.1 us a call
        return Vector3._new(a[i].copy()) if len(a) else Vector3(0.0, 0.0, 0.0)

    def f(self, id: int, sync: bool = False):
        """Force on body ``id`` in the last step [N]."""
        return self._get("force", id)

    def t(self, id: int, sync: bool = False):
        """Torque on body ``id`` in the last step [N m]."""
        return self._get("torque", id)

    m = t

    def permF(self, id: int):
        return self._get("perm_force", id)

    def permT(self, id: int):
        return self._get("perm_torque", id)

    def addF(self, id: int, f, permanent: bool = False) -> None:
        """Add a force [N] to body ``id`` for the current step (or permanently)."""
        b = self._omega._scene.bodies
        i = self._id(id)
        v = as_vec3(f)
        b.force[i] += v
        if permanent:
            b.perm_force[i] += v

    def addT(self, id: int, t, permanent: bool = False) -> None:
        """Add a torque [N m] to body ``id`` for the current step (or permanently)."""
        b = self._omega._scene.bodies
        i = self._id(id)
        v = as_vec3(t)
        b.torque[i] += v
        if permanent:
            b.perm_torque[i] += v

    def setPermF(self, id: int, f) -> None:
        self._omega._scene.bodies.perm_force[self._id(id)] = as_vec3(f)

    def setPermT(self, id: int, t) -> None:
        self._omega._scene.bodies.perm_torque[self._id(id)] = as_vec3(t)

    def reset(self, resetAll: bool = True) -> None:
        b = self._omega._scene.bodies
        b.force[:] = 0.0
        b.torque[:] = 0.0
        if resetAll:
            for column in ("perm_force", "perm_torque"):
                b.stored(column)[:] = 0.0


class Omega:
    """The YADE ``Omega`` object (``O``).

    There is one: ``Omega()`` returns ``O`` (YADE scripts write ``o = Omega()`` and expect the same
    simulation). It holds a list of scenes (``addScene``, ``switchToScene``, ``thisScene``) and, apart,
    the alternative scene of ``switchScene``.
    """

    _instance: Omega | None = None

    def __new__(cls):
        if cls._instance is None:
            cls._instance = super().__new__(cls)
        return cls._instance

    def __init__(self):
        if getattr(self, "_frozen", False):
            return   # Omega() again: the same object, untouched
        self._snapshots: dict = {}
        self._thread: threading.Thread | None = None   # the background run's thread (O.wait joins it)
        #: the thread running steps now (a background run's, or the caller's for O.run(n, True) and O.step)
        self._run_thread: threading.Thread | None = None
        self._idle = threading.Event()   # set while no step runs
        self._idle.set()
        self._error: BaseException | None = None
        self._stop = False
        self._running = False
        self._namespace: dict | None = None
        #: called with the scene between compiled chunks of a run (the browser view takes its frames there)
        self.chunk_hooks: list = []
        self.bodies = BodyContainer(self)
        self.interactions = InteractionContainer(self)
        self.forces = ForceContainer(self)
        self.energy = EnergyTracker(self)
        self.cell = Cell(self)
        self.timingEnabled = False
        #: Counter of force synchronisations (YADE profiling; granum's forces are always in sync)
        self.forceSyncCount = 0
        #: Objects a GUI keeps with the scene (YADE); not saved by O.save
        self.miscParams: list = []
        self.filename: str | None = None
        self._scenes: list = [(Scene(), MaterialContainer())]
        self._this_scene = 0
        self._other_scene: tuple | None = None
        self._started = time.monotonic()
        self._speed = 0.0
        self._sub_stepping = False
        self._new_scene(*self._scenes[0])
        self._frozen = True

    def __setattr__(self, name, value):
        # no silent typos (O.dtt = ...): only existing attributes can be assigned. The private ones are granum's own,
        # set several times a run: not checked (hasattr would run a property's getter)
        if name[:1] != "_" and getattr(self, "_frozen", False) and not hasattr(self, name):
            raise AttributeError(f"Omega has no attribute {name!r}")
        object.__setattr__(self, name, value)

    def _new_scene(self, scene: Scene, materials: MaterialContainer) -> None:
        """Make ``scene`` the current one, in the current slot of the scene list."""
        self._scene = scene
        self.materials = materials
        self._scenes[self._this_scene] = (scene, materials)
        self._runner = Runner(scene, self)
        self._bind_labels(scene.engines)

    def _loaded(self, scene: Scene, materials: list) -> None:
        """Make a loaded checkpoint's scene the current one, with its ``materials`` as O.materials."""
        container = MaterialContainer()
        for m in materials:
            container.append(m)
        self._new_scene(scene, container)

    # ---- several scenes ------------------------------------------------------------------
    @property
    def thisScene(self) -> int:
        """Index of the current scene in the scene list (see :meth:`addScene`)."""
        return self._this_scene

    def addScene(self) -> int:
        """Add a new empty scene to the list; its index (the current scene stays current)."""
        self._scenes.append((Scene(), MaterialContainer()))
        return len(self._scenes) - 1

    def switchToScene(self, i: int) -> None:
        """Make scene ``i`` of the list current (stops a running simulation first)."""
        if not 0 <= int(i) < len(self._scenes):
            raise IndexError(f"O.switchToScene: scene {i} has not been created yet (O.addScene() creates one; "
                             f"there are {len(self._scenes)})")
        self._refuse_while_running()
        self._this_scene = int(i)
        self._new_scene(*self._scenes[self._this_scene])

    def _refuse_while_running(self) -> None:
        if self._running:
            raise RuntimeError("Please stop the simulation first, e.g. O.pause().")

    def switchScene(self) -> None:
        """Swap the current scene with the alternative one (empty at first); again swaps back. Refused while
        the simulation runs, as in YADE."""
        self._refuse_while_running()
        other = self._other_scene or (Scene(), MaterialContainer())
        self._other_scene = (self._scene, self.materials)
        self._new_scene(*other)

    def resetThisScene(self) -> None:
        """Replace the current scene by an empty one (the other scenes stay)."""
        self._stop_and_wait()
        self._new_scene(Scene(), MaterialContainer())

    resetCurrentScene = resetThisScene

    def resetAllScenes(self) -> None:
        """Drop every scene, the alternative one too, and start with one empty scene (as :meth:`reset`)."""
        self.reset()

    # ---- namespace of Python commands --------------------------------------------------
    def namespace(self) -> dict:
        """Globals in which PyRunner commands run.

        The script's (set by the launcher), else ``__main__``'s when it has the YADE
        names (``from granum.yade import *``), else a private YADE namespace.
        """
        if self._namespace is None:
            main = sys.modules["__main__"].__dict__
            if "O" in main:
                return main
            import granum.yade

            self._namespace = granum.yade.namespace()
        return self._namespace

    # ---- clock ---------------------------------------------------------------------------
    @property
    def iter(self) -> int:
        return self._scene.iter

    @property
    def time(self) -> float:
        return self._scene.time

    @property
    def dt(self) -> float:
        return self._scene.dt

    @dt.setter
    def dt(self, value: float) -> None:
        self._scene.dt = value

    @property
    def stopAtIter(self) -> int:
        """Step at which a run stops (ignored when not ahead of ``O.iter``)."""
        return self._scene.stop_at_iter

    @stopAtIter.setter
    def stopAtIter(self, value: int) -> None:
        self._scene.stop_at_iter = int(value)

    @property
    def stopAtTime(self) -> float:
        """Simulated time at which a run stops (ignored when not ahead of ``O.time``)."""
        return self._scene.stop_at_time

    @stopAtTime.setter
    def stopAtTime(self, value: float) -> None:
        self._scene.stop_at_time = float(value)

    @property
    def realtime(self) -> float:
        """Wall-clock time since granum started or since :meth:`resetTime` [s]."""
        return time.monotonic() - self._started

    @property
    def speed(self) -> float:
        """Steps per wall-clock second of the last run [1/s] (0 before any run)."""
        return self._speed

    def resetTime(self) -> None:
        """Set the step number, the simulated time and the wall-clock time (:attr:`realtime`) back to 0."""
        self._scene.iter = 0
        self._scene.time = 0.0
        self._started = time.monotonic()

    def _time_steppers(self) -> list:
        return [e for e in self._scene.engines if isinstance(e, TimeStepper)]

    @property
    def dynDtAvailable(self) -> bool:
        """Whether O.engines has a TimeStepper that :attr:`dynDt` could switch on."""
        return bool(self._time_steppers())

    @property
    def dynDt(self) -> bool:
        """Whether a TimeStepper in O.engines is active (it sets O.dt); assigning switches them all (YADE).
        Assigning O.dt leaves an active stepper active, as in YADE: its next update replaces the value."""
        return any(e.active for e in self._time_steppers())

    @dynDt.setter
    def dynDt(self, on: bool) -> None:
        steppers = self._time_steppers()
        if not steppers:
            raise RuntimeError("No TimeStepper found in O.engines (O.dynDt switches one, e.g. "
                               "GlobalStiffnessTimeStepper)")
        for e in steppers:
            e.active = bool(on)

    #: the name of :attr:`dynDt` in YADE before 2018
    usesTimeStepper = dynDt

    @property
    def subStep(self) -> int:
        """-1 between steps; inside a step, the index of the engine running; with :attr:`subStepping`, the
        index of the engine the next ``O.step()`` runs (``len(O.engines)``: the step's end)."""
        return self._runner.sub_step

    @property
    def subStepping(self) -> bool:
        """Whether ``O.step()`` runs one sub-step: the step's beginning, one engine, or the step's end. Turned
        off in the middle of a step, the next ``O.step()`` finishes that step."""
        return self._sub_stepping

    @subStepping.setter
    def subStepping(self, on: bool) -> None:
        self._sub_stepping = bool(on)

    @property
    def _currEngines(self) -> list:
        """The engines of the step going on (YADE): those its beginning fixed, while it runs sub-step by sub-step."""
        plan = self._runner.sub_plan
        return list(plan.engines) if plan is not None else self.engines

    @property
    def _nextEngines(self) -> list:
        """An engine list assigned during the step going on, which takes over at the next step (YADE); else []."""
        plan = self._runner.sub_plan
        return self.engines if plan is not None and plan.engines != self._scene.engines else []

    @property
    def trackEnergy(self) -> bool:
        return self._scene.track_energy

    @trackEnergy.setter
    def trackEnergy(self, on: bool) -> None:
        self._scene.track_energy = on

    @property
    def periodic(self) -> bool:
        return self._scene.periodic

    @periodic.setter
    def periodic(self, on: bool) -> None:
        self._scene.periodic = on

    @property
    def tags(self) -> dict:
        return self._scene.tags

    @property
    def numThreads(self) -> int:
        import numba

        return numba.get_num_threads()

    # ---- engines -------------------------------------------------------------------------
    @property
    def engines(self) -> list:
        return list(self._scene.engines)

    @engines.setter
    def engines(self, engines) -> None:
        engines = list(engines)
        for e in engines:
            if not isinstance(e, Engine):
                raise TypeError(f"O.engines: expected engines, got {e!r}")
        self._scene.engines = engines
        self._bind_labels(engines)

    def _bind_labels(self, engines) -> None:
        """Make labelled engines and functors names of the script's namespace (:meth:`namespace`), where
        YADE makes them builtins; granum never touches Python's builtins, so a label can change no other
        module (a label ``print`` does not replace Python's ``print``). As a script's own names shadow
        YADE's builtins, a name the namespace or Python's builtins already give to something that is no
        labelled object (``plot``, ``wall``, ``exit``...) keeps its meaning; the engine stays reachable as
        ``O.labeledEngine(label)``."""
        ns = None
        for e in engines:
            for obj in [e] + e.labelled_parts():
                label = obj.label
                if not label:
                    continue
                if not label.isidentifier() or keyword.iskeyword(label):
                    raise ValueError(f"label {label!r} is not a valid Python identifier")
                ns = self.namespace() if ns is None else ns
                current = ns.get(label, getattr(builtins, label, None))
                if current is None or isinstance(current, Engine | Functor):
                    ns[label] = obj

    def labeledEngine(self, label: str):
        """The engine (or functor of an engine) of O.engines labelled ``label``."""
        for e in self._scene.engines:
            for obj in [e] + e.labelled_parts():
                if obj.label == label:
                    return obj
        raise ValueError(f"No engine labeled {label!r}")

    # ---- the class hierarchy (yade.system) --------------------------------------------------
    def isChildClassOf(self, child: str, base: str) -> bool:
        """Whether the class named ``child`` derives from the class named ``base``."""
        from granum.yade import system

        return system.isChildClassOf(child, base)

    def childClassesNonrecursive(self, base: str) -> list:
        """Names of the classes deriving directly from the class named ``base``."""
        from granum.yade import system

        return sorted(system.childClasses(base, recurse=False))

    def plugins(self) -> list:
        """Names of every class of the object model (YADE: of its plugins)."""
        from granum.yade import wrapper

        return sorted(wrapper.CLASSES)

    def disableGdb(self) -> None:
        """Accepted: YADE stops attaching its debugger to crashes; granum never attaches one."""

    def bufferFromIntrsct(self, *args, **kw):
        raise NotImplementedError("O.bufferFromIntrsct: YADE's MPI exchange (yade.mpy) is not implemented in granum")

    def intrsctToBytes(self, *args, **kw):
        raise NotImplementedError("O.intrsctToBytes: YADE's MPI exchange (yade.mpy) is not implemented in granum")

    def runEngine(self, engine) -> None:
        raise NotImplementedError("O.runEngine: running one engine outside O.step() is not implemented in granum")

    # ---- running -------------------------------------------------------------------------
    @property
    def running(self) -> bool:
        return self._running

    def _loop(self, progress: Progress | None = None) -> None:
        scene = self._scene
        first = scene.iter
        started = time.monotonic()
        try:
            with interrupts.deferred():
                while not self._stop:
                    target = self.stopAtIter
                    limit = target - scene.iter if target > scene.iter else 1 << 62
                    stop_time = self.stopAtTime if self.stopAtTime > scene.time else np.inf
                    self._runner.advance(limit, stop_time)
                    for hook in self.chunk_hooks:
                        hook(scene)
                    interrupts.raise_pending()   # Ctrl-C lands here, at a step boundary
                    if progress is not None:
                        progress.update(scene.iter - first)
                    if scene.iter == target or (stop_time < np.inf and scene.time >= stop_time):
                        break
        finally:
            elapsed = time.monotonic() - started
            self._speed = (scene.iter - first) / elapsed if elapsed > 0 else 0.0
            self._stop = False
            self._end_run()
            if progress is not None:
                progress.finish(scene.iter - first)

    def _background(self) -> None:
        try:
            self._loop()
        except BaseException as e:  # re-raised by O.wait()
            self._error = e
            import traceback

            traceback.print_exc()

    def run(self, nSteps: int = -1, wait: bool = False) -> None:
        """Run ``nSteps`` steps (all if negative) in the background; with ``wait`` block until done.

        A run of ``nSteps`` with ``wait`` that lasts more than a second shows a progress bar when
        standard error is a terminal (see :mod:`granum.yade.progress`).
        """
        if isinstance(nSteps, bool) or not isinstance(nSteps, int | float) or not float(nSteps).is_integer():
            raise TypeError(f"O.run: nSteps must be a whole number of steps (<= 0: until paused), got {nSteps!r}")
        if self._running:
            return
        self._runner.finish_step()   # a step begun sub-step by sub-step ends first (it is not counted)
        if nSteps > 0:
            self.stopAtIter = self.iter + int(nSteps)
        self._error = None
        self._stop = False
        if wait:
            self._begin_run(threading.current_thread())
            self._loop(Progress(nSteps) if nSteps > 0 and progress_wanted(sys.stderr) else None)
            return
        self._thread = threading.Thread(target=self._background, name="granum-run", daemon=True)
        self._begin_run(self._thread)
        self._thread.start()

    def _begin_run(self, thread: threading.Thread) -> None:
        self._run_thread = thread
        self._idle.clear()
        self._running = True

    def _end_run(self) -> None:
        self._running = False
        self._run_thread = None
        self._idle.set()

    def pause(self) -> None:
        """Stop after the current step (also from inside an engine)."""
        if self._running:
            self._stop = True

    def wait(self) -> None:
        """Block until the background run stops; re-raise its error, if any."""
        t = self._thread
        if t is not None and t is not threading.current_thread():
            t.join()
        if self._error is not None:
            e, self._error = self._error, None
            raise e

    def step(self) -> None:
        """Run exactly one step in the calling thread (one sub-step with :attr:`subStepping`; the rest of a
        step begun sub-step by sub-step once it is turned off)."""
        if self._running and self._run_thread is not threading.current_thread():
            raise RuntimeError("O.step(): the simulation is running; O.pause() and O.wait() first")
        nested = self._running   # O.step() from an engine of the run itself
        if not nested:
            self._begin_run(threading.current_thread())
        try:
            with interrupts.deferred():
                if self._sub_stepping:
                    self._runner.substep()
                elif self._runner.sub_step >= 0:
                    self._runner.finish_step()
                else:
                    self._runner.advance(1)
                interrupts.raise_pending()
        finally:
            if not nested:
                self._end_run()

    # ---- scenes --------------------------------------------------------------------------
    def reset(self) -> None:
        """Start anew: one empty scene (bodies, interactions, engines, materials, clock); the scenes of
        :meth:`addScene` and :meth:`switchScene` are dropped too, as in YADE."""
        self._stop_and_wait()
        self._scenes = [(Scene(), MaterialContainer())]
        self._this_scene = 0
        self._other_scene = None
        self.filename = None
        self._speed = 0.0
        self._sub_stepping = False   # a scene's setting in YADE: a new scene steps whole
        self._new_scene(*self._scenes[0])

    def _stop_and_wait(self) -> None:
        """Stop a run going on in another thread at its next step boundary, and wait until it has."""
        if self._running and self._run_thread is not threading.current_thread():
            self.pause()
            self._idle.wait()

    def save(self, file, quiet: bool = False) -> None:
        """Save the whole scene to ``file`` (format by extension: ``.yade``, ``.xml``, ``.h5``, optionally
        ``.gz``/``.bz2``; see :mod:`granum.io.checkpoint`). The file is written atomically. ``quiet`` is
        accepted (granum prints nothing either way)."""
        with self._paused():
            checkpoint.checkpoint_write(file, self._scene, self.materials, _namespace())
        self.filename = str(file)

    @contextlib.contextmanager
    def _paused(self):
        """Pause a run going on in another thread for the block (saving needs a still scene), then resume it
        unless it ended meanwhile (reached stopAtIter/stopAtTime or failed)."""
        if not self._running or self._run_thread is threading.current_thread():
            yield
            return
        s = self._scene
        it0, t0 = s.iter, s.time
        self._stop_and_wait()
        try:
            yield
        finally:
            ended = (self.stopAtIter > it0 and s.iter >= self.stopAtIter) or \
                (self.stopAtTime > t0 and s.time >= self.stopAtTime)
            if self._error is None and not ended:
                self.run()

    def load(self, file, quiet: bool = False) -> None:
        """Replace the scene by the one saved in ``file`` with :meth:`save` (stops a running simulation).

        The file is checked before the current scene is replaced (a bad or hostile file raises
        :class:`~granum.io.checkpoint_formats.CheckpointError`), and loading runs no code; but the
        scene's engines come with it, and a ``PyRunner``'s ``command`` is Python code run at
        :meth:`run`, as in YADE. Load only checkpoints you trust, as you would run only scripts you
        trust."""
        self._stop_and_wait()
        self._loaded(*checkpoint.checkpoint_read(file, _namespace()))
        self.filename = str(file)

    def reload(self, quiet: bool = False) -> None:
        """Load again the file the scene was last saved to or loaded from (:attr:`filename`; a scene kept
        with :meth:`saveTmp` is reloaded from memory)."""
        if self.filename is None:
            raise RuntimeError("O.reload: the scene was never saved or loaded (O.filename is None)")
        if self.filename.startswith(_MEMORY):
            self.loadTmp(self.filename[len(_MEMORY):])
        else:
            self.load(self.filename)

    def saveTmp(self, mark: str = "", quiet: bool = False) -> None:
        """Keep the whole scene in memory under ``mark`` (the checkpoint :meth:`save` writes, as bytes)."""
        with self._paused():
            self._snapshots[mark] = checkpoint.checkpoint_bytes(self._scene, self.materials, _namespace())
        self.filename = _MEMORY + mark

    def _tmp(self, mark: str, who: str) -> bytes:
        if mark not in self._snapshots:
            raise RuntimeError(f"O.{who}: no scene saved under mark {mark!r} (use O.saveTmp first)")
        return self._snapshots[mark]

    def loadTmp(self, mark: str = "", quiet: bool = False) -> None:
        """Replace the scene by the copy saved with ``saveTmp(mark)``."""
        data = self._tmp(mark, "loadTmp")
        self._stop_and_wait()
        self._loaded(*checkpoint.checkpoint_from_bytes(data, _namespace(), f"O.saveTmp({mark!r})"))
        self.filename = _MEMORY + mark

    def lsTmp(self) -> list:
        return list(self._snapshots)

    def tmpToString(self, mark: str = "") -> bytes:
        """The scene kept with ``saveTmp(mark)``, as the bytes of a ``.yade`` checkpoint."""
        return self._tmp(mark, "tmpToString")

    def tmpToFile(self, mark: str, filename: str) -> None:
        """Write the scene kept with ``saveTmp(mark)`` to ``filename`` (a ``.yade`` checkpoint, atomically)."""
        from granum.io.atomic import write_bytes

        write_bytes(filename, self._tmp(mark, "tmpToFile"))

    def tmpFilename(self) -> str:
        """A new file name in the temporary folder, for the user to save to (YADE's ``O.tmpFilename``)."""
        import tempfile

        with tempfile.NamedTemporaryFile(prefix="granum-tmp-", delete=False) as fh:
            return fh.name

    def sceneToString(self) -> bytes:
        """The whole scene as the bytes of a ``.yade`` checkpoint (see :meth:`stringToScene`)."""
        with self._paused():
            return checkpoint.checkpoint_bytes(self._scene, self.materials, _namespace())

    def stringToScene(self, data: bytes, mark: str = "") -> None:
        """Replace the scene by one from :meth:`sceneToString` (validated as any checkpoint)."""
        if not isinstance(data, bytes | bytearray):
            raise TypeError(f"O.stringToScene: expected the bytes of O.sceneToString(), got {type(data).__name__}")
        self._stop_and_wait()
        self._loaded(*checkpoint.checkpoint_from_bytes(bytes(data), _namespace(), "O.stringToScene"))

    def default_material(self):
        """The material of bodies created with ``material=-1``: the last in O.materials,
        or YADE's default material, appended to O.materials when there is none."""
        if len(self.materials) == 0:
            self.materials.append(default_material())
        return self.materials[len(self.materials) - 1]

    def exitNoBacktrace(self, status: int = 0) -> None:
        sys.exit(status)


O = Omega()
# a program that ends while a background run goes on (a script that returns after O.run()) would end
# with compiled threads still running and abort: stop the run at a step boundary first
atexit.register(O._stop_and_wait)
