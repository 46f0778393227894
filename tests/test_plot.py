"""Tests of granum.yade.plot: data bookkeeping, YADE-identical text output, headless figures."""

import bz2
import gzip
import importlib.util
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

SRC = Path(__file__).resolve().parents[1] / 'src'
if importlib.util.find_spec('granum') is None:  # allow running from a checkout without installing
    sys.path.insert(0, str(SRC))

from granum.yade import plot  # noqa: E402

REF = Path(__file__).parent / 'reference' / 'yade' / 'plot'


def _load_reference_script():
    spec = importlib.util.spec_from_file_location('plot_make_reference', REF / 'make_reference.py')
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)  # __name__ is not '__main__', so YADE is not imported
    return module


@pytest.fixture(autouse=True)
def fresh(tmp_path, monkeypatch):
    """Empty module state, work in a temporary directory, no exit-time rewrite left behind."""
    monkeypatch.chdir(tmp_path)
    plot.reset()
    plot.headlessFile = None
    yield
    plot._headless_pending = None
    plot.reset()
    import matplotlib.pyplot as plt
    plt.close('all')


def _same(a, b):
    return a == b or (isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b))


def _assert_columns(expected):
    assert list(plot.data) == list(expected)
    for name, values in expected.items():
        got = plot.data[name]
        assert len(got) == len(values) and all(map(_same, got, values)), (name, got, values)


# --- addData -------------------------------------------------------------------------------------

def test_addData_pads_missing_and_backfills_new_columns():
    nan = math.nan
    plot.addData(sigma=12, eps=1e-4)
    plot.addData(eps=1e-3)
    plot.addData(force=1e3)
    # same result YADE 2023.02a prints for its documentation example
    _assert_columns({'sigma': [12, nan, nan], 'eps': [1e-4, 1e-3, nan], 'force': [nan, nan, 1e3]})


def test_all_columns_keep_equal_length():
    rng = np.random.default_rng(3)
    names = [f'c{k}' for k in range(8)]
    for row in range(200):
        chosen = rng.choice(names, size=rng.integers(0, 4), replace=False)
        plot.addData(**{str(n): float(row) for n in chosen})
        lengths = {len(col) for col in plot.data.values()}
        assert len(lengths) <= 1
        if plot.data:
            assert lengths == {max(len(col) for col in plot.data.values())}
            # a value given in this row sits in the last row
            for n in chosen:
                assert plot.data[str(n)][-1] == row


def test_addData_empty_call_is_noop_on_empty_data_and_nan_row_otherwise():
    plot.addData()
    assert plot.data == {}
    plot.addData(a=1)
    plot.addData()
    _assert_columns({'a': [1, math.nan]})
    plot.splitData()
    assert len(plot.data['a']) == 3 and math.isnan(plot.data['a'][2])


def test_addData_dict_arguments_merge_and_keywords_win():
    plot.addData({'my col': 1.5, 'for': 0.3}, {'b': 2}, b=3)
    _assert_columns({'my col': [1.5], 'for': [0.3], 'b': [3]})
    with pytest.raises(TypeError):
        plot.addData(5)


def test_addData_vector_and_matrix_components():
    plot.addData(v=np.array([1.0, 2.0, 3.0]), w=np.array([4, 5]), m=np.arange(9.0).reshape(3, 3),
                 s=np.float64(2.5), k=np.int64(7))
    assert plot.data['v_x'] == [1.0] and plot.data['v_z'] == [3.0] and plot.data['w_y'] == [5.0]
    # YADE's Matrix3 column order: diagonal, upper triangle, lower triangle
    assert [k for k in plot.data if k.startswith('m_')] == [
        'm_xx', 'm_yy', 'm_zz', 'm_xy', 'm_xz', 'm_yz', 'm_yx', 'm_zx', 'm_zy']
    assert plot.data['m_yx'] == [3.0]
    assert type(plot.data['s'][0]) is float and type(plot.data['k'][0]) is int
    for bad in ((1, 2, 3), [1, 2], 'text', np.zeros(4)):
        with pytest.raises(ValueError, match='unhandled sequence type'):
            plot.addData(x=bad)


def test_reset_and_resetData():
    plot.plots = {'a': ('b',)}
    plot.labels = {'a': 'A'}
    plot.addData(a=1)
    plot.resetData()
    assert plot.data == {} and plot.plots == {'a': ('b',)} and plot.labels == {'a': 'A'}
    plot.reset()
    assert plot.data == {} and plot.plots == {} and plot.labels == {}


def test_reverseData():
    plot.addData(a=1)
    plot.addData(a=2, b=3)
    plot.reverseData()
    _assert_columns({'a': [2, 1], 'b': [3, math.nan]})


# --- saveDataTxt ---------------------------------------------------------------------------------

@pytest.mark.parametrize('name', ['out.txt', 'out.txt.bz2', 'out.txt.gz'])
def test_saveDataTxt_round_trip(name, tmp_path):
    for i in range(5):
        plot.addData(i=i, x=i * 0.1 + 1e-9, y=-i ** 2)
    plot.addData(x=7.5)
    plot.saveDataTxt(name)
    opener = {'.bz2': bz2.open, '.gz': gzip.open}.get(Path(name).suffix, open)
    with opener(tmp_path / name, 'rb') as f:
        raw = f.read()
    if name.endswith('.txt'):
        assert raw.startswith(b'# i\t\tx\t\ty\n')
    else:
        assert raw.startswith(b'# i') and (tmp_path / name).read_bytes()[:2] in (b'BZ', b'\x1f\x8b')
    table = np.genfromtxt(tmp_path / name, names=True)  # the use YADE's docstring promises
    assert table.dtype.names == ('i', 'x', 'y')
    for col in ('i', 'x', 'y'):
        np.testing.assert_array_equal(table[col], np.asarray(plot.data[col], dtype=float))


def test_saveDataTxt_vars_order_headers_and_unknown_column(tmp_path):
    plot.addData(z=1, a=2, M=3)
    plot.saveDataTxt('v.txt', vars=('z', 'a'), headers={'note': 'x y', 'n': 3})
    assert (tmp_path / 'v.txt').read_text() == '# note=\tx y\n# n=\t3\n# z\t\ta\n1\t2\n'
    plot.saveDataTxt('s.txt', vars={'z', 'M'})
    assert (tmp_path / 's.txt').read_text().splitlines()[0] == '# M\t\tz'
    with pytest.raises(KeyError):
        plot.saveDataTxt('bad.txt', vars=('a', 'nope'))
    assert not (tmp_path / 'bad.txt').exists()


def test_text_output_identical_to_yade(tmp_path):
    """Same calls as tests/reference/yade/plot/make_reference.py, files compared with YADE's."""
    ref = _load_reference_script()
    ref.record(plot, lambda *xyz: np.array(xyz, dtype=float))
    gnuplot_files = ref.write(plot, prefix=str(tmp_path) + '/')
    assert [Path(f).name for f in gnuplot_files] == ['gp.gnuplot', 'gp-png.gnuplot']
    for name in ('data.txt', 'data-vars.txt', 'data-headers.txt'):
        assert (tmp_path / name).read_text() == (REF / name).read_text(), name
    for name in ('data.txt.bz2', 'gp.data.bz2', 'gp-png.data.bz2'):
        assert bz2.decompress((tmp_path / name).read_bytes()) == bz2.decompress((REF / name).read_bytes())
    for name in ('gp.gnuplot', 'gp-png.gnuplot'):
        ours = (tmp_path / name).read_text(encoding='utf-8').splitlines()
        theirs = (REF / name).read_text(encoding='utf-8').splitlines()
        assert ours[2].startswith('# created ') and theirs[2].startswith('# created ')
        del ours[2], theirs[2]  # the creation time is the only line allowed to differ
        assert ours == theirs, name


# --- saveGnuplot ---------------------------------------------------------------------------------

def test_saveGnuplot_requires_data_and_handles_options(tmp_path):
    plot.plots = {'i': ('a',)}
    with pytest.raises(RuntimeError):
        plot.saveGnuplot('g')
    plot.addData(i=1, a=2)
    (tmp_path / 'sub').mkdir()
    assert plot.saveGnuplot('sub/g', term='png', extension='.png') == 'sub/g.gnuplot'
    text = (tmp_path / 'sub/g.gnuplot').read_text()
    assert "set output 'g.0.png'" in text and '"< bzcat g.data.bz2" using 2:1' in text
    name = plot.saveGnuplot('t', timestamp=True, varData=True)
    text = Path(name).read_text()
    assert name.startswith('t_') and 'dataFile="< bzcat t_' in text and '.data.bz2"\nset term' in text
    assert 'plot  dataFile using 2:1' in text


def test_saveGnuplot_skips_missing_columns_with_warning(tmp_path):
    plot.addData(i=1, a=2)
    plot.plots = {'i': ('a', 'nope'), 'absent': ('a',)}
    with pytest.warns(UserWarning):
        plot.saveGnuplot('m')
    text = (tmp_path / 'm.gnuplot').read_text()
    assert 'nope' not in text and 'absent' not in text and 'using 2:1' in text


# --- plot() --------------------------------------------------------------------------------------

def _fill(n=30):
    for i in range(n):
        plot.addData(i=i, a=math.sin(i / 4), b=1e4 * i, c=-i, kinetic=i * 0.5, gravWork=-i * 0.2)


def test_plot_headless_saves_png(tmp_path, capsys):
    _fill()
    plot.plots = {'i': ('a', None, ('b', 'r--')), 'i ': (('c', 'go-'),)}
    assert plot.plot() is None
    png = tmp_path / 'granum-plot.png'
    assert png.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n' and png.stat().st_size > 5000
    assert f'saved to {png}' in capsys.readouterr().out
    plot.headlessFile = str(tmp_path / 'chosen.png')
    plot.plot(subPlots=False)
    assert (tmp_path / 'chosen-0.png').stat().st_size > 0 and (tmp_path / 'chosen-1.png').stat().st_size > 0


def test_headless_png_rewritten_when_data_grows(tmp_path):
    plot.plots = {'i': ('a',)}
    with pytest.warns(UserWarning, match='empty'):
        plot.plot()  # typical script: plot before running, no data yet
    png = tmp_path / 'granum-plot.png'
    empty = png.read_bytes()
    plot._refresh_headless()
    assert png.read_bytes() == empty  # nothing changed, nothing rewritten
    _fill()
    plot._refresh_headless()  # what the atexit hook does
    assert png.read_bytes() != empty


def test_plot_noShow_returns_figures():
    from matplotlib.figure import Figure
    _fill()
    plot.plots = {'i': ('a', None, 'b'), 'i ': ('c',), ' i': ('kinetic',)}
    plot.labels = {'a': '$a$'}
    fig = plot.plot(noShow=True)
    assert isinstance(fig, Figure)
    main = [ax for ax in fig.axes if ax.get_subplotspec().get_geometry()[2] == 0]
    assert [ax.get_subplotspec().get_geometry()[:2] for ax in fig.axes][0] == (2, 2)  # YADE's grid
    assert sorted(line.get_label() for ax in main for line in ax.get_lines()) == ['$a$', 'b']
    figs = plot.plot(noShow=True, subPlots=False)
    assert isinstance(figs, list) and len(figs) == 3 and all(isinstance(f, Figure) for f in figs)
    plot.plots = {'i': ('a',)}
    assert isinstance(plot.plot(noShow=True, subPlots=False), Figure)  # a single one is not a list


def test_callable_and_dict_y_specs_expand():
    energy = {'kinetic': 0.0, 'gravWork': 0.0}
    _fill()
    plot.plots = {'i': ('a', None, energy.keys), 'c': (energy,)}
    fig = plot.plot(noShow=True)
    labels = [line.get_label() for ax in fig.axes for line in ax.get_lines()]
    assert labels == ['a', 'kinetic', 'gravWork', 'kinetic', 'gravWork']
    plot.saveGnuplot('e')
    assert "title 'kinetic(i) →' with lines axes x1y2" in Path('e.gnuplot').read_text()


def test_plot_missing_columns_warn_not_crash():
    _fill()
    plot.plots = {'i': ('a', 'nope', ('b', 'not-a-format!')), 'missing_x': ('a',)}
    with pytest.warns(UserWarning, match='nope.*missing_x|missing_x.*nope'):
        fig = plot.plot(noShow=True)
    assert [line.get_label() for line in fig.axes[0].get_lines()] == ['a', 'b']
    assert 'nope' not in plot.data  # plotting does not invent columns
    plot.plots = {}
    with pytest.warns(UserWarning, match='empty'):
        assert plot.plot() is None


def test_addAutoData_evaluates_plots():
    counter = {'n': 0}

    class Energy(dict):
        pass

    energy = Energy(kinetic=1.5)
    plot.plots = {'i=counter["n"]': ('2*3', None, 'named=len("abc")', energy.keys), 'x=1': (('1/0', 'r'),)}
    import __main__
    __main__.counter = counter  # addAutoData sees the running script's globals
    try:
        with pytest.warns(UserWarning, match='1/0'):
            plot.addAutoData()
    finally:
        del __main__.counter
    _assert_columns({'i': [0], '2*3': [6], 'named': [3], 'kinetic': [1.5], 'x': [1]})
    with pytest.warns(UserWarning, match='skipped: 1/0$'):
        fig = plot.plot(noShow=True)  # 'name=expr' entries plot the 'name' column
    assert fig.axes[0].get_xlabel() == 'i'
    assert [line.get_label() for line in fig.axes[0].get_lines()] == ['2*3']
    assert [line.get_label() for line in fig.axes[1].get_lines()] == ['named', 'kinetic']


def test_import_is_light():
    code = 'import sys, granum.yade.plot; assert "matplotlib.pyplot" not in sys.modules, "pyplot imported"'
    env_path = str(SRC)
    subprocess.run([sys.executable, '-c', f'import sys; sys.path.insert(0, {env_path!r}); {code}'],
                   check=True)
