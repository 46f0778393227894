"""``yade.config``: what this build of the framework has.

YADE writes this module when it is compiled; granum fills it from what the installed package really
holds. Scripts read ``features`` to decide what they may use (``if 'VTK' in features: ...``), so the list
names only what granum does:

- ``LOGGER``: :mod:`yade.log` filters messages per class name (onto Python's :mod:`logging`);
- ``VTK``: ``VTKRecorder`` and ``export`` write VTK files (granum's own writers, without the VTK library);
- ``OPENMP``: the kernels run on several threads (Numba's thread pool, ``granum -j N``, ``O.numThreads``).

Everything else of YADE's list (``QT5``, ``CGAL``, ``GTS``, ``MPI``, ``PFVFLOW``, ``POTENTIAL_PARTICLES``,
``COMPLEX_MP``, ``MPFR``...) is absent because granum has no counterpart. Real numbers are IEEE doubles
only: ``highPrecisionDecimalPlaces`` is 15 and there is no ``RealHP<N>`` beyond ``N = 1``, hence no mpmath
(``highPrecisionMpmath`` is False; YADE's double build sets it because it also offers long double).
"""

from __future__ import annotations

import os
import sys

import granum

#: the capabilities of this build, in YADE's spelling (upper case)
features: list[str] = ["LOGGER", "VTK", "OPENMP"]

#: granum's version (YADE puts its own release here, e.g. '2023.02a')
version: str = granum.__version__
revision: str = granum.__version__

#: the Python installation granum runs from (YADE: its install prefix, e.g. '/usr')
prefix: str = sys.prefix
#: YADE's builds have a suffix ('-double', '-mpfr150'...); granum has one build, so none
suffix: str = ""
#: the folder of the installed granum package (YADE: the folder of its shared libraries)
libDir: str = os.path.dirname(os.path.abspath(granum.__file__))
#: libDir relative to prefix where it lies inside it, else the absolute folder
libPATH: str = os.path.relpath(libDir, prefix) if libDir.startswith(prefix + os.sep) else libDir
#: the folder that holds the granum package (a source checkout for an editable install)
sourceRoot: str = os.path.dirname(libDir)
#: C++ standard library path given at configure time: granum has no C++, so empty (as YADE's default)
libstdcxx: str = ""
#: the per-user configuration folder
confDir: str = os.path.join(os.path.expanduser("~"), ".config", "granum")
#: the configuration folder of older versions (YADE: ~/.yade-SUFFIX); granum has had no other
oldConfDir: str = os.path.join(os.path.expanduser("~"), ".granum")

#: the precision of Real: IEEE 754 double
highPrecisionName: str = "PrecisionDouble"
highPrecisionDecimalPlaces: int = 15
#: significand bits of Real (YADE's double build reports its configure default, 64, here)
highPrecisionBits: int = 53
#: whether Real needs mpmath on the Python side: never, doubles are Python floats
highPrecisionMpmath: bool = False

metadata: dict = {
    "short_desc": "YADE-compatible discrete element framework in Python (NumPy + Numba)",
    "long_desc": ("granum runs YADE scripts unmodified on a structure-of-arrays core compiled with Numba.\n\n"
                  f"This is version {version} with features {','.join(features)}."),
    "author": "granum developers",
    "license": "GPL-2.0-or-later",
}
