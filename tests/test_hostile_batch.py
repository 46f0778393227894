"""``granum batch`` against hostile input: tables that would run code or break a job, and ports
that would let other machines in. Each case ends in a clear error naming what is wrong, or in the
documented behaviour."""

from __future__ import annotations

import ipaddress
import json
import subprocess
import sys
import time

import psutil
import pytest

from granum.batch.runner import log_name
from granum.batch.table import REFUSED_ENVIRONMENT, TableError, table_read

#: A job that says it started, then waits (at most a minute) for the test to let it finish.
WAITING_SCRIPT = """import os, time
readParamsFromTable(n=0)
open('started', 'w').close()
deadline = time.time() + 60
while not os.path.exists('release') and time.time() < deadline:
    time.sleep(0.05)
"""


def table_error(tmp_path, content: str | bytes) -> str:
    """The message of the TableError that reading ``content`` as a table raises."""
    t = tmp_path / "hostile.table"
    if isinstance(content, bytes):
        t.write_bytes(content)
    else:
        t.write_text(content)
    with pytest.raises(TableError) as e:
        table_read(str(t))
    return str(e.value)


@pytest.mark.parametrize("variable", ["PYTHONPATH", "PYTHONSTARTUP", "PYTHONHOME", "LD_PRELOAD", "LD_LIBRARY_PATH"])
def test_a_column_setting_a_variable_that_loads_code_is_refused(tmp_path, variable):
    message = table_error(tmp_path, f"description !{variable}\nx /tmp/evil\n")
    assert f"hostile.table:1: column '!{variable}' is refused" in message
    assert "load code" in message
    assert variable in REFUSED_ENVIRONMENT


def test_a_refused_column_is_refused_wherever_it_stands_and_whatever_its_values(tmp_path):
    message = table_error(tmp_path, "# comment\n\nn !OMP_NUM_THREADS !LD_PRELOAD\n1 1 ''\n")
    assert "hostile.table:3: column '!LD_PRELOAD' is refused" in message


@pytest.mark.parametrize("variable", ["YADE_BATCH", "PARAM_TABLE"])
def test_a_column_cannot_redirect_the_job_to_another_table_line(tmp_path, variable):
    message = table_error(tmp_path, f"n !{variable}\n1 other.table:2\n")
    assert f"hostile.table:1: column '!{variable}' is refused: granum batch sets {variable}" in message


def test_a_bang_column_without_a_name_is_refused(tmp_path):
    assert "hostile.table:1: column '!' has no environment variable name" in table_error(tmp_path, "n !\n1 2\n")


@pytest.mark.parametrize("column", ["!A=B", "!1X", "!A-B", "!A.B"])
def test_a_bang_column_that_is_no_variable_name_is_refused(tmp_path, column):
    message = table_error(tmp_path, f"n {column}\n1 2\n")
    assert f"hostile.table:1: column '{column}'" in message
    assert "is not an environment variable name" in message


def test_a_column_named_twice_is_refused_even_for_variables(tmp_path):
    assert "hostile.table:1: a column name appears twice" in table_error(tmp_path, "n !FOO !FOO\n1 a b\n")


def test_a_line_with_too_many_values_is_refused(tmp_path):
    assert "hostile.table:3: 3 values for the 2 columns" in table_error(tmp_path, "a b\n1 2\n1 2 3\n")


def test_an_unterminated_quote_between_cells_is_refused(tmp_path):
    assert "hostile.table:2: unterminated quote" in table_error(tmp_path, "a b\n'x 1\n")


def test_a_nul_byte_is_refused_with_its_line(tmp_path):
    assert "hostile.table:3: a NUL byte" in table_error(tmp_path, "description !FOO\nx a\ny b\0c\n")


def test_a_table_that_is_not_utf8_is_refused_with_its_line(tmp_path):
    assert "hostile.table:2: not UTF-8 text (byte 0xff)" in table_error(tmp_path, b"a\n\xff\n")


@pytest.mark.parametrize("threads", ["0", "-1", "two", "1.5"])
def test_a_thread_count_that_is_no_positive_integer_is_refused(tmp_path, threads):
    message = table_error(tmp_path, f"description !THREADS\nx {threads}\n")
    assert f"hostile.table:2 (!THREADS): {threads!r} is not a number of threads" in message


@pytest.mark.parametrize("value", ["9**9**9", "(10**4000)**10000", "'a'*10**10", "10**9*[0]"])
def test_a_value_that_would_fill_the_memory_is_refused(tmp_path, value):
    assert "hostile.table:2 (a): cannot evaluate" in table_error(tmp_path, f"a\n{value}\n")


def test_a_description_cannot_put_the_log_outside_the_working_directory(tmp_path):
    t = tmp_path / "t.table"
    t.write_text("description\n../../etc/x\n")
    (line,) = table_read(str(t))
    assert log_name("$.@.log", "/s/sim.py", line) == "sim.py..._.._etc_x.log"


def granum_batch(cwd, *args) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "granum", "batch", *map(str, args)], cwd=cwd,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def listening_sockets(pid: int) -> list[tuple[int, str, int]]:
    """``(pid, ip, port)`` of every LISTEN socket of process ``pid`` and of its descendants."""
    root = psutil.Process(pid)
    found = []
    for proc in [root, *root.children(recursive=True)]:
        try:
            found += [(proc.pid, c.laddr.ip, c.laddr.port) for c in proc.net_connections(kind="inet")
                      if c.status == psutil.CONN_LISTEN]
        except psutil.NoSuchProcess:
            continue
    return found


@pytest.mark.skipif(sys.platform != "linux", reason="other processes' sockets are read from /proc")
@pytest.mark.parametrize("options", [[], ["--dashboard", ""]], ids=["dashboard", "no-dashboard"])
def test_every_port_of_a_running_batch_listens_on_loopback_only(tmp_path, options):
    """While a job runs, the batch process and its jobs listen on 127.0.0.0/8 or ::1 only, and
    the printed dashboard link is a loopback one."""
    (tmp_path / "t.table").write_text("description n\nx 1\n")
    (tmp_path / "sim.py").write_text(WAITING_SCRIPT)
    batch = granum_batch(tmp_path, *options, "-j", 1, "t.table", "sim.py")
    try:
        deadline = time.time() + 120
        while not (tmp_path / "started").exists():
            assert batch.poll() is None, batch.communicate()
            assert time.time() < deadline, "the job did not start"
            time.sleep(0.05)
        sockets = listening_sockets(batch.pid)
    finally:
        (tmp_path / "release").touch()
        stdout, stderr = batch.communicate(timeout=120)
    assert batch.returncode == 0, stdout + stderr
    assert [s for s in sockets if not ipaddress.ip_address(s[1]).is_loopback] == []
    if not options:
        link = next(line for line in stdout.splitlines() if line.startswith("Dask dashboard: "))
        assert link.startswith("Dask dashboard: http://127.0.0.1:")
        port = int(link.rsplit(":", 1)[1].split("/")[0])
        assert (batch.pid, "127.0.0.1", port) in sockets


@pytest.mark.parametrize(("options", "message"), [
    (["--listen", "somehost"], "--listen 'somehost' is not an IP address"),
    (["--dashboard", "0.0.0.0:8787"], "--dashboard '0.0.0.0:8787' is not a port number"),
])
def test_the_interface_is_widened_only_by_an_explicit_listen_address(tmp_path, options, message):
    (tmp_path / "t.table").write_text("a\n1\n")
    (tmp_path / "sim.py").write_text("raise SystemExit('must not run')\n")
    batch = granum_batch(tmp_path, *options, "t.table", "sim.py")
    stdout, stderr = batch.communicate(timeout=120)
    assert batch.returncode == 2
    assert message in stderr
    assert not list(tmp_path.glob("*.log"))


def test_a_refused_table_runs_no_job(tmp_path):
    (tmp_path / "t.table").write_text("description !PYTHONSTARTUP\nx evil.py\n")
    (tmp_path / "sim.py").write_text("open('ran', 'w').close()\n")
    batch = granum_batch(tmp_path, "t.table", "sim.py")
    stdout, stderr = batch.communicate(timeout=120)
    assert batch.returncode == 2
    assert "t.table:1: column '!PYTHONSTARTUP' is refused" in stderr
    assert not (tmp_path / "ran").exists()
    assert not list(tmp_path.glob("*.log"))


def test_other_variables_reach_the_job_and_its_threads_set_omp_num_threads(tmp_path):
    """As in YADE: ``!NAME`` columns become variables of the job; ``!THREADS`` is no variable, it
    sets the job's threads and OMP_NUM_THREADS (granum caps them at the cores of the batch)."""
    (tmp_path / "t.table").write_text("description !FOO !THREADS\nx 'a b' 3\n")
    (tmp_path / "sim.py").write_text(
        "import json, os\nreadParamsFromTable(n=0)\n"
        "json.dump({k: os.environ.get(k) for k in ('FOO', 'THREADS', 'OMP_NUM_THREADS')}, open('env.json', 'w'))\n")
    batch = granum_batch(tmp_path, "--dashboard", "", "-j", 2, "t.table", "sim.py")
    stdout, stderr = batch.communicate(timeout=300)
    assert batch.returncode == 0, stdout + stderr
    assert "line 2 asks for 3 threads; using the 2 available" in stdout
    assert json.loads((tmp_path / "env.json").read_text()) == {"FOO": "a b", "THREADS": None, "OMP_NUM_THREADS": "2"}
