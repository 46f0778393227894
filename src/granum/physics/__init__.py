"""Pure per-contact and per-body physics, registered with :mod:`granum.physics.registry`.

Importing this package registers the built-in shapes' bounds and geometries, the
materials and the contact laws. A new contact law is a new module here plus one
import line below.
"""

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
