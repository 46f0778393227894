"""Script side of parametric studies: ``readParamsFromTable``, ``waitIfBatch``, ``runningInBatch``.

A batch job gets ``PARAM_TABLE=file:line`` in its environment; the values of that
line of the table override the defaults declared by the script.
"""

from __future__ import annotations

import ast
import os
import shlex

from granum.yade.params import table as _table


def runningInBatch() -> bool:
    """Whether this script runs as a job of a parametric study."""
    return "PARAM_TABLE" in os.environ


def _parse_value(text: str):
    try:
        return ast.literal_eval(text)
    except (ValueError, SyntaxError):
        return text


def read_table_line(path: str, line_no: int) -> dict:
    """Values of line ``line_no`` (1-based, as in the file) of a YADE parameter table."""
    with open(path) as fh:
        lines = fh.read().splitlines()
    names = None
    previous: dict = {}
    for k, raw in enumerate(lines, start=1):
        text = raw.split("#", 1)[0].strip()
        if not text:
            continue
        fields = shlex.split(text)
        if names is None:
            names = fields
            continue
        values = {n: (previous[n] if v == "=" else _parse_value(v)) for n, v in zip(names, fields, strict=False)}
        previous = values
        if k == line_no:
            return values
    raise ValueError(f"{path}: line {line_no} is not a parameter line of the table")


def readParamsFromTable(tableFileLine=None, noTableOk=True, unknownOk=False, **defaults):
    """Declare parameters with defaults; in a batch job take their values from the table.

    The values become attributes of ``yade.params.table`` (``from yade.params.table
    import *``). Returns the dict of values.
    """
    spec = tableFileLine or os.environ.get("PARAM_TABLE")
    values = dict(defaults)
    if spec:
        path, _, line = spec.rpartition(":")
        row = read_table_line(path, int(line))
        for name, v in row.items():
            if name == "description" or name.startswith("!"):
                continue
            if name not in defaults and not unknownOk:
                raise NameError(f"readParamsFromTable: parameter {name!r} of the table is not declared by the script")
            values[name] = v
    elif not noTableOk:
        raise RuntimeError("readParamsFromTable: no parameter table given (PARAM_TABLE is not set)")
    for name, v in values.items():
        setattr(_table, name, v)
    from granum.yade.omega import O

    O.tags["params"] = ",".join(f"{k}={v}" for k, v in values.items() if k in defaults)
    return values


def waitIfBatch() -> None:
    """In a batch job, wait until the simulation stops; otherwise do nothing."""
    if runningInBatch():
        from granum.yade.omega import O

        O.wait()
