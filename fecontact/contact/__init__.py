"""Contact: rigid obstacles, the gap kinematics of every pair kind (g, G = ∂g/∂q, ∇²g), the
set of pairs of a model, and the Alart–Curnier laws solved by semi-smooth Newton."""

# the modules of pairs register theirs with ``register_pair`` on import: ``Contact`` finds them
from . import (  # noqa: F401
    beam3d_edges,
    beam3d_pairs,
    beam3d_solid,
    beam_on_solid,
    beam_sides,
    body_pairs,
    rigid3d_pairs,
    rigid_pairs,
    segment_pairs,
    solid_rigid2d,
    solid_rigid3d,
    tube_beam,
)
from .beam3d_edges import SolidEdges
from .contact_set import ContactSet
from .dispatch import Contact
from .laws import (
    alart_curnier_residual,
    contact_force_multiplier,
    solve_position_correction,
    solve_velocity_jump,
)
from .node_pairs import NodeContact, PointSegmentContact
from .obstacles import Circle, Plane, Point, Sphere
from .registry import register_pair
from .stats import ContactStats, CoulombStats

__all__ = [
    "Circle",
    "Contact",
    "ContactSet",
    "ContactStats",
    "CoulombStats",
    "NodeContact",
    "Plane",
    "Point",
    "PointSegmentContact",
    "SolidEdges",
    "Sphere",
    "alart_curnier_residual",
    "register_pair",
    "contact_force_multiplier",
    "solve_position_correction",
    "solve_velocity_jump",
]
