"""Probes: scalars a run records every step beside the standard history columns."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .errors import InputError

__all__ = ["Probe", "node_probe", "probe_value"]


@dataclass(frozen=True)
class Probe:
    """A scalar recorded every step: ``fn(model, state)`` in ``unit``."""

    fn: Callable
    unit: str
    description: str = ""

    def __post_init__(self):
        if not callable(self.fn):
            raise InputError(f"fn must be a function (model, state) -> number, got {self.fn!r}")
        for name, text in (("unit", self.unit), ("description", self.description)):
            if not isinstance(text, str):
                raise InputError(f"{name} must be a string, got {text!r}")


def probe_value(name: str, probe: Probe, model, st):
    """The value of ``probe`` (named ``name``) at the state ``st``, as it returned it (an
    int, float or bool: booleans go to history.csv as 0/1); ``InputError`` for anything else,
    which would fail in the history's writer with no probe named."""
    value = probe.fn(model, st)
    if np.ndim(value) != 0 or np.asarray(value).dtype.kind not in "biuf":
        raise InputError(f"probe {name!r} must return a number, got {value!r} at t = {st.t:g} s")
    return value


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
    s = model.slice_of(body)
    read = _dof_reader(body, s.start, i, quantity) if body.linear_kinematics else None
    return Probe(read or _array_reader(body, s, i, get), unit, f"{text} of node {i}")


def _array_reader(body, s: slice, i: int, get) -> Callable:
    """The probe of node ``i`` read from the body's output arrays (a rigid body's points)."""
    return lambda m, st: float(get(body, st.q[s], st.v[s])[i])


_AXES = {"x": 0, "y": 1, "z": 2, "ux": 0, "uy": 1, "vx": 0, "vy": 1, "vz": 2}


def _dof_reader(body, offset: int, i: int, quantity: str) -> Callable | None:
    """The probe of node ``i`` of a body with linear kinematics as one global dof read,
    resolved once: the same float as the body's ``positions`` and ``point_data`` give,
    without their arrays at every history row; None where the node's position is not
    X + u (an affine map other than the identity)."""
    if quantity == "rotation":  # (the node's dofs are its components, in order)
        g = offset + body.dofs_per_node * i + body.components.index("theta")
        return lambda m, st: float(st.q[g])
    # X_i exactly: x + (−0.0) is x for every float x, a negative zero included
    X, dofs, J, H = body.point_kinematics(np.full(body.ndof, -0.0), np.array([i]))
    if H is not None or not np.array_equal(J[0], np.eye(body.dim)):
        return None
    k = _AXES[quantity]
    g = offset + int(dofs[0, k])
    if quantity in ("x", "y", "z"):
        x = float(X[0, k])
        return lambda m, st: x + float(st.q[g])
    if quantity.startswith("u"):
        return lambda m, st: float(st.q[g])
    return lambda m, st: float(st.v[g])
