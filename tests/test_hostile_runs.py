"""Hostile or odd uses of O.run, labels and saving from a running engine: a clear error, or the documented
behaviour, never a run that goes on forever or a changed Python builtin."""

from __future__ import annotations

import builtins
import math

import pytest
from conftest import frict_engines


def _scene(y):
    y.O.bodies.append([y.sphere((0, 0, 0), .5, fixed=True), y.sphere((0, 0, .99), .5)])
    y.O.engines = frict_engines(y, gravity=(0, 0, -9.81))
    y.O.dt = 1e-5


@pytest.mark.parametrize("n", [math.nan, math.inf, -math.inf, 1.5, "10", True, None])
def test_run_refuses_a_step_count_that_is_no_whole_number(yade, n):
    _scene(yade)
    with pytest.raises(TypeError, match="nSteps"):
        yade.O.run(n, True)
    assert yade.O.iter == 0 and not yade.O.running


def test_run_with_no_positive_count_runs_until_paused(yade):
    """n <= 0 means 'until paused', as in YADE."""
    _scene(yade)
    yade.O.engines = yade.O.engines + [yade.PyRunner(iterPeriod=50, command="O.pause() if O.iter >= 200 else None")]
    yade.O.run(0, True)
    assert yade.O.iter == 201


def test_saving_from_an_engine_of_a_foreground_run_goes_on(yade, tmp_path):
    """O.save from a PyRunner while O.run(n, True) runs in the same thread (it used to fail on a missing
    background thread)."""
    _scene(yade)
    path = tmp_path / "periodic.yade"
    yade.O.engines = yade.O.engines + [yade.PyRunner(iterPeriod=20, command=f"O.save({str(path)!r})")]
    yade.O.run(100, True)
    assert yade.O.iter == 100 and path.exists()
    yade.O.load(path)
    assert yade.O.iter == 80   # saved by the PyRunner inside step 80, before that step ends (iter += 1)


def test_a_loaded_label_never_replaces_a_python_builtin(yade, tmp_path):
    _scene(yade)
    yade.O.engines = yade.O.engines + [yade.PyRunner(label="print", command="pass"),
                                       yade.PyRunner(label="len", command="pass")]
    yade.O.save(tmp_path / "labels.yade")
    yade.O.reset()
    yade.O.load(tmp_path / "labels.yade")
    assert builtins.print is print and builtins.len is len
    assert yade.O.labeledEngine("print").command == "pass"


def test_facet_options_granum_lacks_are_refused_not_ignored(yade):
    for kw, name in (({"noBound": True}, "noBound"), ({"chain": 3}, "chain")):
        with pytest.raises(NotImplementedError, match=name):
            yade.utils.facet([(0, 0, 0), (1, 0, 0), (0, 1, 0)], **kw)
    assert yade.utils.facet([(0, 0, 0), (1, 0, 0), (0, 1, 0)], noBound=False, chain=-1).shape is not None
