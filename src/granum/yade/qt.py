"""YADE's ``yade.qt`` without a screen: views are cameras for pictures, windows do nothing.

* ``qt.View()`` opens a 3D "view": a camera framing the scene (see
  :class:`granum.yade.snapshot.View`), listed by ``qt.views()``; ``v.saveSnapshot('a.png')``
  renders a picture off-screen.
* ``qt.SnapshotEngine(fileBase='snap-', iterPeriod=100)`` saves pictures periodically, named as
  YADE names them (``snap-00000.png``...).
* ``qt.Renderer()`` returns the display options (``shape``, ``intrPhys``, ``bgColor``...), which
  the pictures honour.
* with a browser view (``granum --view``, the interactive prompt, Jupyter: see :mod:`granum.yade.view`) the
  3D view, the controller, the inspector and the live plots are one page; ``qt.Controller()`` and
  ``qt.Inspector()`` open that page too (they are part of it). Without one they do nothing.
"""

from __future__ import annotations

from granum.yade.snapshot import RENDERER, SnapshotEngine
from granum.yade.snapshot import View as GLViewer

__all__ = ["Controller", "GLViewer", "Inspector", "Renderer", "SnapshotEngine", "View", "close", "views"]

_views: list = []


class _Inert:
    """Accepts any attribute, call or assignment (windows that cannot open without a screen)."""

    def __init__(self, *args, **kw):
        self.__dict__.update(kw)

    def __getattr__(self, name):
        return _Inert()

    def __call__(self, *args, **kw):
        return _Inert()


def _scene():
    from granum.yade.omega import O

    return O._scene


def View(*args, **kw):
    """Open a 3D view: a camera framing the current scene, used by snapshots; return it.

    In the interactive prompt, in Jupyter and under ``granum --view``, the scene is also served live in
    the browser (:mod:`granum.yade.view`); in a plain script run no port is opened and a line says how to
    see the view."""
    from granum.yade import view

    v = GLViewer(_scene)
    _views.append(v)
    view.request()
    return v


def views() -> list:
    """The open views."""
    return list(_views)


def close() -> None:
    """Close all views."""
    _views.clear()


def Controller(*args, **kw):
    """Open the controller (part of the browser view's page; no effect without one)."""
    from granum.yade import view

    view.request()
    return _Inert()


def Inspector(*args, **kw):
    """Open the inspector (part of the browser view's page; no effect without one)."""
    from granum.yade import view

    view.request()
    return _Inert()


def Renderer(*args, **kw):
    """The display options shared by all views (YADE's ``OpenGLRenderer``)."""
    return RENDERER
