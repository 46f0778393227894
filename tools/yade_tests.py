"""Run YADE's own Python unit tests (the modules ``yade --test`` runs) unmodified under granum.

The test files are not part of granum: they are read from an installed YADE (Debian's ``libyade``
package puts them in ``/usr/lib/<arch>/yade-double/py/yade/tests``) or from ``--dir``. Each module
runs in a process of its own under the granum launcher, so a crash in one is reported without
hiding the others. The report gives run/pass/fail/error/skip per module, then each test that did
not pass with the first line of its error.

    python tools/yade_tests.py                 # every module of YADE's allTests list
    python tools/yade_tests.py core pbc        # some of them
    python tools/yade_tests.py --json out.json # also write the outcomes as JSON
"""

from __future__ import annotations

import argparse
import glob
import importlib.abc
import importlib.util
import json
import os
import subprocess
import sys
import types
import unittest

#: the modules of ``allTests`` in YADE 2023.02a's ``yade/tests/__init__.py``, in its order
ALL_TESTS = ("dummyTest", "wrapper", "core", "pbc", "clump", "cohesive-chain", "engines", "utilsModule",
             "libVersions", "testMinieigenHP", "testMath", "enumTest", "ymport-foamfiles")


def find_tests_dir() -> str | None:
    """YADE's test folder of an installed ``libyade`` (double precision first), or None."""
    for pattern in ("/usr/lib/*/yade-double/py/yade/tests", "/usr/lib/*/yade*/py/yade/tests"):
        found = sorted(glob.glob(pattern))
        if found:
            return found[0]
    return None


class _TestsFinder(importlib.abc.MetaPathFinder):
    """Resolve ``yade.tests.X`` to the files of YADE's test folder (ahead of granum's ``yade`` alias, which
    would look for them in granum)."""

    def __init__(self, folder: str):
        self.folder = folder

    def find_spec(self, fullname, path=None, target=None):
        if fullname.startswith("yade.tests."):
            return importlib.util.spec_from_file_location(
                fullname, os.path.join(self.folder, fullname.rsplit(".", 1)[1] + ".py"))
        return None


def _outcomes(result: unittest.TestResult, total: int) -> dict:
    def first_line(text: str) -> str:
        lines = [ln for ln in text.strip().splitlines() if ln.strip()]
        return lines[-1].strip() if lines else ""

    failed = {t.id(): first_line(tb) for t, tb in result.failures}
    errors = {t.id(): first_line(tb) for t, tb in result.errors}
    skipped = {t.id(): reason for t, reason in result.skipped}
    bad = len(failed) + len(errors) + len(skipped)
    return {"run": total, "passed": total - bad, "failed": failed, "errors": errors, "skipped": skipped}


def run_one(module: str, folder: str) -> dict:
    """Run one test module in this process (which the granum launcher started); its outcomes."""
    sys.meta_path.insert(0, _TestsFinder(folder))
    # the package itself without its __init__, which imports every yade module (gridpfacet, mpy...) to run
    # their doctests: only the test modules are run here
    package = types.ModuleType("yade.tests")
    package.__path__ = [folder]
    sys.modules["yade.tests"] = package
    sys.path.insert(0, folder)  # testMath and testMinieigenHP import testMathHelper as a top-level module
    try:
        mod = importlib.import_module("yade.tests." + module)
    except BaseException as exc:  # noqa: BLE001 - the report names whatever stopped the import
        return {"run": 0, "passed": 0, "failed": {}, "errors": {f"{module} (import)": f"{type(exc).__name__}: {exc}"},
                "skipped": {}}
    suite = unittest.defaultTestLoader.loadTestsFromModule(mod)
    result = unittest.TestResult()
    suite.run(result)
    return _outcomes(result, suite.countTestCases())


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("modules", nargs="*", help="modules of YADE's allTests (default: all)")
    p.add_argument("--dir", help="YADE's yade/tests folder (default: the installed libyade's)")
    p.add_argument("--json", help="write the outcomes to this file")
    p.add_argument("--one", help=argparse.SUPPRESS)  # internal: run this module here and print JSON
    args = p.parse_args(argv)
    folder = args.dir or find_tests_dir()
    if not folder or not os.path.isdir(folder):
        print("yade_tests: YADE's test folder not found; install Debian's libyade or give --dir", file=sys.stderr)
        return 2
    if args.one:
        # on a line of its own: a test may leave its last line unfinished (print(..., end=" "))
        print("\nYADE-TESTS-JSON " + json.dumps(run_one(args.one, folder)))
        return 0
    modules = args.modules or list(ALL_TESTS)
    report = {}
    for module in modules:
        proc = subprocess.run([sys.executable, "-m", "granum", os.path.abspath(__file__), "--dir", folder,
                               "--one", module], capture_output=True, text=True, timeout=1800)
        tagged = [ln for ln in proc.stdout.splitlines() if ln.startswith("YADE-TESTS-JSON ")]
        if tagged:
            report[module] = json.loads(tagged[-1].split(" ", 1)[1])
        else:
            tail = (proc.stderr.strip().splitlines() or ["(no output)"])[-1]
            report[module] = {"run": 0, "passed": 0, "failed": {}, "skipped": {},
                              "errors": {f"{module} (process)": f"exit {proc.returncode}: {tail}"}}
    print(f"{'module':<18} {'run':>4} {'pass':>5} {'fail':>5} {'error':>6} {'skip':>5}")
    for module, r in report.items():
        print(f"{module:<18} {r['run']:>4} {r['passed']:>5} {len(r['failed']):>5} {len(r['errors']):>6} "
              f"{len(r['skipped']):>5}")
    total = {k: sum(r[k] for r in report.values()) for k in ("run", "passed")}
    print(f"{'all':<18} {total['run']:>4} {total['passed']:>5}")
    for r in report.values():
        for kind in ("failed", "errors", "skipped"):
            for test, line in r[kind].items():
                print(f"  {kind[:4]} {test}: {line}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(report, fh, indent=1, sort_keys=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
