"""``yade.ymport``: import of particles and surfaces from files (not available yet).

The functions exist so that ``from yade import ymport`` works; calling one explains
that the importer is not implemented in this version of granum.
"""

from __future__ import annotations

# clumps in YADE's x_y_z_r_clumpId text format (written by export.textClumps)
from granum.yade.clump_text import read as textClumps  # noqa: F401


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
