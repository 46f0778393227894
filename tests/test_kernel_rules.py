"""Rules the compiled kernels must follow for Numba to compile them correctly and cheaply.

Numba loses writes made through the fields of a record or named tuple directly in the body of a
``prange`` loop (numba#7135: the parallel loop works on copies of the tuple's arrays). Every parallel
loop over the scene (functions taking the records ``S`` or ``C``) therefore hands its blocks out
through a queue (:mod:`granum.kernels.schedule`) and does the work of a block in exactly one call,
to a function: writes inside a called function are kept. Kernels also copy arrays with loops, never by slice
assignment, whose broadcast check compiles Numba's string formatting into every first run.
"""

from __future__ import annotations

import ast
import pathlib

import granum

PACKAGE = pathlib.Path(granum.__file__).parent


def _prange_loops():
    for path in sorted(PACKAGE.rglob("*.py")):
        tree = ast.parse(path.read_text(), str(path))
        for fn in ast.walk(tree):
            if not isinstance(fn, ast.FunctionDef):
                continue
            params = {a.arg for a in fn.args.args}
            for node in ast.walk(fn):
                if (isinstance(node, ast.For) and isinstance(node.iter, ast.Call)
                        and getattr(node.iter.func, "id", None) == "prange"):
                    yield path.relative_to(PACKAGE), fn.name, params, node


def _calls(node, name):
    return isinstance(node, ast.Call) and getattr(node.func, "id", None) == name


def _is_block_loop(loop):
    """``for w in prange(queue_workers(q)): b = next_block(q, w, -1)``, then
    ``while b >= 0: <one call>; b = next_block(q, w, b)``"""
    def claim(stmt, after):
        return (isinstance(stmt, ast.Assign) and _calls(stmt.value, "next_block")
                and ast.unparse(stmt) == f"b = next_block(queue, {loop.target.id}, {after})")

    body = loop.body
    return (_calls(loop.iter.args[0], "queue_workers") and len(body) == 2 and claim(body[0], "-1")
            and isinstance(body[1], ast.While) and ast.unparse(body[1].test) == "b >= 0" and len(body[1].body) == 2
            and isinstance(body[1].body[0], ast.Expr) and isinstance(body[1].body[0].value, ast.Call)
            and claim(body[1].body[1], "b"))


def test_parallel_loops_over_records_take_blocks_from_a_queue_with_one_call_each():
    loops = list(_prange_loops())
    over_records = [(p, name, loop) for p, name, params, loop in loops if params & {"S", "C"}]
    assert len(over_records) >= 8, "the kernels' parallel loops were not found"
    bad = [f"{p}:{loop.lineno} ({name})" for p, name, loop in over_records if not _is_block_loop(loop)]
    assert not bad, f"prange loops must take blocks from a queue and run each in one call (numba#7135): {bad}"


def _compiled_functions(tree):
    """The functions of a module that Numba compiles: those decorated ``@jit``, those handed to ``kernel(...)``
    (the parallel loops' bodies) and the implementations returned inside ``@overload`` functions."""
    handed = {call.args[0].id for call in ast.walk(tree)
              if _calls(call, "kernel") and call.args and isinstance(call.args[0], ast.Name)}
    for fn in ast.walk(tree):
        if not isinstance(fn, ast.FunctionDef):
            continue
        decorators = {ast.unparse(d).split("(")[0] for d in fn.decorator_list}
        if "jit" in decorators or fn.name in handed:
            yield fn
        elif "overload" in decorators:
            yield from (f for f in ast.walk(fn) if isinstance(f, ast.FunctionDef) and f is not fn)


def _is_number(node):
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        node = node.operand
    return isinstance(node, ast.Constant) and isinstance(node.value, (int, float))


def _stores_into_a_slice(node):
    """Whether the assignment ``node`` stores into a target whose index has a slice or ``...`` (tuple targets
    unpacked)."""
    targets = node.targets if isinstance(node, ast.Assign) else [node.target]
    while any(isinstance(t, ast.Tuple) for t in targets):
        targets = [e for t in targets for e in (t.elts if isinstance(t, ast.Tuple) else [t])]
    for target in targets:
        if isinstance(target, ast.Subscript):
            parts = target.slice.elts if isinstance(target.slice, ast.Tuple) else [target.slice]
            if any(isinstance(e, ast.Slice) or isinstance(e, ast.Constant) and e.value is Ellipsis for e in parts):
                return True
    return False


def test_compiled_functions_copy_arrays_into_slices_with_loops():
    """Assigning an array to a slice (``a[:n] = b``, ``a[i, :] = row``) makes Numba compile a broadcast check whose
    error message formats the shapes: string conversions and concatenation, 36 more functions compiled. The
    work area's growth (``scratch.area``) had one: the bouncing sphere's first run compiled 301 functions instead
    of 265 on one process (2.7-3.8 s more), 3.8-4.5 s more on two. Kernels copy with :mod:`granum.kernels.copy`;
    filling a slice with a number (``a[:n] = 0.0``, not ``+=``, which stores an array back) compiles no check.
    A row assigned by an integer index (``a[i] = row`` on a 2-D array) takes the same path, but only its types
    tell it from a number stored: this scan cannot see it."""
    found, bad = 0, []
    for path in sorted(PACKAGE.rglob("*.py")):
        for fn in _compiled_functions(ast.parse(path.read_text(), str(path))):
            found += 1
            for node in ast.walk(fn):
                if not isinstance(node, (ast.Assign, ast.AugAssign)):
                    continue
                if not (isinstance(node, ast.Assign) and _is_number(node.value)) and _stores_into_a_slice(node):
                    bad.append(f"{path.relative_to(PACKAGE)}:{node.lineno} ({fn.name}): {ast.unparse(node)}")
    assert found >= 300, "the compiled functions were not found"
    assert not bad, f"copy arrays into slices with granum.kernels.copy's loops: {bad}"


LATTICE = """
import numpy
n = 17  # 4913 spheres: above PARALLEL_THRESHOLD, so the parallel kernels run
r, s = 0.01, 0.02 * (1 - 1e-3)
O.bodies.append([sphere((r + i * s, r + j * s, r + k * s), r) for k in range(n) for j in range(n) for i in range(n)])
c = r + 0.5 * (n - 1) * s
O.bodies.append(geom.facetBox((c, c, c), (c - r * 1e-3,) * 3))
O.bodies[5].state.vel = (0.3, -0.2, 0.1)   # something moves and slides
O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Facet_Aabb()], verletDist=0.0002),
             InteractionLoop([Ig2_Sphere_Sphere_ScGeom(), Ig2_Facet_Sphere_ScGeom()],
                             [Ip2_FrictMat_FrictMat_FrictPhys()], [Law2_ScGeom_FrictPhys_CundallStrack()]),
             NewtonIntegrator(damping=0.2, gravity=(0, 0, -9.81))]
O.dt = 0.5 * PWaveTimeStep()
O.trackEnergy = True
O.run(30, True)
# a quarter of the spheres erased (more than a quarter of the contacts end at once) and half of them put back:
# their contacts, made in the next step, come at the pool's end, where that step's compaction finds them and sorts
# them among the others (the pool is over SORT_ROWS_BYTES)
erased = list(range(0, n ** 3, 4))
back = [tuple(O.bodies[i].state.pos) for i in erased[::2]]
for i in erased:
    O.bodies.erase(i)
new_ids = O.bodies.append([sphere(p, r) for p in back])
from granum.core.contacts import C_CONTACTS, C_DEAD, I_ID1, I_ID2
from granum.kernels.interaction import SORT_ROWS_BYTES
dead = int(O._scene.contacts.ctr[C_DEAD])
O.step()
C = O._scene.contacts
rows = C.con_i[:int(C.ctr[C_CONTACTS])]
made = numpy.nonzero(numpy.isin(rows[:, I_ID1], new_ids) | numpy.isin(rows[:, I_ID2], new_ids))[0]
sorted_in = (dead > 0 and int(C.ctr[C_DEAD]) == 0 and len(made) > 0 and made[0] < len(rows) - len(made)
             and rows.shape[0] * C.con_f.shape[1] * C.con_f.itemsize >= SORT_ROWS_BYTES)
O.run(29, True)
numpy.save('state.npy', numpy.array([list(b.state.pos) + list(b.state.vel) + list(b.state.angVel) for b in O.bodies]
                                    + [[O.energy[k] for k in sorted(O.energy.keys())] + [0.0] * 4]))
numpy.save('sorted_in.npy', numpy.array([sorted_in]))
"""


def test_parallel_kernels_equal_serial_ones_bitwise_at_any_thread_count(tmp_path):
    """The dense lattice above the parallel threshold: -j1 (the step loop of the stages' serial variants,
    granum._jit.serial_variant), -j2 (the parallel kernels) and the kernels compiled without parallel loops
    (GRANUM_NOPAR=1) give the same bits (no lost writes, no races, no thread-dependent sums). Midway, spheres are
    erased and some put back, so that one step compacts the contact pool and its sort moves the new contacts from
    the pool's end among the others: on one thread the update adds the forces itself (update_scatter), on two the
    force gather adds them, both in the order the contacts were updated in (before the compaction)."""
    import os
    import subprocess
    import sys

    import numpy as np

    (tmp_path / "lattice.py").write_text(LATTICE)
    states = {}
    for name, args, env in (("j1", ["-j", "1"], {}), ("j2", ["-j", "2"], {}), ("serial", ["-j", "1"],
                                                                                  {"GRANUM_NOPAR": "1"})):
        run = tmp_path / name
        run.mkdir()
        subprocess.run([sys.executable, "-m", "granum", *args, str(tmp_path / "lattice.py")], cwd=run, check=True,
                       timeout=1800, env={**os.environ, **env})
        states[name] = np.load(run / "state.npy")
        assert np.load(run / "sorted_in.npy")[0], "the step after the erasures sorted no new contact into the pool"
    assert np.abs(states["j1"][:-1, 3:6]).max() > 0, "nothing moved"
    assert (states["j1"] == states["j2"]).all()
    assert (states["j1"] == states["serial"]).all()


def _compiled_stages():
    """Every engine stage function granum's engines name (``stage = "module:function"``)."""
    import importlib
    import pkgutil

    import granum.engines

    refs = set()
    for info in pkgutil.iter_modules(granum.engines.__path__):
        module = importlib.import_module(f"granum.engines.{info.name}")
        refs |= {v.stage for v in vars(module).values() if isinstance(getattr(v, "stage", None), str)}
    return {ref: getattr(importlib.import_module(ref.split(":")[0]), ref.split(":")[1]) for ref in refs}


def _parallel_reached(fn, seen) -> set[str]:
    """The items (``kernel``'s ``over``) of the parallel kernels that granum function ``fn`` (a dispatcher or an
    overloaded function) reaches through its globals, those of the functions nested in it and those of granum's
    overloads."""
    from granum import _jit

    if id(fn) in seen:
        return set()
    seen.add(id(fn))
    if fn in _jit._KERNELS:  # a kernel's parallel dispatcher (compiled without prange under GRANUM_NOPAR=1)
        return {_jit._KERNELS[fn][1]}
    py = fn.py_func if hasattr(fn, "py_func") else _jit._OVERLOADS[fn][0]
    return set().union(*(_parallel_reached(value, seen) for _, value in _jit.granum_callees(py)))


def test_the_serial_variants_of_the_stages_reach_no_parallel_code_over_their_items():
    """A step loop of serial variants (small scenes, one thread) compiles no parallel kernel: not through a
    stage's callees, nor through an overload (the collider's broad phase is chosen by one). The variants serial
    over bodies (scenes under the kernels' threshold) compile no parallel kernel over bodies, and still the
    others: the interaction loop's parallel contact update and detection."""
    from granum._jit import ITEMS, serial_variant

    stages = _compiled_stages()
    assert len(stages) >= 15, "the engines' stages were not found"
    parallel = {ref: _parallel_reached(fn, set()) for ref, fn in stages.items()}
    assert parallel["granum.kernels.interaction:interaction_stage"] == {"bodies", "pairs", "contacts"}
    # the collider's pairs: the budgets a run carries over (granum.kernels.motion.carry_budgets)
    assert parallel["granum.kernels.collider:collider_stage"] == {"bodies", "pairs", "contacts"}
    assert parallel["granum.kernels.newton:newton_stage"] == {"bodies"}
    still = [ref for ref, fn in stages.items() if _parallel_reached(serial_variant(fn), set())]
    assert not still, f"serial variants that reach parallel code: {still}"
    interaction = stages["granum.kernels.interaction:interaction_stage"]
    assert serial_variant(interaction) is serial_variant(interaction, ITEMS)
    bodies = {ref: _parallel_reached(serial_variant(fn, {"bodies"}), set()) for ref, fn in stages.items()}
    assert bodies == {ref: items - {"bodies"} for ref, items in parallel.items()}
    assert bodies["granum.kernels.interaction:interaction_stage"] == {"pairs", "contacts"}
    assert serial_variant(stages["granum.kernels.newton:newton_stage"], {"contacts"}) is (
        stages["granum.kernels.newton:newton_stage"]), "a stage without parallel code over the items is its own"
    assert serial_variant(stages["granum.kernels.fields:axial_gravity_stage"]) is (
        stages["granum.kernels.fields:axial_gravity_stage"]), "a stage without parallel code is its own variant"


def test_small_scenes_and_single_threads_run_the_serial_step_loop(yade):
    """The runner gives the serial step loop to a scene under SERIAL_LOOP_BODIES bodies on two threads and to any
    scene on one thread, the loop serial over bodies to a larger scene under the kernels' threshold, and the
    parallel loop to a scene beyond it or one with a factory on two threads; every run reaches the same state
    whichever loop it takes."""
    import types

    import numba
    import numpy as np
    from conftest import frict_engines

    from granum._jit import PARALLEL_THRESHOLD
    from granum.engines.runner import ALL_SERIAL, BODIES_SERIAL, SERIAL_LOOP_BODIES, Plan, Runner

    y = yade
    if numba.config.NUMBA_NUM_THREADS < 2:
        import pytest

        pytest.skip("Numba has one thread here")

    def run(n, threads):
        y.O.reset()
        y.O.bodies.append([y.sphere((0.0, 0.0, 0.99 * k), 0.5) for k in range(n)])
        y.O.bodies[0].state.blockedDOFs = "xyzXYZ"
        y.O.engines = frict_engines(y, gravity=(0, 0, -9.81), damping=0.2)
        y.O.dt = 1e-5
        saved = numba.get_num_threads()
        numba.set_num_threads(threads)
        try:
            y.O.run(20, True)
        finally:
            numba.set_num_threads(saved)
        loops = {serial for _, serial in y.O._runner.plan()._loops}
        return loops, y.O._scene.bodies.pos[:n].copy()

    small = SERIAL_LOOP_BODIES // 2
    assert run(small, 2)[0] == {ALL_SERIAL}
    assert run(SERIAL_LOOP_BODIES, 2)[0] == {BODIES_SERIAL}
    serial_loops, serial_pos = run(SERIAL_LOOP_BODIES, 1)
    assert serial_loops == {ALL_SERIAL}
    assert (serial_pos == run(SERIAL_LOOP_BODIES, 2)[1]).all()
    assert (serial_pos[:, 2] != 0.99 * np.arange(SERIAL_LOOP_BODIES)).any(), "nothing moved"
    run(small, 2)
    saved = numba.get_num_threads()
    numba.set_num_threads(2)
    try:
        runner, plan = y.O._runner, y.O._runner.plan()
        assert runner.serial(plan) == ALL_SERIAL
        assert runner.serial(Plan([y.CircularFactory()])) == frozenset(), "a factory adds bodies"
        scene = types.SimpleNamespace(contacts=runner.scene.contacts)
        for bodies, loop in ((PARALLEL_THRESHOLD - 1, BODIES_SERIAL), (PARALLEL_THRESHOLD, frozenset())):
            scene.body_count = bodies
            assert Runner.serial(types.SimpleNamespace(scene=scene), plan) == loop, bodies
    finally:
        numba.set_num_threads(saved)
