"""The ``granum`` launcher: scripts run headless with YADE's namespace and imports."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import pytest

import granum


def _granum(tmp_path, source: str, *args, module=False):
    script = tmp_path / "script.py"
    script.write_text(textwrap.dedent(source))
    cmd = [sys.executable, "-m", "granum"] if module else [os.path.join(os.path.dirname(sys.executable), "granum")]
    return subprocess.run(cmd + list(args) + [str(script), "a1", "--b2"], capture_output=True, text=True,
                          cwd=tmp_path, timeout=600)


SCRIPT = """
    import sys
    import yade
    from yade import pack, plot, utils, geom, ymport, export, qt, timing
    from yade.params import table
    O.bodies.append([sphere((0, 0, 0), .5, fixed=True), sphere((0, 0, 2), .5)])
    O.engines = [ForceResetter(), InsertionSortCollider([Bo1_Sphere_Aabb()]),
                 InteractionLoop([Ig2_Sphere_Sphere_ScGeom()], [Ip2_FrictMat_FrictMat_FrictPhys()],
                                 [Law2_ScGeom_FrictPhys_CundallStrack()]),
                 NewtonIntegrator(gravity=(0, 0, -9.81), damping=.1),
                 PyRunner(command='hits.append(O.iter)', iterPeriod=10)]
    hits = []
    O.dt = .5e-4 * PWaveTimeStep()
    O.run(30, True)
    qt.View()
    print("RESULT", O.iter, hits, sys.argv[1:], pi == math.pi if 'math' in dir() else pi, yade.O is O,
          type(Vector3(1, 2, 3)).__name__, utils.sphere is sphere)
"""


@pytest.mark.parametrize("module", [False, True])
def test_script_runs_with_yade_namespace_and_imports(tmp_path, module):
    """`granum script.py args` (and `python -m granum`) runs a YADE script unmodified and exits."""
    r = _granum(tmp_path, SCRIPT, "-j", "2", module=module)
    assert r.returncode == 0, r.stderr
    line = [x for x in r.stdout.splitlines() if x.startswith("RESULT")][0]
    assert line == "RESULT 30 [10, 20] ['a1', '--b2'] True True Vector3 True"  # math is a YADE global


def test_script_error_exits_nonzero_with_traceback(tmp_path):
    """An exception in the script is reported with its traceback and a non-zero exit status."""
    r = _granum(tmp_path, "O.bodies[3]\n")
    assert r.returncode != 0
    assert "IndexError" in r.stderr and "script.py" in r.stderr


def test_version_and_missing_script(tmp_path):
    """--version prints the version; a missing script is a clear error."""
    exe = os.path.join(os.path.dirname(sys.executable), "granum")
    r = subprocess.run([exe, "--version"], capture_output=True, text=True, timeout=120)
    assert r.stdout.strip() == f"granum {granum.__version__}"
    r = subprocess.run([exe, str(tmp_path / "nope.py")], capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and "no such script" in r.stderr


CYCLES_SCRIPT = """
    import gc
    import granum.kernels.newton

    class Log:
        def __init__(self):
            self.me = self   # a reference cycle: only the cyclic collector frees it

        def __del__(self):
            print("FINALISED")

    Log()
    gc.collect()
    print("FROZEN", gc.get_freeze_count() > 0, any(o is granum.kernels.newton.__dict__ for o in gc.get_objects()))
"""


def test_launcher_freezes_its_modules_but_not_the_script_objects(tmp_path):
    """The launcher moves the objects of the modules it imported out of the collector's reach (cheaper
    collections, a faster exit), while the script's own cyclic garbage is still collected and finalised."""
    r = _granum(tmp_path, CYCLES_SCRIPT)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["FINALISED", "FROZEN", "True", "False"]   # granum's module dicts are frozen


def test_yade_alias_does_not_leak_to_other_programs():
    """Outside the launcher `import yade` is not redirected to granum."""
    r = subprocess.run([sys.executable, "-c", "import granum.yade\nimport yade"], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode != 0 and "No module named 'yade'" in r.stderr


def test_library_use_without_launcher():
    """`from granum.yade import *` gives an ordinary program the script namespace."""
    code = ("from granum.yade import *\n"
            "O.bodies.append(sphere((0,0,0),1))\n"
            "O.engines=[NewtonIntegrator(gravity=(0,0,-10),damping=0)]\n"
            "O.engines[0].label='newt'\n"
            "O.dt=1e-3; O.run(10,True)\n"
            "print(round(O.bodies[0].state.vel[2], 9), sin(0.0))\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["-0.1", "0.0"]


def test_interactive_prompt_reads_commands(tmp_path):
    """`granum` without a script opens a prompt with the YADE namespace."""
    exe = os.path.join(os.path.dirname(sys.executable), "granum")
    r = subprocess.run([exe], input="print('ITER', O.iter, len(O.bodies))\n", capture_output=True, text=True,
                       timeout=300, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "ITER 0 0" in r.stdout


PROGRESS_SCRIPT = """
    import time
    O.bodies.append(sphere((0, 0, 0), 1))
    O.engines = [ForceResetter(), NewtonIntegrator(), PyRunner(command='time.sleep(0.002)', iterPeriod=1)]
    O.dt = 1e-3
    O.run(1000, True)
    print("END", O.iter)
"""


def _granum_in_terminal(tmp_path, source: str, env: dict) -> str:
    """Run a script with the launcher's stdout and stderr on a pseudo-terminal; return what it showed."""
    import pty

    script = tmp_path / "script.py"
    script.write_text(textwrap.dedent(source))
    master, slave = pty.openpty()
    proc = subprocess.Popen([sys.executable, "-m", "granum", str(script)], stdout=slave, stderr=slave,
                            stdin=subprocess.DEVNULL, cwd=tmp_path, env={**os.environ, **env})
    os.close(slave)
    chunks = []
    while True:
        try:
            data = os.read(master, 4096)
        except OSError:  # EIO: the child closed the terminal
            break
        if not data:
            break
        chunks.append(data)
    os.close(master)
    assert proc.wait(timeout=600) == 0
    return b"".join(chunks).decode(errors="replace")


@pytest.mark.parametrize("where", ["terminal", "pipe", "batch job", "turned off"])
def test_long_runs_show_a_progress_bar_only_in_a_terminal(tmp_path, where):
    """O.run(n, True) lasting over a second draws a bar on a terminal, never into pipes, logs of batch jobs
    or with GRANUM_PROGRESS=0."""
    env = {"batch job": {"YADE_BATCH": "x.table:2"}, "turned off": {"GRANUM_PROGRESS": "0"}}.get(where, {})
    env = {k: v for k, v in os.environ.items() if k not in ("YADE_BATCH", "PARAM_TABLE")} | env
    if where == "pipe":
        script = tmp_path / "script.py"
        script.write_text(textwrap.dedent(PROGRESS_SCRIPT))
        r = subprocess.run([sys.executable, "-m", "granum", str(script)], capture_output=True, text=True,
                           cwd=tmp_path, env=env, timeout=600)
        shown = r.stdout + r.stderr
    else:
        shown = _granum_in_terminal(tmp_path, PROGRESS_SCRIPT, env)
    assert "END 1000" in shown
    if where == "terminal":
        assert "] 100% 1000/1000 steps" in shown
        assert "steps/s" in shown and "\r[" in shown
    else:
        assert "steps/s" not in shown and "[###" not in shown
