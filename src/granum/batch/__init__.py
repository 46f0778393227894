"""``granum batch TABLE SCRIPT``: parametric studies, as YADE's ``yade-batch``.

* :mod:`granum.batch.table` reads YADE's parameter tables.
* :mod:`granum.batch.runner` runs one job per table line on a Dask cluster.

Options follow ``yade-batch`` where it has them: ``-j/--jobs`` (cores for all jobs together),
``--job-threads`` (threads per job, default 1; the table's ``!THREADS`` column overrides it),
``--log`` (``$`` script, ``%`` line number, ``@`` description; default ``$.@.log``),
``-l/--lines`` (``2,3-5``), ``--dry-run``; and, granum's own, ``--scheduler ADDRESS`` (an
existing Dask cluster), ``--resume`` (skip jobs already done), ``--dashboard PORT`` and
``--listen ADDRESS`` (the interface of the local cluster's ports: loopback unless widened
deliberately, see :mod:`granum.batch.runner`).
"""

from __future__ import annotations

import argparse
import os
import sys

from granum.batch.runner import DASHBOARD_PORT, LOOPBACK, Job, dashboard_port, listen_address, log_name, run_batch
from granum.batch.table import TableError, lines_select, table_read

__all__ = ["Job", "jobs_make", "main"]


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="granum batch", description="Run SCRIPT once for each line of the parameter TABLE "
        "(YADE's yade-batch), as jobs on a Dask cluster.")
    p.add_argument("table", metavar="TABLE", help="parameter table (first non-empty line: column names)")
    p.add_argument("script", metavar="SCRIPT", help="YADE script calling readParamsFromTable")
    p.add_argument("-j", "--jobs", type=int, default=None,
                   help="cores used by all jobs together (default: all cores, at most OMP_NUM_THREADS)")
    p.add_argument("--job-threads", type=int, default=1,
                   help="threads of each job (default 1); a !THREADS or !OMP_NUM_THREADS column overrides it")
    p.add_argument("--log", default="$.@.log",
                   help="log file of each job: $ -> script name, %% -> line number, @ -> description "
                   "(default: $.@.log)")
    p.add_argument("-l", "--lines", default=None, help="table lines to run, e.g. 2,3-5,8 (default: all)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="address of a running Dask scheduler (default: a local cluster)")
    p.add_argument("--dashboard", default=str(DASHBOARD_PORT), metavar="PORT",
                   help=f"port of the local cluster's Dask dashboard ('' for none, 0 for any free port; "
                   f"default {DASHBOARD_PORT}); it listens on the --listen address")
    p.add_argument("--listen", default=LOOPBACK, metavar="ADDRESS",
                   help=f"IP address every port of the local cluster listens on (default {LOOPBACK}: "
                   f"this machine only). The dashboard has no authentication: rather than widening it "
                   f"(e.g. --listen 0.0.0.0, all interfaces), reach it from elsewhere with an SSH tunnel, "
                   f"ssh -L {DASHBOARD_PORT}:127.0.0.1:{DASHBOARD_PORT} HOST")
    p.add_argument("--resume", action="store_true",
                   help="skip the jobs that <TABLE>.batch.json records as done with the same values")
    p.add_argument("--dry-run", action="store_true", help="list the jobs without running them")
    return p


def _default_cores() -> int:
    n = os.cpu_count() or 1
    omp = os.environ.get("OMP_NUM_THREADS", "")
    return min(n, int(omp)) if omp.isdigit() and int(omp) > 0 else n


def jobs_make(table: str, lines_spec: str | None, log_format: str, script: str, job_threads: int,
              cores: int, out=sys.stdout) -> list[Job]:
    """The jobs of a batch; raises :class:`TableError` (bad table or lines) or ValueError (bad options)."""
    if job_threads < 1:
        raise ValueError(f"--job-threads must be at least 1, not {job_threads}")
    if not any(c in log_format for c in "$%@"):
        raise ValueError(f"--log {log_format!r} must contain $, % or @, or all jobs would share one log file")
    lines = lines_select(table_read(table), lines_spec)
    if not lines:
        raise TableError(f"{table}: the table has no parameter lines")
    jobs = []
    for k, line in enumerate(lines):
        threads = line.threads or job_threads
        if threads > cores:
            print(f"granum batch: line {line.number} asks for {threads} threads; using the {cores} available",
                  file=out)
            threads = cores
        jobs.append(Job(k, line, threads, log_name(log_format, script, line)))
    logs = [j.log for j in jobs]
    clash = next((name for name in logs if logs.count(name) > 1), None)
    if clash is not None:
        raise ValueError(f"two jobs would write the log file {clash!r}; give the table a description column "
                         f"or use % in --log")
    return jobs


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    out = sys.stdout
    for what, path in (("table", args.table), ("script", args.script)):
        if not os.path.isfile(path):
            print(f"granum batch: no such {what}: {path}", file=sys.stderr)
            return 2
    cores = args.jobs if args.jobs is not None else _default_cores()
    if cores < 1:
        print(f"granum batch: -j must be at least 1, not {cores}", file=sys.stderr)
        return 2
    table, script = os.path.abspath(args.table), os.path.abspath(args.script)
    try:
        listen, dashboard = listen_address(args.listen), dashboard_port(args.dashboard)
        jobs = jobs_make(table, args.lines, args.log, script, args.job_threads, cores, out)
    except (TableError, ValueError) as e:
        print(f"granum batch: {e}", file=sys.stderr)
        return 2
    where = f"the Dask scheduler at {args.scheduler}" if args.scheduler else f"a local Dask cluster of {cores} cores"
    print(f"Will run {os.path.basename(script)} with granum on {where}.", file=out)
    print(f"Will use table {args.table!r}, with lines "
          + ", ".join(f"{j.line.number} ({j.line.description})" for j in jobs) + ".", file=out)
    print("Job summary:", file=out)
    for j in jobs:
        print(f"   {j.name}: YADE_BATCH={args.table}:{j.line.number} granum -j {j.threads} "
              f"{args.script} > {j.log}", file=out)
    if args.dry_run:
        return 0
    failed = run_batch(table, script, jobs, cores=cores, scheduler=args.scheduler, dashboard=dashboard,
                       listen=listen, resume=args.resume, out=out)
    return 1 if failed else 0
