"""File output that does not depend on the YADE layer: atomic writes and VTK file formats.

* :mod:`granum.io.atomic` -- write a file completely or not at all (temporary file + ``os.replace``).
* :mod:`granum.io.vtkxml` -- VTK XML unstructured grids (``.vtu``), poly data (``.vtp``) and
  ParaView time collections (``.pvd``).
* :mod:`granum.io.vtklegacy` -- the legacy ASCII ``.vtk`` format (what YADE's ``export.VTKExporter``
  writes).
"""
