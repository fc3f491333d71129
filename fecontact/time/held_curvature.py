r"""Modified Newton at the step sizes a split step meets once: one factorization of
S(a₀) + C₀ serves the curved updates of the smooth steps at nearby sizes.

A located impact is refined by smooth steps of sizes δ met once (regula falsi on the
closing instant, in :mod:`fecontact.time.localize`), each with its own
S(a) = a M + K, a = β′(δ). Where the contact rows are curved (mortar), each Newton update
solves with S(a) + C, C the curvature of the contact forces: a factorization of it, or the
columns S(a)⁻¹e_i of the dofs C touches, which at a size met once take a factorization of
S(a) too (:class:`fecontact.linalg.UnitColumns`). On the 3D balls that is two to three
factorizations a size, each size's used by its two or three updates only (``stress_3d.md``).

The sizes of one refinement lie close together (on ``two_balls`` at 3 m/s: 13 sizes within
a factor 1.36, most within 1 %), so the factors of S(a₀) + C₀ made at one of them are a
Jacobian for the others: the update through them is exact in the residual, and the iterate
converges to the same root within the Newton tolerance, at the rate of
‖I − (S(a₀) + C₀)⁻¹ (S(a) + C)‖, which the mass term bounds by |a − a₀| / min(a, a₀) (the
eigenvalues of (S(a₀) + C₀)⁻¹ M a-scaled lie below 1 where S + C is positive definite) plus
the change of the curvature. So such factors serve a size within ``NEAR`` of a₀ while each
update through them lowers the relative residual by ``CONTRACTION``, unless the contact
zone (the dofs C touches) changed since the previous update: the active set's change raises
the residual of Newton's own update too (on the P2 balls a zone of 90 dofs growing to 150,
the residual 6e-4 → 1e-2, then 1.5e-4 through the held factors). An update that does not
is made as before (counted ``curvature_reuse_fallbacks``, the factors it makes then held in
their place). The held factors belong to the split step: dropped with its caches
(:func:`fecontact.time.localize.drop_caches`), so no later step depends on them.
"""

from __future__ import annotations

import math

from ..linalg import touched

__all__ = ["CONTRACTION", "HELD", "NEAR", "held_curvature", "hold"]

NEAR = 1.25
"""Largest ratio of a size's a to the held factors' a₀: the mass term alone then contracts
the update's error by at most 0.25 a update (about four updates more for 1e-8 than Newton's
two or three: the residual and solves of one update cost a tenth to a fifth of a
factorization on the P1 and P2 balls)."""

CONTRACTION = 0.5
"""Factor by which each update through held factors must lower the relative residual of
the smooth step (against its previous update), else the update is made as before."""

HELD = ("held curvature",)
"""The key of the held factors in the model's ``column_cache`` (dropped with the split
step's sizes)."""


class HeldCurvature:
    """The factors ``solve`` of S(a₀) + C₀, ``a`` = a₀ (1/s²), with ``last``: by size a, the
    relative residual at the latest update through them (None: no longer trusted there),
    the number of dofs its curvature touched (the contact zone) and its smooth step's
    :class:`~fecontact.time.terms.StepContext` (a step at a size met before starts afresh)."""

    __slots__ = ("a", "solve", "last")

    def __init__(self, a: float, solve, residual: float, zone: int, step):
        self.a, self.solve, self.last = a, solve, {a: (residual, zone, step)}


def held_curvature(model, units, a: float, C, residual: float, step):
    """The held factors of S(a₀) + C₀ for an update at a size ``a`` met once (``units`` the
    size's :class:`~fecontact.linalg.UnitColumns`, ``C`` the curvature, ``residual`` the
    relative residual at the iterate of the smooth ``step``), counted in the ladder's
    ``curvature_reuses``; None where the update is made as before: no factors held within
    ``NEAR``, the size's columns of C's dofs all made (the exact update costs no
    factorization), or the residual did not contract by ``CONTRACTION`` over the step's
    previous update with the same contact zone (counted ``curvature_reuse_fallbacks``)."""
    if not units.once:
        return None
    held = model.column_cache.get(HELD)
    if held is None or max(a / held.a, held.a / a) > NEAR:
        return None
    T = touched(C)
    if all(int(i) in units.columns for i in T):
        return None
    counts = model.ladder.counts
    last, zone, of = held.last.get(a, (math.inf, T.size, step))
    if of is not step:  # (the first update of another smooth step of this size)
        last = math.inf
    elif last is None:  # (refused in this step: made as before to its end)
        return None
    # (a residual that rose where the contact zone changed is the active set's, which
    # Newton's own update meets too: judged at the next update)
    if not residual <= CONTRACTION * last and zone == T.size:
        held.last[a] = (None, T.size, step)
        counts["curvature_reuse_fallbacks"] += 1
        return None
    held.last[a] = (residual, T.size, step)
    counts["curvature_reuses"] += 1
    return held.solve


def hold(model, units, a: float, factors, C, residual: float, step) -> None:
    """Hold the ``factors`` of S(a) + C just made for an update at a size met once (``units``
    the size's columns) at the relative ``residual`` of the smooth ``step``, for the updates at
    nearby sizes."""
    if units.once:
        model.column_cache[HELD] = HeldCurvature(a, factors, residual, touched(C).size, step)
