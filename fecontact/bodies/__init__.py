"""Bodies: the planar geometrically exact beam, elastic solids on scikit-fem meshes with their
materials, and planar rigid bodies. Each owns a slice of the model's dofs."""

from .beam import Beam2D, Material, Section
from .materials import LinearElastic, NeoHookean, StVenantKirchhoff
from .rigid import Disk, PointMass, Polygon, RigidBody2D
from .solid import Solid

__all__ = [
    "Beam2D",
    "Disk",
    "LinearElastic",
    "Material",
    "NeoHookean",
    "PointMass",
    "Polygon",
    "RigidBody2D",
    "Section",
    "Solid",
    "StVenantKirchhoff",
]
