"""``yade.export``: export of the scene to files (not available yet).

``from yade import export`` works; the exporters are planned (VTK for ParaView).
"""

from __future__ import annotations


class VTKExporter:
    """Export spheres, facets and interactions to VTK files (not implemented yet)."""

    def __init__(self, baseName: str, startSnap: int = 0):
        raise NotImplementedError("export.VTKExporter is not implemented in granum yet")


def text(*args, **kw):
    raise NotImplementedError("export.text is not implemented in granum yet")
