"""YADE's example scripts, run unmodified under granum, agree with real YADE 2023.02a on the quantities the
table ``tools/yade_examples.toml`` names (reference values from YADE in tests/reference/yade/examples)."""

import importlib.util
import json
import os
import sys

import pytest

TOOLS = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "tools", "yade_examples.py")
_spec = importlib.util.spec_from_file_location("yade_examples", TOOLS)
harness = importlib.util.module_from_spec(_spec)
sys.modules["yade_examples"] = harness  # its dataclasses look their module up there
_spec.loader.exec_module(harness)

TABLE = harness.load_table()


@pytest.mark.skipif(not os.path.isdir(harness.EXAMPLES), reason="YADE's examples are not installed")
@pytest.mark.parametrize("example", TABLE, ids=[e.path for e in TABLE])
def test_example_agrees_with_yade(example):
    with open(harness.reference_path(example)) as f:
        ref = json.load(f)
    got = harness.run(example, "granum")
    assert got["returncode"] == 0, got["output"]
    assert got["iter"] == ref["iter"] or not example.same_iter
    bad = [row for row in harness.compare(example, got, ref) if row[3]]
    assert not bad, "\n".join(f"{name}: granum {g}, YADE {r}: {why}" for name, g, r, why in bad)


def test_the_table_refuses_an_unknown_field(tmp_path):
    table = tmp_path / "t.toml"
    table.write_text('[[example]]\npath = "a.py"\nstep = 3\n')
    with pytest.raises(ValueError, match=r"unknown field\(s\) \['step'\]"):
        harness.load_table(str(table))


def test_the_play_button_is_made_explicit(tmp_path):
    """A bounded O.run(n) in the script runs its n steps before the script goes on; an unbounded one is left to
    the appended steps (so the probes see a finished, deterministic run)."""
    folder = tmp_path / "ex"
    folder.mkdir()
    (folder / "s.py").write_text("O.dt = 1e-3\nO.run(7)\nseen = O.iter\nO.run()\n")
    example = harness.Example(path="ex/s.py", steps=5, probes={"seen": "seen", "iter": "O.iter"})
    got = harness.run(example, "granum", examples_dir=str(tmp_path))
    assert got["returncode"] == 0, got["output"]
    assert got["probes"] == {"seen": 7, "iter": 12}


def test_max_iter_stops_the_scripts_runs(tmp_path):
    """With max_iter, the script's bounded runs stop at that iteration and the later ones do nothing (a script
    that loops over O.run(n, True) calls is cut short); unbounded runs are still left to the appended steps."""
    folder = tmp_path / "ex"
    folder.mkdir()
    (folder / "s.py").write_text("O.dt = 1e-3\nseen = []\nfor k in range(4):\n    O.run(4, True)\n"
                                 "    seen.append(O.iter)\nO.run()\n")
    example = harness.Example(path="ex/s.py", steps=2, max_iter=10, probes={"seen": "seen", "iter": "O.iter"})
    got = harness.run(example, "granum", examples_dir=str(tmp_path))
    assert got["returncode"] == 0, got["output"]
    assert got["probes"] == {"seen": [4, 8, 10, 10], "iter": 12}


def test_a_probe_outside_its_tolerance_is_reported():
    example = harness.Example(path="x.py", probes={"a": "", "b": "", "c": ""}, rtol=1e-3,
                              tolerances={"b": {"rtol": 0.1}})
    got = {"probes": {"a": [1.0, 2.0], "b": 1.05, "c": {"exception": "NameError", "message": "x"}}}
    ref = {"probes": {"a": [1.0, 2.01], "b": 1.0, "c": 3.0}}
    reasons = {name: why for name, _, _, why in harness.compare(example, got, ref)}
    assert reasons["a"].startswith("2.0 vs 2.01") and reasons["b"] == "" and reasons["c"].startswith("exception")
