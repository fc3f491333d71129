"""Bodies: the planar and spatial geometrically exact beams, elastic solids on scikit-fem
meshes with their materials, planar rigid bodies and rigid bodies in space. Each owns a slice
of the model's dofs."""

from .beam import Beam2D, Material, Section
from .beam3d import Beam3D
from .materials import LinearElastic, NeoHookean, StVenantKirchhoff
from .rigid import Disk, PointMass, Polygon, RigidBody2D
from .rigid3d import RigidBody3D
from .shapes3d import Ball, Box, Capsule, ConvexMesh, Cylinder
from .solid import Solid

__all__ = [
    "Ball",
    "Box",
    "Capsule",
    "ConvexMesh",
    "Cylinder",
    "RigidBody3D",
    "Beam2D",
    "Beam3D",
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
