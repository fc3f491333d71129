r"""The segments of a :class:`~fecontact.bodies.beam3d.Beam3D` (tubes of radius r) against the
convex edges of a 3D solid's boundary: what cuts into a tube between its nodes.

The beam's nodes against the solid's faces (:mod:`.beam3d_solid`) are exact on a face, where a
segment's distance is linear; a convex edge lying across a segment is not seen by them. Here
every segment carries one contact against the solid's closest convex edge (c, d), with the
distance of their closest points (:func:`.segment3d.tube_distance`: exact gradient and
curvature), g = |x₁ − x₂| − r. ``SolidEdges(solid)`` names those edges as a partner:
``Contact(beam, SolidEdges(block), clearance=r)``, added beside ``Contact(beam, block, ...)``.

An edge is convex where the third vertex of either of its two boundary triangles lies below the
other's plane (by more than 1e-6 of the edge's length, in the reference configuration). The
edge's distance is the distance to the solid only in its normal cone, where the direction e from
the edge to the segment has e·t₁ ≥ 0 and e·t₂ ≥ 0 (t_i the unit vector in triangle i normal to
the edge, pointing away from its third vertex); elsewhere a face is closer, and the edge's
distance exceeds the solid's: the row holds what the solid's own rows hold, never more (the
edge is part of the solid). It is kept there: a tube lying on a face across an edge has e
along the face's normal, the cone's border, and a row that read +inf outside the cone went
from its gap to +inf and back with round-off (a rod laid flat over a block's corner: its
position correction cycled). Each segment's edge is the closest at the step's start, held over
the step (:meth:`TubeEdgeContact.look_ahead`). A centreline that passes through the edge
within a step keeps its side (the normal at the step's start, as for two tubes), so that a
segment carried across the edge reads −|x₁ − x₂| − r.
"""

from __future__ import annotations

import numpy as np

from ..bodies.beam3d import Beam3D
from ..bodies.solid import Solid
from ..errors import InputError
from .beam3d_pairs import TubeContact
from .geometry import edge_folds
from .registry import register_pair
from .segment3d import closest_segments, tube_distance

__all__ = ["SolidEdges", "TubeEdgeContact"]

CONVEX = 1e-6
"""Height of a triangle's third vertex below its neighbour's plane, over the edge's length,
from which the edge between them counts as convex."""


class SolidEdges:
    """The convex edges of the boundary of a 3D ``solid`` (a contact partner of a Beam3D's
    segments): ``edges`` (E, 2) node indices and ``opposite`` (E, 2) the third vertices of
    their two boundary triangles."""

    moving = False
    obstacle = None

    def __init__(self, solid: Solid):
        if not isinstance(solid, Solid) or solid.dim != 3:
            raise InputError("solid: SolidEdges takes a 3D Solid")
        self.solid = solid
        tri = solid.contact_facets()
        X = solid.positions(np.zeros(solid.ndof))
        edges, opposite, _, below = edge_folds(X, tri)
        a, b = X[edges[:, 0]], X[edges[:, 1]]
        convex = below > CONVEX * np.linalg.norm(b - a, axis=1)
        self.edges, self.opposite = edges[convex], opposite[convex]
        if len(self.edges) == 0:
            raise InputError("solid: its boundary has no convex edge")


class TubeEdgeContact(TubeContact):
    """The segments of a ``Beam3D`` of tube radius ``clearance`` against the closest convex
    edge of a 3D solid (:class:`SolidEdges`); module docstring."""

    frictional = False

    def __init__(self, body: Beam3D, edges: SolidEdges, restitution=0.0, clearance=0.0):
        super().__init__(body, restitution, clearance)
        self.partner = edges
        self.solid = edges.solid
        self.bodies = (body, edges.solid)
        self.solid_offset = 0
        self.tie = 1e-12 * max(body.characteristic_length, edges.solid.characteristic_length)
        self._held = None  # (each segment's edge over the step, None before one)

    def _solid_x(self, q):
        o = self.solid_offset
        return self.solid.positions(q[o : o + self.solid.ndof])

    def _core(self, q, P):
        """Per segment, its convex edge's end points (m, 2, 3) and its index: the closest at
        the step's start, held over the step (:meth:`look_ahead`)."""
        x = self._solid_x(q)[self.partner.edges]
        which = self._held if self._held is not None else closest_segments(P, x, self.tie)
        return x[which], which, which

    def look_ahead(self, q: np.ndarray, v: np.ndarray, h: float) -> None:
        """Each segment's closest convex edge at the step's start, held over the step. Chosen
        at every iterate, the closest switched between two edges meeting at a corner that a
        segment crosses, as near to within 1e-12 m with common normals 4 mrad apart: a rod
        laid flat over a block's corner turned back and forth by 2e-8 rad at alternate
        iterates of its position correction, which never settled."""
        self._held = None
        super().look_ahead(q, v, h)
        self._held = self._start[1]

    def bind(self, model) -> None:
        super().bind(model)
        self.solid_offset = model.offset_of(self.solid)
        self._held = None

    def _partner_rows(self, dofs, G, H, which):
        nodes = self.partner.edges[which].ravel()
        other = self.solid_offset + self.solid.node_translation_dofs(nodes).reshape(-1, 6)
        return np.concatenate([dofs, other], axis=1), G, H

    def gaps(self, q: np.ndarray) -> np.ndarray:
        P = self._ends(q)
        Q, which, _ = self._core(q, P)
        f, e = tube_distance(P, Q, hessian=False)[:2]
        sigma = self._sides(e, which)
        return sigma * f - self.radius

    def evaluate(self, q: np.ndarray):
        """Gaps (m,), dofs (m, 12), gradients and curvatures."""
        P = self._ends(q)
        Q, which, core = self._core(q, P)
        f, e, _, G, H = tube_distance(P, Q)
        sigma = self._sides(e, which)
        G, H = sigma[:, None] * G, sigma[:, None, None] * H
        dofs, G, H = self._partner_rows(self._beam_dofs(), G, H, core)
        return sigma * f - self.radius, dofs, G, H


@register_pair(Beam3D, SolidEdges)
def _beam3d_edges(beam, edges, nodes, restitution, clearance):
    """The segments against a solid's convex edges."""
    if nodes is not None:
        raise InputError("nodes: a Beam3D meets a solid's edges through its segments")
    return TubeEdgeContact(beam, edges, restitution, clearance)
