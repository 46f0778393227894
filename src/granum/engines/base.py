"""Engine base classes.

An engine is one stage of the per-step pipeline. A *compiled* engine names a
compiled stage function (``stage = "module:function"``, called as
``stage(S, C, P)`` on the scene and contact records) and builds its parameters ``P``
in :meth:`Engine.params` (a named tuple declared beside the stage); it holds
configuration only, no physics. A *Python* engine (``stage is None``)
implements :meth:`Engine.run_python`; the runner returns to Python only at steps
where such an engine is due.
"""

from __future__ import annotations

import time

from granum.core.attrs import Attr, Attributed, to_bool, to_float, to_int, to_str


class Engine(Attributed):
    """Base of all engines (YADE ``Engine``)."""

    _attrs = {
        "dead": Attr(False, "If True, the engine is skipped", to_bool),
        "label": Attr("", "Name under which the engine is reachable from scripts", to_str("label")),
        "ompThreads": Attr(-1, "Accepted for compatibility; granum's thread count is global (-j)",
                           to_int("ompThreads")),
        "execTime": Attr(0, "Time spent in this engine [ns] (with O.timingEnabled)"),
        "execCount": Attr(0, "Number of times the engine ran (with O.timingEnabled)"),
    }

    #: ``"module:function"`` of the compiled stage, or None for an engine run in Python.
    stage: str | None = None
    #: Whether the engine adds bodies as the run goes (a factory): on several threads its plans get the parallel
    #: step loop from the start, however small the scene (:meth:`granum.engines.runner.Runner.serial`).
    adds_bodies: bool = False

    #: position + 1 of a compiled engine in the current plan (set by the runner)
    _plan_index = 0

    def params(self, scene, engines) -> tuple:
        """Parameters ``P`` of the compiled stage: the named tuple its kernel module declares beside it, built
        by keyword (``engines``: the whole engine list). A stage without parameters gets ``()``."""
        return ()

    #: Whether :meth:`params_key` reads nothing but the edit tokens of Attributed objects
    #: (:func:`granum.core.attrs.edit_token`) and the scene's values in :meth:`Runner.scene_stamp
    #: <granum.engines.runner.Runner.scene_stamp>`: while no declared attribute anywhere was assigned
    #: (:func:`granum.core.attrs.assignments`) and those values stay, the runner keeps the parameters without
    #: computing the key.
    key_from_edits: bool = False

    def params_key(self, scene, held: list):
        """None, or a key such that :meth:`params` gives the same parameters while it is equal: the runner then
        keeps them from chunk to chunk instead of building them anew (a run with a Python engine due at every
        step has a chunk a step). Objects the key identifies by id go into ``held``, which the runner keeps.
        An engine whose parameters read the scene's changing state returns None (the default)."""
        return None

    def run_hook(self, omega) -> None:
        """Python part of a compiled engine, run after a step in which its stage asked for it."""

    def hook_due(self) -> bool:
        """Whether this engine's stage asked for its hook in the last step, for an engine whose stage may share
        that step's hook slot (``iscal[SI_HOOK]``) with another one's: its hook runs too."""
        return False

    def due(self, scene) -> bool:
        """Whether a Python engine must run in the current step."""
        return True

    def run_python(self, omega) -> None:
        """Body of a Python engine."""

    def functors(self) -> list:
        """The functors this engine owns (a collider's Bo1, an InteractionLoop's Ig2/Ip2/Law2)."""
        return []

    def labelled_parts(self) -> list:
        """The objects this engine owns whose labels become names too (O.labeledEngine finds them): its
        functors, or the engines a CombinedKinematicEngine combines."""
        return self.functors()

    def in_place(self) -> list:
        """The engines a step runs in this engine's place, in order: itself unless dead (a ParallelEngine:
        its live slaves)."""
        return [] if self.dead else [self]


class GlobalEngine(Engine):
    """Engine acting on the whole scene (YADE ``GlobalEngine``)."""


class PartialEngine(Engine):
    """Engine acting on the bodies listed in ``ids`` (YADE ``PartialEngine``)."""

    _attrs = {"ids": Attr([], "Ids of the bodies the engine acts on", lambda o, v: [int(i) for i in v])}

    def id_array(self, scene):
        import numpy as np

        ids = np.asarray(self.ids, np.int64)
        bad = ids[(ids < 0) | (ids >= scene.body_count)]
        if bad.size:
            raise IndexError(f"{type(self).__name__}.ids: body id {int(bad[0])} out of range "
                             f"(there are {scene.body_count} bodies)")
        return ids


class PeriodicEngine(GlobalEngine):
    """Engine run periodically in steps, simulated time or wall-clock time (YADE ``PeriodicEngine``).

    It runs in a step where any of the enabled periods has elapsed since its last
    run (``iterPeriod`` steps, ``virtPeriod`` seconds of simulated time or
    ``realPeriod`` seconds of wall-clock time), at most ``nDo`` times (unlimited if
    negative), never before step ``firstIterRun``. The first time it is reached it
    only sets its reference point, unless ``initRun``; that first call counts towards
    ``nDo`` (YADE's behaviour).
    """

    _attrs = {
        "iterPeriod": Attr(0, "Period in steps (0: disabled)", to_int("iterPeriod")),
        "virtPeriod": Attr(0.0, "Period in simulated time [s] (0: disabled)", to_float("virtPeriod")),
        "realPeriod": Attr(0.0, "Period in wall-clock time [s] (0: disabled)", to_float("realPeriod")),
        "nDo": Attr(-1, "Maximum number of runs (negative: unlimited)", to_int("nDo")),
        "initRun": Attr(False, "Run also the first time the engine is reached", to_bool),
        "firstIterRun": Attr(0, "Step at which the engine may run for the first time", to_int("firstIterRun")),
        "iterLast": Attr(0, "Step of the last run", to_int("iterLast")),
        "virtLast": Attr(0.0, "Simulated time of the last run [s]", to_float("virtLast")),
        "realLast": Attr(0.0, "Wall-clock time of the last run [s]", to_float("realLast")),
        "nDone": Attr(0, "Number of runs so far", to_int("nDone")),
    }

    def __init__(self, **kw):
        super().__init__(**kw)
        if "realLast" not in kw:
            self.realLast = time.time()

    def due(self, scene) -> bool:
        it = scene.iter
        if it < self.firstIterRun:
            return False
        now = time.time()
        elapsed = (self.virtPeriod > 0 and scene.time - self.virtLast >= self.virtPeriod) or \
            (self.realPeriod > 0 and now - self.realLast >= self.realPeriod) or \
            (self.iterPeriod > 0 and it - self.iterLast >= self.iterPeriod)
        if (self.nDo < 0 or self.nDone < self.nDo) and elapsed:
            run = True
        elif self.nDone == 0:
            # the first call only sets the reference point (and counts towards nDo), as in YADE
            run = self.initRun
        else:
            return False
        # the values are of the declared types already: set without the converters (due() runs for every Python
        # engine at every step it may be due), but counted as edits all the same
        self.__dict__.update(iterLast=int(it), virtLast=float(scene.time), realLast=now, nDone=self.nDone + 1)
        object.__setattr__(self, "_edits", self._edits + 4)
        return run

    def next_due_iter(self, scene) -> int | None:
        """Earliest step at which the engine must be called because of its step counters.

        That is the first call (which sets its reference point), or the step at which
        ``iterPeriod`` elapses; None if only time periods can make it due.
        """
        if self.nDone == 0:
            return max(scene.iter, self.firstIterRun)
        if 0 <= self.nDo <= self.nDone:
            return None
        if self.iterPeriod > 0:
            return max(self.iterLast + self.iterPeriod, self.firstIterRun)
        return None
