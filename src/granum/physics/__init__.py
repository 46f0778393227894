"""Pure per-contact and per-body physics, registered with :mod:`granum.physics.registry`.

Importing this package registers the built-in shapes' bounds and geometries, the
materials and the contact laws. A new contact law is a new module here plus one
import line below.
"""

import importlib

from granum.physics import (  # noqa: F401  (imported for their registrations)
    box,
    facet,
    frict,
    l3geom,
    materials,
    mindlin,
    sphere,
    viscel,
    wall,
)

# Registered after the others because the contact pool's history columns come in registration order: a plan
# is as wide as the last group it uses, so these laws' groups (ScGeom6D, cohesion) come after the older ones
# and leave their pools as narrow as they were.
importlib.import_module("granum.physics.cohfrict")   # ScGeom6D (physics.scgeom6d) and the cohesive law
