"""The closings a step's trial crosses: the contacts open at its start whose gap at its end is
below the tolerance, their instants on the cubic Hermite interpolant of the gap
(:mod:`fecontact.time.hermite`), one closing per node of twin rows
(:mod:`fecontact.time.localize`, which locates them)."""

from __future__ import annotations

import numpy as np

from ..contact.mortar_safeguard import real_starts
from .hermite import hermite_root

__all__ = ["closings", "one_closing_per_node", "own_closings"]


def closings(contacts, st, phases, left, closing, g0, aim, F):
    """(g_0, (rows, τ, slopes in s, sloped, ends)) of the ``closing`` contacts (a mask) of the
    trial ``phases`` over ``left`` (s) from ``st``: τ their Hermite instants (``aim``: the gap
    aimed at), ends the brackets' closed ends (the trial's end, its gap less the aim), g_0
    the start's gaps ``g0`` with a placeholder's read where it has none."""
    g1 = phases.g_tilde
    rows = (closing & np.isfinite(g0)).nonzero()[0]
    _, G0 = contacts.jacobian(st.q, rows)
    if not G0.any(axis=1).all():  # (a row without a gradient: a pointwise placeholder)
        g0, G0 = real_starts(contacts, st.q, rows, g0, G0)
    G1 = G0 if contacts.affine else contacts.jacobian(phases.q, rows)[1]  # (affine: constant)
    s0, s1 = left * (G0 @ st.v[F]), left * (G1 @ phases.v[F])  # slopes in s
    tau, slope = hermite_root(g0[rows] - aim, s0, g1[rows] - aim, s1)
    rows, tau, slope, sloped = own_closings(contacts.twins, rows, tau, slope, G0)
    # (the bracket's closed end: the trial's end, its gap less the aim)
    return g0, (rows, tau, slope, sloped, (np.ones(rows.size), g1[rows] - aim))


def own_closings(twins, rows, tau, slope, G0):
    """(rows, τ, slopes, whether each row has a gradient) of the crossing ``rows`` (gradients
    ``G0``) that stand for their nodes: of twin rows the earlier (:func:`one_closing_per_node`),
    and the rows with a gradient where any has one (a deep node's row above half its allowance
    whose real gap is unknown, :func:`real_starts`, has none, and a placeholder's instant is
    not its node's: the master's nodes have no twin; ball_on_slab at 10 m/s,
    localization.md)."""
    sloped = G0.any(axis=1)
    if twins is None and sloped.all():  # (every row its node's own, and sloped: most steps)
        return rows, tau, slope, sloped
    keep = np.ones(rows.size, dtype=bool)
    if twins is not None:  # (no twin rows: every crossing stands for its node)
        keep = one_closing_per_node(twins, rows, tau)
    if (keep & sloped).any():
        keep &= sloped
    return rows[keep], tau[keep], slope[keep], sloped[keep]


def one_closing_per_node(twins, rows: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """Which of the crossing ``rows`` (instants ``tau``) stand for their node: of two twin
    rows (``twins``: a mortar node's weighted row and its pointwise row,
    :func:`fecontact.contact.mortar_safeguard.twin_rows`; None: none) that both cross, the
    earlier instant (the first row on a tie). A pointwise row reads a placeholder gap while
    its node is shallower than half its allowance, so its Hermite instant is not the node's;
    counted as one more instant it made a ring of closings beside a pressed pole look like
    an accumulation, and the step was left whole."""
    keep = np.ones(rows.size, dtype=bool)
    if twins is None or not rows.size:
        return keep
    where = np.full(twins.size, -1)
    where[rows] = np.arange(rows.size)
    twin = twins[rows]
    partner = np.where(twin >= 0, where[np.maximum(twin, 0)], -1)  # its index among rows
    both = partner >= 0
    other = np.where(both, partner, 0)
    later = (tau > tau[other]) | ((tau == tau[other]) & (rows > rows[other]))
    return ~(both & later)
