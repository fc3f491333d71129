r"""A beam against a 2D solid, both ways: the solid's boundary nodes against the beam's two-sided
surface (:class:`~.beam_sides.PointBeamContact`), and the beam's nodes against the solid's
boundary segments, kept the clearance c away (:class:`BeamNodeSurface`).

The beam's surface is its centreline offset by ± c; the solid's is its boundary polygon. In
2D the closest points of two polylines that do not cross include a vertex of one of them: a
solid node (its row on the beam's surface) or a beam node (its row here). A beam element that
crosses the boundary has a beam node inside, or a solid node across its centreline, whose row
is negative. The two sets of rows hold the pair in both directions and no smaller set does:
with the solid's rows alone a beam node between two boundary nodes of a coarser solid enters
its face unheld (a strip pressed onto a block of 10 cm cells entered it by 5.3 % of c;
docs/validation/stress_2d.md).

A beam node's row is the node-to-segment gap of :class:`~.body_pairs.NodeSurfaceContact` less
the clearance, g = n·(x − x₁) − c against its closest boundary segment, with that pair's
search (widened by c), choice of facet and exact derivatives. Beyond a convex vertex of the
solid the gap is the larger of the two plane gaps, so the node is kept out of the boundary
offset with sharp corners (at most c (1/cos(θ/2) − 1) farther than the round offset, θ the
turn of the boundary there); the vertex's own row on the beam holds the round part.

Where a beam node meets a solid node the two rows hold one relative motion: the pair declares
``redundant_rows`` and the run takes minimum-norm multipliers (decided once per model;
docs/validation/redundant_rows.md).

With ``friction`` μ both families slip as the point of the beam's surface that touches: the
section's point at the arm c n from the centreline (n the row's unit normal toward the solid),
which the section's turn moves by θ̇ e_z × c n. A solid node's row slips as the node against
the beam's material point at the row's ξ, ẋ − ((1 − ξ) ẋ_a + ξ ẋ_b + ω(ξ) e_z × c n), the
section's turn interpolated as the centreline (:class:`~.beam_sides.PointBeamContact`'s rows,
whose node arm c_a is 0 here); a beam node's row as
its section's point x − c n (n out of the solid) against the segment's material point under
it, ẋ + θ̇ e_z × (−c n) − ((1 − ξ) ẋ₁ + ξ ẋ₂): the turn adds c θ̇ along the row's tangent.
Over a step both take the sections' turns exactly (each section point turned back with its
section), so that a rigid motion of both bodies slips nothing.
"""

from __future__ import annotations

import numpy as np

from ..bodies.beam import Beam2D
from ..bodies.solid import Solid
from ..errors import InputError
from .beam_sides import PointBeamContact
from .body_pairs import NodeSurfaceContact
from .registry import register_pair

__all__ = ["BeamNodeSurface", "SolidBeamContact"]


class BeamNodeSurface(NodeSurfaceContact):
    """Every node of a ``Beam2D`` against the boundary segments of a 2D ``Solid``, kept the
    ``clearance`` c (m, half the section height) outside it: g = n·(x − x₁) − c (module
    docstring). The companion of a :class:`SolidBeamContact` ``owner``, whose μ it takes."""

    meets_back = False  # (its counterpart is a PointBeamContact, not a pass of its kind)
    frictional = True

    def __init__(self, beam, solid, restitution: float = 0.0, clearance: float = 0.0, owner=None):
        super().__init__(beam, solid, None, restitution)
        # a beam node's row and the solid node's row it meets (set after the base's
        # __init__, which sets its own: a class attribute here was shadowed by it)
        self.redundant_rows = True
        self.clearance = float(clearance)
        self.margin = self.base_margin + self.clearance
        self.owner = owner

    @property
    def friction(self) -> float:
        """Coulomb's μ of the pair that brings the rows (``Contact`` sets it there)."""
        return 0.0 if self.owner is None else self.owner.friction

    def _sections(self, q: np.ndarray):
        """The rows' dofs (m, k) and slip rows (m, 1, k) of the translations
        (:meth:`NodeSurfaceContact.tangents`), their tangents T (m, 1, 2), the beam's local
        dofs, the nodes (m,) and the arms −c n (m, 2) from the nodes to their touching points."""
        dofs, GT, T = super().tangents(q)
        n = np.stack([-T[:, 0, 1], T[:, 0, 0]], axis=1)  # (T = (n_y, −n_x); zero: no facet)
        oa = self.offsets[0]
        qb = q[oa : oa + self.body.ndof]
        return dofs, GT, T, qb, self.nodes[self._row_node], -self.clearance * n

    def tangents(self, q: np.ndarray):
        """Dofs (m, k + 1), slip rows (m, 1, k + 1) and tangents T (m, 1, 2): the node's
        section point x − c n against the segment's point under it (module docstring); the
        last column is the node's rotation."""
        dofs, GT, T, qb, nodes, arms = self._sections(q)
        turns, B = self.body.section_turns(qb, nodes, arms)
        GT = np.concatenate([GT, np.einsum("mti,mik->mtk", T, B)], axis=2)
        return np.concatenate([dofs, self.offsets[0] + turns], axis=1), GT, T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """The step's slip (m, 1): the translations' linear form (exact) and the section
        point's arm against where its section held it at q_n, arm − R(θ_n − θ) arm (exact
        for any turn)."""
        dofs, GT, _, qb, nodes, arms = self._sections(q)
        slip = np.einsum("mtk,mk->mt", GT, (q - q_n)[dofs])
        oa = self.offsets[0]
        qb_n = q_n[oa : oa + self.body.ndof]
        back = self.body.section_points_before(qb, qb_n, nodes, arms)
        back = back - self.body.positions(qb_n)[nodes]
        return slip + np.einsum("mtd,md->mt", T, arms - back)

    @staticmethod
    def check_bodies(body, master) -> None:
        """A ``Beam2D`` against a distinct 2D ``Solid``."""
        if not isinstance(body, Beam2D) or not isinstance(master, Solid) or master.dim != 2:
            raise InputError("a beam's nodes take a Beam2D against a 2D Solid")

    def _set_margin(self, margin: float) -> None:
        # a node within the detection margin of the offset surface is within margin + c of
        # the boundary segments the search finds
        super()._set_margin(margin + self.clearance)

    def _evaluate(self, q):
        g, dofs, G, H = super()._evaluate(q)
        return g - self.clearance, dofs, G, H

    def penetration(self, q: np.ndarray) -> float:
        """Depth (m, ≥ 0) of the deepest beam node in the solid's offset: c less its signed
        distance to the boundary (negative inside), by the inside/outside test of every node
        within c of the solid's box (the others: none)."""
        xs, xm = self.positions(q)
        s, _ = self.surface.signed_distance(xm, xs, pad=self.clearance)
        return max(self.clearance - float(s.min()), 0.0)


class SolidBeamContact(PointBeamContact):
    """A 2D ``Solid``'s boundary nodes (or ``nodes``) against a ``Beam2D``'s two-sided surface,
    with the beam's nodes against the solid's whole boundary as its companion
    (:class:`BeamNodeSurface`, module docstring)."""

    def __init__(self, body, beam, nodes=None, restitution: float = 0.0, clearance=0.0):
        super().__init__(body, beam, nodes, restitution, clearance)
        self.companions = (BeamNodeSurface(beam, body, restitution, clearance, self),)

    def bind(self, model) -> None:
        super().bind(model)
        for pair in self.companions:
            pair.bind(model)

    def watch(self):
        """None: the companion's rows hold the beam's nodes, and its penetration measures
        them."""
        return None


@register_pair(Solid, Beam2D)
def _solid_on_beam(solid, beam, nodes, restitution, clearance):
    """A 2D solid's boundary nodes (or ``nodes``) against the beam's two-sided surface, and the
    beam's nodes against the solid's boundary."""
    return SolidBeamContact(solid, beam, nodes, restitution, clearance)
