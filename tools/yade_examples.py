"""Run YADE's example scripts unmodified under granum and compare them with real YADE.

The scripts are not part of granum: they are read from Debian's ``yade`` package
(``/usr/share/doc/yade/examples``) or from ``--examples``. The table ``tools/yade_examples.toml`` says, per
script, how many steps to run after the script's own text (``O.run(steps, True)``, for scripts that leave the
run to YADE's play button or run without end) and which quantities to compare (``probes``: Python
expressions evaluated in the script's namespace after the run). See the table's header for its fields.
YADE's play button is made explicit: while the script's text runs, a bounded ``O.run(n)`` runs its n steps to
the end before the script goes on (or up to the entry's ``max_iter``), and an unbounded ``O.run()`` is left to the
appended steps.

Each run happens in a fresh copy of the script's folder (scripts read their meshes and write their outputs
next to themselves), in a process of its own:

- under granum, the script's text unmodified;
- under real YADE (``yade -n -x``, one thread), the same text with ``yade.qt`` replaced by an object that takes
  every call and does nothing: YADE 2023.02a crashes under a virtual display on some scripts that open a 3D
  view, and the view does not change the physics.

    python tools/yade_examples.py --reference test/helix.py   # real YADE -> tests/reference/yade/examples/<slug>.json
    python tools/yade_examples.py test/helix.py               # granum, compared with the committed reference
    python tools/yade_examples.py                             # every table entry under granum
    python tools/yade_examples.py --spread 40 --program yade clumps/apply-buoyancy-clumps.py
        # the spread of the probes over 40 runs (for the tolerances of scripts that draw unseeded random numbers)
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import tomllib
from dataclasses import dataclass, field

HERE = os.path.dirname(os.path.abspath(__file__))
TABLE = os.path.join(HERE, "yade_examples.toml")
REFERENCE_DIR = os.path.join(os.path.dirname(HERE), "tests", "reference", "yade", "examples")
EXAMPLES = "/usr/share/doc/yade/examples"
RESULT_FILE = "_example_probes.json"


@dataclass(frozen=True)
class Example:
    """One entry of the table: a script, what to run after it, what to compare and how closely."""

    path: str
    steps: int = 0
    probes: dict[str, str] = field(default_factory=dict)
    rtol: float = 1e-6
    atol: float = 0.0
    #: per-probe tolerances overriding rtol/atol: {probe: {"rtol": .., "atol": ..}}
    tolerances: dict[str, dict[str, float]] = field(default_factory=dict)
    #: Python run after the script's text and before the appended steps (both under granum and YADE)
    before: str = ""
    timeout: float = 900.0
    #: whether both programs must end at the same O.iter (False where the script stops on a condition that a
    #: random packing reaches at another step)
    same_iter: bool = True
    #: > 0: the script's bounded runs stop at this O.iter (the later ones do nothing), for scripts that run
    #: longer than a reference run can take
    max_iter: int = 0
    #: files the script keeps between runs outside its folder (a ``memoizeDb`` in /tmp), removed before each run
    #: so that both programs start from the same state
    fresh: tuple[str, ...] = ()
    why: str = ""

    @property
    def slug(self) -> str:
        return self.path.removesuffix(".py").replace("/", "__")


_FIELDS = set(Example.__dataclass_fields__)


def load_table(path: str = TABLE) -> list[Example]:
    """The table's entries, with an error naming any unknown field (a typo must not pass silently)."""
    with open(path, "rb") as f:
        raw = tomllib.load(f)
    examples = []
    for k, entry in enumerate(raw.get("example", [])):
        if not isinstance(entry, dict):
            raise ValueError(f"{path}: example #{k + 1} is not a table")
        unknown = set(entry) - _FIELDS
        if unknown:
            raise ValueError(f"{path}: example #{k + 1} ({entry.get('path')}): unknown field(s) {sorted(unknown)}")
        examples.append(Example(**entry))
    slugs = [e.slug for e in examples]
    if len(set(slugs)) != len(slugs):
        raise ValueError(f"{path}: a script is listed twice")
    return examples


#: under YADE, ``yade.qt`` is replaced by an object that takes every call and attribute and does nothing
QT_STUB = (
    "import sys as _sys, yade as _yade\n"
    "class _NoView:\n"
    "    def __getattr__(self, name):\n"
    "        return self\n"
    "    def __call__(self, *args, **kw):\n"
    "        return self\n"
    "    def __setattr__(self, name, value):\n"
    "        pass\n"
    "_sys.modules['yade.qt'] = _yade.qt = _NoView()\n"
)


def driver_source(example: Example, script: str, stub_qt: bool = False) -> str:
    """The driver both programs run: the script's text in the driver's own namespace (the launcher's, with
    YADE's names), then ``before``, the appended steps and the probes, written as JSON."""
    probes = json.dumps(example.probes)
    return (
        (QT_STUB if stub_qt else "")
        + "import json as _json\n"
        "class _Omega:\n"
        "    # O with YADE's play button made explicit: a bounded O.run(n) runs to its end before the script\n"
        "    # goes on; an unbounded O.run() is left to the steps the harness appends\n"
        "    def __init__(self, omega):\n"
        "        object.__setattr__(self, '_omega', omega)\n"
        "    def run(self, nSteps=-1, wait=False):\n"
        "        if nSteps is not None and nSteps > 0:\n"
        + (f"            nSteps = min(nSteps, {example.max_iter} - self._omega.iter)\n" if example.max_iter else "")
        + "            if nSteps > 0:\n"
        "                self._omega.run(nSteps, True)\n"
        "    def __getattr__(self, name):\n"
        "        return getattr(self._omega, name)\n"
        "    def __setattr__(self, name, value):\n"
        "        setattr(self._omega, name, value)\n"
        "_O = O\n"
        "O = _Omega(_O)\n"
        f"exec(compile(open({script!r}).read(), {script!r}, 'exec'))\n"
        "O = _O\n"
        f"{example.before}\n"
        + (f"O.run({example.steps}, True)\n" if example.steps else "")
        + "def _plain(v):\n"
        "    if isinstance(v, (bool, int, str)) or v is None:\n"
        "        return v\n"
        "    try:\n"
        "        return float(v)\n"
        "    except (TypeError, ValueError):\n"
        "        return [_plain(x) for x in v]\n"
        "_out = {}\n"
        f"for _name, _expr in _json.loads({probes!r}).items():\n"
        "    try:\n"
        "        _out[_name] = _plain(eval(_expr))\n"
        "    except Exception as _e:\n"
        "        _out[_name] = {'exception': type(_e).__name__, 'message': str(_e)}\n"
        f"_json.dump({{'iter': O.iter, 'probes': _out}}, open({RESULT_FILE!r}, 'w'), indent=1)\n"
    )


def run(example: Example, program: str, examples_dir: str = EXAMPLES, granum: list[str] | None = None) -> dict:
    """Run ``example`` under ``program`` ("granum" or "yade"); its probes, iteration, exit status and output."""
    src = os.path.join(examples_dir, example.path)
    if not os.path.exists(src):
        raise FileNotFoundError(f"{src}: no such example script (is Debian's yade package installed?)")
    for kept in example.fresh:
        if os.path.exists(kept):
            os.remove(kept)
    with tempfile.TemporaryDirectory(prefix="granum-example-") as tmp:
        folder = os.path.join(tmp, "run")
        shutil.copytree(os.path.dirname(src), folder)
        script = os.path.join(folder, os.path.basename(src))
        driver = os.path.join(folder, "_example_driver.py")
        with open(driver, "w") as f:
            f.write(driver_source(example, script, stub_qt=program == "yade"))
        if program == "yade":
            cmd = ["yade", "-n", "-j1", "-x", driver]
        else:
            cmd = (granum or [sys.executable, "-m", "granum"]) + [driver]
        env = dict(os.environ, MPLBACKEND="Agg")
        try:
            proc = subprocess.run(cmd, cwd=folder, capture_output=True, text=True, timeout=example.timeout,
                                  env=env, stdin=subprocess.DEVNULL)
        except subprocess.TimeoutExpired:
            return {"returncode": None, "output": f"timed out after {example.timeout} s", "probes": {}}
        result = {"returncode": proc.returncode, "output": (proc.stdout + proc.stderr)[-4000:]}
        out = os.path.join(folder, RESULT_FILE)
        if os.path.exists(out):
            with open(out) as f:
                result.update(json.load(f))
        else:
            result["probes"] = {}
        return result


def _flat(v) -> list:
    if isinstance(v, list):
        return [x for item in v for x in _flat(item)]
    return [v]


def compare(example: Example, got: dict, ref: dict) -> list[tuple[str, object, object, str]]:
    """One row per probe: (name, granum's value, YADE's value, failure reason or "")."""
    rows = []
    for name in example.probes:
        g, r = got.get("probes", {}).get(name), ref["probes"].get(name)
        tol = {"rtol": example.rtol, "atol": example.atol, **example.tolerances.get(name, {})}
        reason = ""
        if isinstance(r, dict) or isinstance(g, dict):
            reason = "" if g == r else f"exception: granum {g}, YADE {r}"
        elif isinstance(r, (str, bool)) or r is None:
            reason = "" if g == r else "differs"
        else:
            gf, rf = _flat(g), _flat(r)
            if len(gf) != len(rf):
                reason = f"length {len(gf)} != {len(rf)}"
            else:
                for a, b in zip(gf, rf, strict=True):
                    # numpy's rule: the two tolerances add (math.isclose would take the larger)
                    if not isinstance(a, (int, float)) or not abs(a - b) <= tol["atol"] + tol["rtol"] * abs(b):
                        reason = f"{a!r} vs {b!r} (rtol {tol['rtol']}, atol {tol['atol']})"
                        break
        rows.append((name, g, r, reason))
    return rows


def reference_path(example: Example) -> str:
    return os.path.join(REFERENCE_DIR, example.slug + ".json")


def write_reference(example: Example, examples_dir: str) -> dict:
    result = run(example, "yade", examples_dir)
    if result["returncode"] != 0:
        raise RuntimeError(f"YADE failed on {example.path}:\n{result['output']}")
    version = subprocess.run(["yade", "--version"], capture_output=True, text=True).stdout.strip().splitlines()
    result = {"script": example.path, "steps": example.steps, "yade": version[-1] if version else "",
              "command": f"python tools/yade_examples.py --reference {example.path}",
              "iter": result["iter"], "probes": result["probes"]}
    os.makedirs(REFERENCE_DIR, exist_ok=True)
    with open(reference_path(example), "w") as f:
        json.dump(result, f, indent=1)
        f.write("\n")
    return result


def _short(v) -> str:
    text = json.dumps(v)
    return text if len(text) <= 40 else text[:37] + "..."


def print_spread(example: Example, program: str, runs: int, examples_dir: str) -> int:
    """Run ``example`` ``runs`` times under ``program``; print each numeric probe's least, greatest, mean and
    standard deviation over the runs and its lowest values. Returns how many runs failed."""
    values: dict[str, list[float]] = {}
    failed = 0
    for _ in range(runs):
        got = run(example, program, examples_dir)
        if got["returncode"] != 0:
            failed += 1
            continue
        for name, v in got.get("probes", {}).items():
            if isinstance(v, (int, float)) and not isinstance(v, bool):
                values.setdefault(name, []).append(float(v))
    print(f"{example.path} under {program}: {runs - failed} of {runs} runs")
    for name, v in values.items():
        v.sort()
        sd = statistics.stdev(v) if len(v) > 1 else 0.0
        print(f"  {name}: {v[0]:.6g} .. {v[-1]:.6g}, mean {statistics.mean(v):.6g}, sd {sd:.3g}; lowest "
              + ", ".join(f"{x:.6g}" for x in v[:4]))
    return failed


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("paths", nargs="*", help="table entries (paths under the examples folder); all if none")
    parser.add_argument("--reference", action="store_true", help="run real YADE and write the reference JSON")
    parser.add_argument("--examples", default=EXAMPLES, help="YADE's examples folder")
    parser.add_argument("--spread", type=int, default=0, metavar="N",
                        help="run each script N times under --program and print its numeric probes' spread")
    parser.add_argument("--program", choices=("granum", "yade"), default="granum", help="for --spread")
    args = parser.parse_args(argv)
    table = {e.path: e for e in load_table()}
    unknown = [p for p in args.paths if p not in table]
    if unknown:
        parser.error(f"not in {TABLE}: {', '.join(unknown)}")
    failures = 0
    for path in args.paths or list(table):
        example = table[path]
        if args.spread:
            failures += print_spread(example, args.program, args.spread, args.examples)
            continue
        if args.reference:
            ref = write_reference(example, args.examples)
            print(f"{path}: YADE ran {ref['iter']} steps -> {reference_path(example)}")
            continue
        with open(reference_path(example)) as f:
            ref = json.load(f)
        got = run(example, "granum", args.examples)
        if got["returncode"] != 0:
            failures += 1
            print(f"{path}: FAILED to run under granum\n{got['output']}")
            continue
        rows = compare(example, got, ref)
        bad = [r for r in rows if r[3]]
        failures += bool(bad) or (example.same_iter and got["iter"] != ref["iter"])
        agree = len(rows) - len(bad)
        print(f"{path}: granum {got['iter']} steps, YADE {ref['iter']}; {agree}/{len(rows)} probes agree")
        for name, g, r, reason in rows:
            print(f"  {'ok  ' if not reason else 'FAIL'} {name}: granum {_short(g)}  YADE {_short(r)}  {reason}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
