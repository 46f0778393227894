"""Base material classes: ``Material`` (density) and ``ElastMat`` (elastic moduli).

Material parameters are stored in the scene's material table, one column per
parameter name (see :func:`granum.physics.registry.material_columns`); compiled code
reads them through the column indices exported here.
"""

from __future__ import annotations

from granum.physics import registry
from granum.physics.registry import MaterialKind, Param, Range

#: a material parameter that must not be negative (a stiffness, a damping, a density) [any unit]
NON_NEGATIVE = Range(0.0)

registry.register_material(MaterialKind(
    "Material", None,
    (Param("density", 1000.0, "Density [kg/m^3] (0: a massless body, which must then be fixed)",
           valid=Range(0.0, why="a negative density gives a negative mass")),),
    doc="Base material: density only."))
registry.register_material(MaterialKind(
    "ElastMat", "Material",
    (Param("young", 1e9, "Young's modulus [Pa] (0: contacts without normal stiffness)",
           valid=Range(0.0, why="a negative Young's modulus makes contacts pull the bodies together")),
     Param("poisson", 0.25, "Poisson's ratio, or the ratio of shear to normal contact stiffness [-]",
           valid=Range(0.0, why="granum's linear laws take it as the ratio ks/kn, and a negative shear "
                                "stiffness would push along the slip"))),
    doc="Elastic material."))


def column(name: str) -> int:
    """Index of material parameter column ``name`` in the compiled material table."""
    return registry.material_columns().index(name)


M_DENSITY = column("density")
M_YOUNG = column("young")
M_POISSON = column("poisson")
