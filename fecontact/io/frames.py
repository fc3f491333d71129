"""What a run writes at its frames: every body's mesh in its reference configuration with its
point data (displacement, velocity, contact and friction impulses and forces, the contact
pressure of solids, the section radius of beams) and cell data (stress), and the outlines of
the rigid obstacles, drawn under the bodies' motion. The deformed shape is the points plus
``displacement``."""

from __future__ import annotations

import math

import numpy as np

from ..bodies.centreline import Centreline
from ..time import State
from .vtu import body_mesh, line_mesh

__all__ = [
    "bodies_box",
    "contact_pressure",
    "frame_parts",
    "friction_totals",
    "grown",
    "section_radius",
    "static_parts",
]


def frame_parts(model, state: State):
    contacts = model.contacts
    h = state.h if state.h > 0 else math.inf
    f_imp, f_smooth = np.zeros(model.n), np.zeros(model.n)
    if state.impulse.any():  # (no contact acted in this step: nothing to evaluate)
        f_imp = contacts.generalized_force(state.q, contacts.all, state.impulse, model.n)
    if state.force.any():
        f_smooth = contacts.generalized_force(state.q, contacts.all, state.force, model.n)
    friction = contacts.frictional
    if friction:
        impulse = None if state.friction is None else state.friction.impulse
        force = None if state.smooth is None else state.smooth.tangential
        f_t, flag = _friction_parts(model, state, impulse)
        f_ts = _friction_parts(model, state, force)[0]
    parts = {}
    for i, body in enumerate(model.bodies):
        s = model.body_slice(i)
        q = state.q[s]
        data = dict(body.point_data(q, state.v[s]))
        data["contact_impulse"] = _point_impulse(body, f_imp[s])
        # the mean force over the step: the smooth λ plus the impulse over the step
        data["contact_force"] = data["contact_impulse"] / h + _point_impulse(body, f_smooth[s])
        if friction:
            data["tangential_impulse"] = _point_impulse(body, f_t[s])
            smooth_t = _point_impulse(body, f_ts[s])
            data["tangential_force"] = data["tangential_impulse"] / h + smooth_t
            data["friction_state"] = np.max(np.abs(_point_impulse(body, flag[s])), axis=1)
        if body.continuum:
            data["contact_pressure"] = contact_pressure(data["contact_force"], body)
        if isinstance(body, Centreline):
            # a beam is a line: ParaView's Tube filter draws its section from this scalar
            data["section_radius"] = np.full(body.n_nodes, section_radius(body.section))
        cell_data = {k: [v] for k, v in body.cell_data(q).items()} or None
        reference = body.positions(np.zeros_like(q))
        parts[_part_name(body, i)] = body_mesh(reference, body.cells(), data, cell_data)
    if model.contacts.moving:
        parts.update(_obstacle_parts(model, True, bodies_box(model, state.q)))
    return parts


def section_radius(section) -> float:
    """The radius (m) of the circle of the ``section``'s area, √(A/π): that of
    ``Section.circle`` (to round-off), the circle of the same area for other sections."""
    return math.sqrt(section.area / math.pi)


def contact_pressure(force: np.ndarray, body) -> np.ndarray:
    """Lumped contact pressure (Pa) at the nodes of a solid: the magnitude of each node's
    contact force (N, (n, d)) over the boundary area it carries (m², the body's
    ``tributary_areas``); zero off the boundary. Σ_a p_a A_a is then the sum of the nodal
    force magnitudes: the contact force when the nodes push one way."""
    area = body.tributary_areas()
    magnitude = np.linalg.norm(force, axis=1)
    return np.divide(magnitude, area, out=np.zeros_like(magnitude), where=area > 0.0)


def friction_totals(st: State) -> list[float]:
    """Σ_j |k Λ_T,j| of the step (N·s) and the work friction dissipated since t = 0 (J)."""
    if st.friction is None:
        return [0.0, 0.0]
    return [float(np.linalg.norm(st.friction.impulse, axis=1).sum()), float(st.friction.work)]


def _friction_parts(model, state: State, lam_t):
    """Generalized tangential impulse Σ_j G_T,jᵀ k Λ_T,j (n,) (``lam_t`` the step's k Λ_T),
    or smooth force Σ_j G_T,jᵀ λ_T,j (``lam_t`` the smooth λ_T), and per-dof friction state
    (0 none, 1 stick, 2 slip: the largest among the contacts on the dof)."""
    n = model.n
    status = None if state.friction is None else state.friction.status
    if lam_t is None or not np.any(status):
        return np.zeros(n), np.zeros(n)
    contacts = model.contacts
    select = np.flatnonzero(status)
    return contacts.tangent_force(state.q, select, lam_t[select], status[select], n)


def _point_impulse(body, f: np.ndarray) -> np.ndarray:
    """Contact impulse at the output points: nodal for deformable bodies; for a rigid body
    the resultant (N·s) is drawn at its centre of mass."""
    center = body.center_index
    if center is None:
        return body.nodal(f)
    out = np.zeros((body.n_nodes, 2))
    out[center] = f[:2]
    return out


def _part_name(body, i: int) -> str:
    return f"{type(body).__name__.lower()}{i}"


def static_parts(model, box=None):
    return _obstacle_parts(model, moving=False, box=box)


def bodies_box(model, q: np.ndarray) -> np.ndarray:
    """The corners (2, dim) of the box holding every body's points at q (m)."""
    x = np.vstack([b.positions(q[model.body_slice(i)]) for i, b in enumerate(model.bodies)])
    return np.stack([x.min(axis=0), x.max(axis=0)])


def grown(box, other: np.ndarray) -> np.ndarray:
    if box is None:
        return other
    return np.stack([np.minimum(box[0], other[0]), np.maximum(box[1], other[1])])


def _obstacle_parts(model, moving: bool, box=None):
    """Outlines of the rigid obstacles that move (drawn every frame) or stay (drawn once).
    A plane without its own ``extent`` is drawn under the bodies: around the foot of the
    centre of ``box`` (the corners of the bodies' box over the run, m), as wide as it."""
    parts = {}
    for j, pair in enumerate(model.contacts.pairs):
        obs = pair.obstacle
        if obs is None or obs.moving != moving:
            continue  # a contact between bodies: nothing static to draw
        size, around = obs.extent or 2.0 * model.length, None
        if box is not None and obs.extent is None:
            around = box.mean(axis=0)
            size = max(size, 1.2 * float(np.linalg.norm(box[1] - box[0])))
        pts = obs.outline(size, around)
        conn = np.stack([np.arange(len(pts) - 1), np.arange(1, len(pts))], axis=1)
        parts[f"obstacle{j}"] = line_mesh(pts, conn, {})
    return parts
