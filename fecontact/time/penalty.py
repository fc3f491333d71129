r"""Penalty contact in the generalized-α step, a baseline for the work–precision benchmarks.

It has the signature ``step(model, state, h, options, timer) -> State`` of every stepper, and it
penetrates, by design.

**Penalty** contact in the smooth generalized-α step (the Newton of step 1 of
:mod:`fecontact.time.nsga` with a contact force, no position correction, no velocity jump):

    M v̇_{n+1} + f_int(q_{n+1}) + C v_{n+1} − f_ext(t_{n+1}) − Σ_j G_jᵀ λ_j = 0,
    λ_j = [k_j δ_j + c_j min(−ġ_j, δ_j/τ)]_+,  δ_j = −g_j > 0 (λ_j = 0 when g_j ≥ 0),

a spring–dashpot clipped at zero (no adhesion), whose dashpot builds up over the first
τ = h/2 of a contact: the plain dashpot would jump to c_j|ġ_j| at first touch, a force no
implicit step can balance (Newton then cycles between open and closed), while this λ_j is
continuous in q and tends to [k_j δ_j − c_j ġ_j]_+ as h → 0. The exact tangent on the
contacts with λ_j > 0 is w_j G_jᵀG_j − λ_j ∇²g_j, w_j = k_j + γ′c_j (or k_j + c_j/τ on the
ramp; ∂ġ/∂q = γ′G, the dashpot's ∂G/∂q v term left out). An update that does not lower the
residual is halved (up to six times). The impulse of a step is h λ_j(q_{n+1}).

Penalty parameters (options ``penalty_stiffness``, ``penalty_damping``):

- k_j = ``penalty_stiffness`` (N/m) for every contact; if None (default), automatic
  k_j = m_j (2π/(10 h₁))² with h₁ the first step of the run from t = 0 and m_j the effective
  mass of the contact (1/(G_j M⁻¹ G_jᵀ), with M⁻¹ restricted by the joints) where it first
  closes: the contact oscillator m_j, k_j has a period of 10 h₁, so an elastic impact lasts
  five steps whatever h₁. Each k_j then stays fixed over the run (a halved step does not
  stiffen the contact; the force stays conservative). With it the penetration shrinks like
  h₁, but an impact is always resolved by about five steps, so the rebound velocity keeps
  an error of a few per cent (0.80–0.82 for e = 0.8 on the ball at any h; 0.54 for e = 0.5
  on the rigid pendulum) that does not shrink with h. With a fixed k_p the rebound
  converges as h → 0 and the penetration stalls at v⁻√(m_j/k_j).
  :func:`automatic_penalty_stiffness` gives the value for a chosen step.
- c_j = 2ζ_j √(k_j m_j) (fixed with k_j); ζ = ``penalty_damping`` (damping ratio, ≥ 0) for
  every contact, or if None (default) from each contact's restitution e_j through the
  restitution of the clipped linear spring–dashpot (Schwager & Pöschel 2007; separation
  where λ returns to 0, not where g does): with s = √(1 − ζ²) and x = atan2(2ζs, 2ζ² − 1),
  e(ζ) = exp(−ζx/s) ((ζ/s) sin x − cos x) (hyperbolic functions for ζ > 1; e(0) = 1,
  e(1) = e⁻², e ≈ 1/(4ζ²) for large ζ), inverted numerically. Below e⁻² ≈ 0.135 (e = 0
  included) ζ stays at 1: an overdamped dashpot is stiffer than the step resolves (with
  ζ = 16, for e = 10⁻³, and the automatic k_j the point rebounds at 0.66 v⁻), so these
  contacts rebound at about 0.135 v⁻; set ``penalty_damping`` for another choice.

=============  ===================================================================
q, v           positions and velocities (dof vectors; the free dofs in the algebra)
g_j, G_j       gap of contact j (m) and its gradient ∂g_j/∂q; G_b those of the joints
λ_j, k_j, c_j  penalty force (N), stiffness (N/m) and dashpot (N·s/m)
m_j            effective mass of contact j (kg)
β′, γ′         ∂v̇/∂q and ∂v/∂q of the generalized-α step
=============  ===================================================================
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from ..linalg import factorize
from .constraints import bordered, plus_curvature
from .generalized_alpha import Coefficients
from .newton import NewtonPlan
from .records import PenaltyRecord
from .settings import run_settings
from .state import IntegratorOptions, PhaseTimer, State
from .terms import Damping, Elastic, ExternalLoad, ForceTerm, Joints

__all__ = [
    "PenaltyContact",
    "automatic_penalty_stiffness",
    "damping_ratio",
    "effective_masses",
    "penalty_plan",
    "penalty_step",
]


def effective_masses(model, q, select=None) -> np.ndarray:
    """m_j = 1/(G_j Y_j) (kg) of the contacts ``select`` (default all) at configuration ``q``,
    with Y = M⁻¹G_jᵀ restricted by the joints ([[M, G_bᵀ], [G_b, 0]] [Y; μ] = [G_jᵀ; 0]): the
    mass the contact point carries when pushed along its normal. Zero for a contact that
    moves no free dof."""
    select = model.contacts.all if select is None else select
    _, G = model.contacts.jacobian(q, select)
    if not G.shape[0]:
        return np.zeros(0)
    n, joints = G.shape[1], model.joints
    if joints.size:
        Gb = joints.jacobian(q, joints.all)[1]
        rhs = np.vstack([G.T, np.zeros((joints.size, G.shape[0]))])
        Y = factorize(bordered(model.M, Gb), solver=model.solver)(rhs)
        Y = Y.reshape(n + joints.size, -1)[:n]
    else:
        Y = model.solve_M(G.T).reshape(n, -1)
    inverse = np.einsum("ij,ji->i", G, Y)
    return np.divide(1.0, inverse, out=np.zeros_like(inverse), where=inverse > 0.0)


def automatic_penalty_stiffness(model, h: float, q=None) -> np.ndarray:
    """k_j = m_j (2π/(10 h))² (N/m) per contact at ``q`` (default: the reference state): a
    contact period of ten steps of size h."""
    q = np.zeros(model.n) if q is None else q
    return effective_masses(model, q) * (2.0 * math.pi / (10.0 * h)) ** 2


def _dashpot_restitution(zeta: float) -> float:
    """Restitution of the clipped linear spring–dashpot with damping ratio ζ ≥ 0."""
    if zeta == 1.0:
        return math.exp(-2.0)
    if zeta < 1.0:
        s = math.sqrt(1.0 - zeta * zeta)
        x = math.atan2(2.0 * zeta * s, 2.0 * zeta * zeta - 1.0)
        return math.exp(-zeta * x / s) * (zeta / s * math.sin(x) - math.cos(x))
    s = math.sqrt(zeta * zeta - 1.0)
    x = math.atanh(2.0 * zeta * s / (2.0 * zeta * zeta - 1.0))
    return math.exp(-zeta * x / s) * (zeta / s * math.sinh(x) - math.cosh(x))


def damping_ratio(restitution) -> np.ndarray:
    """ζ ∈ [0, 1] of the clipped spring–dashpot whose restitution is e (1 for e ≤ e⁻²)."""
    from scipy.optimize import brentq  # lazily: scipy.optimize takes 0.1 s to import

    e = np.asarray(restitution, dtype=float)
    values = {
        x: 0.0 if x >= 1.0 else brentq(lambda z, x=x: _dashpot_restitution(z) - x, 0.0, 1.0)
        for x in np.unique(np.maximum(e, math.exp(-2.0)))
    }
    e = np.maximum(e, math.exp(-2.0))
    return np.array([values[x] for x in e.ravel()]).reshape(e.shape)


class _PenaltyLaw:
    """k_j and c_j of every contact of a run, each fixed where the contact first closes
    (its effective mass m_j depends on the configuration: a rotating body, a joint). They
    live in the run's :class:`fecontact.time.records.PenaltyRecord` (the state's
    ``penalty``): k_j, c_j (NaN until the contact closes) and h₁, the first step of the run."""

    def __init__(self, model, record: PenaltyRecord, stiffness, zeta):
        self.model, self.stiffness, self.zeta = model, stiffness, zeta
        self.record = record
        self.k, self.c = record.k, record.c
        self.h1 = float(record.h1)

    def __call__(self, q, A):
        """(k_j, c_j) of the contacts A at configuration q."""
        new = A[np.isnan(self.k[A])]
        if new.size:
            m_eff = effective_masses(self.model, q, new)
            k = self.stiffness
            if k is None:
                k = m_eff * (2.0 * math.pi / (10.0 * self.h1)) ** 2
            zeta = self.zeta
            if zeta is None:
                zeta = damping_ratio(self.model.contacts.restitution[new])
            self.k[new] = k
            self.c[new] = 2.0 * zeta * np.sqrt(k * m_eff)
        return self.k[A], self.c[A]


def _penalty_law(model, st, h, opts):
    """The penalty law of the run ``st`` belongs to (a new one at t = 0)."""
    record = st.penalty
    if st.t == 0.0 or record is None:
        nan = np.full(model.contacts.size, np.nan)
        record = PenaltyRecord(nan, nan.copy(), float(h))
    return _PenaltyLaw(model, record, opts.penalty_stiffness, opts.penalty_damping)


def _penalty_force(model, q, v, law, gp, tau):
    """Σ G_jᵀ λ_j on the free dofs, its tangent −∂/∂q (the contact stiffness), λ and the gaps
    (all contacts). ``gp`` = γ′ = ∂v/∂q along the generalized-α Newton, ``tau`` the time
    over which the dashpot builds up."""
    F, contacts = model.free, model.contacts
    lam = np.zeros(contacts.size)
    g = contacts.gaps(q)
    A = np.flatnonzero(g < 0.0)
    if not A.size:
        return None, None, lam, g
    _, G = contacts.jacobian(q, A)
    kp, cp = law(q, A)
    delta, gdot = -g[A], G @ v[F]
    rate = -gdot <= delta / tau  # the dashpot acts on ġ, else on δ/τ
    lam_A = kp * delta + cp * np.where(rate, -gdot, delta / tau)
    on = lam_A > 0.0
    A, G, lam_A = A[on], G[on], lam_A[on]
    lam[A] = lam_A
    if not A.size:
        return None, None, lam, g
    w = kp[on] + cp[on] * np.where(rate[on], gp, 1.0 / tau)
    if sp.issparse(model.M):
        Gs = sp.csr_matrix(G)
        Kc = (Gs.T @ sp.diags(w) @ Gs).tocsr()
    else:
        Kc = G.T @ (w[:, None] * G)
    if not contacts.linear:
        Kc = plus_curvature(Kc, -1.0, contacts.curvature(q, A, lam_A))
    return G.T @ lam_A, Kc, lam, g


class PenaltyContact(ForceTerm):
    """The spring–dashpot forces λ_j of every contact as a force term of the smooth Newton
    loop: force −Σ G_jᵀλ_j, tangent the contact stiffness (w_j G_jᵀG_j − λ_j ∇²g_j on the
    contacts with λ_j > 0, the dashpot's rate γ′ in w_j). Per step it carries the run's
    :class:`_PenaltyLaw` and the last evaluation: ``lam`` (N) and the gaps ``g`` (m) of every
    contact."""

    phase = "contact"
    own_tangent = True

    def __init__(self, model):
        self.model = model
        self.law = self.fc = self.Kc = self.lam = self.g = None
        self.gp = self.tau = 0.0

    def begin(self, step):
        c = step.c
        self.law = _penalty_law(self.model, step.st, c.h, step.opts)
        self.gp, self.tau = c.gp, 0.5 * c.h
        return self

    def evaluate(self, step, it):
        self.fc, self.Kc, self.lam, self.g = _penalty_force(
            self.model, step.q, step.v, self.law, self.gp, self.tau
        )

    def residual(self, r):
        if self.fc is not None:
            r -= self.fc
        return r

    def tangent(self, S):
        return S if self.Kc is None else S + self.Kc


def penalty_plan(model, smooth: bool, friction: bool, extra=()) -> NewtonPlan:
    """The penalty step's Newton loop for a run of ``model``: the force terms elastic, load,
    penalty contact, Rayleigh damping and joints where the model has them, then ``extra``;
    S_t assembled at every iteration (the contact stiffness changes), an update that does not
    lower the residual halved. (``smooth``, ``friction``: unused, penalty forces have no
    friction.)"""
    elastic = Elastic(model, tangent=True, fused=False)
    terms: list[ForceTerm] = [elastic, ExternalLoad(model), PenaltyContact(model)]
    if any(model.damping):
        terms.append(Damping(model, elastic, constant=False))
    if model.joints.size:
        terms.append(Joints(model, scaled=False, linearize_first=False))
    return NewtonPlan((*terms, *extra), False, False, True, False, "penalty step")


def penalty_step(model, st: State, h: float, opts: IntegratorOptions, timer: PhaseTimer) -> State:
    """One generalized-α step with spring–dashpot contact forces λ_j (no position
    correction, no velocity jump): the smooth Newton loop over :func:`penalty_plan`'s terms.
    A contact opening or closing between two iterates can make Newton cycle; an update that
    does not lower the residual is halved (up to six times) before the next Newton
    direction."""
    opts = run_settings(model, opts, plan=penalty_plan)
    c = Coefficients(opts.rho_inf, h)
    newton = opts.plan.loop(model, opts, timer).start(st, st.t + h, c)
    it, stale = newton.run()
    contact = next(term for term in newton.terms if isinstance(term, PenaltyContact))
    if stale:  # the forces and gaps at the final q
        contact.evaluate(newton.step, it)
    q, v, vd, a = newton.step.X
    gaps = contact.g
    return State(
        st.t + h,
        q,
        v,
        vd,
        a,
        h=h,
        gaps=gaps,
        candidates=np.flatnonzero(gaps <= opts.detection_margin * model.length),
        nu=np.zeros(model.contacts.size),
        impulse=h * contact.lam,
        lam=newton.form.lam(),
        iterations={"smooth": it, "position": 0, "velocity": 0},
        penalty=contact.law.record,
    )
