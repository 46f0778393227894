"""The execution model: run the engine list in compiled chunks between Python engines.

Each step runs the engines in list order. Compiled engines are fused into one
generated loop (:mod:`granum.kernels.steploop`) that runs many steps without
returning to Python; the runner only comes back to Python for a step in which a
Python engine (a ``PyRunner``) is due, when the run must stop, or every
:data:`CHUNK_SECONDS` so that ``O.pause()`` and Ctrl-C stay responsive. Such a step
is run segment by segment, calling the Python engines in between.

Python engines are due by step count (predicted exactly), by simulated time
(checked inside the compiled loop with the same comparison as in Python) or by
wall-clock time (checked at chunk boundaries, hence with the chunk's latency).
"""

from __future__ import annotations

import time

import numba
import numpy as np

from granum._jit import ITEMS, PARALLEL_THRESHOLD, PARALLEL_THRESHOLD_CONTACTS, call, entry
from granum.core import heap
from granum.core.arrays import SI_HOOK
from granum.core.attrs import assignments
from granum.core.contacts import (
    C_COLLIDER_RUNS,
    C_CONTACTS,
    C_ERR_A,
    C_ERR_B,
    C_PAIRS,
    C_STATUS,
)
from granum.core.records import Record
from granum.engines import interrupts
from granum.engines.base import Engine, PeriodicEngine
from granum.engines.status import status_message
from granum.kernels import steploop
from granum.kernels.cell import advance_clock, step_begin
from granum.kernels.newton import first_massless_free_body
from granum.kernels.static import Static
from granum.physics import cpm, registry

# numba.get_num_threads() takes a process lock and a thread lock at every call (about 1 us of each O.step());
# once Numba's threads are launched (granum._jit does that at import) its C function answers alone, for the
# calling thread as numba.get_num_threads() does
_thread_count = getattr(numba.np.ufunc.parallel, "_get_num_threads", None) or numba.get_num_threads

#: Longest wall-clock time of one compiled chunk [s].
CHUNK_SECONDS = 0.25
#: a run that finds the body count changed by this much first gives the freed heap back (granum.core.heap)
TRIM_BODIES = 10_000
_NONE = np.zeros(0)  # no engine with a period in simulated time
#: Scenes with fewer bodies than this run the serial step loop (:meth:`Runner.serial`) on several threads: even
#: densely packed (coordination 12: 6 contact rows a sphere) with a wall each they stay below the kernels'
#: parallel thresholds (64 x 7 = 448 rows < PARALLEL_THRESHOLD_CONTACTS), so that a scene rarely compiles both
#: loops. Larger ones, which start a run with no contacts, would run serially only until their contacts form,
#: and compile both.
SERIAL_LOOP_BODIES = 64
#: Every kernel serial: the step loop of one thread and of small scenes.
ALL_SERIAL = ITEMS
#: The kernels over bodies serial: the step loop of scenes with fewer bodies than the kernels' threshold, whose
#: body count changes only when a script edits the scene.
BODIES_SERIAL = frozenset({"bodies"})


class SimulationError(RuntimeError):
    """A step could not be completed (missing functor, NaN, exploding velocity...).

    The scene stays as the failed step left it, for inspection.
    """


class Plan:
    """The engine list split into compiled segments and Python engines (a ParallelEngine's slaves in its
    place)."""

    def __init__(self, engines: list, one_stage_per_segment: bool = False):
        """``one_stage_per_segment``: each compiled engine a segment of its own (YADE's sub-stepping runs one
        engine at a time)."""
        self.engines = list(engines)
        self.live = live_engines(self.engines)
        self.items: list = []       # ("segment", k) or ("python", engine), in step order
        self.first_engine: list[int] = []   # per item, the index in ``live`` of its first engine (O.subStep)
        segments: list[list] = []
        for k, e in enumerate(self.live):
            if e.stage is None:
                self.items.append(("python", e))
                self.first_engine.append(k)
            else:
                if one_stage_per_segment or not self.items or self.items[-1][0] != "segment":
                    segments.append([])
                    self.items.append(("segment", len(segments) - 1))
                    self.first_engine.append(k)
                segments[-1].append(e)
        self.compiled = [e for seg in segments for e in seg]
        self.python = [e for e in self.live if e.stage is None]
        self.segments = [[e.stage for e in seg] for seg in segments]
        self.key = plan_key(engines)
        #: whether the engines a step runs follow from the engine list and the engines' declared attributes only
        #: (their ``dead`` flags: no ParallelEngine, whose slaves' lists could change in place), so that the plan
        #: is known to hold while the scene keeps the same list and no declared attribute was assigned
        #: (:meth:`Runner.plan`)
        self.stamped = all(type(e).in_place is Engine.in_place for e in self.engines)
        #: the scene's engine list and the :func:`~granum.core.attrs.assignments` stamp this plan was last found
        #: current for (:meth:`Runner.plan`)
        self.checked: tuple = (None, None)
        #: the compiled engines with the collider's counters (YADE's numAction, numReinit)
        self.counted = [e for e in self.compiled if "numAction" in e._attrs]
        #: the compiled engines whose stage may ask for their hook in a slot another one's names
        #: (:meth:`~granum.engines.base.Engine.hook_due`: the others' is always False)
        self.hooked = [e for e in self.compiled if type(e).hook_due is not Engine.hook_due]
        #: whether an engine adds bodies during the steps (a class attribute: it cannot change with the plan)
        self.adds_bodies = any(e.adds_bodies for e in self.compiled)
        #: the stages' time array of an untimed chunk (zeros, never written)
        self.untimed = np.zeros((len(self.compiled), 2), np.int64)
        self._loops: dict = {}
        self._type_keys: dict = {}   # id -> (object, type key): see _known_type_key
        self._last_loop: tuple = (None, None, None, None, None)   # see run_steps

    def run_steps(self, nmax: int, segment: int, S, C, PP: tuple, stop_time: float, virt_last: np.ndarray,
                  virt_period: np.ndarray, timing: bool, times: np.ndarray, serial: frozenset = frozenset()):
        """Run the compiled step loop (``run_steps`` of :mod:`granum.kernels.steploop`, whose docstring gives the
        arguments); with ``serial`` (items, :data:`granum._jit.ITEMS`), the loop of the stages' variants serial
        over those items (:meth:`Runner.serial`).

        The first time for the types of the scene, contacts and parameters, the functions the loop calls
        (the stages, the cell's step boundaries) are loaded from the disk cache or compiled, on two processes
        (:func:`granum.kernels.steploop.loop`), and the loop is generated to call their symbols (on the plain
        compile path, a Python loop calls their entry points). It is kept per argument types: calls skip Numba's
        typing. The types of the other arguments never change (the runner passes Python integers, a float,
        1-D float64 arrays, a bool and a 2-D int64 array), so the key is made of those three.
        """
        args = (int(nmax), int(segment), S, C, PP, float(stop_time), virt_last, virt_period, bool(timing), times)
        last = self._last_loop   # the last call's: records of the same Numba types (interned) and the same PP
        if last[0] is S._type and last[1] is C._type and last[2] is PP and last[3] == serial:
            return last[4](*args)
        key = (self._known_type_key(S), self._known_type_key(C), self._known_type_key(PP)), serial
        loop = self._loops.get(key)
        if loop is None:
            loop = self._loops[key] = steploop.loop(self.segments, args, serial)
        self._last_loop = (S._type, C._type, PP, serial, loop)
        return loop(*args)

    def _known_type_key(self, value):
        """:func:`_type_key` of ``value``, remembered for the stages' parameters (named tuples) of the last
        chunks and the tuple of them: the engines keep theirs while nothing changed (:meth:`Runner.params`), and the
        same object's type cannot have changed. The remembered objects are kept, so that their ids stay theirs (a
        few small arrays each; records, which hold the scene's arrays, are typed afresh: that is cheap)."""
        if not isinstance(value, tuple):
            return _type_key(value)
        kept = self._type_keys.get(id(value))
        if kept is not None and kept[0] is value:
            return kept[1]
        if len(self._type_keys) >= 64:
            self._type_keys.clear()
        # the parameters of all stages (a plain tuple): stage by stage
        key = tuple(self._known_type_key(v) for v in value) if type(value) is tuple else _type_key(value)
        self._type_keys[id(value)] = (value, key)
        return key


def _type_key(value):
    """What determines the Numba type of a kernel argument, computed faster than the type itself for
    records, arrays, Python scalars, static values and tuples of them (anything else is typed by Numba):
    the step loop is compiled per type."""
    if isinstance(value, tuple):   # a stage's named parameters: their class is part of the type
        key = tuple(_type_key(v) for v in value)
        return key if type(value) is tuple else (type(value), key)
    if isinstance(value, np.ndarray):
        f = value.flags
        return value.dtype.str, value.ndim, f.c_contiguous, f.f_contiguous, f.writeable, f.aligned
    if isinstance(value, Static):
        return value.value
    if isinstance(value, Record):
        return value._type
    if value is None or type(value) in (bool, int, float):
        return type(value)
    return numba.typeof(value)


def live_engines(engines) -> list:
    """The engines a step runs, in order: the live ones, a ParallelEngine replaced by its live slaves."""
    return [s for e in engines for s in e.in_place()]


def plan_key(engines) -> tuple:
    """Changes when the engine list, or the engines a step runs (dead flags, a ParallelEngine's slaves), change."""
    return tuple(map(id, engines)), tuple(map(id, live_engines(engines)))


class Runner:
    """Advances a scene by running its engine list."""

    def __init__(self, scene, omega):
        heap.configure()
        self.scene = scene
        self.omega = omega
        self._plan: Plan | None = None
        #: YADE's ``O.subStep``: -1 between steps; while a step runs item by item, the index (in the engines
        #: it runs) of the engine running or, when sub-stepping, of the next one; ``len(items)``: the step's
        #: end is next
        self.sub_step = -1
        #: the plan of a step run sub-step by sub-step (O.subStepping), kept until that step ends
        self.sub_plan: Plan | None = None
        # running estimate of the wall time of one step; pessimistic until measured, so that the first
        # chunk is one step and O.pause(), Ctrl-C and realPeriod are honoured from the start
        self._step_seconds = CHUNK_SECONDS
        self._trimmed_at = 0
        self._last_params: tuple | None = None   # see params()
        self._massless_checks: dict = {}   # record type -> entry point (see _massless_check)
        self._params_for: tuple = (None, None)   # the plan and the scene_stamp() of the last params() that ended

    def plan(self) -> Plan:
        """The plan of the scene's engine list, made anew when the list or the engines a step runs changed;
        without comparing the engines while the scene keeps the list object and no declared attribute was
        assigned since (:attr:`Plan.stamped`; the scene's list is replaced, never changed in place)."""
        engines = self.scene.engines
        plan = self._plan
        stamp = assignments()
        if plan is not None and plan.stamped and plan.checked[0] is engines and plan.checked[1] == stamp:
            return plan
        if plan is None or plan.key != plan_key(engines):
            plan = self._plan = Plan(engines)
            self.scene.note_contact_functors()
        plan.checked = (engines, stamp)
        return plan

    def params(self, plan: Plan) -> tuple:
        """The compiled engines' parameters, built anew before every chunk of steps, but for engines whose
        :meth:`params_key <granum.engines.base.Engine.params_key>` is the same as for the last ones they gave in
        this scene and plan (the step loop's types are then known: :meth:`Plan.run_steps`); for an engine whose
        key is made of edit tokens (:attr:`~granum.engines.base.Engine.key_from_edits`), without computing it
        while :meth:`scene_stamp` stays. When every engine keeps its parameters, so does the tuple of them."""
        out = []
        scene = self.scene
        stamp = self.scene_stamp()
        # the same plan and stamp as the last call that went through: an engine keyed by edits whose kept parameters
        # are still this scene's and plan's, at its place, kept them through that call, under this stamp, with its
        # plan index (another scene's runner would have replaced them), so the stamp needs no comparing engine by
        # engine. Forgotten until this call ends: one that raises may have kept some engines' parameters under its
        # own stamp, which a scene value changed back would make look current
        same = self._params_for[0] is plan and self._params_for[1] == stamp
        self._params_for = (None, None)
        for k, e in enumerate(plan.compiled):
            kept = e.__dict__.get("_params_kept")
            if (same and e.key_from_edits and kept is not None and kept[0][0] == k and kept[0][1] is scene
                    and kept[0][2] is plan):
                out.append(kept[1])
                continue
            object.__setattr__(e, "_plan_index", k + 1)  # what a stage writes to SI_HOOK to call back
            where = (k, scene, plan)   # the scene and the plan compare by identity
            if e.key_from_edits and kept is not None and kept[3] == stamp and kept[0][:3] == where:
                out.append(kept[1])
                continue
            held: list = []
            key = e.params_key(self.scene, held)
            if key is None:
                e.__dict__.pop("_params_kept", None)
            else:
                key = (*where, key)
                if kept is not None and kept[0] == key:
                    object.__setattr__(e, "_params_kept", (key, kept[1], kept[2], stamp))
                    out.append(kept[1])
                    continue
            p = e.params(self.scene, plan.engines)
            if key is not None:
                object.__setattr__(e, "_params_kept", (key, p, held, stamp))
            out.append(p)
        self._params_for = (plan, stamp)
        last = self._last_params
        if last is not None and len(last) == len(out) and all(a is b for a, b in zip(last, out, strict=True)):
            return last   # the same object: the step loop's types are known by its identity (Plan._known_type_key)
        self._last_params = out = tuple(out)
        return out

    def scene_stamp(self) -> tuple:
        """What the keys of engines with :attr:`~granum.engines.base.Engine.key_from_edits` read besides edit
        tokens: the assignments so far (:func:`granum.core.attrs.assignments`), the registrations, the scene's
        materials (their versions follow their assignments), periodicity, energy tracking and the functors of
        its contacts when the plan began."""
        scene = self.scene
        return (assignments(), registry.functor_generation, len(registry.MATERIALS), tuple(scene.materials),
                scene.periodic, scene.track_energy, scene._contact_functors)

    def check_scene(self, S) -> None:
        """Errors that would otherwise surface as NaN inside the kernels, checked before compiled code runs with
        the scene's record ``S``."""
        b = self.scene.bodies
        i = cpm.body_without_state(b, self.scene.materials)
        if i >= 0:
            raise SimulationError(f"body {i} has a CpmMat material but a plain State; the concrete model needs a "
                                  f"CpmState (give it CpmState(), or make it with utils.sphere)")
        i = self._massless_check(S)(S)
        if i >= 0:
            raise SimulationError(f"body {i} has mass {b.mass[i]} but free translational DOFs; "
                                  f"give it a positive mass (density) or block its DOFs (fixed=True)")

    def _massless_check(self, S):
        """:func:`~granum.kernels.newton.first_massless_free_body`'s entry point for records of ``S``'s type (a
        C function that takes the record without Numba's dispatcher typing it: about 1 us of each chunk)."""
        check = self._massless_checks.get(S._type)
        if check is None:
            check = self._massless_checks[S._type] = entry(first_massless_free_body, S)
        return check

    def serial(self, plan: Plan) -> frozenset:
        """Over which items (:data:`granum._jit.ITEMS`) the next chunk of steps of ``plan`` runs the kernels'
        serial variants (:func:`granum._jit.serial_variant`).

        All (:data:`ALL_SERIAL`) on one thread, or in a scene small enough to stay below every kernel's size
        threshold for running in parallel (fewer than :data:`SERIAL_LOOP_BODIES` bodies, and the potential pairs
        and contact rows below their thresholds). The bodies (:data:`BODIES_SERIAL`) in a larger scene with fewer
        bodies than :data:`granum._jit.PARALLEL_THRESHOLD`: its pairs and contacts may grow past theirs, its body
        count does not. None with an engine that adds bodies. The kernels left serial then run serially anyway,
        so the results are the same, and a first run compiles no parallel code over those items. Chosen at each
        chunk (at most :data:`CHUNK_SECONDS`): a scene that outgrows the thresholds during a run is back in
        parallel within one (and has compiled both loops)."""
        if _thread_count() == 1:
            return ALL_SERIAL
        if plan.adds_bodies:
            return frozenset()
        ctr = self.scene.contacts.ctr
        bodies = self.scene.body_count
        if (bodies < SERIAL_LOOP_BODIES and ctr[C_PAIRS] < PARALLEL_THRESHOLD
                and ctr[C_CONTACTS] < PARALLEL_THRESHOLD_CONTACTS):
            return ALL_SERIAL
        return BODIES_SERIAL if bodies < PARALLEL_THRESHOLD else frozenset()

    def steps_allowed(self, plan: Plan, limit: int) -> int:
        """How many whole steps may run compiled before a Python engine could be due."""
        scene = self.scene
        m = limit
        now = time.time()
        for e in plan.python:
            if not isinstance(e, PeriodicEngine):
                return 0
            nxt = e.next_due_iter(scene)
            if nxt is not None:
                m = min(m, nxt - scene.iter)
            if e.realPeriod > 0 and not 0 <= e.nDo <= e.nDone:
                m = min(m, int((e.realLast + e.realPeriod - now) / self._step_seconds))
        m = min(m, max(1, int(CHUNK_SECONDS / self._step_seconds)))
        return max(m, 0)

    def advance(self, limit: int, stop_time: float = np.inf) -> int:
        """Run at most ``limit`` steps (at least one unless ``stop_time`` is reached); return the count."""
        scene = self.scene
        plan = self.plan()
        if abs(scene.body_count - self._trimmed_at) >= TRIM_BODIES:  # a large scene was just built
            heap.trim()
            self._trimmed_at = scene.body_count
        m = self.steps_allowed(plan, limit)
        if m > 0:
            virt_last, virt_period = self.virtual_periods(plan)
            t0 = time.perf_counter()
            done, why = self.run_compiled(plan, m, -1, float(stop_time), virt_last, virt_period)
            if done:
                self._step_seconds = max((time.perf_counter() - t0) / done, 1e-9)
            if why == steploop.WHY_ERROR:
                self.raise_status()
            if why == steploop.WHY_HOOK:
                self.run_hooks(plan)
            if done or why == steploop.WHY_TIME:
                return done
        self.slow_step(plan)
        return 1

    @staticmethod
    def virtual_periods(plan: Plan) -> tuple[np.ndarray, np.ndarray]:
        """``virtLast`` and ``virtPeriod`` of the Python engines due by simulated time, which the compiled loop
        checks at every step (two empty arrays without Python engines)."""
        if not plan.python:
            return _NONE, _NONE
        virt = [e for e in plan.python if e.virtPeriod > 0 and e.nDone > 0 and not 0 <= e.nDo <= e.nDone]
        return np.array([e.virtLast for e in virt]), np.array([e.virtPeriod for e in virt])

    def run_compiled(self, plan: Plan, nmax: int, segment: int, stop_time: float, virt_last: np.ndarray,
                     virt_period: np.ndarray) -> tuple[int, int]:
        """Run :meth:`Plan.run_steps` (whose arguments these are) with the engines' parameters, the scene's record
        (checked) and its contacts, which go back to the scene whatever Ctrl-C does meanwhile; the stages' counters
        and times go to their engines. Returns the steps done and why the loop stopped."""
        scene = self.scene
        timing, times = self.timing(plan)
        PP = self.params(plan)
        S = scene.arrays()   # after the parameters: a functor's prepare may add columns (granum.physics.cpm)
        self.check_scene(S)
        with interrupts.shielded():
            C = scene.contacts_record()
            out = plan.run_steps(nmax, segment, S, C, PP, stop_time, virt_last, virt_period, timing, times,
                                 serial=self.serial(plan))
            scene.take_contacts(C)
        self.sync_counters(plan, timing, times)
        return out

    def timing(self, plan: Plan) -> tuple[bool, np.ndarray]:
        """Whether stages are timed (``O.timingEnabled``), and the (stages, 2) array they add to (untimed, the
        plan's array of zeros, which the stages leave alone)."""
        if getattr(self.omega, "timingEnabled", False):
            return True, np.zeros((len(plan.compiled), 2), np.int64)
        return False, plan.untimed

    def sync_counters(self, plan: Plan, timing: bool, times: np.ndarray) -> None:
        """Copy the kernels' counters into the engines' read-only YADE attributes, and add the stages'
        measured times (ns) and runs to their ``execTime`` and ``execCount`` (``timing``: they were timed)."""
        if plan.counted:
            runs = int(self.scene.contacts.ctr[C_COLLIDER_RUNS])
            for e in plan.counted:
                object.__setattr__(e, "numAction", runs)
                object.__setattr__(e, "numReinit", runs)
        if timing:
            for k, e in enumerate(plan.compiled):
                if times[k, 1]:
                    e.execTime += int(times[k, 0])
                    e.execCount += int(times[k, 1])

    def slow_step(self, plan: Plan) -> None:
        """One step, segment by segment, with the Python engines that are due."""
        self.step_begin()
        try:
            for k in range(len(plan.items)):
                self.sub_step = plan.first_engine[k]
                self.run_item(plan, k)
        finally:
            self.sub_step = -1
        self.end_step(plan)

    def run_item(self, plan: Plan, k: int) -> None:
        """Item ``k`` of a step: a compiled segment, or a Python engine if it is due."""
        scene = self.scene
        kind, item = plan.items[k]
        if kind == "segment":
            self.run_compiled(plan, 0, item, np.inf, _NONE, _NONE)
            if scene.contacts.ctr[C_STATUS]:
                self.raise_status()
            for e in plan.hooked:   # the Python engines after this segment see what these hooks add
                if e.hook_due():
                    e.run_hook(self.omega)
            return
        if not item.dead and item.due(scene):
            t0 = time.perf_counter_ns()
            with interrupts.user_code():
                item.run_python(self.omega)
            if self.omega.timingEnabled:
                item.execTime += time.perf_counter_ns() - t0
                item.execCount += 1

    def step_begin(self) -> None:
        """The beginning of a step run item by item: a periodic cell deforms (:func:`granum.kernels.cell.step_begin`,
        which does nothing else)."""
        if self.scene.periodic:
            call(step_begin, self.scene.arrays())

    def end_step(self, plan: Plan) -> None:
        """The end of a step run item by item: the clock and the cell advance (:func:`granum.kernels.cell.
        advance_clock`, on its four arrays: the scene's record is not needed), then the hooks stages asked for."""
        scene = self.scene
        call(advance_clock, scene.scal, scene.iscal, scene.cell_velgrad, scene.cell_prev_velgrad)
        self.run_hooks(plan)

    def substep(self) -> None:
        """One sub-step of YADE's sub-stepping (``O.subStepping``): the step's beginning, then one engine at
        a time, then its end. The engines of the step are fixed at its beginning (an engine list assigned
        meanwhile takes over at the next step, as in whole steps)."""
        if self.sub_step < 0:
            self.sub_plan = Plan(self.scene.engines, one_stage_per_segment=True)
            self.scene.note_contact_functors()
            self.step_begin()
            self.sub_step = 0
        elif self.sub_step < len(self.sub_plan.items):
            self.run_item(self.sub_plan, self.sub_step)
            self.sub_step += 1
        else:
            plan, self.sub_plan, self.sub_step = self.sub_plan, None, -1
            self.end_step(plan)

    def finish_step(self) -> None:
        """Run what is left of a step begun sub-step by sub-step."""
        while self.sub_step >= 0:
            self.substep()

    def run_hooks(self, plan: Plan) -> None:
        """Run the Python hook a compiled engine asked for during the last step, then those of the engines
        whose stage asked too (:meth:`~granum.engines.base.Engine.hook_due`: one slot names one engine)."""
        k = int(self.scene.iscal[SI_HOOK])
        if k:
            self.scene.iscal[SI_HOOK] = 0
            plan.compiled[k - 1].run_hook(self.omega)
        for e in plan.hooked:
            if e.hook_due():
                e.run_hook(self.omega)

    def raise_status(self):
        """Raise the SimulationError of the failure status a kernel left in the contact counters (and clear it)."""
        ctr = self.scene.contacts.ctr
        status, a, b = int(ctr[C_STATUS]), int(ctr[C_ERR_A]), int(ctr[C_ERR_B])
        ctr[C_STATUS] = 0
        raise SimulationError(status_message(self.scene, status, a, b))
