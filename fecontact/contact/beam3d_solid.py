r"""A :class:`~fecontact.bodies.beam3d.Beam3D` against a 3D :class:`~fecontact.Solid`: the
beam's nodes, on the axis of a tube of radius r (the ``clearance``), against the solid's
boundary triangles.

``Contact(beam, solid, clearance=r, method="node-to-surface")`` (or the two named the other
way) builds this pair; the default for the two is dual mortar over the solid's boundary
against the tube (:mod:`fecontact.contact.mortar_beam3d`).

Node-to-surface (:class:`~fecontact.contact.body_pairs.NodeSurfaceContact`) with the beam's
nodes as slaves: each node's gap is its signed distance from the plane of its closest boundary
triangle less r, g = n·(x_s − x_a) − r, with that pair's exact gradient, curvature, search and
inside/outside test. A segment's distance to a plane is linear along it, so against a face its
nodes are exact; a convex edge of the solid lying across a segment cuts into the tube between
the nodes, which the segments' pair against the solid's convex edges holds
(:class:`~fecontact.contact.beam3d_edges.SolidEdges`).
"""

from __future__ import annotations

import numpy as np

from ..bodies.beam3d import Beam3D
from ..bodies.solid import Solid
from ..errors import InputError
from .body_pairs import NodeSurfaceContact
from .registry import register_pair

__all__ = ["TubeSolidContact"]


class TubeSolidContact(NodeSurfaceContact):
    """The nodes of a ``Beam3D`` (``nodes``, default all) kept ``clearance`` (m, the tube's
    radius) out of a 3D ``Solid``'s boundary; Newton's ``restitution`` e_N in [0, 1]."""

    def __init__(self, body, master, nodes=None, restitution=0.0, clearance=0.0):
        super().__init__(body, master, nodes, restitution)
        self.clearance = float(clearance)

    @staticmethod
    def check_bodies(body, master) -> None:
        if not isinstance(body, Beam3D) or not isinstance(master, Solid) or master.dim != 3:
            raise InputError("a Beam3D's nodes meet the boundary of a 3D Solid")

    def evaluate(self, q: np.ndarray):
        """The node-to-surface gaps less the tube's radius (m), their dofs and gradients."""
        g, dofs, G, H = super().evaluate(q)
        return g - self.clearance, dofs, G, H


@register_pair(Beam3D, Solid)
def _beam3d_solid(beam, solid, nodes, restitution, clearance):
    """The beam's nodes (a tube of radius ``clearance``) against the solid's boundary."""
    return TubeSolidContact(beam, solid, nodes, restitution, clearance)


@register_pair(Solid, Beam3D)
def _solid_beam3d(solid, beam, nodes, restitution, clearance):
    """The same pair named the other way round (``nodes`` of the beam)."""
    return _beam3d_solid(beam, solid, nodes, restitution, clearance)
