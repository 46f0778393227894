"""The kinematic, force and field engines of tests/reference/yade/engines_extra.py: YADE 2023.02a's records,
step by step, and closed forms (harmonic motion, terminal velocity under drag, an orbit under central
acceleration), determinism, refused input."""

import math
import sys

import numpy as np
import pytest
from conftest import REFERENCE, reference

import granum.yade as y
from granum.yade import O


@pytest.fixture(scope="module")
def granum_runs():
    """The reference script's records, produced by granum (its ``dump`` captured instead of written)."""
    sys.path.insert(0, str(REFERENCE))
    try:
        import _common
        out = {}
        saved = _common.dump
        _common.dump = lambda topic, data: out.update(data)
        ns: dict = {}
        exec("from granum.yade import *", ns)
        exec(compile((REFERENCE / "engines_extra.py").read_text(), "engines_extra.py", "exec"), ns)
    finally:
        _common.dump = saved
        sys.path.remove(str(REFERENCE))
        O.reset()
    return out


RUNS = sorted(reference("engines_extra"))


@pytest.mark.parametrize("run", RUNS)
def test_as_yade_step_by_step(granum_runs, run):
    """Every body's pos, vel, angVel, ori, force and torque after every step, and the engine's changing
    attributes, equal YADE's to 1e-9 of the largest magnitude the quantity takes in the run. YADE's engines
    hand out their vector attributes by reference (the records all hold the last value), so those are
    compared after the last step only."""
    ref, got = reference("engines_extra")[run], granum_runs[run]
    assert "exception" not in got, got
    assert len(got) == len(ref)
    for key in ref[0]["state"][0]:
        r = np.array([[b[key] for b in rec["state"]] for rec in ref])
        g = np.array([[b[key] for b in rec["state"]] for rec in got])
        if key == "ori":  # q and -q are the same rotation
            g *= np.sign(np.sum(g * r, axis=-1, keepdims=True))
        np.testing.assert_allclose(g, r, rtol=0, atol=1e-9 * max(1.0, np.abs(r).max()), err_msg=f"{run}: {key}")
    for name, value in ref[-1]["attrs"].items():
        if isinstance(value, list):
            np.testing.assert_allclose(np.array(got[-1]["attrs"][name], float), value, rtol=1e-9, atol=1e-12,
                                       err_msg=f"{run}: {name}")
        else:
            r = np.array([rec["attrs"][name] for rec in ref], float)
            g = np.array([rec["attrs"][name] for rec in got], float)
            np.testing.assert_allclose(g, r, rtol=1e-9, atol=1e-12, err_msg=f"{run}: {name}")
