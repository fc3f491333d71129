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
import time
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from ..linalg import factorize
from .constraints import StepFailure, bordered, factorize_or_fail, plus_curvature
from .generalized_alpha import Coefficients, predict
from .records import PenaltyRecord
from .state import IntegratorOptions, PhaseTimer, State

__all__ = ["automatic_penalty_stiffness", "damping_ratio", "effective_masses", "penalty_step"]


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


def penalty_step(model, st: State, h: float, opts: IntegratorOptions, timer: PhaseTimer) -> State:
    """One generalized-α step with spring–dashpot contact forces λ_j (no position
    correction, no velocity jump)."""
    c = Coefficients(opts.rho_inf, h)
    law = _penalty_law(model, st, h, opts)
    q, v, vd, a, lam, lam_c, gaps, it = _penalty_smooth_step(
        model, st, st.t + h, c, law, opts, timer
    )
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
        impulse=h * lam_c,
        lam=lam,
        iterations={"smooth": it, "position": 0, "velocity": 0},
        penalty=law.record,
    )


class PenaltyStep(NamedTuple):
    """Positions, velocities, accelerations v̇ and a, joint multipliers λ_b, contact forces
    λ_j (N), gaps (m) at the end of the step, and the Newton iterations."""

    q: np.ndarray
    v: np.ndarray
    vd: np.ndarray
    a: np.ndarray
    lam: np.ndarray
    lam_c: np.ndarray
    gaps: np.ndarray
    iterations: int


def _halves(dq, rnorm: float, previous: float, s: float) -> bool:
    """Whether the last update ``dq`` (None: none yet) is halved: it did not lower the
    residual, and it was halved fewer than six times."""
    return dq is not None and rnorm >= previous and s > 1.0 / 64.0


def _joints_hold(gb, tol: float) -> bool:
    """Whether the joints' gaps ``gb`` (None: no joints) are within ``tol`` (m)."""
    return gb is None or np.max(np.abs(gb)) <= tol


def _penalty_matrix(c, M, K, Kc, Ct):
    """S = β′M + K_t + K_c (the contact stiffness, None without) + γ′C_t (None: undamped)."""
    S = c.bp * M + K
    if Kc is not None:
        S = S + Kc
    if Ct is not None:
        S = S + c.gp * Ct
    return S


def _penalty_update(model, S, r, joint_rows, q, lam, residual: float):
    """Newton's update (dq, Δλ_b): with S alone, or bordered by the joints' rows
    ``joint_rows`` = (g_b, G_b) at q (None, None without joints) and their curvature."""
    gb, Gb = joint_rows
    if gb is None:
        return -factorize_or_fail(S, residual, True, model.solver)(r), 0.0
    joints, n = model.joints, model.n_free
    Cb = None if joints.linear else joints.curvature(q, joints.all, lam)
    Kb = plus_curvature(S, 1.0, Cb)
    x = -factorize_or_fail(bordered(Kb, Gb), residual, False, model.solver)(np.concatenate([r, gb]))
    return x[:n], x[n:]


def _penalty_smooth_step(model, st, t, c, law, opts, timer) -> PenaltyStep:
    """Newton on M v̇ + C_t v + f_int(q) − Σ G_jᵀλ_j + G_bᵀλ_b = f_ext(t), g_b(q) = 0, with
    (q, v, v̇, a) linked as in the generalized-α step. A contact opening or closing between
    two iterates can make Newton cycle; an update that does not lower the residual is
    halved (up to six times) before the next Newton direction."""
    F, h, M = model.free, c.h, model.M
    q, v, vd, a = predict(st, c)
    lam = st.lam.copy()
    fext = model.external(t)[F]
    joints = model.joints
    nb = joints.size
    alpha, beta_k = model.damping
    tol_b = opts.tol_gap * model.length
    previous, s, dq, dlam = math.inf, 1.0, None, 0.0

    def move(x):
        q[F] += x
        v[F] += c.gp * x
        vd[F] += c.bp * x
        a[F] += c.da * x

    clock = time.perf_counter()
    for it in range(opts.max_iterations + 1):
        _, fint, K = model.internal(q)
        clock = timer.add("assembly", clock)
        fc, Kc, lam_c, g = _penalty_force(model, q, v, law, c.gp, 0.5 * h)
        clock = timer.add("contact", clock)
        Mvd = M @ vd[F]
        r = Mvd + fint[F] - fext
        if fc is not None:
            r -= fc
        Ct = alpha * M + beta_k * K if alpha or beta_k else None
        if Ct is not None:
            r += Ct @ v[F]
        gb = Gb = None
        if nb:
            gb, Gb = joints.jacobian(q, joints.all)
            r += Gb.T @ lam
        clock = timer.add("assembly", clock)
        fi = fint[F]
        ref = math.sqrt(max(fext @ fext, fi @ fi, Mvd @ Mvd, 1e-300))
        rnorm = math.sqrt(r @ r)
        if not np.isfinite(rnorm):
            raise StepFailure("penalty step diverged", rnorm)
        if rnorm <= opts.tol_residual * ref and _joints_hold(gb, tol_b):
            break
        if it == opts.max_iterations:
            raise StepFailure("penalty step", rnorm / ref)
        if _halves(dq, rnorm, previous, s):
            s *= 0.5
            move(-s * dq)
            lam = lam - s * dlam
            continue
        previous, s = rnorm, 1.0
        S = _penalty_matrix(c, M, K, Kc, Ct)
        dq, dlam = _penalty_update(model, S, r, (gb, Gb), q, lam, rnorm / ref)
        lam = lam + dlam
        move(dq)
        clock = timer.add("solve", clock)
        if model.update_size(dq) <= opts.tol_increment and _joints_hold(gb, tol_b):
            _, _, lam_c, g = _penalty_force(model, q, v, law, c.gp, 0.5 * h)
            it += 1
            break
    return PenaltyStep(q, v, vd, a, lam, lam_c, g, it)
