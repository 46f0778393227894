"""Parametric studies: YADE's table format, readParamsFromTable's tags, and ``granum batch`` on Dask."""

from __future__ import annotations

import json
import pathlib
import shutil
import subprocess
import sys

import pytest
from conftest import REFERENCE

from granum.batch.table import TableError, lines_select, table_read

BATCH_REF = REFERENCE / "batch"
TUTORIALS = pathlib.Path(__file__).resolve().parents[1] / "examples" / "tutorial"


def granum_batch(cwd, *args, timeout=900) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "granum", "batch", "--dashboard", "", *map(str, args)], cwd=cwd,
                          capture_output=True, text=True, timeout=timeout)


def test_table_format_of_the_users_manual(tmp_path):
    """Headings, '=' repeats, comments, blank lines, quoted strings, math expressions, ! columns."""
    t = tmp_path / "t.table"
    t.write_text("description density v  !OMP_NUM_THREADS # headings\n"
                 "reference   2400    10 1\n"
                 "hi_v        =       20 =   # repeat\n"
                 "\n# a comment line\n"
                 "s           'a # b' radians(90) 2\n")
    lines = table_read(str(t))
    assert [ln.number for ln in lines] == [2, 3, 6]
    assert [ln.params for ln in lines] == [{"density": 2400, "v": 10}, {"density": 2400, "v": 20},
                                           {"density": "a # b", "v": pytest.approx(1.5707963267948966)}]
    assert [ln.description for ln in lines] == ["reference", "hi_v", "s"]
    assert [ln.threads for ln in lines] == [1, 1, 2]
    assert lines[2].env == {}  # the thread count, not a variable: the job's OMP_NUM_THREADS is its threads
    assert [ln.number for ln in lines_select(lines, "3,6")] == [3, 6]


@pytest.mark.parametrize(("text", "message"), [
    ("a b\n1\n", "1 values for the 2 columns"),
    ("a b\n= 1\n", "no previous line"),
    ("a a\n1 2\n", "appears twice"),
    ("a\nword\n", "cannot evaluate 'word'"),
    ("a\n__import__('os')\n", "cannot evaluate"),
    ("a\n'open\n", "unterminated quote"),
    ("# only a comment\n", "no heading line"),
])
def test_bad_tables_name_the_file_and_line(tmp_path, text, message):
    t = tmp_path / "bad.table"
    t.write_text(text)
    with pytest.raises(TableError, match=message) as e:
        table_read(str(t))
    assert str(t) in str(e.value)


@pytest.mark.parametrize("table", ["params.table", "params_nodesc.table"])
def test_jobs_see_what_yade_batch_gives_them(tmp_path, table):
    """Parameters, descriptions, O.tags and log file names as real yade-batch produced them."""
    ref = json.loads((BATCH_REF / "yade_batch.json").read_text())[table]
    for f in (table, "sim.py"):
        shutil.copy(BATCH_REF / f, tmp_path)
    r = granum_batch(tmp_path, "-j", 2, table, "sim.py")
    assert r.returncode == ref["returncode"] == 0, r.stdout + r.stderr
    for line, expected in ref["jobs"].items():
        got = json.loads((tmp_path / f"job-{line}.json").read_text())
        assert got["values"] == pytest.approx(expected["values"])
        assert got["tags"] == expected["tags"]
        assert got["batch"] is True
    assert sorted(p.name for p in tmp_path.glob("*.log")) == ref["logs"]


def test_a_failing_job_is_reported_and_the_others_finish_then_resume_reruns_it(tmp_path):
    """Exit status 1 with the failed job named; --resume skips the jobs that succeeded."""
    (tmp_path / "t.table").write_text("description n\nok1 1\nbad 2\nok2 3\n")
    (tmp_path / "sim.py").write_text(
        "import os\nreadParamsFromTable(n=0)\nfrom yade.params.table import n\n"
        "open('out-%d.txt' % n, 'a').write('ran\\n')\n"
        "if n == 2 and not os.path.exists('fixed'):\n    raise RuntimeError('job %d fails' % n)\n")
    r = granum_batch(tmp_path, "-j", 2, "t.table", "sim.py")
    assert r.returncode == 1
    assert "#1 (bad/1) FAILED  (exit status 1)" in r.stdout
    assert "2 done, 1 failed" in r.stdout
    assert all((tmp_path / f"out-{n}.txt").exists() for n in (1, 2, 3))
    assert "RuntimeError: job 2 fails" in (tmp_path / "sim.py.bad.log").read_text()
    state = json.loads((tmp_path / "t.table.batch.json").read_text())
    assert sorted((j["description"], j["status"]) for j in state["jobs"]) == [("bad", 1), ("ok1", 0), ("ok2", 0)]
    (tmp_path / "fixed").touch()
    r = granum_batch(tmp_path, "--resume", "t.table", "sim.py")
    assert r.returncode == 0, r.stdout + r.stderr
    assert "#0 (ok1/1) skipped" in r.stdout and "#2 (ok2/1) skipped" in r.stdout
    assert [(tmp_path / f"out-{n}.txt").read_text().count("ran") for n in (1, 2, 3)] == [1, 2, 1]


@pytest.mark.parametrize(("args", "message"), [
    (["missing.table", "sim.py"], "no such table"),
    (["t.table", "missing.py"], "no such script"),
    (["-l", "7", "t.table", "sim.py"], "line 7 is not a parameter line"),
    (["--log", "same.log", "t.table", "sim.py"], "must contain"),
    (["--job-threads", "0", "t.table", "sim.py"], "at least 1"),
])
def test_bad_batch_arguments_are_refused_before_any_job_runs(tmp_path, args, message):
    (tmp_path / "t.table").write_text("a\n1\n2\n")
    (tmp_path / "sim.py").write_text("raise SystemExit('must not run')\n")
    r = granum_batch(tmp_path, *args)
    assert r.returncode == 2
    assert message in r.stderr
    assert not list(tmp_path.glob("*.log"))


@pytest.mark.slow
def test_oedometric_tutorial_table_runs_as_a_batch_on_a_local_cluster(tmp_path):
    """The documentation's 03-oedometric-test.table: three jobs, each leaving its data file."""
    for f in ("03-oedometric-test.table", "03-oedometric-test.py"):
        shutil.copy(TUTORIALS / f, tmp_path)
    r = granum_batch(tmp_path, "-j", 2, "03-oedometric-test.table", "03-oedometric-test.py", timeout=1800)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "3 done, 0 failed" in r.stdout
    for fuzz in (".1", ".2", ".3"):
        desc = f"rMean=.05,rRelFuzz={fuzz},maxLoad=1e6"
        data = list(tmp_path.glob(f"{desc}.*.txt"))
        assert len(data) == 1, f"job {desc}: no data file"
        rows = [ln.split() for ln in data[0].read_text().splitlines() if not ln.startswith("#")]
        assert len(rows) > 20
        assert (tmp_path / f"03-oedometric-test.py.{desc}.log").exists()
