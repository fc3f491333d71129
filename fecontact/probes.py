"""Probes: scalars a run records every step beside the standard history columns."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from .errors import InputError

__all__ = ["Probe", "node_probe"]


@dataclass(frozen=True)
class Probe:
    """A scalar recorded every step: ``fn(model, state)`` in ``unit``."""

    fn: Callable
    unit: str
    description: str = ""


_NODE_QUANTITIES = {
    "x": ("m", "position x", lambda b, q, v: b.positions(q)[:, 0]),
    "y": ("m", "position y", lambda b, q, v: b.positions(q)[:, 1]),
    "z": ("m", "position z", lambda b, q, v: b.positions(q)[:, 2]),
    "ux": ("m", "displacement x", lambda b, q, v: b.point_data(q, v)["displacement"][:, 0]),
    "uy": ("m", "displacement y", lambda b, q, v: b.point_data(q, v)["displacement"][:, 1]),
    "vx": ("m/s", "velocity x", lambda b, q, v: b.point_data(q, v)["velocity"][:, 0]),
    "vy": ("m/s", "velocity y", lambda b, q, v: b.point_data(q, v)["velocity"][:, 1]),
    "vz": ("m/s", "velocity z", lambda b, q, v: b.point_data(q, v)["velocity"][:, 2]),
    "rotation": ("rad", "rotation", lambda b, q, v: b.point_data(q, v)["rotation"]),
}


def node_probe(model, body, node: int, quantity: str) -> Probe:
    """Probe of one node of ``body``: ``quantity`` in x, y, z (m), ux, uy (m), vx, vy, vz
    (m/s), rotation (rad, counter-clockwise); z and vz of a body in space."""
    if quantity not in _NODE_QUANTITIES:
        raise InputError(f"quantity must be one of {', '.join(_NODE_QUANTITIES)}, got {quantity!r}")
    if quantity in ("z", "vz") and body.dim != 3:
        raise InputError(f"quantity {quantity!r}: a {type(body).__name__} moves in the plane")
    if quantity == "rotation" and "theta" not in body.components:
        kind = type(body).__name__
        raise InputError(f"quantity 'rotation': a {kind} node has none; use x, y, ux, uy, vx, vy")
    unit, text, get = _NODE_QUANTITIES[quantity]
    i = body.node_index(node)
    s = model.body_slice(model.bodies.index(body))
    return Probe(lambda m, st: float(get(body, st.q[s], st.v[s])[i]), unit, f"{text} of node {i}")
