"""Edits of a scene's structure while it runs in another thread.

``O.bodies.append``/``erase`` and the like grow or rewrite the arrays a background run is reading; from
another thread (a script editing bodies while ``O.run()`` goes on) they would race the compiled kernels.
Such an edit pauses the run at its next step boundary, applies the change and resumes the run, as
``O.save`` does (``Omega._paused``); from the run's own thread (a PyRunner) it applies at once.
"""

from __future__ import annotations

import functools


def pauses_the_run(method):
    """Decorate a method of a container holding ``_omega`` that changes the scene's structure."""

    @functools.wraps(method)
    def edit(self, *args, **kw):
        with self._omega._paused():
            return method(self, *args, **kw)

    return edit
