r"""Moreau–Jean time stepping, a baseline for the work–precision benchmarks.

The classical alternative to the nonsmooth generalized-α step on the same ``Model``, with the
same signature ``step(model, state, h, options, timer) -> State``. It does not enforce the gap
g ≥ 0: it penetrates, by design.

**Moreau–Jean** (Jean 1999; Acary & Brogliato 2008, §10.1), a θ-method whose only contact law
is Newton's impact law at velocity level:

    M (v_{n+1} − v_n) = h [(1 − θ) f_n + θ f_{n+1}] + Σ_{j∈I} G_jᵀ P_j + G_bᵀ P_b,
    q_{n+1} = q_n + h [(1 − θ) v_n + θ v_{n+1}],      f = f_ext(t) − f_int(q) − C v,
    0 ≤ ġ_j⁺ + e_j ġ_j⁻ ⊥ P_j ≥ 0 (j ∈ I),   G_b v_{n+1} = 0 (joints),
    ġ_j⁺ = G_j(q_{n+1}) v_{n+1},  ġ_j⁻ = G_j(q_n) v_n,  I = {j : g_j(q_n + ½h v_n) ≤ 0}.

Newton on f_int: each iteration linearises the smooth residual with
Ŵ = M + hθ C_t + h²θ² K_t − hθ Σ P_j ∇²g_j and solves the impact law for the free velocity
v_free = v^k − Ŵ⁻¹R(v^k) with :func:`fecontact.contact.solve_velocity_jump` (Alart–Curnier,
semi-smooth Newton); linear bodies converge in one iteration, rigid ones (K_t = 0, constant
G) need no second assembly. The predictor is v_n: v_n + h v̇_n is exact in free flight but,
after impacts, extrapolates the ringing θ = ½ leaves in stiff modes and derails Newton.
θ = ½ is the trapezoidal rule (second order in smooth motion, no numerical dissipation),
θ = 1 implicit Euler (first order, dissipative). Without dissipation the high-frequency
ringing that impacts leave in a geometrically exact beam can grow: the flexible pendulum
with e = 0.5, h = 10⁻³ and θ = ½ blows up at t ≈ 1.46 s, while θ = 0.51 runs (measured).
A contact closes once its predicted gap is ≤ 0, and the impact ends with a penetration in
[0, h|ġ⁻|) (O(h)), kept for as long as the contact lasts: nothing pulls the point back to
g = 0. ``State.vd`` holds M⁻¹ f_{n+1}, so f_n is not assembled again.

=============  ===================================================================
q, v           positions and velocities (dof vectors; the free dofs in the algebra)
h, θ           step and the θ of Moreau–Jean (option ``theta``, default ½)
f              smooth force f_ext − f_int − C v (N)
g_j, G_j       gap of contact j (m) and its gradient ∂g_j/∂q; G_b those of the joints
ġ⁻, ġ⁺         normal velocity at the start and end of a step (m/s)
e_j            Newton's coefficient of restitution
P_j, P_b       impulse of contact j and of the joints over a step (N·s)
I              Moreau–Jean index set: contacts closed at the predicted q_n + ½h v_n
Ŵ              Moreau–Jean iteration matrix
=============  ===================================================================
"""

from __future__ import annotations

import math
import time
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from ..contact.restitution import friction_dissipation
from .constraints import (
    Constraints,
    StepFailure,
    factorize_or_fail,
    impact_law,
    plus_curvature,
)
from .coulomb import frictional_jump
from .newton import NewtonPlan
from .poisson import poisson_jump
from .records import FrictionRecord
from .settings import run_settings
from .state import IntegratorOptions, PhaseTimer, State, length_scale
from .terms import Damping, Elastic, ExternalLoad, StepContext

__all__ = ["ImpactRows", "VelocityForm", "moreau_plan", "moreau_step"]


def moreau_step(model, st: State, h: float, opts: IntegratorOptions, timer: PhaseTimer) -> State:
    """One Moreau–Jean step from ``st`` over ``h`` (s): θ-method with Newton's impact law
    at velocity level on the contacts closed at q_n + ½h v_n, joints as G_b v_{n+1} = 0."""
    opts = run_settings(model, opts, plan=moreau_plan)
    theta = float(opts.theta)  # in (0, 1], checked by IntegratorOptions
    F, m = model.free, model.contacts.size
    clock = time.perf_counter()
    g_pred = model.contacts.gaps(st.q + 0.5 * h * st.v)
    # closed to the gap tolerance, or pressed in the last step and still within the detection
    # margin: the velocity-level law lets a resting contact drift by round-off, and a corner
    # that drifts past the tolerance would leave the set for a step and let the body tip
    # (a contact in the set that separates takes no impulse, so keeping it costs nothing)
    pressed = st.impulse > 0.0 if st.impulse.size == m else np.zeros(m, bool)
    index_set = np.flatnonzero(
        (g_pred <= opts.tol_gap * length_scale(model, st.q))
        | (pressed & (g_pred <= opts.detection_margin * model.length))
    )
    rows = _impact_rows(model, st, index_set)
    timer.add("contact", clock)
    friction = model.contacts.frictional and index_set.size
    slip = (index_set, opts.tol_gap * length_scale(model, st.q) / h) if friction else None
    ht = h * theta
    c = MoreauRates(h, ht, ht, 1.0 / (ht * ht))
    law = ImpactRows(rows, slip)
    newton = opts.plan.loop(model, opts, timer).start(st, st.t + h, c, law=law)
    it, _ = newton.run()
    form = newton.form
    v, P, f, tangential = form.v, form.P, form.f, form.tangential
    its = (it, form.lcp)
    q, vfull, vd = st.q.copy(), np.zeros(model.n), np.zeros(model.n)
    v_theta = (1.0 - theta) * st.v[F] + theta * v
    q[F] += h * v_theta
    vfull[F] = v
    record = None
    if model.contacts.frictional:
        record = FrictionRecord.start(st.friction, m, model.dim)
    if tangential is not None:
        P_t, status, GT = tangential
        record.impulse[index_set] = P_t
        record.status[index_set] = status
        record.work += _friction_work(model, form, index_set, v, slip[1])
    vd[F] = model.solve_M(f)
    impulse = np.zeros(m)
    impulse[index_set] = P[: index_set.size]
    clock = time.perf_counter()
    gaps = model.contacts.gaps(q)
    near = np.flatnonzero(np.minimum(g_pred, gaps) <= opts.detection_margin * model.length)
    timer.add("contact", clock)
    return State(
        st.t + h,
        q,
        vfull,
        vd,
        vd.copy(),
        h=h,
        gaps=gaps,
        candidates=near,
        nu=np.zeros(m),
        impulse=impulse,
        lam=-P[index_set.size :] / h,  # as the smooth step's λ: the joint force is −G_bᵀλ
        iterations={"smooth": its[0], "position": 0, "velocity": its[1]},
        friction=record,
    )


def _friction_work(model, form, closed, v, tol: float) -> float:
    """The energy (J) the step's tangential impulses P_T take, read against the slip rates
    at the step's start and end, G_T v_n and G_T v_{n+1} (relative to moving obstacles,
    G_T at q_{n+1}), through :func:`fecontact.contact.restitution.friction_dissipation` in
    the metric Ŵ of the last iteration: a process in which friction opposes the slip. Where
    P_T opposes the slip at both ends it is −P_T·G_T (v_n + v_{n+1})/2, the impulse times
    the slip the update q_{n+1} = q_n + h v_θ makes at θ = ½; where the slip stops within
    the step it is not the impulse times that slip, which counts the reaction of a contact
    that sticks, along the slip before the step, as positive work. ``tol``: the slip rate
    (m/s) below which a contact sticks, as Coulomb's law's."""
    P_t, status, GT = form.tangential
    nc, nt = closed.size, GT.shape[1]
    G = form.G.toarray() if sp.issparse(form.G) else np.asarray(form.G)
    A = np.concatenate([np.concatenate([G[:nc, None], GT], axis=1).reshape(-1, G.shape[1]),
                        G[nc:]])  # fmt: skip
    D = A @ form.solve(A.T).reshape(G.shape[1], -1)
    speed = model.contacts.obstacle_motion(closed, velocity=True)
    drag = 0.0  # the obstacle's tangential velocity (m/s), (nc, nt)
    if speed is not None:
        T = model.contacts.tangent_jacobian(form.step.X[0], closed)[1]
        drag = np.einsum("mtd,md->mt", T, speed)
    w0, w = (_block_rates(G, GT, u, drag) for u in (form.vn, v))
    # a contact the law holds stuck ends the step stuck: the slip it keeps is the law's
    # solver tolerance, which may lie a little above the stick threshold ``tol``
    stuck = np.flatnonzero(status == 1)
    for k in range(nt):
        w[stuck * (1 + nt) + 1 + k] = 0.0
    P = form.P
    x = np.concatenate([np.column_stack([P[:nc], P_t]).ravel(), P[nc:]])
    return friction_dissipation(x, w0, w, D, model.contacts.friction[closed], nt, tol)


def _block_rates(G, GT, u, drag):
    """The rates of ``u`` in the layout of ``friction_dissipation``: per contact, its normal
    then tangential rates (less the obstacle's ``drag``), then the joints'."""
    nc = GT.shape[0]
    g = G @ u
    return np.concatenate([np.column_stack([g[:nc], GT @ u - drag]).ravel(), g[nc:]])


def _impact_rows(model, st, index_set):
    """(rows, e ġ⁻, e, ġ⁻) of the impact law: the contacts ``index_set`` and every joint;
    None when there are none."""
    if not index_set.size and not model.joints.size:
        return None
    rows = Constraints(model, index_set)
    e = np.concatenate([model.contacts.restitution[index_set], np.zeros(model.joints.size)])
    approach = rows.jacobian(st.q)[1] @ st.v[model.free] if np.any(e) else np.zeros(e.size)
    return rows, e * approach, e, approach


class MoreauRates(NamedTuple):
    """The rates of the Moreau–Jean Newton in its unknown v_{n+1}: q = q_n + h(1 − θ)v_n +
    hθ v, so ∂q/∂v = hθ (``ht``), and the damping's ∂f/∂v enters Ŵ with ``gp`` = hθ."""

    h: float
    ht: float
    gp: float
    bp: float


class MoreauElastic(Elastic):
    """The elastic term of the Moreau–Jean Newton: it opens Ŵ = M + (hθ)² K_t."""

    def begin(self, step):
        self.ht2 = step.c.ht * step.c.ht
        return self

    def tangent(self, S):
        return self.model.M + self.ht2 * self.K


def moreau_plan(model, smooth: bool = False, friction: bool = False, extra=()) -> NewtonPlan:
    """The Moreau–Jean Newton's force terms for a run of ``model``: elastic, load and
    Rayleigh damping where the model has it (the contacts and joints are its impact law's
    rows, not terms)."""
    elastic = MoreauElastic(model, tangent=True)
    terms = [elastic, ExternalLoad(model)]
    if any(model.damping):
        terms.append(Damping(model, elastic, constant=False))
    return NewtonPlan(
        (*terms, *extra), False, False, False, False, "Moreau–Jean step", form=VelocityForm
    )


class ImpactRows(NamedTuple):
    """What Moreau–Jean's form needs of a step besides its state: the impact law's ``rows``
    (Constraints of the index set and the joints, e ġ⁻, e, ġ⁻; None without any) and, with
    friction, ``slip`` = (the contacts of the rows, the Coulomb tolerance in m/s)."""

    rows: tuple | None
    slip: tuple | None


class VelocityForm:
    """Moreau–Jean's form of the shared Newton loop ``newton``
    (:class:`~fecontact.time.newton.SmoothNewton`): Newton on R(v) − G(q(v))ᵀP −
    G_T(q(v))ᵀP_T = 0, R(v) = M(v − v_n) − h[(1 − θ) f_n + θ f(q(v), v)], f = f_ext − Σ_k
    f_k over the plan's force terms, for the unknown v = v_{n+1} from the predictor v_n
    (``st``), with q = q_n + h(1 − θ)v_n + hθ v (the rates ``c``, :class:`MoreauRates`) and
    the impact law on the rows of ``law`` (:class:`ImpactRows`) inside each update; with its
    ``slip``, Coulomb's law on their slip rates G_T v. Without stiffness (K_t = 0: rigid
    bodies) and with constant G the residual is linear in v and one iteration is exact."""

    __slots__ = (
        "G GP P R f ff_t h hf_n ht lcp model newton opts q0 ref rnorm rows size slip solve st "
        "step tangential v vn"
    ).split()

    def __init__(self, newton, st, c, t: float, P, law: ImpactRows):
        model = newton.model
        F, h, ht = model.free, c.h, c.ht
        self.newton, self.model, self.opts, self.st = newton, model, newton.opts, st
        self.h, self.ht, (self.rows, self.slip) = h, ht, law
        self.vn = st.v[F]
        self.hf_n = (h - ht) * (model.M @ st.vd[F])  # st.vd = M⁻¹ f_n
        self.q0 = st.q[F] + (h - ht) * self.vn
        nr = len(self.rows[0].bilateral) if self.rows else 0
        self.v, self.P, self.GP, self.G = self.vn.copy(), np.zeros(nr), 0.0, None
        self.tangential, self.ff_t, self.size, self.lcp = None, 0.0, math.inf, 0
        self.solve = self.f = self.R = None  # (solve: Ŵ⁻¹ of the last update)
        self.rnorm, self.ref = math.inf, 1.0
        # the step's context at the predictor v_n (no persistent contacts: ``P`` unused)
        X = np.zeros((4, model.n))
        X[0], X[1] = st.q, st.v
        self.step = StepContext(model, c, t, st, self.opts, None, X)

    def residual(self, it: int) -> bool:
        """r at v (q = q_n + h(1 − θ)v_n + hθ v); whether it has converged: the residual or
        the last update below tolerance, with rows not before the law was solved once."""
        newton, model, F, X, rows = self.newton, self.model, self.model.free, self.step.X, self.rows
        X[0, F] = self.q0 + self.ht * self.v
        X[1, F] = self.v
        newton.evaluate(it)
        # f = f_ext − f_int − C v = −Σ_k f_k: the sum starts from −0 (−0 + x = x exactly)
        # and 0 − s negates it exactly, zeros included, as the direct sum would round
        self.f = f = 0.0 - newton.forces(np.full(self.v.size, -0.0))
        Mdv = model.M @ (self.v - self.vn)
        self.R = R = Mdv - self.hf_n - self.ht * f
        nr = self.P.size
        if nr and (it == 0 or not rows[0].linear):  # (constant gradients: evaluated once)
            self.G = rows[0].jacobian(X[0])[1]
        if nr:
            self.GP, self.ff_t, self.tangential = _constraint_forces(
                model, X[0], self.G, self.P, self.tangential, self.slip
            )
        r = R - self.GP - self.ff_t
        newton.clock = newton.timer.add("assembly", newton.clock)
        self.rnorm, self.ref = _norms(r, (Mdv, self.hf_n, self.h, f), self.GP if nr else None)
        return _converged(it, nr, self.rnorm, self.ref, self.size, self.opts)

    def update(self) -> bool:
        """v ← v − Ŵ⁻¹R, then the impact law from there; whether one iteration was exact."""
        newton, model, rows, q = self.newton, self.model, self.rows, self.step.X[0]
        What = newton.tangent()
        if rows and not rows[0].linear and np.any(self.P):
            What = plus_curvature(What, -self.ht, rows[0].curvature(q, self.P))
        self.solve = solve = factorize_or_fail(What, self.rnorm / self.ref, True, model.solver)
        v_new = self.v - solve(self.R)
        newton.clock = newton.timer.add("solve", newton.clock)
        if self.P.size:
            law = _contact_law(model, self.st, q, v_new, self.G, rows, solve, self.opts,
                               self.slip, self.h)  # fmt: skip
            W, self.P, n, self.tangential = law
            v_new += W
            self.lcp += n
            newton.clock = newton.timer.add("contact", newton.clock)
        if _exact(model, rows, newton.elastic.K, self.slip):
            damping = next((term for term in newton.terms if isinstance(term, Damping)), None)
            if damping is not None:  # (f at v_{n+1})
                self.f = _minus_damping(self.f, damping.Ct, v_new - self.v)
            self.v = v_new
            return True
        self.size = model.update_size(self.ht * (v_new - self.v))
        self.v = v_new
        return False


def _minus_damping(f, Ct, v):
    """f − C_t v (``Ct`` None: no damping, f itself)."""
    if Ct is None:
        return f
    f -= Ct @ v
    return f


def _norms(r, parts, GP):
    """|r| and its reference: the largest of |M(v − v_n)|, |h(1 − θ)f_n|, |h f| (``parts``
    = (M(v − v_n), h(1 − θ)f_n, h, f)) and |GᵀP| (``GP``, None without constraint rows)."""
    Mdv, hf_n, h, f = parts
    ref = max(Mdv @ Mdv, hf_n @ hf_n, h * h * (f @ f), 1e-300)
    rnorm = math.sqrt(r @ r)
    if not math.isfinite(rnorm):
        raise StepFailure("Moreau–Jean step diverged", rnorm)
    return rnorm, math.sqrt(ref if GP is None else max(ref, GP @ GP))


def _converged(it: int, nr: int, rnorm: float, ref: float, dq: float, opts) -> bool:
    """The residual or the last update below tolerance; with constraint rows (``nr``), not
    before the impact law has been solved once."""
    return bool(it or not nr) and (rnorm <= opts.tol_residual * ref or dq <= opts.tol_increment)


def _exact(model, rows, K, slip) -> bool:
    """Whether one iteration is exact: no stiffness (K_t = 0: rigid bodies), constant
    constraint gradients and no turning slip rows (the residual is linear in v)."""
    return (rows is None or rows[0].linear) and _is_zero(K) and not _turning(model, slip)


def _constraint_forces(model, q, G, P, tangential, slip):
    """(GᵀP, Σ G_Tᵀ P_T, tangential) at q: the impulses' generalized forces, with the slip
    rows' G_T of the last law's (P_T, status) taken at q (None without friction)."""
    GP, friction_force = G.T @ P, 0.0
    if tangential is not None:
        GT = model.contacts.tangent_jacobian(q, slip[0])[0]
        friction_force = np.einsum("mt,mtk->k", tangential[0], GT)
        tangential = (tangential[0], tangential[1], GT)
    return GP, friction_force, tangential


def _contact_law(model, st, q, v_free, G, rows, solve, opts, slip, h):
    """The impact law at the velocity ``v_free`` (free dofs) in the metric Ŵ: W, P (normal
    then joint impulses), iterations, and with ``slip`` Coulomb's (P_T, status, G_T).
    Poisson's law where the options ask for it and a row restitutes (e > 0)."""
    if opts.impact_law == "poisson" and np.any(rows[2]):
        return _poisson_law(model, st, q, v_free, G, rows, solve, opts, h)
    if slip is not None:
        return _coulomb_law(model, st, q, v_free, G, rows, solve, opts, slip)
    Y = solve(G.T).reshape(G.shape[1], -1)  # Ŵ⁻¹Gᵀ
    W, P, n = impact_law(G, G @ v_free + rows[1], solve, Y, opts, rows[0].bilateral)
    return W, P, n, None


def _coulomb_law(model, st, q, v_free, G, rows, solve, opts, slip):
    """The impact law with Coulomb's cone on the slip rates (``frictional_jump`` in the
    metric Ŵ): W, P (normal then joint impulses), iterations, (P_T, status, G_T)."""
    index_set, tol = slip
    v = np.zeros(model.n)
    v[model.free] = v_free
    W, P_n, P_t, status, its, _, P_b = frictional_jump(
        model, st, q, v, index_set, G, G @ v_free + rows[1], opts, tol, solve
    )
    GT = model.contacts.tangent_jacobian(q, index_set)[0]
    return W, np.concatenate([P_n, P_b]), its, (P_t, status, GT)


def _poisson_law(model, st, q, v_free, G, rows, solve, opts, h):
    """Poisson's law (:func:`fecontact.time.poisson.poisson_jump`) in the metric Ŵ, with the
    result of :func:`_coulomb_law` (P_T, status, G_T = None without friction)."""
    v = np.zeros(model.n)
    v[model.free] = v_free
    index_set = rows[0].select
    tol = opts.tol_gap * length_scale(model, st.q) / h  # (m/s), as Coulomb's law's
    W, P, its, friction, _ = poisson_jump(
        model, st, q, v, index_set, G, G @ v_free, rows[2], rows[3][: index_set.size], opts,
        tol, solve=solve, bilateral=rows[0].bilateral,
    )  # fmt: skip
    if friction is None:
        return W, P, its, None
    GT = model.contacts.tangent_jacobian(q, index_set)[0]
    return W, P, its, (friction[0], friction[1], GT)


def _turning(model, slip) -> bool:
    """Whether the slip rows depend on q (rotating bodies): then the friction force of the
    residual needs the next iteration's G_T."""
    return slip is not None and not model.contacts.linear


def _is_zero(K) -> bool:
    return not (K.data.any() if sp.issparse(K) else K.any())


# -- penalty contact in the smooth generalized-α step -------------------------------------------
