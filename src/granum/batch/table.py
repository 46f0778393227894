"""YADE's parameter tables (user's manual, section 4.2.4): one simulation per line.

The format::

    description density initialVelocity   # the first non-empty line names the columns
    reference   2400    10
    hi_v           =    20                # '=' repeats the value of the previous line
    # comments and blank lines are ignored
    hi_rho      5000    'ten'             # quoted values are strings

* ``description`` names the job (log files, ``O.tags['description']``); without that column a
  job is described by its values, ``density=2400,initialVelocity=10``.
* Columns starting with ``!`` set environment variables of the job instead of script
  parameters (``!NAME``: a letter or ``_``, then letters, digits or ``_``). ``!THREADS`` and
  ``!OMP_NUM_THREADS`` give the number of threads of the job instead (a positive integer; the
  job gets ``OMP_NUM_THREADS`` set to its threads, as in YADE). Variables that would make each
  job load code from elsewhere (:data:`REFUSED_ENVIRONMENT`: ``PYTHONPATH``, ``LD_PRELOAD``...)
  and those ``granum batch`` sets itself (``YADE_BATCH``, ``PARAM_TABLE``) are refused: a table
  is data, and running it must not run code other than the script.
* Values are Python expressions over the names of :mod:`math`, as YADE evaluates them:
  ``1e6``, ``.05``, ``pi/4``, ``radians(30)``, ``(1, 2)``, ``True``, ``'a string'``. They are
  evaluated without ``eval``: only literals, arithmetic, and :mod:`math`'s constants and
  functions are allowed. A value that is none of these (an unquoted word) is an error, as in
  YADE. ``description`` and ``!`` columns are text.

Line numbers are those of the file, counted from 1, as ``yade-batch`` counts them. The file is
UTF-8 text; a NUL byte or undecodable bytes are errors naming the line.
"""

from __future__ import annotations

import ast
import math
import operator
import re
from dataclasses import dataclass, field

#: A cell: a run of quoted strings and other characters without blanks; or the start of a comment.
_TOKEN = re.compile(r"""((?:"[^"]*"|'[^']*'|[^\s"'#])+)|(#.*)""")
#: Columns that give the number of threads of a job.
THREAD_COLUMNS = ("!THREADS", "!OMP_NUM_THREADS")
#: Environment variables a ``!`` column may not set: each makes the job's Python or its dynamic
#: linker load code from another place than granum's installation (modules, a startup file, a
#: standard library, shared libraries).
REFUSED_ENVIRONMENT = ("PYTHONPATH", "PYTHONSTARTUP", "PYTHONHOME", "PYTHONUSERBASE", "LD_PRELOAD",
                       "LD_LIBRARY_PATH", "LD_AUDIT", "DYLD_INSERT_LIBRARIES", "DYLD_LIBRARY_PATH")
#: Environment variables ``granum batch`` sets for each job itself (which table line it runs).
BATCH_ENVIRONMENT = ("YADE_BATCH", "PARAM_TABLE")
_ENVIRONMENT_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


class TableError(ValueError):
    """A parameter table that cannot be read: the message names the file and the line."""


@dataclass
class TableLine:
    """One line of a parameter table.

    Attributes:
        number: line number in the file (1-based).
        values: column name -> value (Python literal or string), ``=`` resolved.
        texts: column name -> the value as written (quotes kept), ``=`` resolved.
    """

    number: int
    values: dict
    texts: dict = field(default_factory=dict)

    @property
    def params(self) -> dict:
        """The script parameters of this line (columns other than ``description`` and ``!...``)."""
        return {k: v for k, v in self.values.items() if k != "description" and not k.startswith("!")}

    @property
    def env(self) -> dict[str, str]:
        """Environment variables this line sets (``!NAME`` columns other than the thread columns,
        without the ``!``)."""
        return {k[1:]: str(v) for k, v in self.values.items() if k.startswith("!") and k not in THREAD_COLUMNS}

    @property
    def threads(self) -> int | None:
        """Threads this job asks for (``!THREADS`` or ``!OMP_NUM_THREADS``), or None."""
        for k in THREAD_COLUMNS:
            if k in self.values:
                return int(self.values[k])
        return None

    @property
    def description(self) -> str:
        """The ``description`` column, or ``name=value,...`` of the parameters (quotes removed)."""
        if "description" in self.values:
            return str(self.values["description"])
        return ",".join(f"{k}={_unquote(self.texts[k])}" for k in self.params)


def _quoted(text: str) -> bool:
    return len(text) >= 2 and text[0] == text[-1] and text[0] in "'\""


def _unquote(text: str) -> str:
    return text[1:-1] if _quoted(text) else text


def _tokens(text: str, where: str) -> list[str]:
    out = []
    pos = 0
    for m in _TOKEN.finditer(text):
        if text[pos:m.start()].strip():  # only an unmatched quote is left between cells
            raise TableError(f"{where}: unterminated quote in {text[pos:].strip()!r}")
        pos = m.end()
        if m.group(2):
            return out
        out.append(m.group(1))
    if text[pos:].strip():
        raise TableError(f"{where}: unterminated quote in {text[pos:].strip()!r}")
    return out


_BINARY = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
           ast.FloorDiv: operator.floordiv, ast.Mod: operator.mod, ast.Pow: operator.pow}
_UNARY = {ast.UAdd: operator.pos, ast.USub: operator.neg}
_MATH = {k: v for k, v in vars(math).items() if not k.startswith("_")}
_NAMES = _MATH | {"True": True, "False": False, "None": None}


#: Largest result of ``**`` on integers (bits) and of repeating a string, tuple or list (items):
#: a table cell must not take the memory or the time of the machine.
_MAX_INT_BITS = 100_000
_MAX_REPEAT = 1_000_000


def _size_check(op: ast.operator, left, right) -> None:
    """ValueError for an operation whose result would be huge (``9**9**9``, ``'a'*10**10``)."""
    if isinstance(op, ast.Pow) and isinstance(right, int | float) and abs(right) > 1e4:
        raise ValueError("exponent too large")
    if (isinstance(op, ast.Pow) and isinstance(left, int) and isinstance(right, int)
            and abs(left).bit_length() * right > _MAX_INT_BITS):
        raise ValueError(f"the result would have more than {_MAX_INT_BITS} bits")
    if isinstance(op, ast.Mult):
        for seq, count in ((left, right), (right, left)):
            if isinstance(seq, str | tuple | list) and isinstance(count, int) and len(seq) * count > _MAX_REPEAT:
                raise ValueError(f"the result would have more than {_MAX_REPEAT} items")


def _evaluate(node):
    if isinstance(node, ast.Constant):
        return node.value
    if isinstance(node, ast.Tuple | ast.List):
        items = [_evaluate(e) for e in node.elts]
        return tuple(items) if isinstance(node, ast.Tuple) else items
    if isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
        return _UNARY[type(node.op)](_evaluate(node.operand))
    if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
        left, right = _evaluate(node.left), _evaluate(node.right)
        _size_check(node.op, left, right)
        return _BINARY[type(node.op)](left, right)
    if isinstance(node, ast.Name) and node.id in _NAMES:
        return _NAMES[node.id]
    if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and callable(_MATH.get(node.func.id))
            and not node.keywords):
        return _MATH[node.func.id](*[_evaluate(a) for a in node.args])
    raise ValueError(f"{ast.unparse(node)!r} is not a number, a quoted string or an expression of math's names")


def value_parse(text: str, where: str = "table"):
    """The value of the table cell ``text`` (see the module docstring); ``where`` names it in errors."""
    try:
        return _evaluate(ast.parse(text, mode="eval").body)
    except (ValueError, SyntaxError, TypeError, ArithmeticError, MemoryError, RecursionError) as e:
        raise TableError(f"{where}: cannot evaluate {text!r}: {e} (quote strings: '{text}')") from None


def _headings_check(names: list[str], where: str) -> None:
    """Refuse duplicate column names and ``!`` columns that are no environment variable a table may set."""
    if len(set(names)) != len(names):
        raise TableError(f"{where}: a column name appears twice in the headings {names}")
    for name in names:
        if not name.startswith("!"):
            continue
        variable = name[1:]
        if not variable:
            raise TableError(f"{where}: column '!' has no environment variable name after the '!'")
        if not _ENVIRONMENT_NAME.fullmatch(variable):
            raise TableError(f"{where}: column {name!r}: {variable!r} is not an environment variable name "
                             f"(a letter or _, then letters, digits or _)")
        if variable in REFUSED_ENVIRONMENT:
            raise TableError(f"{where}: column {name!r} is refused: {variable} would make each job load code "
                             f"from elsewhere; set it in the environment of granum batch itself if you mean it")
        if variable in BATCH_ENVIRONMENT:
            raise TableError(f"{where}: column {name!r} is refused: granum batch sets {variable} for each job")


def _threads_parse(text: str, where: str) -> int:
    """The thread count of a ``!THREADS``/``!OMP_NUM_THREADS`` cell: a positive integer."""
    if not text.isdigit() or int(text) < 1:
        raise TableError(f"{where}: {text!r} is not a number of threads (a positive integer)")
    return int(text)


def _text_lines(path: str) -> list[str]:
    """The lines of the UTF-8 file ``path``; TableError naming the line of a NUL or undecodable byte."""
    with open(path, "rb") as fh:
        data = fh.read()
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        number = data.count(b"\n", 0, e.start) + 1
        raise TableError(f"{path}:{number}: not UTF-8 text (byte {data[e.start]:#04x})") from None
    lines = text.splitlines()
    nul = next((number for number, line in enumerate(lines, start=1) if "\0" in line), None)
    if nul is not None:
        raise TableError(f"{path}:{nul}: a NUL byte in the table")
    return lines


def table_read(path: str) -> list[TableLine]:
    """All parameter lines of the table ``path``, in file order.

    Raises:
        OSError: the file cannot be read.
        TableError: no heading line, a line with more or fewer values than headings, ``=`` on
            the first parameter line, duplicate headings, a refused or malformed ``!`` column, a
            thread count that is no positive integer, a NUL byte, a file that is not UTF-8.
    """
    lines = _text_lines(path)
    names: list[str] | None = None
    previous: dict[str, str] = {}
    out = []
    for number, raw in enumerate(lines, start=1):
        where = f"{path}:{number}"
        tokens = _tokens(raw, where)
        if not tokens:
            continue
        if names is None:
            _headings_check(tokens, where)
            names = tokens
            continue
        if len(tokens) != len(names):
            raise TableError(f"{where}: {len(tokens)} values for the {len(names)} columns {names}")
        texts = {}
        for name, text in zip(names, tokens, strict=True):
            if text == "=":
                if name not in previous:
                    raise TableError(f"{where}: '=' in column {name!r} but there is no previous line")
                text = previous[name]
            texts[name] = text
        previous = texts
        values = {k: _cell_value(k, t, f"{where} ({k})") for k, t in texts.items()}
        out.append(TableLine(number, values, texts))
    if names is None:
        raise TableError(f"{path}: the table has no heading line")
    return out


def _cell_value(column: str, text: str, where: str):
    """The value of a cell: text for ``description`` and ``!`` columns (a thread count for the
    thread columns), else a Python value."""
    if column in THREAD_COLUMNS:
        return _threads_parse(_unquote(text), where)
    if column == "description" or column.startswith("!"):
        return _unquote(text)
    return value_parse(text, where)


def table_line(path: str, number: int) -> TableLine:
    """Line ``number`` (1-based, as in the file) of the table ``path``."""
    for line in table_read(path):
        if line.number == number:
            return line
    raise TableError(f"{path}: line {number} is not a parameter line of the table")


def lines_select(lines: list[TableLine], spec: str | None) -> list[TableLine]:
    """The lines named by ``spec`` (``yade-batch --lines`` syntax: ``2,3-5,8``); all if None."""
    if not spec:
        return lines
    wanted: set[int] = set()
    for part in spec.split(","):
        a, sep, b = part.strip().partition("-")
        try:
            lo, hi = int(a), int(b) if sep else int(a)
        except ValueError:
            raise TableError(f"--lines: {part!r} is not a line number or a range like 3-5") from None
        wanted.update(range(lo, hi + 1))
    available = {line.number for line in lines}
    missing = sorted(wanted - available)
    if missing:
        raise TableError(f"--lines: line {missing[0]} is not a parameter line of the table "
                         f"(available: {', '.join(map(str, sorted(available)))})")
    return [line for line in lines if line.number in wanted]
