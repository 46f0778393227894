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
    mindlin_cdm,
    sphere,
    viscel,
    wall,
)

# Each law's history groups start right after the groups it combines with (register_history(after=...)),
# sharing columns with the other laws' groups, so a pool is only as wide as its own laws need.
importlib.import_module("granum.physics.cohfrict")   # ScGeom6D (physics.scgeom6d) and the cohesive law
importlib.import_module("granum.physics.cpm")        # the concrete particle model
