"""YADE's ``yade.qt`` without a screen: every call is accepted and does nothing.

3D views, controllers and renderers need a display; granum runs headless, so these
names exist for scripts that call them and have no effect (off-screen snapshots are
a separate feature).
"""

from __future__ import annotations


class _Inert:
    """Accepts any attribute, call or assignment."""

    def __init__(self, *args, **kw):
        self.__dict__.update(kw)

    def __getattr__(self, name):
        return _Inert()

    def __call__(self, *args, **kw):
        return _Inert()


def View(*args, **kw):
    """Open a 3D view (no effect without a screen)."""
    return _Inert()


def Controller(*args, **kw):
    """Open the controller window (no effect without a screen)."""
    return _Inert()


def Renderer(*args, **kw):
    """Rendering options (accepted, unused without a screen)."""
    return _Renderer


def views():
    return []


def close():
    """Close all views."""


_Renderer = _Inert()
