"""YADE's ``yade.plot``: history of scalar variables, text/gnuplot export, matplotlib figures.

Design
------
The module keeps YADE's module-level state so that scripts written for YADE work unchanged:

* ``data`` maps a column name to a list of values.  Every column always has the same length:
  :func:`addData` appends one row to *all* columns, putting NaN into the columns it was not
  given and back-filling a new column with NaN for the rows recorded before it existed.
  Rows therefore stay aligned and any column can be plotted against any other.
* ``plots`` maps an x column to a tuple of y specifications.  A y specification is a column
  name, a ``(name, matplotlib_fmt)`` pair, ``None`` (everything after it goes on a right-hand
  y axis), a dict-like object (its current keys) or a callable such as ``O.energy.keys``
  (called at plot time, so columns that appear later are picked up).  Because dict keys are
  unique, the same x column may be used several times by adding spaces (``'i '``, ``' i'``);
  x names are stripped before they are looked up in ``data``.
* ``labels`` maps a column name to the text shown on axes and legends.

Output formats follow what YADE 2023.02a writes, checked against it as a black box:
:func:`saveDataTxt` writes ``# name1<TAB><TAB>name2...`` then tab-separated ``str()`` values
(columns sorted by name unless ``vars`` is given), compressed by a ``.bz2`` / ``.gz`` suffix;
:func:`saveGnuplot` writes ``baseName.gnuplot`` plus ``baseName.data.bz2``.

Plotting is deliberately lazy: ``import granum.yade.plot`` imports only numpy; matplotlib and
pyplot are imported by :func:`plot` itself.  Without a display (or under a non-interactive
matplotlib backend) :func:`plot` renders with Agg into a PNG file and returns instead of
opening a window; see :func:`plot` for the file name.  With a browser view open
(:mod:`granum.yade.view`) the figures are also shown in its page and redrawn every ``liveInterval``
seconds while ``live`` (turned on when the view opens, as YADE does with a display); matplotlib windows
are not updated live, and ``autozoom`` is accepted for compatibility.

Deliberate differences from YADE: all positional dicts given to :func:`addData` are merged
(YADE silently keeps only the first); :func:`reset` also clears ``labels`` as its YADE
docstring says (YADE's code leaves them); columns missing from ``data`` are skipped with a
warning by :func:`plot` and :func:`saveGnuplot` instead of being added as NaN columns or
raising; ``saveGnuplot(varData=True)`` ends the ``dataFile=`` line with a newline (YADE's
file is not valid gnuplot there); ``qt`` counts as a screen terminal; a leading dot of
``extension`` is dropped.
"""

from __future__ import annotations

import atexit
import bz2
import gzip
import math
import os
import re
import sys
import time
import warnings
from pathlib import Path

import numpy as np

data: dict[str, list] = {}
plots: dict = {}
labels: dict[str, str] = {}

# Live updating of the figures in the browser view's page (granum.yade.view), every liveInterval seconds.
live = False
liveInterval = 1
autozoom = True
# Scientific (offset/exponent) tick labels on linear axes.
scientific = True
# Legend positions of the left and right y axes.
legendLoc = ('upper left', 'upper right')
# Separator between a vector/matrix column name and its component suffix (``v_x``, ``m_xy``).
componentSeparator = '_'
# File :func:`plot` writes when there is no display; ``None`` means ``<script stem>-plot.png``.
headlessFile: str | None = None

_nan = math.nan
_VECTOR_SUFFIXES = ('x', 'y', 'z')
# Same order YADE uses for Matrix3 components: diagonal first, then upper, then lower triangle.
_MATRIX_SUFFIXES = (((0, 0), 'xx'), ((1, 1), 'yy'), ((2, 2), 'zz'), ((0, 1), 'xy'), ((0, 2), 'xz'),
                    ((1, 2), 'yz'), ((1, 0), 'yx'), ((2, 0), 'zx'), ((2, 1), 'zy'))
_NON_INTERACTIVE = {'agg', 'cairo', 'pdf', 'pgf', 'ps', 'svg', 'template'}
# gnuplot terminals that draw windows; any other terminal writes numbered output files.
_SCREEN_TERMS = ('wxt', 'x11', 'qt')
# ``name=expression`` in a plots entry; the name may not contain comparison operators or brackets
# so that expressions such as ``a==b`` or ``f(x=1)`` are not split.
_NAMED_EXPR = re.compile(r'^\s*([^=<>!()\[\]]+?)\s*=(?!=)(.+)$')

_headless_pending: dict | None = None  # what the last headless plot() saved, for the exit refresh
_shown_figures: list = []


def reset():
    """Reset data, plot specification and labels (``data``, ``plots``, ``labels``)."""
    global data, plots, labels
    data, plots, labels = {}, {}, {}


def resetData():
    """Reset all data; keep ``plots`` and ``labels``."""
    global data
    data = {}


def _nrows() -> int:
    return max((len(col) for col in data.values()), default=0)


def _components(name: str, value) -> dict:
    """Split one addData value into columns: vectors and 3x3 matrices get one column per component."""
    if isinstance(value, np.generic):
        return {name: value.item()}  # plain Python numbers print the same as YADE's in saveDataTxt
    if not hasattr(value, '__len__'):
        return {name: value}
    # YADE refuses plain sequences and strings; guessing what a tuple means would hide mistakes.
    if not isinstance(value, (str, bytes, tuple, list, dict, set)):
        try:
            arr = np.asarray(value, dtype=float)  # Vector2/Vector3/Matrix3 or a numpy array
        except (TypeError, ValueError):
            arr = np.empty(0)
        if arr.ndim == 0:
            return {name: arr.item()}
        if arr.shape in ((2,), (3,)):
            return {f'{name}{componentSeparator}{_VECTOR_SUFFIXES[k]}': float(v) for k, v in enumerate(arr)}
        if arr.shape == (3, 3):
            return {f'{name}{componentSeparator}{s}': float(arr[ij]) for ij, s in _MATRIX_SUFFIXES}
    raise ValueError(f'plot.addData given unhandled sequence type (is a {type(value).__name__}, '
                     'must be number or Vector2/Vector3/Matrix3)')


def addData(*d_in, **kw):
    """Append one row to ``data``: ``addData(i=O.iter, Ek=...)`` or ``addData({'my col': 1}, t=...)``.

    Columns not given get NaN in this row; new columns are back-filled with NaN for earlier rows, so
    all columns keep the same length.  Positional dicts are merged in order, keywords win.  Vectors
    (length 2 or 3) and 3x3 matrices are split into ``name_x``... / ``name_xx``... columns.  Calling
    ``addData()`` with no values adds a row of NaN (a break in the curves) unless ``data`` is empty.
    Example: ``addData(a=1); addData(b=2); addData(a=3, b=4)`` gives
    ``{'a': [1, nan, 3], 'b': [nan, 2, 4]}``.
    """
    row = {}
    for d in d_in:
        if not hasattr(d, 'keys'):
            raise TypeError(f'plot.addData positional arguments must be dicts, not {type(d).__name__}')
        row.update(d)
    row.update(kw)
    cells = {}
    for name, value in row.items():
        cells.update(_components(name, value))
    n = _nrows()
    if n == 0 and not cells:
        return
    for col in data.values():  # repair columns a user shortened by hand, so rows stay aligned
        col.extend([_nan] * (n - len(col)))
    for name, value in cells.items():
        if name not in data:
            data[name] = [_nan] * n
        data[name].append(value)
    for col in data.values():
        if len(col) == n:
            col.append(_nan)


def splitData():
    """Add a row of NaN to all columns, making every plotted curve discontinuous at this point."""
    addData()


def reverseData():
    """Reverse the order of rows in all columns."""
    for col in data.values():
        col.reverse()


def _eval_namespace() -> dict:
    # YADE evaluates in its own module namespace, where the script's variables are invisible;
    # granum's scripting namespace (if loaded) plus the running script's globals is a superset.
    layer = sys.modules.get('granum.yade')
    ns = {k: v for k, v in vars(layer).items() if not k.startswith('__')} if layer else {}
    main = sys.modules.get('__main__')
    ns.update(vars(main) if main else {})
    return ns


def _mapping_like(obj) -> bool:
    return hasattr(obj, 'keys') and hasattr(obj, '__getitem__') and not isinstance(obj, (str, type))


def addAutoData():
    """Add one row by evaluating every entry of ``plots`` (x keys and y specifications).

    A string is a Python expression (``'O.iter'``) or ``'name=expression'``; a dict-like object
    contributes all its current items; a bound ``keys`` method (``O.energy.keys``) contributes the
    items of its object; another callable is called and must return a mapping.  Expressions that
    raise are skipped with a warning, as in YADE.
    """
    ns = _eval_namespace()
    row: dict = {}
    specs: list = []
    for xkey, yspecs in plots.items():
        specs.append(xkey.strip())
        specs.extend(_as_spec_tuple(yspecs))
    for spec in specs:
        if isinstance(spec, (tuple, list)) and spec and isinstance(spec[0], str):
            spec = spec[0]  # (name, fmt)
        if spec is None:
            continue
        if isinstance(spec, str):
            m = _NAMED_EXPR.match(spec)
            name, expr = (m.group(1), m.group(2)) if m else (spec, spec)
            try:
                row[name] = eval(expr, ns)
            except Exception:
                warnings.warn(f'ignoring exception raised while evaluating auto-column `{expr}`',
                              stacklevel=2)
            continue
        if callable(spec) and _mapping_like(getattr(spec, '__self__', None)):
            spec = spec.__self__
        elif callable(spec):
            spec = spec()
        if _mapping_like(spec):
            row.update({k: spec[k] for k in list(spec.keys())})
        else:
            warnings.warn(f'addAutoData: cannot get values from {spec!r}', stacklevel=2)
    addData(row)


def _open_text(fileName: str, mode: str):
    # Compression is chosen by suffix, case-sensitively like YADE ('x.BZ2' is written as plain text).
    if fileName.endswith('.bz2'):
        return bz2.open(fileName, mode + 't', encoding='utf-8')
    if fileName.endswith('.gz'):
        return gzip.open(fileName, mode + 't', encoding='utf-8')
    return open(fileName, mode, encoding='utf-8')


def saveDataTxt(fileName, vars=None, headers=None):
    """Save ``data`` as a text table readable by ``numpy.genfromtxt(fileName, names=True)``.

    Layout (as YADE): optional ``# key=<TAB>value`` lines from the ``headers`` mapping, then
    ``# name1<TAB><TAB>name2...``, then one line per row with ``str()`` of each value separated by
    single tabs (missing values are ``nan``).

    :param fileName: output path; a ``.bz2`` / ``.gz`` suffix compresses with bzip2 / gzip.
    :param vars: column names to save, in this order; ``None`` saves all columns sorted by name.
    :param headers: mapping written as header lines before the column names.
    """
    fileName = os.fspath(fileName)
    if vars is None:
        names = sorted(data)
    elif isinstance(vars, (set, frozenset)):
        names = sorted(vars)  # a set has no order of its own; sort for reproducible files
    else:
        names = list(vars)
    missing = [n for n in names if n not in data]
    if missing:  # check before opening so no truncated file is left behind
        raise KeyError(missing[0])
    if headers is not None and not hasattr(headers, 'items'):
        raise TypeError('saveDataTxt: headers must be a mapping of name -> value')
    nrows = max((len(data[n]) for n in names), default=0)
    with _open_text(fileName, 'w') as f:
        for k, v in (headers or {}).items():
            f.write(f'# {k}=\t{v}\n')
        f.write('# ' + '\t\t'.join(names) + '\n')
        for i in range(nrows):
            f.write('\t'.join(str(data[n][i]) if i < len(data[n]) else 'nan' for n in names) + '\n')


def _as_spec_tuple(yspecs) -> tuple:
    # 'i':('t') is just the string 't' in Python; a lone callable or dict-like is one spec too.
    if isinstance(yspecs, str) or callable(yspecs) or _mapping_like(yspecs):
        return (yspecs,)
    return tuple(yspecs)


def _expand_spec(spec) -> list[tuple[str, str | None]]:
    """One y specification -> list of (column name, fmt or None)."""
    if isinstance(spec, str):
        return [(_column_name(spec), None)]
    if isinstance(spec, (tuple, list)) and spec and isinstance(spec[0], str):
        return [(_column_name(spec[0]), spec[1] if len(spec) > 1 else None)]
    if _mapping_like(spec):
        return [(str(k), None) for k in spec.keys()]
    if callable(spec):
        names = spec()
        names = names.keys() if _mapping_like(names) else names
        return [(str(k), None) for k in names]
    warnings.warn(f'plot: ignoring y specification {spec!r}', stacklevel=3)
    return []


def _split_axes(yspecs) -> tuple[list, list]:
    """y specifications -> (left axis [(name, fmt)...], right axis [...]) split at ``None``."""
    left: list = []
    right: list = []
    side = left
    for spec in _as_spec_tuple(yspecs):
        if spec is None:
            side = right
            continue
        side.extend(_expand_spec(spec))
    return left, right


def _column_name(spec: str) -> str:
    """Column of ``data`` named by a plots entry: the entry itself, or ``name`` of ``name=expr``."""
    if spec in data:
        return spec
    m = _NAMED_EXPR.match(spec)
    return m.group(1) if m else spec


def saveGnuplot(baseName, term='wxt', extension=None, timestamp=False, comment=None, title=None,
                varData=False):
    """Write ``baseName.data.bz2`` (all columns, :func:`saveDataTxt` format) and ``baseName.gnuplot``.

    The gnuplot file draws one plot per ``plots`` entry, right-axis curves with ``axes x1y2``.
    Screen terminals (``wxt``, ``x11``, ``qt``) open persistent windows; any other terminal writes
    ``baseName.<plot number>.<extension>`` (extension defaults to the terminal name).  With
    ``timestamp`` the base name gets ``_YYYYmmdd_HH:MM``.  ``comment`` is embedded as ``#`` lines,
    ``title`` is set on every plot, ``varData`` declares the data source once as ``dataFile``.

    :return: name of the gnuplot file.
    """
    if not data:
        raise RuntimeError('No data for plotting were saved.')
    baseName = os.fspath(baseName)
    stamp = time.strftime('%Y%m%d_%H:%M')
    if timestamp:
        baseName += '_' + stamp
    names = sorted(data)
    dataFile = baseName + '.data.bz2'
    saveDataTxt(dataFile, vars=names)
    ext = (extension or term).lstrip('.')
    base = os.path.basename(baseName)  # gnuplot runs next to its file, so paths are relative to it
    inline = f'"< bzcat {os.path.basename(dataFile)}"'
    source = 'dataFile' if varData else inline
    out = f'#!/usr/bin/env gnuplot\n#\n# created {time.asctime()} ({stamp})\n#\n'
    if comment:
        out += '\n'.join('# ' + line for line in comment.split('\n')) + '#\n'
    if varData:
        out += f'dataFile={inline}\n'
    skipped: list = []
    for i, (xkey, yspecs) in enumerate(plots.items()):
        xname = _column_name(xkey.strip())
        left, right = ([n for n, _ in side] for side in _split_axes(yspecs))
        skipped += [n for n in [xname, *left, *right] if n not in data]
        if xname not in data:
            continue
        left, right = [n for n in left if n in data], [n for n in right if n in data]
        if term in _SCREEN_TERMS:
            out += f'set term {term} {i} persist\n'
        else:
            out += f"set term {term}; set output '{base}.{i}.{ext}'\n"
        xlabel = labels.get(xkey, xname if '=' in xkey else xkey)  # YADE keeps the spaces of 'i '
        out += f"set xlabel '{xlabel}'\nset grid\nset datafile missing 'nan'\n"
        if title:
            out += f"set title '{title}'\n"
        out += "set ylabel '" + ','.join(labels.get(n, n) for n in left) + "'\n"
        if right:
            out += "set y2label '" + ','.join(labels.get(n, n) for n in right) + "'\nset y2tics\n"
        xcol = names.index(xname) + 1
        xlab = labels.get(xname, xname)
        using = f'{source} using {xcol}:'
        curves = [f"{using}{names.index(n) + 1} title '← {labels.get(n, n)}({xlab})' with lines"
                  for n in left]
        curves += [f"{using}{names.index(n) + 1} title '{labels.get(n, n)}({xlab}) →' with lines axes x1y2"
                   for n in right]
        if curves:
            out += 'plot  ' + ', '.join(curves) + '\n'
    if skipped:
        warnings.warn('saveGnuplot: columns not in plot.data, skipped: ' + ', '.join(dict.fromkeys(skipped)),
                      stacklevel=2)
    gnuplotFile = baseName + '.gnuplot'
    with open(gnuplotFile, 'w', encoding='utf-8') as f:
        f.write(out)
    return gnuplotFile


def _has_display() -> bool:
    # Only X11/Wayland announce themselves in the environment; macOS and Windows always have one.
    if sys.platform in ('darwin', 'win32'):
        return True
    return bool(os.environ.get('DISPLAY') or os.environ.get('WAYLAND_DISPLAY'))


def _pyplot_headless():
    """Import pyplot, selecting Agg first when there is no display; return (pyplot, headless)."""
    import matplotlib
    if 'matplotlib.pyplot' not in sys.modules and not os.environ.get('MPLBACKEND') and not _has_display():
        matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    backend = plt.get_backend().lower()
    # 'module://...' backends (Jupyter inline) render in the notebook even without a display.
    headless = backend in _NON_INTERACTIVE or (not _has_display() and not backend.startswith('module://'))
    return plt, headless


def _series(name: str, skipped: list):
    """Column as a float array (None -> NaN, i.e. a gap), or None (noted in skipped) if unusable."""
    if name not in data:
        skipped.append(name)
        return None
    try:
        return np.asarray(data[name], dtype=float)
    except (TypeError, ValueError):
        skipped.append(f'{name} (not numeric)')
        return None


def _draw(ax, xkey: str, yspecs, skipped: list):
    """Fill one Axes (plus a twin for the right y axis) from one ``plots`` entry."""
    xname = _column_name(xkey.strip())
    ax.set_xlabel(labels.get(xname, xname))
    ax.grid(True)
    x = _series(xname, skipped)
    ncurve = 0  # colour index shared by both y axes, whose colour cycles are independent
    for side, specs in enumerate(_split_axes(yspecs)):
        curves = [(name, fmt, _series(name, skipped)) for name, fmt in specs]
        curves = [c for c in curves if c[2] is not None and x is not None]
        if not curves:
            continue
        axis = ax if side == 0 else ax.twinx()
        axis.set_ylabel(', '.join(labels.get(name, name) for name, _, _ in curves))
        for name, fmt, y in curves:
            kw = {'label': labels.get(name, name)}
            if not fmt or not re.search(r'[bgrcmykw]|C\d', fmt):  # fmt without a colour of its own
                kw['color'] = f'C{ncurve % 10}'
            ncurve += 1
            try:
                axis.plot(x, y, *([fmt] if fmt else []), **kw)
            except ValueError:
                skipped.append(f'{name} (bad format {fmt!r}, drawn with default)')
                axis.plot(x, y, **kw)
        axis.legend(loc=legendLoc[side], fontsize='small')
        if scientific:
            try:
                axis.ticklabel_format(style='sci', scilimits=(-3, 4), useMathText=True)
            except AttributeError:  # not a ScalarFormatter (e.g. log axis): leave as is
                pass


def _make_figures(plt, subPlots: bool) -> tuple[list, list]:
    """Figures for ``plots``; also returns the problems met (missing columns...) for one warning."""
    entries = list(plots.items())
    skipped: list = []
    if subPlots:
        # YADE's grid: ceil(sqrt(n)) rows and enough columns; the page grows with the grid so that
        # several subplots stay legible in a saved PNG.
        rows = math.ceil(math.sqrt(len(entries)))
        cols = math.ceil(len(entries) / rows)
        fig = plt.figure(figsize=(6.4 if cols == 1 else 4.8 * cols, 4.8 if rows == 1 else 3.6 * rows))
        for k, (xkey, yspecs) in enumerate(entries):
            _draw(fig.add_subplot(rows, cols, k + 1), xkey, yspecs, skipped)
        figs = [fig]
    else:
        figs = [plt.figure() for _ in entries]
        for fig, (xkey, yspecs) in zip(figs, entries, strict=True):
            _draw(fig.add_subplot(), xkey, yspecs, skipped)
    for fig in figs:
        with warnings.catch_warnings():
            warnings.simplefilter('ignore')  # tight_layout may complain harmlessly about twin axes
            fig.tight_layout()
    return figs, list(dict.fromkeys(skipped))


def _headless_paths(nfig: int) -> list[Path]:
    first = Path(headlessFile) if headlessFile else None
    if first is None:
        stem = 'granum'
        main = sys.modules.get('__main__')
        for cand in (getattr(main, '__file__', None), sys.argv[0] if sys.argv else None):
            # 'python -m pkg' runs pkg/__main__.py, which names no script of the user's
            if cand and str(cand).endswith('.py') and Path(cand).stem != '__main__':
                stem = Path(cand).stem
                break
        first = Path.cwd() / f'{stem}-plot.png'
    if nfig == 1:
        return [first]
    return [first.with_name(f'{first.stem}-{k}{first.suffix}') for k in range(nfig)]


def _save_headless(plt, figs: list, subPlots: bool, announce: str) -> list[Path]:
    global _headless_pending
    paths = _headless_paths(len(figs))
    for fig, path in zip(figs, paths, strict=True):
        fig.savefig(path)
        plt.close(fig)  # never shown, so do not let pyplot keep it alive
        print(f'plot: {announce} {path}')
    _headless_pending = {'subPlots': subPlots, 'signature': (_nrows(), tuple(data)), 'paths': paths}
    return paths


def _refresh_headless():
    """Re-save the last headless figure if ``data`` changed since; registered with ``atexit``.

    Scripts usually call ``plot.plot()`` before ``O.run()``, when there is no data yet; on screen
    the window would fill up live, headless this rewrites the PNG with the final history.
    """
    pending = _headless_pending
    if not pending or not plots or pending['signature'] == (_nrows(), tuple(data)):
        return
    try:
        plt, _ = _pyplot_headless()
        figs, _ = _make_figures(plt, pending['subPlots'])
        _save_headless(plt, figs, pending['subPlots'], 'figure updated with the final data in')
    except Exception as e:  # at interpreter exit a plotting problem must not end in a traceback
        print(f'plot: could not update {pending["paths"][0]}: {e}')


atexit.register(_refresh_headless)  # a no-op unless a headless plot() happened


def plot(noShow=False, subPlots=True):
    """Draw ``plots`` from ``data`` with matplotlib.

    :param noShow: return the figure instead of showing it: one ``matplotlib.figure.Figure``, or a
        list of them when ``subPlots`` is False and there are several plots (as YADE).
    :param subPlots: all plots as subplots of one figure (grid of ceil(sqrt(n)) rows); otherwise
        one figure per ``plots`` entry.

    With a display and an interactive backend the figures are shown without blocking (figures of
    the previous call are closed first).  Headless -- no ``DISPLAY``/``WAYLAND_DISPLAY``, or a
    non-interactive backend such as Agg -- nothing is shown: the figure is written to
    ``<script stem>-plot.png`` in the current directory (``<stem>`` is the running ``.py`` script's
    name, ``granum`` when there is none; set ``plot.headlessFile`` to choose the path), with ``-0``,
    ``-1``... inserted for several figures, and one line is printed saying where.  If ``data``
    changes afterwards the file is rewritten at interpreter exit, so it shows the final history.
    Columns missing from ``data`` are skipped with one warning.  Returns None unless ``noShow``.
    """
    if not plots:
        warnings.warn('plot: plot.plots is empty, nothing to plot', stacklevel=2)
        return None
    plt, headless = _pyplot_headless()
    figs, skipped = _make_figures(plt, subPlots)
    if skipped:
        why = 'plot.data is still empty' if not data else 'skipped: ' + ', '.join(skipped)
        warnings.warn(f'plot: {why}', stacklevel=2)
    if noShow:
        return figs[0] if len(figs) == 1 else figs
    from granum.yade import view

    if view.current() is not None:   # the browser view's page shows them, updated while `live`
        view.current().show_plots()
    if headless:
        _save_headless(plt, figs, subPlots, 'no display, figure saved to')
        return None
    for fig in _shown_figures:
        plt.close(fig)
    _shown_figures[:] = figs
    plt.show(block=False)
    plt.pause(0.001)  # let the GUI event loop draw the windows before the script goes on
    return None
