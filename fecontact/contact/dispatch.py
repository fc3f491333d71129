"""``Contact``: one entry point that builds the pair of a body and an obstacle or a second body."""

from __future__ import annotations

from ..bodies.base import Body
from ..bodies.beam import Beam2D
from ..bodies.solid import Solid
from ..errors import InputError, check_positive
from .beam_sides import PointBeamContact
from .node_pairs import NodeContact, PointSegmentContact
from .obstacles import Circle, Point
from .segment_pairs import SegmentCircleContact

__all__ = ["Contact"]


def Contact(
    body,
    obstacle,
    nodes=None,
    restitution: float = 0.0,
    clearance: float = 0.0,
    friction: float = 0.0,
):
    """Contact pair between ``body`` and a rigid ``obstacle`` or a second body.

    ``Plane`` and ``Circle`` act on ``nodes`` of the body (all nodes, or all polygon vertices
    of a rigid body, by default); a ``Circle`` seen from outside acts on a ``Beam2D``'s
    centreline segments unless ``nodes`` are named (a chord cuts into it between its nodes);
    a ``Point`` acts on the beam's centreline segments. ``clearance`` (m, ≥ 0) keeps the
    points or segments that far from a rigid obstacle: half the thickness of a beam, whose
    centreline the gaps measure. A rigid
    disk (``RigidBody2D`` with a ``Disk``) contacts a ``Plane``, a ``Circle``, another disk, a
    rigid polygon or a ``Beam2D`` through its centre and radius; see
    :mod:`fecontact.contact.rigid_pairs`.
    Two deformable bodies: a ``Solid`` against a ``Solid`` is a node-to-surface pair (``nodes``
    of ``body``, default its boundary nodes, against the boundary of the second; add the
    reversed pair for the other direction), a ``Beam2D`` against a ``Beam2D`` an end-to-end
    pair along the bar axis (``nodes`` = (end of body, end of the other), default the closest
    ends); see :mod:`fecontact.contact.body_pairs`. A ``Solid``'s boundary nodes (or ``nodes``)
    against a ``Beam2D``, and a ``Beam2D``'s nodes against another with a ``clearance`` > 0 (two
    strips: the sum of their half thicknesses), meet the beam's two-sided surface, its
    centreline offset by ± ``clearance`` (:mod:`fecontact.contact.beam_sides`; add the reversed
    pair for two strips). ``restitution`` is Newton's e_N in [0, 1].

    ``friction`` is Coulomb's coefficient μ ≥ 0 of every contact of the pair (0: frictionless,
    today's path at no cost): the tangential impulse stays in |Λ_T| ≤ μ Λ_N and opposes the
    slip of the contact points (:mod:`fecontact.contact.friction`). Every pair but the
    end-to-end beam pair takes it.
    """
    friction = check_positive("friction", friction, allow_zero=True)
    pair = _pair(body, obstacle, nodes, restitution, clearance)
    if friction:
        if not pair.frictional:
            raise InputError(f"friction: not available for a {type(pair).__name__}; use 0")
        pair.friction = friction
    return pair


def _pair(body, obstacle, nodes, restitution, clearance):
    from .rigid_pairs import rigid_pair

    clearance = check_positive("clearance", clearance, allow_zero=True)
    pair = rigid_pair(body, obstacle, nodes, restitution, clearance)
    if pair is not None:
        return pair
    if isinstance(obstacle, Beam2D) and (clearance or isinstance(body, Solid)):
        return PointBeamContact(body, obstacle, nodes, restitution, clearance)
    if isinstance(body, Beam2D) and isinstance(obstacle, Solid):
        raise InputError("a beam against a solid: give it as Contact(solid, beam, clearance=c)")
    if isinstance(obstacle, Body):
        if clearance:
            raise InputError("clearance: not available between two deformable bodies; use 0")
        from .body_pairs import body_pair

        return body_pair(body, obstacle, nodes, restitution)
    if isinstance(obstacle, Point):
        if nodes is not None:
            raise InputError("nodes: a Point obstacle acts on beam segments, not on nodes")
        return PointSegmentContact(body, obstacle, restitution, clearance)
    if isinstance(body, Beam2D) and isinstance(obstacle, Circle) and not obstacle.inside:
        if nodes is None:  # the chords cut into a convex obstacle between the nodes
            return SegmentCircleContact(body, obstacle, restitution, clearance)
    return NodeContact(body, obstacle, nodes, restitution, clearance)
