"""YADE's 3D view, controller, inspector and live plots, in the browser (``pip install granum[view]``).

``qt.View()`` in the interactive prompt or in Jupyter, and every script run as ``granum --view
script.py``, serve one page on ``127.0.0.1`` (``--view-host`` chooses another interface) at a free port,
with a random access token in the URL printed (requests without it are refused), and open the browser
when there is a display. A script run as plain ``granum script.py`` opens no port: ``qt.View()`` prints
how to see the view and gives the headless camera of :mod:`granum.yade.snapshot` as before.

Modules: :mod:`frames` (the arrays drawn, NumPy only), :mod:`session` (the link to ``O``: frames between
compiled chunks, commands, plots), :mod:`app` (the trame page, drawn by vtk.js).
"""

from __future__ import annotations

import os
import secrets
import sys

INSTALL_HINT = "the browser view needs the view extra: python -m pip install 'granum[view]' (trame, trame-vtk)"

_allowed: bool | None = None   # None: decided from the context (interactive or not)
_host = "127.0.0.1"
_session = None
_hinted = False


def allow(host: str = "127.0.0.1") -> None:
    """Let ``qt.View()`` serve the page (``granum --view``, the interactive prompt), on ``host``."""
    global _allowed, _host
    _allowed, _host = True, host


def forbid() -> None:
    """``qt.View()`` opens no port (a plain ``granum script.py``): it prints how to see the view."""
    global _allowed
    _allowed = False


def _interactive() -> bool:
    """An interactive prompt or a Jupyter kernel (not a script run by the launcher)."""
    if hasattr(sys, "ps1") or sys.flags.interactive:
        return True
    ipython = sys.modules.get("IPython")
    return bool(ipython is not None and getattr(ipython, "get_ipython", lambda: None)())


def allowed() -> bool:
    return _allowed if _allowed is not None else _interactive()


def current():
    """The served view's :class:`session.Session`, or None."""
    return _session


def request() -> None:
    """What ``qt.View()`` does beyond the camera: serve the page if allowed, else say how to see it."""
    global _hinted
    if allowed():
        open_view()
    elif not _hinted:
        _hinted = True
        print("granum: qt.View() opens no port in a script run; to see the view in a browser run "
              "`granum --view script.py` (optional: --view-host)", file=sys.stderr)


def _require():
    try:
        import trame  # noqa: F401
        import trame_vtk  # noqa: F401
    except ImportError as e:
        raise ImportError(INSTALL_HINT) from e


def _has_display() -> bool:
    if sys.platform in ("darwin", "win32"):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def open_view(open_browser: bool | None = None):
    """Serve the page (once per process) and return its session; print the URL with its token."""
    global _session
    if _session is not None:
        return _session
    _require()
    from granum.yade.omega import O
    from granum.yade.snapshot import RENDERER
    from granum.yade.view.app import serve
    from granum.yade.view.session import Session

    session = Session(O, RENDERER)
    token = secrets.token_urlsafe(24)
    port = serve(session, _host, token)
    shown = f"[{_host}]" if ":" in _host else _host
    session.url = f"http://{shown}:{port}/?token={token}"
    O.chunk_hooks.append(session.between_chunks)
    _session = session
    from granum.yade import plot

    plot.live = True   # YADE's default when there is a display to plot on
    if plot._headless_pending is not None or plot._shown_figures:   # plot.plot() came first
        session.show_plots()
    print(f"granum view: {session.url}", file=sys.stderr)
    if _host in ("127.0.0.1", "localhost", "::1"):
        print(f"  from another machine: ssh -L {port}:127.0.0.1:{port} HOST, then open the URL above",
              file=sys.stderr)
    if _in_notebook():
        from IPython.display import IFrame, display

        display(IFrame(session.url, width="100%", height=600))
    elif open_browser if open_browser is not None else _has_display():
        import webbrowser

        webbrowser.open(session.url)
    return session


def _in_notebook() -> bool:
    """A Jupyter kernel (the page is shown in the notebook, under the cell)."""
    ipython = sys.modules.get("IPython")
    shell = ipython.get_ipython() if ipython is not None and hasattr(ipython, "get_ipython") else None
    return type(shell).__name__ == "ZMQInteractiveShell"


def close_view() -> None:
    """Stop serving the page (its port closes) and take the view's hook off ``O``."""
    global _session
    session, _session = _session, None
    if session is None:
        return
    import asyncio

    session.close()
    if session.loop is not None and session.server is not None:
        asyncio.run_coroutine_threadsafe(session.server.stop(), session.loop).result(10)
