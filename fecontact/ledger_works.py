"""The works the energy ledger reads off a step (J): the impulses of a velocity jump at the
mean of the rates before and after it, Moreau–Jean's impulses over its step, the
penalty baseline's contact forces and Rayleigh damping."""

from __future__ import annotations

import math

import numpy as np

from .contact.restitution import impulse_work

__all__ = [
    "damping_force",
    "damping_step_work",
    "impulse_step_work",
    "joint_step_work",
    "jump_work",
    "moreau_works",
    "slip_step_work",
    "spring_step_work",
]


def jump_work(model, q, v, W, closed, G1, rates, lam, lam_t) -> np.ndarray:
    """The work (J) of the impulses of a velocity jump v → v + ``W`` at the mean of the rates
    before and after it, (normal, tangential, joints): ``G1`` the rows (``closed`` contacts,
    then joints) at ``q``, ``rates`` their rates at v (relative to moving obstacles), ``lam``
    their impulses (N·s), ``lam_t`` the tangential impulses (len(closed), nt)
    (:func:`fecontact.contact.restitution.impulse_work`)."""
    F, m = model.free, closed.size
    GT, T = model.contacts.tangent_jacobian(q, closed)
    slip = GT @ v[F]
    speed = model.contacts.obstacle_motion(closed, velocity=True)
    if speed is not None:
        slip -= np.einsum("mtd,md->mt", T, speed)
    nt = GT.shape[1]
    w0 = np.concatenate([np.column_stack([rates[:m], slip]).ravel(), rates[m:]])
    dw = np.concatenate([np.column_stack([G1[:m] @ W, GT @ W]).ravel(), G1[m:] @ W])
    x = np.concatenate([np.column_stack([lam[:m], lam_t]).ravel(), lam[m:]])
    return impulse_work(x, w0, w0 + dw, m, nt)


def moreau_works(model, last, st) -> np.ndarray:
    """(normal, tangential, joints) works (J) of Moreau–Jean's impulses of the step from
    ``last`` to ``st`` at its mean velocity (v_n + v_{n+1})/2, rates at q_{n+1}."""
    normal, slip = -impulse_step_work(model, last, st), -slip_step_work(model, last, st)
    return np.array([normal, slip, joint_step_work(model, last, st)])


def impulse_step_work(model, last, st) -> float:
    """−Σ P_j G_j(q_{n+1}) v_mid of Moreau–Jean's normal impulses (J)."""
    j = np.flatnonzero(st.impulse)
    G = model.contacts.linearize(st.q, j)[1]
    v_mid = 0.5 * (st.v + last.v)[model.free]
    rate = G @ v_mid
    if model.contacts.moving:
        rate = rate + model.contacts.rates(st.q, j)
    return -float(st.impulse[j] @ rate)


def joint_step_work(model, last, st) -> float:
    """Σ P_b G_b(q_{n+1}) v_mid of Moreau–Jean's joint impulses P_b = −h λ (J) in a step
    with contact impulses."""
    joints = model.joints
    if not joints.size or st.lam is None or st.lam.size != joints.size:
        return 0.0
    Gb = joints.jacobian(st.q, joints.all)[1]
    v_mid = 0.5 * (st.v + last.v)[model.free]
    return -st.h * float(st.lam @ (Gb @ v_mid))


def slip_step_work(model, last, st) -> float:
    """−Σ P_T,j·G_T,j(q_{n+1}) v_mid (J), Moreau–Jean's tangential impulses times the
    mean slip of the step: what they take from the bodies; the part friction's reading
    does not explain is the impact's (0 where the impulse opposes the slip throughout)."""
    record = st.friction
    if record is None or not np.any(record.impulse):
        return 0.0
    j = np.flatnonzero(np.any(record.impulse != 0.0, axis=1))
    contacts = model.contacts
    GT, T = contacts.tangent_jacobian(st.q, j)
    v_mid = 0.5 * (st.v + last.v)[model.free]
    slip = GT @ v_mid
    speed = contacts.obstacle_motion(j, velocity=True)
    if speed is not None:
        slip = slip - np.einsum("mtd,md->mt", T, speed)
    return -float(np.sum(record.impulse[j] * slip))


def spring_step_work(last, st) -> float:
    """−½(λ_n + λ_{n+1})·Δg (J): what the penalty forces took from the bodies."""
    lam = st.impulse / st.h
    lam0 = last.impulse / last.h if last.h > 0 else np.zeros_like(lam)
    if lam0.size != lam.size or last.gaps.size != st.gaps.size:
        return 0.0
    g0, g1 = last.gaps, st.gaps
    if math.isfinite(np.add.reduce(g0) + np.add.reduce(g1)):  # (every row has its gap)
        return -0.5 * float(np.sum((lam0 + lam) * (g1 - g0)))
    both = np.isfinite(g0) & np.isfinite(g1)  # (rows without a gap at either end: no work)
    return -0.5 * float(np.sum((lam0[both] + lam[both]) * (g1[both] - g0[both])))


def damping_force(model, q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """C(q)v on the free dofs (N), C = αM + βK(q)."""
    alpha, beta = model.damping
    v = v[model.free]
    out = alpha * (model.M @ v)
    if beta:
        out += beta * (model.internal(q, tangent=True)[2] @ v)
    return out


def damping_step_work(model, last, st, last_force, smooth_end=None) -> tuple[float, np.ndarray]:
    """What damping took over the step from ``last`` to ``st`` (J), given the force C(q)v the
    step starts with, and the force the next step starts with: the mean force times the
    step's displacement h(v_n + v_{n+1})/2, the trapezoidal rule's own damping work (ρ∞ = 1).
    ½h(vᵀCv at both ends) exceeded it by ¼h ΔvᵀCΔv, which the numerical term took back as a
    creation where Δv is large: a ringing disk with β = 1e-5 s booked 0.573 J of damping for
    0.310 J. ``smooth_end`` (q̃ or None, ṽ): the smooth step's end where a correction or a
    jump moved v after it. The force acted up to there, not at the jump's velocities, whose
    kinks at the contact nodes βK reads as a strong force (a disk struck at 20 m/s: 50.8 J
    booked in its first step for 0.03 J), and it is C(q̃)ṽ that v̇ carries into the next
    step (docs/explanation/energy_ledger.md, *Damping*)."""
    q_end, v_end = st.q, st.v
    if smooth_end is not None:
        q_end = st.q if smooth_end[0] is None else smooth_end[0]
        v_end = smooth_end[1]
    force = damping_force(model, q_end, v_end)
    v_mid = 0.5 * (last.v + v_end)[model.free]
    return 0.5 * st.h * float(v_mid @ (last_force + force)), force
