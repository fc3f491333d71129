"""Contact pairs by the kinds of their two sides.

``Contact(body, partner)`` builds its pair with the factory registered for the classes of the
two: ``(Beam2D, Circle)``, ``(Solid, Solid)``, ``(RigidBody2D, Beam2D)``, ... Each module of
pairs registers its own, and a body type defined anywhere registers the pairs it takes part in
the same way, without a change to the code that chooses them::

    @register_pair(MyBody, Plane)
    def my_body_on_a_plane(body, plane, nodes, restitution, clearance):
        return NodeContact(body, plane, nodes, restitution, clearance)

The most specific registration wins: the body's own class before its bases, then, for that
class, the partner's own class before its bases (``object`` as the body kind matches any body).
"""

from __future__ import annotations

from collections.abc import Callable

from ..errors import InputError

__all__ = ["PairFactory", "pair_factory", "register_pair", "partners_of"]

PairFactory = Callable[..., object]
"""``factory(body, partner, nodes, restitution, clearance) -> pair``: ``nodes`` as given to
``Contact`` (None: the factory's default), ``restitution`` Newton's e_N, ``clearance`` (m, ≥ 0,
already checked) the distance kept from the partner."""

PAIRS: dict[tuple[type, type], PairFactory] = {}
"""The registered factories by (body class, partner class)."""


def register_pair(kind: type, partner: type) -> Callable[[PairFactory], PairFactory]:
    """Decorator: pairs of a ``kind`` body with a ``partner`` (an obstacle or a body class)
    are built by the decorated factory. Registering a key again replaces its factory."""
    if not isinstance(kind, type) or not isinstance(partner, type):
        raise TypeError(f"register_pair takes two classes, got {kind!r} and {partner!r}")

    def register(factory: PairFactory) -> PairFactory:
        PAIRS[(kind, partner)] = factory
        return factory

    return register


def pair_factory(body, partner) -> PairFactory:
    """The factory of the pair of ``body`` with ``partner``; an ``InputError`` naming what the
    body can contact when no registration fits."""
    for kind in type(body).__mro__:
        for other in type(partner).__mro__:
            factory = PAIRS.get((kind, other))
            if factory is not None:
                return factory
    known = ", ".join(sorted(partners_of(body))) or "nothing"
    raise InputError(
        f"no contact between a {type(body).__name__} and a {type(partner).__name__}: "
        f"a {type(body).__name__} contacts {known}"
    )


def partners_of(body) -> set[str]:
    """Names of the partner classes registered for the kinds of ``body``."""
    kinds = type(body).__mro__
    return {other.__name__ for kind, other in PAIRS if kind in kinds}
