"""The ``granum`` command: run a YADE script headless, or open an interactive prompt.

``granum script.py [args]`` runs the script in a YADE namespace and exits when it
returns (like ``yade -n -x``); ``-j N`` sets the number of compute threads;
``granum`` alone opens an IPython prompt with the same namespace;
``granum batch TABLE script.py`` runs a parametric study (see :mod:`granum.batch`).
"""

from __future__ import annotations

import argparse
import gc
import importlib.abc
import importlib.util
import os
import sys
import time
import types


class _YadeAlias(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Resolve ``yade`` and ``yade.*`` to ``granum.yade``, ``gts`` (PyGTS, which YADE scripts import) to
    ``granum.yade.gts`` and the top-level ``bf`` to ``granum.yade.bf`` (installed by the launcher only): YADE's
    launcher puts its package folder on ``sys.path``, and its breakage examples ``from bf import ...``."""

    #: top-level names of yade submodules that YADE's scripts import without ``yade.``
    TOP_LEVEL = ("bf", "gts")

    def find_spec(self, fullname, path=None, target=None):
        top = fullname.split(".")[0]
        if fullname == "yade" or fullname.startswith("yade.") or top in self.TOP_LEVEL:
            return importlib.util.spec_from_loader(fullname, self)
        return None

    def create_module(self, spec):
        name = spec.name if spec.name.split(".")[0] == "yade" else "yade." + spec.name
        return importlib.import_module("granum." + name)

    def exec_module(self, module):
        sys.modules[module.__spec__.name] = module


def install_yade_alias() -> None:
    """Let scripts ``import yade`` (this process only; a real YADE elsewhere is not shadowed)."""
    if not any(isinstance(f, _YadeAlias) for f in sys.meta_path):
        sys.meta_path.insert(0, _YadeAlias())


def _parser() -> argparse.ArgumentParser:
    from granum import __version__

    p = argparse.ArgumentParser(prog="granum", description="Run a YADE script with granum.",
                                epilog="granum batch TABLE SCRIPT runs a parametric study (granum batch -h).")
    p.add_argument("-j", "--threads", type=int, default=None, help="number of compute threads (default: all cores)")
    p.add_argument("-n", action="store_true", help="accepted for YADE compatibility (granum is always headless)")
    p.add_argument("-x", action="store_true", help="accepted for YADE compatibility (exit when the script ends)")
    p.add_argument("--wait", action="store_true",
                   help="when the script returns with a run going on in the background (O.run()), let it go on "
                        "until the script's own hooks pause it (or Ctrl-C); without it the run stops there")
    p.add_argument("--view", action="store_true",
                   help="serve a live 3D view, controller and plots of the script's scene in the browser "
                        "(needs granum[view]); the URL printed holds an access token; Ctrl-C quits")
    p.add_argument("--view-host", default="127.0.0.1", metavar="HOST",
                   help="interface the view listens on (default 127.0.0.1, loopback only: use an SSH tunnel)")
    p.add_argument("--version", action="version", version=f"granum {__version__}")
    p.add_argument("script", nargs="?", help="YADE script to run")
    p.add_argument("args", nargs=argparse.REMAINDER, help="arguments passed to the script as sys.argv[1:]")
    return p


def _set_threads(n: int | None) -> None:
    if n is None:
        return
    if n < 1:
        raise SystemExit("granum: -j needs a positive number of threads")
    # numba fixes the size of its thread pool when it is first imported
    os.environ["NUMBA_NUM_THREADS"] = str(max(n, os.cpu_count() or 1))
    import numba

    import granum._jit  # noqa: F401  (chooses the threading layer before the pool starts)

    numba.set_num_threads(n)


def freeze_imported() -> None:
    """Move the objects of the modules imported so far (granum's, Numba's, NumPy's: about 90,000 tracked objects,
    which live until the process ends) out of the cyclic garbage collector's reach: it no longer walks them, neither
    in the collections of a run nor in the several collections of the interpreter's exit, which took 0.2 s of a
    two-sphere script's 0.85. Objects made afterwards (the script's, the prompt's) are collected as ever."""
    gc.freeze()


def run_script(path: str, argv: list[str], threads: int | None = None) -> None:
    """Execute a YADE script as ``__main__`` with the YADE namespace (``threads``: the -j option, for
    ``opts.threads``)."""
    install_yade_alias()
    import granum.yade as gy

    freeze_imported()
    with open(path, encoding="utf-8") as fh:
        source = fh.read()
    module = types.ModuleType("__main__")
    module.__dict__.update(gy.namespace())
    module.__file__ = os.path.abspath(path)
    module.__builtins__ = __builtins__
    sys.modules["__main__"] = module
    sys.argv = [path] + list(argv)
    gy.opts.script = path
    gy.opts.threads = threads
    gy.opts.args[:] = sys.argv   # the same list as the namespace's `args`, as in YADE
    sys.path.insert(0, os.path.dirname(os.path.abspath(path)))
    gy.O._namespace = module.__dict__
    exec(compile(source, path, "exec"), module.__dict__)


def interactive() -> None:
    """An interactive prompt with the YADE namespace (IPython when installed)."""
    install_yade_alias()
    import granum.yade as gy

    freeze_imported()
    ns = gy.namespace()
    gy.O._namespace = ns
    banner = "granum: YADE-compatible DEM. O, utils, pack, plot ... are available."
    try:
        from IPython import start_ipython
    except ImportError:
        import code

        code.interact(banner=banner, local=ns)
        return
    start_ipython(argv=[], user_ns=ns, display_banner=False)


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["batch"] and not os.path.isfile("batch"):
        from granum.batch import main as batch_main

        return batch_main(argv[1:])
    args = _parser().parse_args(argv)
    _set_threads(args.threads)
    from granum.yade import view

    if args.script is None or args.view:
        view.allow(args.view_host)   # a view asked for: the prompt, or --view
    else:
        view.forbid()                # a script run opens no port
    if args.script is None:
        interactive()
        return 0
    if not os.path.exists(args.script):
        print(f"granum: no such script: {args.script}", file=sys.stderr)
        return 2
    if args.view:
        view.open_view()
    run_script(args.script, args.args, args.threads)
    if args.view:
        return serve_until_interrupted()
    return finish_background_run(args.wait)


def serve_until_interrupted() -> int:
    """``--view``: the script has returned; the page stays up (the run goes on if it was started) until
    Ctrl-C, which stops a run at a step boundary and ends the process."""
    from granum.yade import O

    print("granum view: the script has returned; Ctrl-C quits", file=sys.stderr)
    try:
        while True:
            time.sleep(3600)
    except KeyboardInterrupt:
        O.pause()
        O.wait()
    return 0


def finish_background_run(wait: bool) -> int:
    """What happens to a background run (``O.run()``) still going on when the script returns: it stops at
    the next step boundary, as under ``yade -x`` (the process must not end while compiled threads run), or
    with ``wait`` goes on until paused (Ctrl-C pauses it). The exit status: 1 if the run failed."""
    from granum.yade import O

    if not O.running:
        return 0
    if not wait:
        O.pause()
    try:
        O.wait()
    except KeyboardInterrupt:
        O.pause()
        O.wait()
    except Exception:  # noqa: BLE001 - the run's thread printed the traceback when it failed
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
