r"""Globalized Newton updates of the smooth step.

Without joints the smooth step is stationary for the incremental potential

    Π(q) = ½ β′ |q − q̂|²_M + ½ γ′ |q − q̂|²_C + (M v̇̂ + C v̂ − f_ext)·(q − q̂) + W(q),

(hats: the predictor; W the strain energy; C frozen at the iterate when it depends on q), whose
gradient is the residual r and whose Hessian is S_t = β′M + γ′C + K_t. Newton's direction
d = −S_t⁻¹ r descends Π only while S_t is positive definite along it. Right after an impact
the geometric stiffness of a slender beam can make S_t indefinite on the nodes' rotations (the
rotational inertia is tiny), and d then points uphill: r·d > 0. Every update is therefore
checked and globalized in units of energy:

1. the direction must descend, r·d < 0, else d is recomputed with the mass-shifted matrix
   S_t + τ β′M, τ = 1, 10, 100, … (a step of the same equations with a smaller effective
   time step, tending to steepest descent in the metric M);
2. its length s = 1, ½, ¼, … is the first with the Armijo decrease
   Π(q + s d) − Π(q) ≤ 10⁻⁴ s r·d. The full step is tested with the strain energy that the
   next iteration's internal forces bring anyway; only a failed test costs evaluations of W.

On a Lie group (q = q_n ⊕ D, :mod:`.lie`) S_t is not symmetric: Newton's direction is kept
(no shift), and step 2 runs in D, with W at q_n ⊕ (D + s d), its slope f_int·T(D)d and the
quadratic part of Π without the stiffness K T(D) that S_t holds; the gyroscopic forces stay
in Π's linear and quadratic parts as the residual and S_t carry them. In a plane T(D) acts as
the identity and the test is the planar one, cut for cut: a beam struck in the plane took
whole, without it, a 2 rad update of its tip's rotation (S_t indefinite at the predictor)
that the planar step cut, and left its planar twin. With the slope f_int·d instead, the test
cut a free tumbling beam's Newton near convergence (the slope's missing f_int·(T − I)d) and
its momentum drift lost its order 2.

Updates below the increment tolerance are taken whole: they end the iteration, and there the
change of W is a difference of nearly equal sums that has lost its digits (I₁ − 3 of a small
strain), so no test on Π could decide.

The strain energy is summed from strains formed as differences of numbers near one (a
stretch l/L − 1, F = I + ∇u), each off by a few ulps ε; W then carries a round-off of about
ε ∫|σ| dV ≤ ε √(2W ∫E dV) (Cauchy–Schwarz with W = ∫σ²/2E dV), far above ε W at small strains
(ε/strain times W). A change of Π within that round-off decides nothing. The full update
is therefore taken when Π(q + d) − Π(q) ≤ 10⁻⁴ r·d + δ, δ = 4 ε √(2 W₀ ∫E dV) (two ulps per
strain, W at both ends): like an update below the tolerance, Newton's own near the root
(counted: ``roundoff_accepts``). The cuts keep the strict test: one is tried because the
full update raised Π by more than δ, and a cut whose change lies within δ shows no
decrease either; a direction along which no cut decreases Π still fails the step. A planar
strip struck at 30 m/s (W₀ = 12 J, ∫E dV = 2.1e7 J: δ = 2.0e-11 J) had an update of 1.7e-8
of its length predicting −1.4e-12 J, while W's change read up to 1.8e-12 J of round-off
along it: without δ every cut "increased" Π, and the step was halved.

A direction that no shift makes descend, or a line search that finds no decrease, fails the
step (then halved), never a silent tiny step. Both events are counted in the run's
:class:`fecontact.time.stats.NewtonStats`, which ``fecontact.run`` reports in ``summary.json``
(``smooth_newton``).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from .constraints import StepFailure, factorize_or_fail
from .stats import NewtonStats

__all__ = ["Armijo", "descent_direction", "energy_roundoff"]

ARMIJO = 1e-4
MAX_CUTS = 30
MAX_SHIFTS = 12
EPS = float(np.finfo(float).eps)
# ulps of one strain (a norm, a quotient, the subtraction of one), times two evaluations of W
ROUNDOFF_ULPS = 4.0


def energy_roundoff(model, W: float) -> float:
    """δ (J): the round-off of a change of the strain energy W (J) of ``model`` (module
    docstring); 0 where W is not finite (no test passes on it)."""
    if not math.isfinite(W):
        return 0.0
    return ROUNDOFF_ULPS * EPS * math.sqrt(2.0 * max(W, 0.0) * model.stiffness_volume)


class Armijo(NamedTuple):
    """Armijo's test of a full update dq from q, decided by the strain energy W₁ at q + dq,
    which the next iteration's internal forces bring at no cost: Π(q + dq) − Π(q) =
    lin + quad + W₁ − W₀ ≤ 10⁻⁴ slope. ``lin`` = (r − f_int)·dq and ``quad`` =
    ½ dqᵀ(S − K)dq are the exact linear and quadratic parts of Π along dq."""

    X: np.ndarray  # the iterate (q, v, v̇, a) the update started from
    dq: np.ndarray
    lin: float
    quad: float
    slope: float
    W0: float
    residual: float  # the relative residual at X, reported if the step fails
    floor: float  # δ, the round-off of W's change (:func:`energy_roundoff`)

    def accepts(self, W1: float, stats: NewtonStats | None = None) -> bool:
        """Whether the full update passes, within δ (counted in ``stats``)."""
        change = self.lin + self.quad + (W1 - self.W0)
        if change <= ARMIJO * self.slope:
            return True
        if change > ARMIJO * self.slope + self.floor:
            return False
        if stats is not None:
            stats.roundoff_accepts += 1
        return True

    def backtrack(self, model, stats: NewtonStats | None = None, lie=None) -> float:
        """The first s = ½, ¼, … that passes the test, from the strain energy at q + s dq
        (on a group, ``lie``: at q_n ⊕ (D + s dq), the iterate's first row being D; each
        halving counted in ``stats``)."""
        stats = NewtonStats() if stats is None else stats
        q = self.X[0]
        qt = q.copy()
        s = 1.0
        for _ in range(MAX_CUTS):
            s *= 0.5
            stats.line_search_cuts += 1
            qt[model.free] = q[model.free] + s * self.dq
            at = qt if lie is None else lie.configuration(qt)
            change = s * self.lin + s * s * self.quad + (model.strain_energy(at) - self.W0)
            if change <= ARMIJO * s * self.slope:
                return s
        raise StepFailure("smooth step: the line search found no decrease", self.residual)


def descent_direction(
    model,
    r,
    fi,
    S,
    K,
    solve,
    shift,
    tol_increment: float,
    residual: float,
    stats=None,
    solver=None,
):
    """Newton's direction −S⁻¹r of the free dofs, or the mass-shifted one where it does not
    descend Π.

    ``r`` is the residual (the gradient of Π), ``fi`` the internal force in it, ``S`` the
    iteration matrix and ``K`` the tangent of ``fi`` (both free × free), ``solve`` applies
    S⁻¹, ``shift`` is the positive definite matrix β′M added to shift S. ``residual`` is the
    relative residual, reported if the step fails. Returns dq, lin and quad (see
    :class:`Armijo`) and the slope r·dq < 0; slope None for an update below
    ``tol_increment`` (:meth:`fecontact.model.Model.update_size`), taken whole. The update and
    its shifts are counted in ``stats`` (:class:`fecontact.time.stats.NewtonStats`); ``solver``
    (:class:`fecontact.linalg.LinearSolver`) factorizes the shifted matrices.
    """
    stats = NewtonStats() if stats is None else stats
    stats.iterations += 1
    dq = -solve(r)
    if model.update_size(dq) <= tol_increment:
        return dq, 0.0, 0.0, None
    tau = 0.0
    for _ in range(MAX_SHIFTS):
        slope = float(r @ dq)
        if slope < 0.0:
            return dq, *line_terms(r, fi, S, K, dq), slope
        tau = 1.0 if tau == 0.0 else 10.0 * tau
        stats.shifted_directions += 1
        dq = -factorize_or_fail(_plus(S, tau * shift), residual, True, solver)(r)
    raise StepFailure("smooth step: no descent direction of the incremental potential", residual)


def group_direction(model, r, elastic, S, solve, lie, X, tol_increment: float, residual: float):
    """Newton's update dq = −S⁻¹r on a Lie group and its :class:`Armijo` test where it
    descends above the increment tolerance (else whether it is below: taken whole, an
    update below the tolerance ending the iteration). ``lie`` is the step's
    :class:`fecontact.time.lie.LieStep`, ``X`` the iterate (its first row D), ``elastic``
    the elastic term at it. In D the strain energy changes along dq by f_int·T(D)dq and
    S_t holds K T(D): the slope and the quadratic part are taken so (module docstring)."""
    dq = -solve(r)
    if model.update_size(dq) <= tol_increment:  # (most steps' last update)
        return dq, True
    fi = elastic.fi
    lin = float((r - fi) @ dq)
    Td = _tangent_times(lie, dq)
    slope = lin + float(fi @ Td)
    if slope >= 0.0:
        return dq, False
    quad = 0.5 * (float(dq @ (S @ dq)) - float(dq @ (elastic.K @ Td)))
    floor = energy_roundoff(model, elastic.W)
    return dq, Armijo(X.copy(), dq, lin, quad, slope, elastic.W, residual, floor)


def _tangent_times(lie, v: np.ndarray) -> np.ndarray:
    """T(D) v on the free dofs: each rotation triple of v times its T(D), the rest kept."""
    if not lie.model.rotations.size:
        return v
    T, block = lie.T, lie.group.block
    cols = block if block is not None else lie.cols
    out = v.copy()
    out[cols] = np.einsum("kij,kj->ki", T, v[cols].reshape(T.shape[0], 3)).ravel()
    return out


def line_terms(r, fi, S, K, dq) -> tuple[float, float]:
    """(lin, quad) of :class:`Armijo` along ``dq``."""
    return float((r - fi) @ dq), 0.5 * (float(dq @ (S @ dq)) - float(dq @ (K @ dq)))


def _plus(S, T):
    if sp.issparse(S) or not sp.issparse(T):
        return S + T
    return S + T.toarray()
