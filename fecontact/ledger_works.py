"""The works the energy ledger reads off a step (J): the impulses of a velocity jump at the
mean of the rates before and after it, Moreau–Jean's impulses over its step, the
penalty baseline's contact forces and Rayleigh damping."""

from __future__ import annotations

import math

import numpy as np

from .contact.base import PairDefaults
from .contact.restitution import impulse_work

__all__ = [
    "closing_contacts",
    "gripping",
    "jump_gripping",
    "damping_force",
    "damping_step_work",
    "impulse_step_work",
    "joint_step_work",
    "jump_work",
    "moreau_works",
    "obstacle_work",
    "penalty_obstacle_work",
    "smooth_obstacle_work",
    "slip_step_work",
    "unmeasured_motion",
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


def obstacle_work(model, q, normal, tangential=None) -> float:
    """The work (J, or W for forces) that the contact impulses (N·s, or forces in N) do
    through the motion of the obstacles at q: −Σ x_N,j ∂g_j/∂t of the ``normal`` ones (m,)
    and Σ x_T,j·T_j ḋ_j of the ``tangential`` ones (m, nt) or None, with ḋ_j the velocity of
    contact j's obstacle at its current time. The bodies take x·(G v) from them; the rest of
    x·ġ (rates relative to the obstacles) is the obstacle's."""
    contacts, out = model.contacts, 0.0
    if normal is not None and normal.size == contacts.size:
        j = np.flatnonzero(normal)
        if j.size:
            out -= float(normal[j] @ contacts.rates(q, j))
    if tangential is None or tangential.shape[0] != contacts.size:
        return out
    j = np.flatnonzero(np.any(tangential != 0.0, axis=1))
    speed = contacts.obstacle_motion(j, velocity=True) if j.size else None
    if speed is not None:
        T = contacts.tangent_jacobian(q, j)[1]
        if T is None:  # (no pair with friction: no tangential force)
            return out
        out += float(np.sum(tangential[j] * np.einsum("mtd,md->mt", T, speed)))
    return out


def unmeasured_motion(model) -> bool:
    """True where a moving obstacle meets a pair that does not measure its ∂g/∂t (a pair
    without its own ``rate``): its velocity rows do not see the obstacle move,
    the position correction alone carries the body along, and the work it does that way
    is no impulse's or force's that :func:`obstacle_work` could read."""
    return any(
        pair.obstacle is not None and pair.obstacle.moving and type(pair).rate is PairDefaults.rate
        for pair in model.contacts.pairs
    )


def smooth_obstacle_work(model, last, st, gamma: float) -> float:
    """The moving obstacles' work (J) through NSGA's smooth contact forces over the step
    from ``last`` to ``st``: :func:`obstacle_work` of the impulse h((1 − γ) λ^a_n + γ λ^a_{n+1})
    by which they move v, λ^a the forces a carries (``SmoothForces.in_a``), as the step's
    v_{n+1} = v_n + h((1 − γ) a_n + γ a_{n+1}) does."""
    forces = [None if x.smooth is None else x.smooth.in_a for x in (last, st)]
    if forces[0] is None and forces[1] is None:
        return 0.0
    a0, a1 = (np.zeros_like(next(f for f in forces if f is not None)) if f is None else f
              for f in forces)  # fmt: skip
    if a0.shape != a1.shape:
        return 0.0
    x = st.h * ((1.0 - gamma) * a0 + gamma * a1)
    return obstacle_work(model, st.q, x[:, 0], x[:, 1:] if model.contacts.frictional else None)


def penalty_obstacle_work(model, last, st) -> float:
    """The moving obstacles' work (J) through the penalty forces over the step:
    −½(λ_n + λ_{n+1})·(Δg − ½(G_n + G_{n+1}) Δq), the part of the gaps' change that the
    bodies' motion does not make (0 where the obstacles stand)."""
    if last.h <= 0.0 or last.impulse.size != st.impulse.size or last.gaps.size != st.gaps.size:
        return 0.0
    lam = last.impulse / last.h + st.impulse / st.h
    both = np.isfinite(last.gaps) & np.isfinite(st.gaps)
    j = np.flatnonzero((lam != 0.0) & both)
    if not j.size:
        return 0.0
    dq = (st.q - last.q)[model.free]
    Gdq = 0.5 * (model.contacts.jacobian(last.q, j)[1] + model.contacts.jacobian(st.q, j)[1]) @ dq
    return -0.5 * float(lam[j] @ (st.gaps[j] - last.gaps[j] - Gdq))


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


def closing_contacts(last, st) -> list[int]:
    """The contacts the position correction of the step ``st`` pushed out that no force
    pressed in the step before (``last``): they closed within the step."""
    if last is None or st.nu.size != st.impulse.size or last.impulse.size != st.nu.size:
        return []
    return np.flatnonzero((st.nu > 0.0) & ~last.pressed()).tolist()


def jump_gripping(st) -> list[int]:
    """The contacts that carried a tangential impulse in the contact phase of ``st``."""
    record = st.friction
    if record is None or record.impulse is None:
        return []
    return np.flatnonzero(np.any(record.impulse != 0.0, axis=1)).tolist()


def gripping(st) -> list[int]:
    """The contacts that carried a tangential force or impulse in the step ``st``."""
    grip = np.zeros(st.impulse.size, bool)
    friction, smooth = st.friction, st.smooth
    arrays = (
        None if friction is None else friction.impulse,
        None if friction is None else friction.nu,
        None if smooth is None else smooth.tangential,
    )
    for x in arrays:
        if x is not None and x.shape[0] == grip.size:
            grip |= np.any(x != 0.0, axis=1)
    return np.flatnonzero(grip).tolist()
