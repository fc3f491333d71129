r"""Coulomb friction on the pointwise safeguard rows of a mortar interface.

A node held by its safeguard row (:mod:`fecontact.contact.mortar_safeguard`) carries the
normal force that row takes, and that force must carry Coulomb's friction as any contact
does: frictionless, the rows let a disk rolling on a finer block keep the part of its weight
that its held (master) nodes bear without friction, and it rolled on at 0.83 v₀ instead of
the node-to-surface 0.61–0.66 v₀ (docs/validation/stress_2d.md, *Corners, rings, rotated
scenes and rolling*). The rows take the interface's μ.

Their slip rows follow the row's own normal, whatever form its gap has (a facet's plane, a
smooth maximum of the planes around a vertex): the gradient G of g_s over the node's and the
other surface's point translations is read as a normal n (the node's block of G, made a
unit vector) and weights w_i = G_i·n / |n| of the points (1 for the node; −N_i(ξ) of a
facet's vertices; each plane's share of them for a smooth maximum), and the slip rate is
T·Σ w_i ẋ_i with T the tangents of n (:func:`fecontact.contact.friction.point_tangents`).
The weights sum to zero (g_s does not change when both solids translate together), so a
rigid translation slips nothing. A row whose node is not deep (no gradient) has no slip rows.

No node is rubbed twice for one force: a slave node's weighted row and its own row are twins
of which one active set holds one (:func:`fecontact.contact.laws.one_of_twins`), and a
master node's row carries a force of its own, which no weighted row bears.
"""

from __future__ import annotations

import numpy as np

from .friction import point_tangents

__all__ = ["SafeguardSlip", "row_tangents"]


def row_tangents(G: np.ndarray, dim: int):
    """Slip rows (m, nt, k) and unit tangents (m, nt, dim) of rows whose gradients G (m, k)
    act on point translations, the first point the node (module docstring): G scaled so that
    the node's block is a unit normal, then :func:`point_tangents`. Rows with a zero node block
    (a shallow node) get zero slip rows and tangents."""
    norm = np.linalg.norm(G[:, :dim], axis=1)
    unit = G / np.where(norm > 0.0, norm, 1.0)[:, None]
    GT = point_tangents(unit, dim)
    return GT, GT[:, :, :dim]


class SafeguardSlip:
    """The slip rows of a safeguard's pointwise rows (a base of
    :class:`fecontact.contact.mortar_safeguard.DeepNodeRows`; module docstring). The pair
    provides ``evaluate`` and ``dim``; its ``friction`` is the interface's μ, set where the
    model gathers the interfaces' rows
    (:func:`fecontact.contact.mortar_interface.merge_interfaces`)."""

    frictional = True

    def tangents(self, q: np.ndarray):
        """dofs (m, k), slip rows (m, nt, k) and unit tangents (m, nt, d) of every node's row
        at q, along its gradient's normal."""
        _, dofs, G, _ = self.evaluate(q)
        return (dofs, *row_tangents(G, self.dim))
