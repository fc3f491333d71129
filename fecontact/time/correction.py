"""The position correction of the NSGA step (step 2): q = q̃ + U in the metric H = S_t/β′
or M, with the contacts' Alart–Curnier multipliers and the joints kept as equalities."""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from ..contact import solve_position_correction
from ..contact.mortar_safeguard import twins_among
from ..linalg import UnitColumns, low_rank_solver, touched
from ..rotations import exp
from .configuration import plus
from .constraints import (
    Constraints,
    StepFailure,
    augmentation,
    constraint_columns,
    factorize_or_fail,
    plus_curvature,
)
from .momentum_planar import planar_momentum
from .momentum_rigid import common_normal, rigid_momentum

__all__ = [
    "MomentumKept",
    "correction_metric",
    "curved_factors",
    "momentum_held",
    "momentum_kept",
    "position_correction",
    "unit_columns",
]


def correction_metric(model, q, S, c, kind):
    """(H, solve_H) of the position correction, H = S_t/β′ (``kind`` "stiffness") or H = M
    ("mass"); H itself is returned as a function, needed only when the gaps are curved."""
    if kind == "mass":
        return lambda: model.M, model.solve_M
    if S is None and model.linear:
        S = model.iteration_matrix(c.bp, c.gp)[:2]
    if S is None:
        _, _, K = model.internal(q)
        S = model.iteration_sum(c.bp, K)
        alpha, beta_k = model.damping
        if alpha or beta_k:
            S = S + c.gp * (alpha * model.M + beta_k * K)
        S = (S, factorize_or_fail(S, math.nan, True, model.solver))
    matrix, solve_S = S
    return lambda: matrix / c.bp, lambda b: c.bp * solve_S(b)


def position_correction(model, q_tilde, cand, metric, c, opts, tol_gap, nu0=None, held=None):
    """Step 2: q = q̃ + U, H U = Σ G_jᵀ [k ν_j − p g_j]_+ over the contacts ``cand``, with
    the joints kept as equalities (always active, multipliers of any sign); ``metric`` is
    (H, solve_H) from :func:`correction_metric`, ``nu0`` the contacts' multipliers of the previous
    step. The ``held`` contacts (a mask over ``cand``: pressed by a smooth force at q̃) are
    equalities too, g_j = 0 with ν_j of either sign: the correction of a contact that closes
    beside them neither lifts them off nor pushes them in (:mod:`.smooth_contact`); where
    they freeze its active sets with the law unsettled, it is solved again with them
    unilateral (counted in ``released_corrections``)."""
    F = model.free
    H, solve_H = metric
    cons = Constraints(model, cand)
    if held is not None:
        cons.bilateral[: cand.size] = held
    _, G0 = cons.jacobian(q_tilde)
    constant = model.linear or opts.metric == "mass"
    Y0 = constraint_columns(model, (opts.metric, c.bp, c.gp), cand, G0, solve_H, cons, constant)
    p = augmentation(opts.penalty_scale, G0, Y0)
    k = opts.multiplier_scale

    def shifted(U):
        return plus(model, q_tilde, U)

    units = []  # H⁻¹e_i, made on the first curved system

    def system(U, s, A):
        if cons.linear:  # constant gradients: H⁻¹G_Aᵀ are columns of Y0
            return (lambda B: Y0[:, A]), None
        C = cons.curvature(shifted(U), np.where(A, s, 0.0))
        if sp.issparse(C) and C.nnz and np.unique(C.row).size <= len(F) // 4:
            # the curvature touches the contact zone only: update H's factors on its dofs
            if not units:
                units.append(unit_columns(model, (opts.metric, c.bp, c.gp), solve_H, constant))
            factors = curved_factors(model, units[0], H, C, math.nan)
            if factors is not None:
                return factors, C
            try:
                return low_rank_solver(solve_H, C, units[0]), C
            except np.linalg.LinAlgError:
                raise StepFailure("singular position-correction matrix", math.nan) from None
        return factorize_or_fail(H() - C, math.nan, True, model.solver), C

    try:
        U, nu, its = solve_position_correction(
            lambda U: cons.jacobian(shifted(U)),
            system,
            len(F),
            p,
            k,
            tol_gap,
            0.1 * tol_gap,
            opts.max_iterations,
            bilateral=cons.bilateral,
            nu0=None if nu0 is None else np.concatenate([nu0, np.zeros(model.joints.size)]),
            stats=opts.stats.contact,
            twins=twins_among(model.contacts.twins, cand, model.joints.size),
            scale=opts.penalty_scale,  # (p_j D_jj: the stop in metres whatever p)
            held_rows=_with_joints(held, model.joints.size),
        )
    except RuntimeError as err:
        raise StepFailure(str(err), np.nan) from None
    return U, k * nu, its


def _with_joints(held, joints: int):
    """The mask ``held`` over the contacts extended over the joints (never held: equalities
    by nature), or None."""
    return None if held is None else np.concatenate([held, np.zeros(joints, bool)])


def unit_columns(model, key, solve_H, constant: bool) -> UnitColumns:
    """H⁻¹e_i of the dofs that gap curvatures touch, kept over the run when H is constant
    (else over one correction); ``key``: (the metric, β′, γ′). Where H is of a size met once,
    factorizations of H − C may stand in for them (:meth:`UnitColumns.factorize_instead`)."""
    if not constant:
        return UnitColumns(solve_H, model.n_free)
    units = model.column_cache.get(("unit", *key))
    if units is None:
        ladder = model.ladder  # (a size met once: H's factors serve one step)
        once = key[0] != "mass" and model.passing and ladder is not None
        units = UnitColumns(solve_H, model.n_free, once and ladder.met_once(key[1]))
        model.column_cache[("unit", *key)] = units
    return units


def curved_factors(model, units: UnitColumns, H, C, residual: float):
    """The factors of H − C (``H()`` the matrix) where ``units`` takes them instead of its
    columns (:meth:`UnitColumns.factorize_instead`, counted in the ladder's
    ``curvature_factorizations``), else None."""
    if not (units.once and units.factorize_instead(touched(C))):
        return None
    model.ladder.counts["curvature_factorizations"] += 1
    return factorize_or_fail(plus_curvature(H(), -1.0, C), residual, True, model.solver)


class MomentumKept:
    """The angular momentum of a free beam in space about its contacts' common normal, held
    through a position correction.

    The correction q̃ → q is a projection of the positions, not a force: it moves the nodes
    but leaves the velocities, so a body's angular momentum L = Σ x_i × p_i + Σ R_i π_i
    (p, π the translational and rotational momenta M v, π in the node frame R_i) changes by
    Σ U_i × p_i and by the rotation of R_i π_i. In the stiffness metric U is mostly the rigid
    response of the body (a tilt about a horizontal axis for a rod struck at one end), whose
    horizontal displacements crossed with a spinning rod's horizontal momenta change its
    momentum about the vertical, which vertical contact forces never change.

    Where every contact of the correction pushes the body along one normal n (a plane, or a
    single contact), their forces have no moment about any axis along n: the component L·n is
    then held, by the rigid angular velocity δω = ℓ n/(nᵀI n) about the centre of mass c,
    v_i += δω × (x_i − c), Ω_i += R_iᵀδω (I the locked inertia, ℓ the lost L·n): of the
    velocities that return L·n to its value at (q̃, ṽ), the one of least kinetic energy. The
    linear momentum is unchanged. The other components are left alone: the contact forces
    change them (for a slender rod, holding them all would force a torsional spin, the
    corrected axis being tilted against L).

    Decided once per model: the beams in space (a rotation vector at every node) without
    support or joint (a held body's momentum is not its own), in a frictionless model (a
    frictional correction moves the nodes along the tangents too). Free rigid bodies in space
    are held by ``rigid`` (:mod:`.momentum_rigid`: a free pair's total L, a lone body's L·n),
    free planar rigid bodies in contact only with each other by ``planar``
    (:mod:`.momentum_planar`: the group's total L).
    """

    def __init__(self, model):
        self.bodies = []  # (body, global slice, its free dofs, mass matrix, node masses (kg))
        self.rigid = rigid_momentum(model)
        self.planar = planar_momentum(model)
        if model.joints.size or model.contacts.frictional:
            return
        for i, b in enumerate(model.bodies):
            if not b.slender or b.fixed or len(b.rotation_triples) != b.n_nodes:
                continue
            M, s = b.mass_matrix(), model.body_slice(i)
            m = (M @ b.translation_field([1.0, 0.0, 0.0]))[::6]
            self.bodies.append((b, s, model.free_index[s], M, m))

    def __call__(self, q_tilde, q, v, G, GT=None) -> np.ndarray:
        """The increment (all dofs) of the velocity ``v`` (ṽ) that holds each body's angular
        momentum (kg·m²/s) about its contacts' common normal at its value at (q̃, ṽ) after the
        correction to ``q``; ``G``: the gradients (free dofs) of the correction's contacts."""
        dv = np.zeros_like(v) if self.rigid is None else self.rigid(q_tilde, q, v, G, GT)
        if self.planar is not None:
            dv += self.planar(q_tilde, q, v, G)
        for b, s, free, M, m in self.bodies:
            Gb = G[:, free]
            Gb = Gb[np.abs(Gb).max(axis=1) > 0.0]
            x = b.positions(q[s])
            fields = _rotation_fields(x - m @ x / m.sum(), q[s])
            n = common_normal(Gb, fields)
            if n is None:
                continue
            lost = _momentum(b, M, q_tilde[s], v[s]) - _momentum(b, M, q[s], v[s])
            f = n @ fields  # the rigid rotation about n through c
            dv[s] = (n @ lost) / (n @ _momentum(b, M, q[s], f)) * f
        return dv


def _momentum(body, M, q, v) -> np.ndarray:
    """L = Σ x_i × p_i + Σ R_i π_i (kg·m²/s) of a beam in space, about the origin."""
    p = (M @ v).reshape(-1, 6)
    R = exp(q.reshape(-1, 6)[:, 3:])
    x = body.positions(q)
    return np.cross(x, p[:, :3]).sum(axis=0) + np.einsum("nij,nj->i", R, p[:, 3:])


def _rotation_fields(r, q) -> np.ndarray:
    """(3, ndof) velocities of the rigid rotations about e_x, e_y, e_z through the centre of
    mass (r = x − c the nodes' positions from it): v_i = e_k × r_i, Ω_i = R_iᵀe_k."""
    R = exp(q.reshape(-1, 6)[:, 3:])
    fields = np.zeros((3, len(r), 6))
    fields[:, :, :3] = np.cross(np.eye(3)[:, None, :], r)
    fields[:, :, 3:] = np.einsum("nji,kj->kni", R, np.eye(3))  # R_iᵀ e_k
    return fields.reshape(3, -1)


def momentum_held(kept, model, q_tilde, q, v, work) -> tuple[np.ndarray, np.ndarray | None]:
    """(v, Δv): the velocity ``v`` after the correction q̃ → q over the contacts ``work`` with
    the increment Δv of ``kept``, the run's :class:`MomentumKept` (None, v itself, for models
    without such bodies: :func:`momentum_kept`)."""
    if kept is None:
        return v, None
    GT = None
    if kept.rigid is not None and kept.rigid.frictional:
        GT = model.contacts.tangent_jacobian(q, work)[0]
    dv = kept(q_tilde, q, v, model.contacts.linearize(q, work)[1], GT)
    return v + dv, dv


def momentum_kept(model) -> MomentumKept | None:
    """The model's :class:`MomentumKept`, decided once per run; None when no body qualifies."""
    kept = MomentumKept(model)
    return kept if kept.bodies or kept.rigid is not None or kept.planar is not None else None
