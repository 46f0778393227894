"""``yade.ymport``: import of particles and surfaces from files (not available yet).

The functions exist so that ``from yade import ymport`` works; calling one explains
that the importer is not implemented in this version of granum.
"""

from __future__ import annotations


def _missing(name):
    def f(*args, **kw):
        raise NotImplementedError(f"ymport.{name} is not implemented in granum yet")

    f.__name__ = name
    return f


stl = _missing("stl")
gts = _missing("gts")
gmsh = _missing("gmsh")
textFacets = _missing("textFacets")
text = _missing("text")
textClumps = _missing("textClumps")
