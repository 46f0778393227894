"""Base material classes: ``Material`` (density) and ``ElastMat`` (elastic moduli).

Material parameters are stored in the scene's material table, one column per
parameter name (see :func:`granum.physics.registry.material_columns`); compiled code
reads them through the column indices exported here.
"""

from __future__ import annotations

from granum.physics import registry
from granum.physics.registry import MaterialKind, Param

registry.register_material(MaterialKind(
    "Material", None, (Param("density", 1000.0, "Density [kg/m^3]"),),
    doc="Base material: density only."))
registry.register_material(MaterialKind(
    "ElastMat", "Material",
    (Param("young", 1e9, "Young's modulus [Pa]"),
     Param("poisson", 0.25, "Poisson's ratio, or the ratio of shear to normal contact stiffness [-]")),
    doc="Elastic material."))


def column(name: str) -> int:
    """Index of material parameter column ``name`` in the compiled material table."""
    return registry.material_columns().index(name)


M_DENSITY = column("density")
M_YOUNG = column("young")
M_POISSON = column("poisson")
