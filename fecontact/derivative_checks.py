r"""Checks of contact pairs' derivatives against central differences of their own rows: the
gradients G and the curvatures that Newton's tangent uses, on the additive path and on the
rotation group (increments composed on the right)."""

from __future__ import annotations

import numpy as np

__all__ = [
    "derivative_errors_near_contact",
    "gap_steps_along",
    "gap_derivatives_error",
    "group_derivative_errors",
    "group_gradient_error",
    "moved_on_group",
    "rigidly_placed",
    "turn_gap_steps",
    "slip_derivative_errors",
    "slip_step_errors",
]


def gap_derivatives_error(pair, q: np.ndarray, eps: float = 1e-7, rows=None):
    """Largest errors of a pair's gradient and Hessian against central differences of its
    own gaps and gradients at q (each relative to the largest entry, or absolute below 1),
    over ``rows`` (default: every row with a finite gap). A dof listed twice in a row
    carries the sum of its entries."""
    g, dofs, G_, H = pair.evaluate(q)
    finite = np.flatnonzero(np.isfinite(g))
    rows = finite if rows is None else np.intersect1d(finite, rows)
    Hs = np.zeros((len(g),) + (dofs.shape[1],) * 2)
    if H is not None or pair.lazy_hessians:
        Hs[rows] = pair.hessians(q, rows) if pair.lazy_hessians else H[rows]
    err_g = err_h = 0.0
    for j in rows:
        for i in np.unique(dofs[j]):
            at = dofs[j] == i
            dq = np.zeros_like(q)
            dq[i] = eps
            gp, _, Gp, _ = pair.evaluate(q + dq)
            gm, _, Gm, _ = pair.evaluate(q - dq)
            dg = (gp[j] - gm[j]) / (2 * eps)
            err_g = max(err_g, abs(dg - G_[j, at].sum()) / max(1.0, abs(dg)))
            dG = (Gp[j] - Gm[j]) / (2 * eps)
            h = Hs[j][:, at].sum(axis=1)
            err_h = max(err_h, float(np.max(np.abs(dG - h))) / max(1.0, np.abs(h).max()))
    return err_g, err_h


def derivative_errors_near_contact(pair, n: int, margin: float = 0.02, spread: float = 1e-3):
    """(rows with a finite gap, gradient error, Hessian error) of ``pair`` of a model of ``n``
    dofs, its rows detected within ``margin`` (m), at dofs drawn from a normal distribution of
    deviation ``spread`` (m, seed 1): :func:`gap_derivatives_error` with steps of 1e-7 m."""
    pair.detect_within(margin)
    q = np.random.default_rng(1).normal(0.0, spread, n)
    finite = int(np.isfinite(pair.evaluate(q)[0]).sum())
    return (finite, *gap_derivatives_error(pair, q, 1e-7))


def moved_on_group(model, q: np.ndarray, d: np.ndarray) -> np.ndarray:
    """q moved by d: added, but on the model's rotation triples composed on the right,
    R exp(d̃) (the increments along which rows are differentiated)."""
    from .rotations import compose

    out = q + d
    for triple in model.free[model.rotations]:  # (the triples are in free numbering)
        out[triple] = compose(q[triple], d[triple])
    return out


def group_gradient_error(pair, model, q: np.ndarray, along, step: float = 1e-7) -> float:
    """Largest error of ``pair``'s gradients G (absolute, m/m) at q against central
    differences of its rows along each dof of ``along``, moved on the group
    (:func:`moved_on_group`), over its rows with a finite gap: for rows without curvature."""
    g, dofs, G_, _ = pair.evaluate(q)
    rows = np.flatnonzero(np.isfinite(g))
    err = 0.0
    for j in along:
        d = np.zeros(model.n)
        d[j] = step
        # (the rows with a gap at q only: the others read +inf on both sides)
        fd = (
            pair.gaps(moved_on_group(model, q, d))[rows]
            - pair.gaps(moved_on_group(model, q, -d))[rows]
        )
        col = (dofs[rows] == j).astype(float)
        err = max(err, float(np.max(np.abs(fd / (2 * step) - np.sum(G_[rows] * col, 1)))))
    return err


def group_derivative_errors(pair, model, q: np.ndarray, along, step: float = 1e-7):
    """Largest errors of ``pair``'s gradients G (absolute, m/m) and curvatures (relative to the
    largest curvature entry) at q against central differences of its rows and G along each
    dof of ``along``, moved on the group (:func:`moved_on_group`), over its rows with a finite
    gap. A dof listed twice in a row carries the sum of its entries."""
    g, dofs, G_, _ = pair.evaluate(q)
    rows = np.flatnonzero(np.isfinite(g))
    H = pair.hessians(q, rows)
    err_g = err_h = 0.0
    for j in along:
        d = np.zeros(model.n)
        d[j] = step
        gp, _, Gp, _ = pair.evaluate(moved_on_group(model, q, d))
        gm, _, Gm, _ = pair.evaluate(moved_on_group(model, q, -d))
        col = (dofs[rows] == j).astype(float)
        fd = (gp[rows] - gm[rows]) / (2 * step)
        err_g = max(err_g, float(np.max(np.abs(fd - np.sum(G_[rows] * col, axis=1)))))
        fd = (Gp[rows] - Gm[rows]) / (2 * step)
        err_h = max(err_h, float(np.max(np.abs(fd - np.einsum("mkl,ml->mk", H, col)))))
    return err_g, err_h / np.abs(H).max()


def slip_derivative_errors(pair, model, q: np.ndarray, T, steps=(1e-5, 1e-6), seed: int = 2):
    """Errors (m, largest over rows) of ``pair``'s slip rows W d against central differences
    of its exact slips from q to q moved by ±εd on the group (:func:`moved_on_group`), for a
    random direction d and each ε of ``steps``, and the largest |W d| they compare with."""
    dofs, W, _ = pair.tangents(q)
    d = np.random.default_rng(seed).normal(size=model.n)
    linear = np.einsum("mtk,mk->mt", W, d[dofs])
    errors = []
    for eps in steps:
        plus = pair.slips(moved_on_group(model, q, eps * d), q, T)
        minus = pair.slips(moved_on_group(model, q, -eps * d), q, T)
        errors.append(float(np.abs((plus - minus) / (2 * eps) - linear).max()))
    return errors, float(np.abs(linear).max())


def slip_step_errors(pair, q: np.ndarray, d: np.ndarray, rows, scales=(1.0, 0.1)):
    """Relative errors of ``pair``'s slip rows W (at q) as the slips of the step q → q + s d,
    for each s of ``scales``, over ``rows``: the slip over a step is W times the step to
    second order, so the error falls as s."""
    dofs, W, T = pair.tangents(q)
    errors = []
    for s in scales:
        step = np.einsum("mtk,mk->mt", W, s * d[dofs])[rows]
        errors.append(float(np.abs(pair.slips(q + s * d, q, T)[rows] - step).max()))
        errors[-1] /= float(np.abs(step).max())
    return errors


def gap_steps_along(pair, q0: np.ndarray, q1: np.ndarray, samples: int):
    """The rows' gap changes (m) between neighbouring points of the straight path from q0 to
    q1 (``samples`` points), and the larger of the linear predictions |G Δq| at the two ends,
    over the rows with a finite gap at both ends: a continuous gap changes by no more than its
    slopes allow, a jump by far more."""
    s = np.linspace(0.0, 1.0, samples)
    dq = (q1 - q0) * (s[1] - s[0])
    g, slope = [], []
    for t in s:
        gq, dofs, G, _ = pair.evaluate(q0 + t * (q1 - q0))
        g.append(gq)
        slope.append(np.abs(np.sum(G * dq[dofs], axis=1)))
    g, slope = np.array(g), np.array(slope)
    both = np.isfinite(g[1:]) & np.isfinite(g[:-1])
    change = np.abs(np.diff(np.where(np.isfinite(g), g, 0.0), axis=0))[both]
    return change, np.maximum(slope[1:], slope[:-1])[both]


def rigidly_placed(model, body, angle: float, shift) -> np.ndarray:
    """q of ``model`` with the planar ``body`` turned by ``angle`` (rad, counter-clockwise)
    about the mean of its nodes and moved by ``shift`` (m); the other bodies where they lie."""
    c, s = np.cos(angle), np.sin(angle)
    centre = body.X.mean(axis=0)
    x = (body.X - centre) @ np.array([[c, s], [-s, c]]) + centre
    q = np.zeros(model.n)
    o = model.offset_of(body)
    q[o : o + body.ndof] = (x + np.asarray(shift) - body.X).ravel()
    return q


def turn_gap_steps(pair, model, body, angle: float, shift, samples: int = 401):
    """:func:`gap_steps_along` the path on which the planar ``body``, moved by ``shift`` (m),
    turns by ``angle`` (rad) about its nodes' mean (node positions linear in the step)."""
    q0 = rigidly_placed(model, body, 0.0, shift)
    return gap_steps_along(pair, q0, rigidly_placed(model, body, angle, shift), samples)
