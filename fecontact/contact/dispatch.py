"""``Contact``: one entry point that builds the pair of a body and an obstacle or a second body,
with the factory registered for their kinds (:mod:`fecontact.contact.registry`)."""

from __future__ import annotations

from ..errors import InputError, check_positive
from .registry import pair_factory

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
    ends); see :mod:`fecontact.contact.body_pairs`. ``restitution`` is Newton's e_N in [0, 1].

    ``friction`` is Coulomb's coefficient μ ≥ 0 of every contact of the pair (0: frictionless,
    today's path at no cost): the tangential impulse stays in |Λ_T| ≤ μ Λ_N and opposes the
    slip of the contact points (:mod:`fecontact.contact.friction`). Every pair but the
    end-to-end beam pair takes it.

    The pair comes from the factory registered for the classes of ``body`` and ``obstacle``
    (:func:`fecontact.contact.registry.register_pair`): a new body type registers its own.
    """
    friction = check_positive("friction", friction, allow_zero=True)
    clearance = check_positive("clearance", clearance, allow_zero=True)
    pair = pair_factory(body, obstacle)(body, obstacle, nodes, restitution, clearance)
    if friction:
        if not pair.frictional:
            raise InputError(f"friction: not available for a {type(pair).__name__}; use 0")
        pair.friction = friction
    return pair
