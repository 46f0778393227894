"""Running the jobs of a parametric study on Dask (``granum batch``, YADE's ``yade-batch``).

Each line of the parameter table is one *job*: the script run by the granum launcher in its own
process, with ``YADE_BATCH=table:line`` in its environment (``readParamsFromTable`` reads that
line), its output in a log file. The jobs are tasks of a ``dask.distributed`` cluster:

* by default a :class:`~distributed.LocalCluster` in this process whose worker offers ``--jobs``
  cores; every job asks for the cores it runs with (``--job-threads`` or the table's ``!THREADS``
  column), so Dask starts a job only when its cores are free, as ``yade-batch`` does;
* with ``--scheduler ADDRESS`` an existing cluster. Its workers must see the script, the table
  and the working directory under the same paths (a shared file system) and have granum
  installed. Workers started with ``--resources cores=N`` get the same core accounting;
  otherwise each worker thread runs one job.

A job that fails (non-zero exit status, or a launcher that cannot start) is reported and the
others go on. The state of every finished job is kept in ``<table>.batch.json`` in the working
directory, rewritten atomically after each job, so ``--resume`` skips the jobs that already
succeeded with the same script and the same table values. The Dask dashboard shows the jobs
while they run.

Every port the local cluster opens (the dashboard, the scheduler's and the worker's HTTP
servers) listens on the loopback address 127.0.0.1 unless ``--listen`` names another: the
dashboard has no authentication and shows the jobs, their paths and logs. Widening it is a
deliberate choice (``--listen 0.0.0.0``); an SSH tunnel (``ssh -L 8787:127.0.0.1:8787 host``)
shows a remote dashboard without exposing it.
"""

from __future__ import annotations

import ipaddress
import json
import os
import socket
import subprocess
import sys
import threading
import time
from dataclasses import dataclass

from granum.batch.table import TableLine
from granum.io.atomic import write_text

#: Interface of every port of the local cluster unless ``--listen`` names another.
LOOPBACK = "127.0.0.1"
#: Port of the local cluster's dashboard unless ``--dashboard`` names another.
DASHBOARD_PORT = 8787

#: Process of each job running in this process (local cluster), terminated on Ctrl-C.
_RUNNING: dict[str, subprocess.Popen] = {}
_RUNNING_LOCK = threading.Lock()


@dataclass
class Job:
    """One job of a batch.

    Attributes:
        index: position in the batch (``#0``, ``#1``... in the reports).
        line: the table line.
        threads: compute threads of the job (``granum -j``).
        log: path of the log file.
    """

    index: int
    line: TableLine
    threads: int
    log: str

    @property
    def name(self) -> str:
        return f"#{self.index} ({self.line.description}/{self.threads})"

    def key(self, script: str) -> dict:
        """What a finished job is recognised by when resuming: script, line and its values."""
        return {"script": script, "line": self.line.number, "values": self.line.texts}


def log_name(fmt: str, script: str, line: TableLine) -> str:
    """The log file of a job: ``fmt`` with ``$`` -> script name, ``%`` -> line number, ``@`` -> description
    (path separators in the description become ``_``, so a job never writes outside the log directory)."""
    desc = line.description.replace(os.sep, "_").replace("\0", "_") or f"l{line.number}"
    return fmt.replace("$", os.path.basename(script)).replace("%", str(line.number)).replace("@", desc)


def job_run(job_id: str, args: list[str], env: dict[str, str], cwd: str, log: str) -> dict:
    """Run one job (on a Dask worker): ``python -m granum ARGS`` with ``env`` added, output to ``log``.

    Returns ``{"status": exit status (or -1 if the job could not start), "duration": s, "host": name}``;
    never raises for a failing job.
    """
    start = time.time()
    full_env = {**os.environ, **env}
    try:
        with open(log, "wb") as out:
            proc = subprocess.Popen([sys.executable, "-m", "granum", *args], cwd=cwd, env=full_env, stdout=out,
                                    stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)
            with _RUNNING_LOCK:
                _RUNNING[job_id] = proc
            try:
                status = proc.wait()
            finally:
                with _RUNNING_LOCK:
                    _RUNNING.pop(job_id, None)
    except OSError as e:
        with open(log, "a", encoding="utf-8") as out:
            out.write(f"granum batch: cannot start the job: {e}\n")
        status = -1
    return {"status": status, "duration": time.time() - start, "host": socket.gethostname()}


def _terminate_running() -> None:
    with _RUNNING_LOCK:
        procs = list(_RUNNING.values())
    for p in procs:
        p.terminate()
    for p in procs:
        try:
            p.wait(timeout=5)
        except subprocess.TimeoutExpired:
            p.kill()


def _duration(s: float) -> str:
    s = int(round(s))
    return f"{s // 3600:02d}:{s // 60 % 60:02d}:{s % 60:02d}"


class State:
    """The ``<table>.batch.json`` record of finished jobs (written atomically after each job)."""

    def __init__(self, path: str):
        self.path = path
        self.jobs: list[dict] = []
        if os.path.exists(path):
            try:
                with open(path, encoding="utf-8") as fh:
                    data = json.load(fh)
                self.jobs = [j for j in data.get("jobs", []) if isinstance(j, dict)]
            except (OSError, ValueError, AttributeError) as e:
                raise RuntimeError(f"granum batch: cannot read the batch state {path!r} ({e}); remove it to start "
                                   f"afresh") from e

    def succeeded(self, key: dict) -> dict | None:
        return next((j for j in self.jobs if j.get("key") == key and j.get("status") == 0), None)

    def record(self, key: dict, entry: dict) -> None:
        self.jobs = [j for j in self.jobs if j.get("key") != key] + [{"key": key, **entry}]
        write_text(self.path, json.dumps({"format": "granum-batch", "jobs": self.jobs}, indent=1) + "\n")


def listen_address(text: str) -> str:
    """The ``--listen`` address: an IP address of this machine (``127.0.0.1``, ``::1``, or
    ``0.0.0.0``/``::`` for all interfaces); ValueError for anything else, host names included."""
    try:
        return str(ipaddress.ip_address(text.strip("[]")))
    except ValueError:
        raise ValueError(f"--listen {text!r} is not an IP address (127.0.0.1, ::1, or 0.0.0.0 for all "
                         f"interfaces)") from None


def dashboard_port(text: str) -> int | None:
    """The ``--dashboard`` port (``8787`` or ``:8787``; ``0``: any free port), None for ``''`` (no dashboard).

    Raises ValueError for a host in it: the interface is ``--listen``'s, so that widening it is never
    a side effect of choosing a port.
    """
    if not text:
        return None
    port = text[1:] if text.startswith(":") else text
    if not port.isdigit() or int(port) > 65535:
        raise ValueError(f"--dashboard {text!r} is not a port number (the interface is given by --listen)")
    return int(port)


def _url_host(address: str) -> str:
    return f"[{address}]" if ":" in address else address


def _cluster(scheduler: str | None, cores: int, dashboard: int | None, listen: str, out):
    """``(client, local cluster or None, whether jobs ask for core resources)``.

    The local cluster's scheduler and worker talk in-process; their HTTP servers (the dashboard's,
    and the worker's that Dask always starts) listen on ``listen`` only.
    """
    from distributed import Client, LocalCluster

    if scheduler:
        client = Client(scheduler)
        workers = client.scheduler_info().get("workers", {}).values()
        with_cores = bool(workers) and all("cores" in w.get("resources", {}) for w in workers)
        print(f"Using the Dask scheduler at {scheduler} ({len(workers)} workers"
              + (", core resources" if with_cores else ", one job per worker thread") + ")", file=out)
        return client, None, with_cores
    # Dask listens on all interfaces for an address without a host (":8787") and for None (its
    # scheduler serves HTTP even without a dashboard), so both servers get an explicit (host, port).
    cluster = LocalCluster(n_workers=1, threads_per_worker=cores, processes=False, resources={"cores": cores},
                           dashboard_address=[(listen, dashboard or 0)], worker_dashboard_address=[(listen, 0)],
                           scheduler_kwargs={"dashboard": dashboard is not None})
    return Client(cluster), cluster, True


def _dashboard_link(client, listen: str) -> str:
    """The dashboard's address as seen from this machine (Dask's own link names the external address)."""
    if ipaddress.ip_address(listen).is_unspecified:
        return client.dashboard_link
    port = client.scheduler_info()["services"]["dashboard"]
    return f"http://{_url_host(listen)}:{port}/status"


def run_batch(table: str, script: str, jobs: list[Job], *, cores: int, scheduler: str | None = None,
              dashboard: int | None = DASHBOARD_PORT, listen: str = LOOPBACK, resume: bool = False,
              out=sys.stdout) -> int:
    """Run ``jobs`` of ``script`` with parameters from ``table``; returns the number of failed jobs.

    Args:
        table, script: absolute paths.
        jobs: the jobs to run (see :func:`granum.batch.jobs_make`).
        cores: cores of the local cluster (ignored with ``scheduler``).
        scheduler: address of an existing Dask scheduler, or None for a local cluster.
        dashboard: port of the local cluster's dashboard (0: any free one), or None for none.
        listen: IP address the local cluster's ports listen on (see :func:`listen_address`).
        resume: skip the jobs that ``<table>.batch.json`` records as succeeded.
        out: where reports go.
    """
    from distributed import as_completed

    state = State(os.path.join(os.getcwd(), os.path.basename(table) + ".batch.json"))
    todo = []
    for job in jobs:
        done = state.succeeded(job.key(script)) if resume else None
        if done is not None:
            print(f"{job.name} skipped: already done (exit status 0, log {done.get('log')})", file=out)
        else:
            todo.append(job)
    if not todo:
        print("All jobs were done already.", file=out)
        return 0
    client, cluster, with_cores = _cluster(scheduler, cores, dashboard, listen, out)
    failed = 0
    start = time.time()
    try:
        if scheduler:
            print(f"Dask dashboard: {client.dashboard_link}", file=out)
        elif dashboard is not None:
            print(f"Dask dashboard: {_dashboard_link(client, listen)}", file=out)
        if not scheduler and not ipaddress.ip_address(listen).is_loopback:
            print(f"granum batch: warning: the local cluster listens on {listen}, reachable from other machines "
                  f"without authentication", file=out)
        futures = {}
        for job in todo:
            env = {**job.line.env, "YADE_BATCH": f"{table}:{job.line.number}",
                   "PARAM_TABLE": f"{table}:{job.line.number}", "OMP_NUM_THREADS": str(job.threads)}
            args = ["-j", str(job.threads), script]
            job_id = f"granum-batch-{os.getpid()}-{job.index}"
            fut = client.submit(job_run, job_id, args, env, os.getcwd(), os.path.abspath(job.log), key=job_id,
                                resources={"cores": job.threads} if with_cores else None, pure=False)
            futures[fut] = job
        print(f"{len(todo)} jobs queued at {time.strftime('%c')}", file=out, flush=True)
        for fut in as_completed(futures):
            job = futures[fut]
            try:
                r = fut.result()
            except Exception as e:  # noqa: BLE001 - a worker lost; report the job as failed
                r = {"status": -1, "duration": 0.0, "host": "", "error": f"{type(e).__name__}: {e}"}
            ok = r["status"] == 0
            failed += not ok
            word = "done   " if ok else "FAILED "
            extra = f" ({r['error']})" if "error" in r else ""
            print(f"{job.name} {word} (exit status {r['status']}), duration {_duration(r['duration'])}, "
                  f"log {job.log}{extra}", file=out, flush=True)
            state.record(job.key(script), {"description": job.line.description, "log": job.log, **r})
    except KeyboardInterrupt:
        _terminate_running()
        raise
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    print(f"All jobs finished, total time {_duration(time.time() - start)}: {len(todo) - failed} done, "
          f"{failed} failed", file=out)
    print("Log files: " + " ".join(j.log for j in todo), file=out, flush=True)
    return failed
