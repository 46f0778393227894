"""Reference output of yade.plot's text writers, produced by real YADE.

Regenerate from this directory with ``yade -n -x make_reference.py``.  tests/test_plot.py imports
``record`` and ``write`` from here and runs them against granum.yade.plot, so both sides execute
exactly the same calls; only the ``# created ...`` line of the gnuplot file (a clock) may differ.
"""


def record(plot, vector3):
    """Fill plot.data / plot.plots / plot.labels; ``vector3`` builds a 3-vector (Vector3 in YADE)."""
    plot.reset()
    plot.labels = {'Ek': '$E_k$', 'i ': 'step'}
    plot.plots = {'i': ('Ek', None, ('w', 'r--')), 'i ': ('unb',), 't': ('v_x', 'v_z')}
    plot.addData(i=0, t=0.0, Ek=0.0, w=-1.5e-7)
    plot.addData(i=10, t=1e-4, unb=0.5)                        # new column, back-filled with nan
    plot.addData({'Ek': 2.25, 'my col': 3}, i=20, t=0.1 + 0.2)  # dict positional argument
    plot.addData()                                             # a row of nan only
    plot.addData(i=30, t=1.23456789012345e20, v=vector3(1, -2, 3.5), ok=True, unb=-7)


def write(plot, prefix=''):
    """Write every reference file under ``prefix``."""
    plot.saveDataTxt(prefix + 'data.txt')
    plot.saveDataTxt(prefix + 'data-vars.txt', vars=('t', 'i', 'Ek'))
    plot.saveDataTxt(prefix + 'data-headers.txt', headers={'material': 'FrictMat', 'n': 3})
    plot.saveDataTxt(prefix + 'data.txt.bz2')
    return [plot.saveGnuplot(prefix + 'gp'), plot.saveGnuplot(prefix + 'gp-png', term='png', title='T',
                                                                comment='two\nlines')]


if __name__ == '__main__':
    from yade import Vector3, plot

    record(plot, Vector3)
    write(plot)
