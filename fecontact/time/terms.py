r"""Force terms of the smooth Newton loop (:mod:`.newton`).

The loop solves r(X) = M v̇ + Σ_k f_k(q, v, t) = 0 for the iterate X = (q, v, v̇, a) of a
generalized-α step, Newton moving q and (v, v̇, a) following at the rates (γ′, β′, ∂a/∂q).
A term k contributes

- its force f_k (N, on the free dofs, with the sign of an internal force: it enters r with +;
  a load enters with −),
- its tangent: ∂f_k/∂q (stiffness-like, entering S_t = β′M + Σ_k (∂f_k/∂q + γ′ ∂f_k/∂v) with
  coefficient 1) and ∂f_k/∂v (damping-like, with γ′),
- where it carries multipliers, constraint rows (g, G, curvature) that border S_t,
- its own convergence tests, at an iterate (``converged``) and after an update (``settled``).

:class:`ForceTerm` gives every method a neutral default, so a term states only what it has.
A run builds its list once (:func:`fecontact.time.settings.run_settings`): a feature the model
lacks is a term absent from the list. Each step calls ``begin``, which returns the term as it
acts in that step (itself, a fresh object with per-step data, or None: absent this step).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from ..joints import newton_remainder
from ..linalg import low_rank_solver
from .constraints import StepFailure
from .correction import curved_factors, unit_columns
from .coulomb import SmoothFriction
from .held_curvature import held_curvature, hold
from .lie import InertialForces
from .smooth_contact import SmoothContacts
from .state import JointTolerance

__all__ = [
    "Damping",
    "Elastic",
    "ExternalLoad",
    "ForceTerm",
    "Gyroscopic",
    "Joints",
    "PersistentContacts",
    "SmoothContact",
    "StepContext",
]


class StepContext:
    """What the terms of one smooth step read: the ``model``, the generalized-α coefficients
    ``c`` (β′ = c.bp, γ′ = c.gp), the time ``t`` (s) at the step's end, the start state
    ``st``, the run's ``opts``, the persistent contacts ``P`` and the iterate ``X`` (rows q,
    v, v̇, a: views that follow every update). ``tolerance`` is the constraints' gap
    tolerance (:class:`JointTolerance` at the predictor), made on first use."""

    __slots__ = ("model", "c", "t", "st", "opts", "P", "X", "q", "v", "vd", "a", "_tol")

    def __init__(self, model, c, t, st, opts, P, X):
        self.model, self.c, self.t, self.st, self.opts, self.P, self.X = model, c, t, st, opts, P, X
        self.q, self.v, self.vd, self.a = X
        self._tol = None

    @property
    def tolerance(self) -> JointTolerance:
        if self._tol is None:
            self._tol = JointTolerance(self.model, self.q, self.opts.tol_gap)
        return self._tol


class ForceTerm:
    """A force term f(q, v, t) of the smooth Newton loop; every method's default is the term
    that is not there. ``phase`` names the timer phase its evaluation is charged to.
    ``own_tangent``: it adds a tangent of its own (then S_t is assembled at every iteration,
    not reused from a linear model's factorization). ``rows``: it can border S_t with
    constraint rows. ``per_step``: its ``begin`` may return another object or None (else
    it returns the term itself, and the loop sorts its roles once per run)."""

    phase = "assembly"
    per_step = False
    own_tangent = False
    rows = False
    schur = False
    schur_only = False  # its rows cannot border S_t (a law solved on its Delassus matrix)

    def begin(self, step: StepContext) -> ForceTerm | None:
        """The term as it acts in the step ``step`` (None: absent in it)."""
        return self

    def evaluate(self, step: StepContext, it: int) -> None:
        """Evaluate at the iterate ``step.X`` of Newton iteration ``it``."""

    def residual(self, r: np.ndarray) -> np.ndarray:
        """r + f (N), in place where r is the loop's own array."""
        return r

    def reference(self) -> float:
        """|f|² of a force that sets the residual's scale (N²; 0: none)."""
        return 0.0

    def tangent(self, S):
        """S + ∂f/∂q + γ′ ∂f/∂v (free × free)."""
        return S

    def converged(self, step: StepContext) -> bool:
        """The term's own test at the iterate (its constraints, its complementarity)."""
        return True

    def settled(self, step: StepContext) -> bool:
        """The term's own test after an update below the increment tolerance."""
        return True

    def solved(self, step: StepContext) -> bool:
        """The term's own test after an exact update (:attr:`NewtonPlan.exact`), which
        leaves the term as it is: False where it cannot tell (the residual decides)."""
        return False

    # -- a term with rows (``rows``) also has:

    def touching(self) -> bool:
        """Whether its rows border S_t in this update."""
        return False

    def border(self, step: StepContext):
        """(g, G, C): its rows' values, gradients (rows × free dofs) and curvature (None:
        none) at the iterate."""
        raise NotImplementedError

    def take(self, x: np.ndarray) -> None:
        """Apply the bordered solve's update ``x`` of its multipliers."""

    def complementary(self) -> bool:
        """Whether its update is its rows' linearised law solved whole
        (:mod:`.smooth_redundant`), not a bordered or Schur solve of its active rows."""
        return False

    def retreat(self, s: float) -> None:
        """Take back the fraction ``s`` of the last update of its multipliers."""


class Elastic(ForceTerm):
    """The internal forces f_int(q) of the bodies and their tangent K_t; it opens the
    iteration matrix with the inertia, β′M + K_t (``fused``: summed in the model's sparse
    pattern, else as two matrices). ``tangent``: K_t is assembled (False where a linear
    model's S_t is reused); ``constant``: it is the same at every q (a linear model), assembled
    once. The loop's energy descent reads the strain energy ``W``."""

    def __init__(self, model, tangent: bool, fused: bool = True, constant: bool = False):
        self.model, self.F, self.assemble, self.fused = model, model.free_slice, tangent, fused
        self.W = self.fint = self.fi = self.K = None
        self.bp = 0.0
        self.constant = constant and tangent

    def evaluate(self, step, it):
        self.bp = step.c.bp  # (of the step: its tangent opens with β′M)
        if self.constant and self.K is not None:
            self.W, self.fint, _ = self.model.internal(step.q, tangent=False)
        else:
            self.W, self.fint, self.K = self.model.internal(step.q, tangent=self.assemble)
        self.fi = self.fint[self.F]

    def residual(self, r):
        return r + self.fi

    def reference(self):
        return self.fi @ self.fi

    def tangent(self, S):
        if self.fused:
            return self.model.iteration_sum(self.bp, self.K)
        return self.bp * self.model.M + self.K


class ExternalLoad(ForceTerm):
    """The applied loads f_ext(t) (gravity, point loads), constant over the step; a model
    without time-dependent loads has them constant over the run, taken once."""

    def __init__(self, model):
        self.model, self.F = model, model.free_slice
        self.steady = not model.loads
        self.fext, self.ff = None, 0.0
        if self.steady:
            self._take(0.0)

    def _take(self, t: float) -> None:
        self.fext = self.model.external(t)[self.F]
        self.ff = self.fext @ self.fext

    def begin(self, step):
        if not self.steady:
            self._take(step.t)
        return self

    def residual(self, r):
        return r - self.fext

    def reference(self):
        return self.ff


class Gyroscopic(ForceTerm):
    """The velocity-dependent inertial forces of rotating bodies, Ω × JΩ in their body frames
    (:mod:`.lie`); their tangent ∂f/∂v enters S_t with γ′."""

    own_tangent = True

    def __init__(self, model):
        self.model, self.f, self.C_v, self.gp = model, None, None, 0.0
        self.forces = InertialForces(model)  # each body's scatter, decided once

    def begin(self, step):
        self.gp = np.array(step.c.gp)  # (0-d: numpy scales an array by it faster than by a float)
        return self

    def evaluate(self, step, it):
        self.f, self.C_v = self.forces(step.q, step.v)

    def residual(self, r):
        return r + self.f

    def tangent(self, S):
        return S + self.gp * self.C_v

    def remainder(self, step, dq: np.ndarray) -> float:
        """|f(v + γ′dq) − f(v) − γ′C_v dq| (N, N·m) after a Newton update dq of the free
        dofs: f(γ′dq) itself, as the forces Ω × JΩ are quadratic forms of v."""
        dv = np.zeros(self.model.n)
        dv[self.model.free_slice] = self.gp * dq
        r = self.forces(step.q, dv, tangent=False)[0]
        return math.sqrt(r @ r)


class Damping(ForceTerm):
    """Rayleigh damping C_t v, C_t = αM + βK_t (K_t of ``elastic``); its tangent γ′C_t (the
    ∂K_t/∂q v part left out). ``constant``: a linear model's C, kept with its S_t."""

    def __init__(self, model, elastic: Elastic, constant: bool):
        self.model, self.elastic, self.constant = model, elastic, constant
        self.alpha, self.beta = model.damping
        self.F, self.Ct, self.c = model.free_slice, None, None

    def begin(self, step):
        self.c = step.c
        return self

    def evaluate(self, step, it):
        if self.constant:
            self.Ct = self.model.iteration_matrix(self.c.bp, self.c.gp)[2]
        else:
            self.Ct = self.alpha * self.model.M + self.beta * self.elastic.K
        self.v = step.v

    def residual(self, r):
        r += self.Ct @ self.v[self.F]
        return r

    def tangent(self, S):
        return S + self.c.gp * self.Ct


class FixedTolerance:
    """A gap tolerance of ``value`` (m), as :class:`JointTolerance` tests it."""

    def __init__(self, value: float):
        self.value = value

    def admits(self, x: float, factor: float = 1.0) -> bool:
        return x <= factor * self.value


class Joints(ForceTerm):
    """The joints g_b(q) = 0 with multipliers λ_b: force G_bᵀλ_b, rows (g_b, G_b) and their
    curvature Σ λ_i ∇²g_i. ``scaled``: the gap tolerance follows the model's extent at the
    predictor (:class:`JointTolerance`), else it is tol_gap × model.length.
    ``linearize_first``: their curvature is evaluated with the gradient in every iteration,
    else when a solve asks for it."""

    rows = True

    def __init__(self, model, scaled: bool, linearize_first: bool):
        self.model, self.joints, self.n = model, model.joints, model.joints.size
        self.scaled, self.first = scaled, linearize_first
        self.lam = self.gb = self.Gb = self.Cb = self.tol = self.dlam = None

    def begin(self, step):
        self.lam = step.st.lam.copy()
        if self.scaled:
            self.tol = step.tolerance
        else:
            self.tol = FixedTolerance(step.opts.tol_gap * self.model.length)
        return self

    def evaluate(self, step, it):
        joints = self.joints
        # the curvature with the gradient (``linearize_first``: a bordered solve follows
        # every iteration that does not converge, and the curvature costs less than a second
        # evaluation of the joints), else only once a solve asks for it
        weights = self.lam if self.first and not joints.linear else None
        self.gb, self.Gb, self.Cb = joints.linearize(step.q, joints.all, weights)

    def residual(self, r):
        r += self.Gb.T @ self.lam
        return r

    def converged(self, step):
        return self.tol.admits(np.abs(self.gb).max())

    settled = converged

    def touching(self) -> bool:
        return True

    def border(self, step):
        """(g, G, C): the rows and their curvature."""
        if self.Cb is None and not self.joints.linear:
            self.Cb = self.joints.curvature(step.q, self.joints.all, self.lam)
        return self.gb, self.Gb, self.Cb

    def take(self, x: np.ndarray) -> None:
        self.dlam = x
        self.lam = self.lam + x

    def retreat(self, s: float) -> None:
        self.lam = self.lam - s * self.dlam

    def bound(self, step, dq, x, ff: float, extra=None) -> bool:
        """Whether the update (dq, x = Δλ_b) ends the iteration by the remainder bound: when
        it is below half the tolerances the next residual test passes at the same q (the
        other half covers the solve's round-off). The reference max(|f_ext|, |M v̇|) is at
        most that of the test (which includes |f_int|); ``ff`` = |f_ext|², ``extra()`` (N)
        the remainder of the other nonlinear forces (None: none)."""
        bound = newton_remainder(self.joints, dq, self.lam, x)
        if bound is None:
            return False
        gap, force = bound
        if not self.tol.admits(gap, 0.5):
            return False
        if extra is not None:
            force += extra()
        limit = 0.5 * step.opts.tol_residual
        if force <= limit * math.sqrt(ff):
            return True
        Mvd = self.model.M @ step.vd[self.model.free_slice]
        return force <= limit * math.sqrt(Mvd @ Mvd)


class SmoothContact(ForceTerm):
    """The persistent contacts of a step (:mod:`.smooth_contact`, :class:`SmoothFriction`
    with friction) as forces −Σ G_jᵀλ_j (− G_Tᵀλ_T), under complementarity. Absent in a
    step without persistent contacts."""

    rows = True
    per_step = True

    def __init__(self, model, friction: bool):
        self.model, self.friction = model, friction
        self.curved = not model.contacts.linear
        # (set for the rest of a split step, :mod:`.localize`: the multipliers start from
        # the forces that the restarted acceleration carries in v̇, not from zero)
        self.carried = False

    def begin(self, step):
        P = step.P
        if P is None or not P.size:
            return None
        return PersistentContacts(self._contacts(step), self.curved)

    def _contacts(self, step):
        model, st = self.model, step.st
        model.contacts.set_time(step.t)
        if self.friction:
            return SmoothFriction(model, st, step.P, step.t, step.opts)
        force = None if st.smooth is None else st.smooth.normal
        force0 = np.zeros(step.P.size) if force is None else force[step.P]
        if self.carried and st.smooth is not None:
            force0 = np.maximum(force0, st.smooth.in_vd[step.P, 0])
        return SmoothContacts(model, step.P, force0, step.opts)


class PersistentContacts(ForceTerm):
    """:class:`SmoothContact` in one step: ``sc`` the contacts' law
    (:class:`SmoothContacts` or :class:`SmoothFriction`)."""

    rows = True
    schur = True

    def __init__(self, sc, curved: bool):
        self.sc, self.curved = sc, curved
        self.schur_only = isinstance(sc, SmoothFriction)

    def evaluate(self, step, it):
        self.sc.update(step.q, self.curved)

    def residual(self, r):
        r -= self.sc.force_term()
        return r

    def converged(self, step):
        return self.sc.satisfied(step.tolerance.admits)

    def settled(self, step):
        return self.sc.settled(step.q, step.tolerance.admits)

    def solved(self, step):
        return self.sc.holds(step.q, step.tolerance.admits)

    def touching(self) -> bool:
        return bool(self.sc.active.any())

    def border(self, step):
        gA, GA = self.sc.rows()
        return gA, GA, self.sc.C

    def take(self, x: np.ndarray) -> None:
        self.sc.take(x)

    def complementary(self) -> bool:
        return not self.schur_only and self.sc.complementary

    def live_border(self):
        """(L, G_L, C): the rows of P that can hold (a finite gap, a nonzero gradient),
        their gradients (dense) and the curvature of the forces at the iterate, for
        :meth:`SmoothContacts.complementary_update`."""
        sc = self.sc
        G = sc.G.toarray() if sp.issparse(sc.G) else np.asarray(sc.G)
        L = np.flatnonzero((sc.g < np.inf) & G.any(axis=1))
        return L, G[L], sc.C

    def retreat(self, s: float) -> None:
        self.sc.retreat(s)

    def forces(self, m: int):
        """(λ (m,), λ_T (m, nt) or None without friction, the work of λ_T over the step (J))
        of every contact (N), zero outside the persistent ones."""
        sc = self.sc
        if isinstance(sc, SmoothFriction):
            return (*sc.forces(m), sc.work())
        return sc.forces(m), None, 0.0

    def schur_update(self, step, r, solve, constant: bool, residual: float) -> np.ndarray:
        """The update with these rows alone, through S_t's own factors ``solve``
        (``constant``: S_t is fixed at this step size)."""
        return schur_update(step, self.sc, r, solve, constant, residual)


def schur_update(step, sc, r, solve, constant: bool, residual: float) -> np.ndarray:
    """The contacts' update through S_t's ``solve``: straight gaps by the Schur complement
    (S_t⁻¹G_jᵀ kept per contact when S_t is ``constant``), curved ones with the curvature as
    a low-rank correction of S_t's factors, or at a size met once S_t plus the curvature
    factorized where that costs less than the correction's columns, those factors then
    serving the updates at nearby sizes (:mod:`.held_curvature`)."""
    model, c = step.model, step.c
    if sc.C is None:
        return sc.schur_update(model, r, solve, (c.bp, c.gp) if constant else None)
    units = unit_columns(model, ("smooth", c.bp, c.gp), solve, constant)
    held = held_curvature(model, units, c.bp, sc.C, residual, step)  # (modified Newton)
    if held is not None:
        return sc.schur_update(model, r, held)
    S = model.iteration_matrix  # (S_t at this size: the matrix the curvature adds to)
    factors = curved_factors(model, units, lambda: S(c.bp, c.gp)[0], -sc.C, residual)
    if factors is not None:  # (a size met once: cheaper than the columns)
        hold(model, units, c.bp, factors, sc.C, residual, step)
        return sc.schur_update(model, r, factors)
    return sc.schur_update(model, r, with_curvature(solve, sc.C, units, residual))


def with_curvature(solve, C, units, residual):
    """(S + C)⁻¹ from S's ``solve`` and the columns S⁻¹e_i (``units``) of the few dofs the
    curvature C of the contact forces touches (:func:`fecontact.linalg.low_rank_solver`)."""
    try:
        return low_rank_solver(solve, -C, units)
    except np.linalg.LinAlgError:
        raise StepFailure("singular smooth-step matrix in contact", residual) from None
