"""``Contact``: one entry point that builds the pair of a body and an obstacle or a second body,
with the factory registered for their kinds (:mod:`fecontact.contact.registry`)."""

from __future__ import annotations

from ..bodies.base import BODY, BodyDefaults
from ..bodies.beam3d import Beam3D
from ..bodies.rigid3d import RigidBody3D
from ..bodies.solid import Solid
from ..errors import InputError, check_kind, check_positive
from .mortar import MortarContact, finer_first
from .mortar3d import MortarContact3D
from .mortar_p2_segments import MortarContactP2
from .mortar_rigid3d import MortarRigid3D
from .registry import pair_factory
from .tube_line_mortar import tube_mortar

__all__ = ["Contact"]


def Contact(
    body,
    obstacle,
    nodes=None,
    restitution: float = 0.0,
    clearance: float = 0.0,
    friction: float = 0.0,
    method: str | None = None,
):
    """Contact pair between ``body`` and a rigid ``obstacle`` or a second body.

    ``Plane`` and ``Circle`` act on ``nodes`` of the body (all nodes, or all polygon vertices
    of a rigid body, by default); a ``Circle`` seen from outside acts on a ``Beam2D``'s
    centreline segments and on a 2D P1 ``Solid``'s boundary segments unless ``nodes`` are
    named (a chord cuts into it, a peg narrower than an edge enters, between two nodes;
    :mod:`fecontact.contact.segment_pairs`); where a solid's or a beam's nodes hold it
    (named, or on P2 cells) the run measures its depth into the boundary segments or the
    beam's elements (a ``Beam3D``'s named nodes against a ``Sphere`` the same), in
    ``max_penetration``, and warns; a ``Point`` acts on the beam's centreline segments.
    ``clearance`` (m, ≥ 0) keeps the points or segments that far from a rigid obstacle: half
    the thickness of a beam, whose centreline the gaps measure. A rigid disk
    (``RigidBody2D`` with a ``Disk``) contacts a ``Plane``, a ``Circle``, another disk, a
    rigid polygon or a ``Beam2D`` through its centre and radius; see
    :mod:`fecontact.contact.rigid_pairs`. A 2D ``Solid``'s boundary nodes (or ``nodes``) meet a
    ``RigidBody2D``'s exact disk or convex polygon, named either way round
    (:mod:`fecontact.contact.solid_rigid2d`).
    Two deformable bodies: a ``Solid`` against a ``Solid`` is a dual mortar interface of their
    whole boundaries (``method``, below), a ``Beam2D`` against a ``Beam2D`` an end-to-end
    pair along the bar axis (``nodes`` = (end of body, end of the other), default the closest
    ends); see :mod:`fecontact.contact.body_pairs`. A ``Solid``'s boundary nodes (or ``nodes``)
    against a ``Beam2D``, and a ``Beam2D``'s nodes against another with a ``clearance`` > 0 (two
    strips: the sum of their half thicknesses), meet the beam's two-sided surface, its
    centreline offset by ± ``clearance`` (:mod:`fecontact.contact.beam_sides`; add the reversed
    pair for two strips: declared one way, the second strip's nodes are not held, and their
    depth in the first is reported in ``max_penetration`` and warned); a solid against a
    beam holds the beam's nodes out of the solid's boundary too
    (:mod:`fecontact.contact.beam_on_solid`). ``restitution`` is Newton's e_N in [0, 1].

    ``friction`` is Coulomb's coefficient μ ≥ 0 of every contact of the pair (0: frictionless,
    today's path at no cost): the tangential impulse stays in |Λ_T| ≤ μ Λ_N and opposes the
    slip of the contact points (:mod:`fecontact.contact.friction`); a beam slips at its
    section's surface, which the section's turn moves (its nodes against a ``Plane`` or
    ``Circle``, a tube's segments against a ``Sphere``, ``Ball`` or ``Capsule``, a ``Beam2D``
    under a rigid disk or ``Point``, a 2D ``Solid`` or another ``Beam2D``'s nodes, the
    ``clearance`` of two strips split between their sections by their thicknesses; against a
    ``Box`` or another tube at the centreline). Two bars end to end slip across their axis.

    ``method`` chooses the discretization of a contact between two solids: ``"mortar"`` (the
    default, None: dual mortar, weighted gaps integrated over the first body's boundary in
    3D, in 2D over the finer of the two boundaries (the first where they are alike),
    :mod:`fecontact.contact.mortar` in 2D, on the quadratic segments themselves between two
    P2 solids, :mod:`fecontact.contact.mortar_p2_segments`; :mod:`fecontact.contact.mortar3d`
    in 3D, P2 faces split into flat triangles (``MortarContact3DP2`` of
    :mod:`fecontact.contact.mortar3d_p2` takes the curved faces, built explicitly); ``nodes``
    must be None, and the pair declared both ways is one interface) or ``"node-to-surface"``
    (``nodes`` of ``body``, default its boundary nodes, against the boundary of the second;
    add the reversed pair for the other direction). A 3D ``Solid`` against a ``RigidBody3D``
    (``Ball`` or ``Box``, named either way round) takes the same option: ``"mortar"`` (the
    default: the solid's boundary against the body's exact shape,
    :mod:`fecontact.contact.mortar_rigid3d`) or ``"node-to-surface"`` (its ``nodes``,
    :mod:`fecontact.contact.solid_rigid3d`). So does a 3D ``Solid`` against a ``Beam3D``
    (either way round, ``clearance`` the tube's radius): ``"mortar"`` (the default: the
    solid's boundary against the tube, :mod:`fecontact.contact.mortar_beam3d`, or on faces
    of cells at least 4 radii wide the beam's centreline against the solid's boundary,
    :mod:`fecontact.contact.tube_line_mortar`) or
    ``"node-to-surface"`` (the beam's ``nodes`` against the solid's boundary,
    :mod:`fecontact.contact.beam3d_solid`). Other pairs take None only.

    The pair comes from the factory registered for the classes of ``body`` and ``obstacle``
    (:func:`fecontact.contact.registry.register_pair`): a new body type registers its own.
    """
    check_kind("body", body, BodyDefaults, BODY)
    friction = check_positive("friction", friction, allow_zero=True)
    clearance = check_positive("clearance", clearance, allow_zero=True)
    pair = _mortar_pair(body, obstacle, nodes, restitution, clearance, method)
    if pair is None:
        pair = pair_factory(body, obstacle)(body, obstacle, nodes, restitution, clearance)
    if friction:
        if not pair.frictional:
            raise InputError(f"friction: not available for a {type(pair).__name__}; use 0")
        pair.friction = friction
    return pair


def _mortar_pair(body, obstacle, nodes, restitution, clearance, method):
    """The mortar pair of ``body`` and ``obstacle`` where ``method`` asks for one or it is
    their default, else None (``method`` checked by name)."""
    solids = isinstance(body, Solid) and isinstance(obstacle, Solid)
    rigid = _solid3d_and(RigidBody3D, body, obstacle)
    tube = _solid3d_and(Beam3D, body, obstacle)
    if method == "mortar" or (method is None and (solids or rigid or tube)):
        if tube:
            return _whole_boundary(tube_mortar, *tube, nodes, restitution, clearance, method)
        if rigid:
            return _whole_boundary(MortarRigid3D, *rigid, nodes, restitution, clearance, method)
        return _mortar(body, obstacle, nodes, restitution, clearance, solids, method)
    if method not in (None, "node-to-surface"):
        raise InputError(f"method must be 'node-to-surface' or 'mortar', got {method!r}")
    if method is not None and not (solids or rigid or tube):
        raise InputError(
            "method: 'node-to-surface' applies between two solids or a 3D solid and a "
            "RigidBody3D or a Beam3D; use None"
        )
    return None


def _solid3d_and(kind: type, body, obstacle):
    """(the solid, the other) of a 3D Solid and a ``kind`` body named either way, else None."""
    for a, b in ((body, obstacle), (obstacle, body)):
        if isinstance(a, Solid) and a.dim == 3 and isinstance(b, kind):
            return a, b
    return None


def _whole_boundary(pair_class, solid, other, nodes, restitution, clearance, method):
    """``pair_class``'s mortar pair of the solid's whole boundary against ``other``."""
    if nodes is not None:
        kind = type(other).__name__
        default = f" (the default between a 3D solid and a {kind})" if method is None else ""
        raise InputError(
            f"nodes: a mortar contact{default} takes the solid's whole boundary; "
            "method='node-to-surface' constrains chosen nodes"
        )
    return pair_class(solid, other, restitution, clearance)


def _mortar(body, obstacle, nodes, restitution, clearance, solids: bool, method):
    if not solids:
        raise InputError(
            "method: 'mortar' applies between two solids or a 3D solid and a RigidBody3D "
            "or a Beam3D"
        )
    if nodes is not None or clearance:
        default = " (the default between two solids)" if method is None else ""
        raise InputError(
            f"nodes, clearance: a mortar contact{default} takes the whole boundaries; "
            "method='node-to-surface' constrains chosen nodes"
        )
    if body.dim == 3:
        return MortarContact3D(body, obstacle, restitution)
    body, obstacle = finer_first(body, obstacle)  # the finer boundary carries the gaps
    if body.element == obstacle.element == "P2":  # the curved faces themselves
        return MortarContactP2(body, obstacle, restitution)
    return MortarContact(body, obstacle, restitution)
