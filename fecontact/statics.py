"""Static equilibrium: Newton's method with load stepping (f_int(q) = λ f, λ: 0 → 1), and a
linear solid pressed on a plane (the discrete Signorini problem, solved exactly)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .errors import InputError, SolverError
from .linalg import factorize

__all__ = ["solve_static", "solve_static_contact", "static_contact"]


def solve_static(
    model, load: np.ndarray, steps: int = 10, tol: float = 1e-10, max_iterations: int = 30
) -> np.ndarray:
    """Displacements (full dof vector) in equilibrium with the nodal ``load`` (N, N·m).

    The load is applied in ``steps`` equal increments, each solved by Newton's method to a
    relative residual ``tol``; contacts and gravity are ignored. Raises ``SolverError`` if an
    increment does not converge.
    """
    if any(len(b.rotation_triples) for b in model.bodies):
        raise InputError(
            "model: its rotations in space do not add; use "
            "fecontact.statics_rotations.solve_static_rotations"
        )
    F = model.free
    q = np.zeros(model.n)
    scale = max(np.linalg.norm(load[F]), 1e-300)
    for lam in np.linspace(0.0, 1.0, steps + 1)[1:]:
        for it in range(max_iterations + 1):
            _, f, K = model.internal(q)
            r = f[F] - lam * load[F]
            if np.linalg.norm(r) <= tol * scale:
                break
            if it == max_iterations:
                raise SolverError(
                    f"static Newton did not converge at load factor {lam:.3g}",
                    residual=float(np.linalg.norm(r) / scale),
                )
            q[F] -= factorize(K, symmetric=True)(r)
    return q


def solve_static_contact(
    model, load: np.ndarray, small: bool = False, tol: float = 1e-12, max_iterations: int = 40
):
    """Equilibrium of the bodies of ``model`` under the nodal ``load`` (N) with the model's
    frictionless contacts, f_int(q) = load + Σ_j G_jᵀ λ_j, 0 ≤ g_j ⊥ λ_j ≥ 0, in one load step.

    Newton's method on the bordered system [K − Σ λ_j ∇²g_j, G_Aᵀ; G_A, 0] with a primal–dual
    active set A = {j : λ_j − c g_j ≥ −c tol L} (c = the largest diagonal entry of K) re-evaluated
    after every update. Returns (q (all dofs, m), λ (N, one per contact)); stops when the
    update is below ``tol`` × the model size, the active set repeats and λ ≥ 0, g ≥ −tol L;
    raises ``SolverError`` otherwise. For static patch tests of contact discretizations.
    ``small``: small displacements, the gaps linearised at the reference configuration,
    g(q) = g(0) + G(0) q (with a linear material, the problem of the classical patch test);
    else they are evaluated where the bodies are.
    """
    F, contacts = model.free, model.contacts
    q, lam = np.zeros(model.n), np.zeros(contacts.size)
    L, A_prev = model.length, None
    g0, G0 = contacts.linearize(q, contacts.all)[:2]
    if small:
        finite = np.isfinite(g0)
        g0, G0 = np.where(finite, g0, np.inf), np.where(finite[:, None], G0, 0.0)

    def gaps(q):
        return g0 + G0 @ q[F] if small else contacts.gaps(q)

    def linearize(q, rows, weights):
        if small:
            return gaps(q)[rows], G0[rows], np.zeros((len(F), len(F)))
        return contacts.linearize(q, rows, weights)

    for _ in range(max_iterations):
        _, f, K = model.internal(q)
        K = K.toarray() if sp.issparse(K) else np.asarray(K)
        c = float(np.max(np.abs(np.diag(K))))
        g_all = gaps(q)
        # closed gaps (within tol L) start active: the bodies may touch without force
        s_j = lam - c * np.where(np.isfinite(g_all), g_all, 0.0)
        A = np.isfinite(g_all) & (s_j >= -c * tol * L)
        rows = np.flatnonzero(A)
        g, G, C = linearize(q, rows, lam[rows])
        Kt = K - (C.toarray() if sp.issparse(C) else C)
        m, n = len(rows), len(F)
        M = np.block([[Kt, -G.T], [G, np.zeros((m, m))]])
        sol = np.linalg.solve(M, np.concatenate([load[F] - f[F] + 0.0, -g]))
        du, lam = sol[:n], np.zeros(contacts.size)
        lam[rows] = sol[n:]
        q[F] += du
        done = np.max(np.abs(du), initial=0.0) <= tol * L and np.array_equal(A, A_prev)
        if done and np.all(lam >= 0.0) and np.min(gaps(q), initial=0.0) >= -tol * L:
            return q, lam
        A_prev = A
    raise SolverError("static contact: Newton or the active set did not settle")


def static_contact(solid, load: np.ndarray, plane, within: float, hold: float = 1e-6):
    """Equilibrium of a linear elastic ``solid`` pressed on a rigid ``plane`` by the nodal
    ``load`` (N, the solid's dof vector), frictionless: the discrete Signorini problem solved
    exactly. Returns (displacements u (m), indices of the nodes in contact).

    The node nearest the plane is held on it (it must carry a compressive reaction, checked);
    the other boundary nodes closer to the plane than ``within`` (m) are unknown reactions
    r ≥ 0 with gaps g ≥ 0, r g = 0 (the gap g = n·(x − p) along the plane's normal n), on the
    Schur complement S = G A⁻¹ Gᵀ, solved by principal pivoting (S is symmetric positive
    definite). The rigid motions that the contact leaves free carry no load and are held by
    a mass term: A = K + ε M, ε = ``hold`` · E/(ρ L²), L half the solid's largest extent, a
    body force ``hold`` times what the stiffness E L would take at the same displacement
    (a ball of 0.05 m pressed by 1 N: 8e-5 of the load, taken from the reactions).
    Raises ``SolverError`` if the active set does not settle or a node beyond ``within``
    penetrates, and ``InputError`` for a solid whose stiffness is not constant."""
    if not solid.linear:
        raise InputError("static_contact: the solid's material must be linear elastic")
    X, n = solid.X, plane.normal
    length = 0.5 * float(np.max(np.ptp(X, axis=0)))
    M = solid.mass_matrix()
    A = solid.stiffness_matrix() + hold * solid.material.E / (solid.material.rho * length**2) * M
    solve = factorize(A.tocsc(), symmetric=True)
    gap0 = (X - plane.point) @ n
    boundary = solid.boundary_nodes()
    pole = int(boundary[np.argmin(gap0[boundary])])
    nodes = np.concatenate([[pole], boundary[(gap0[boundary] < within) & (boundary != pole)]])
    G = sp.csr_matrix(
        (np.tile(n, nodes.size), (np.repeat(np.arange(nodes.size), solid.dim), _dofs(nodes, n))),
        shape=(nodes.size, solid.ndof),
    )
    u0 = solve(load)
    Z = solve(G.T.toarray())
    S, g0 = G @ Z, gap0[nodes] + G @ u0
    r = _signorini(S, g0, 1e-12 * length)
    if r[0] <= 0.0:
        raise SolverError("static contact: the node nearest the plane pulls on it", residual=r[0])
    u = u0 + Z @ r
    beyond = np.setdiff1d(boundary, nodes)
    if np.min(gap0[beyond] + u.reshape(-1, solid.dim)[beyond] @ n, initial=0.0) < -1e-12 * length:
        raise SolverError(f"static contact: a node beyond within = {within:g} m penetrates")
    return u, nodes[r > 0.0]


def _dofs(nodes: np.ndarray, n: np.ndarray) -> np.ndarray:
    return (n.size * nodes[:, None] + np.arange(n.size)).ravel()


def _signorini(S: np.ndarray, g0: np.ndarray, tol: float) -> np.ndarray:
    """Reactions r ≥ 0 with g = g0 + S r ≥ −tol, r g = 0, the first one always active."""
    active = np.zeros(g0.size, bool)
    active[0] = True
    for _ in range(g0.size + 1):
        r = np.zeros(g0.size)
        r[active] = np.linalg.solve(S[np.ix_(active, active)], -g0[active])
        # active gaps are zero by construction: only the inactive ones are tested
        closing = ~active & (g0 + S[:, active] @ r[active] < -tol)
        if np.any(r[1:] < 0.0):
            active[1:] &= r[1:] > 0.0
        elif np.any(closing):
            active |= closing
        else:
            return r
    raise SolverError("static contact: the active set did not settle")
