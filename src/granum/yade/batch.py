"""Script side of parametric studies: ``readParamsFromTable``, ``waitIfBatch``, ``runningInBatch``.

A batch job (see :mod:`granum.batch`) gets ``YADE_BATCH=file:line`` (YADE 2023's name; the
older ``PARAM_TABLE`` is read too) in its environment; the values of that line of the table
override the defaults the script declares. The tags YADE sets for a batch job are set here:
``line`` (``l<number>``), ``description``, ``d.id`` and ``id.d`` (description joined to the run's
unique ``id``), ``params`` (the table's values as written) and ``defaultParams`` (the declared
parameters the table does not give).
"""

from __future__ import annotations

import os

from granum.batch.table import table_line
from granum.yade.params import table as _table

#: Environment variables naming the table line of a batch job, in order of precedence.
BATCH_ENV = ("YADE_BATCH", "PARAM_TABLE")


def _batch_spec() -> str | None:
    return next((os.environ[k] for k in BATCH_ENV if os.environ.get(k)), None)


def runningInBatch() -> bool:
    """Whether this script runs as a job of a parametric study."""
    return _batch_spec() is not None


def readParamsFromTable(tableFileLine=None, noTableOk=True, unknownOk=False, **defaults):
    """Declare parameters with defaults; in a batch job take their values from the table.

    Args:
        tableFileLine: ``"file:line"`` to read instead of the batch job's line.
        noTableOk: if False, running outside a batch is an error.
        unknownOk: accept table columns the script does not declare.
        **defaults: the parameters and their default values.

    The values become attributes of ``yade.params.table`` (``from yade.params.table
    import *``). Returns the dict of values.
    """
    from granum.yade.omega import O

    spec = tableFileLine or _batch_spec()
    values = dict(defaults)
    if not spec:
        if not noTableOk:
            raise RuntimeError("readParamsFromTable: no parameter table given (not running in a batch; "
                               "YADE_BATCH is not set)")
        given = {}
    else:
        path, sep, number = spec.rpartition(":")
        if not sep or not number.isdigit():
            raise ValueError(f"readParamsFromTable: {spec!r} is not of the form file:line")
        line = table_line(path, int(number))
        given = line.params
        unknown = [k for k in given if k not in defaults]
        if unknown and not unknownOk:
            raise NameError(f"readParamsFromTable: parameter {unknown[0]!r} of {path} is not declared by the "
                            f"script (declared: {', '.join(defaults)}); pass unknownOk=True to accept it")
        values.update(given)
        desc = line.description
        tags = O.tags
        tags.update({"line": f"l{line.number}", "description": desc, "d.id": f"{desc}.{tags['id']}",
                     "id.d": f"{tags['id']}.{desc}"})
        given = {k: line.texts[k] for k in given}
    for name, v in values.items():
        setattr(_table, name, v)
    O.tags["params"] = ",".join(f"{k}={t}" for k, t in given.items())
    O.tags["defaultParams"] = ",".join(f"{k}={v}" for k, v in defaults.items() if k not in given)
    return values


def waitIfBatch() -> None:
    """In a batch job, wait until the simulation stops; otherwise do nothing."""
    if runningInBatch():
        from granum.yade.omega import O

        O.wait()
