"""granum: a discrete element method framework that runs YADE scripts.

The package is organised by lifetime and role of the code (see ARCHITECTURE.md):
``granum.core`` holds the structure-of-arrays storage, ``granum.physics`` the pure
per-contact functions, ``granum.kernels`` the compiled loops over arrays,
``granum.engines`` the thin engine objects and ``granum.yade`` the YADE-compatible
scripting layer (``from granum.yade import *``).
"""

__version__ = "0.1.0"
