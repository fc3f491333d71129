"""The geometry of quadratic (3-node) segments of 2D P2 boundaries in Jet arithmetic: a
segment's curve, its points and tangents, the foot of a point on it along its normals and
the point another curve's normal meets, with the exact first and second derivatives of those
implicit functions (one Chebyshev step from the converged root). Shared by the mortar rows
of quadratic segments (:mod:`fecontact.contact.mortar_p2_segments`) and their pointwise
rows (:mod:`fecontact.contact.mortar_p2_safeguard`)."""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = [
    "curve_at",
    "curve_foot",
    "curve_meet",
    "dot",
    "quadratic_curve",
    "quadratic_segments",
]

_NEWTON = 30  # iterations of the slave projection's cubic (converges in 3-5 on a face)


def quadratic_segments(body) -> np.ndarray:
    """The P2 boundary segments (a, b, m) of a 2D ``body`` (ends along the counter-clockwise
    boundary, then the mid node), from its boundary split through the mid nodes."""
    split = body.contact_facets()
    n = len(split) // 2
    first, second = split[:n], split[n:]
    if body.element != "P2" or not np.array_equal(first[:, 1], second[:, 0]):
        raise InputError("body: quadratic mortar segments need a 2D P2 solid")
    return np.ascontiguousarray(np.stack([first[:, 0], second[:, 1], first[:, 1]], axis=1))


def quadratic_curve(a, b, m):
    """Coefficients (c, d, e) of x(ξ) = c + ξ d + ξ² e, each a pair of components."""
    return (
        m,
        tuple((b[i] - a[i]) * 0.5 for i in range(2)),
        tuple((a[i] + b[i]) * 0.5 - m[i] for i in range(2)),
    )


def dot(u, w):
    """u·w of two pairs of components (Jets or arrays)."""
    return u[0] * w[0] + u[1] * w[1]


def curve_at(curve, xi):
    """x(ξ) and x′(ξ) of a curve (c, d, e)."""
    c, d, e = curve
    x = tuple(c[i] + xi * (d[i] + xi * e[i]) for i in range(2))
    t = tuple(d[i] + xi * (e[i] * 2.0) for i in range(2))
    return x, t


def _root(coef, x0, order):
    """The root near the values x0 of Σ_k coef_k ξ^k (Jets), with the derivatives of the
    implicit function from one Chebyshev step (exact to second order): ξ₀ − u − p″/(2p′) u²,
    u = p/p′ at the constant ξ₀."""
    if order == 0:
        return coef[0].constant_like(x0)
    p = sum(c * x0**k for k, c in enumerate(coef))
    dp = sum(c * (k * x0 ** (k - 1)) for k, c in enumerate(coef) if k >= 1)
    ddp = sum(c * (k * (k - 1) * x0 ** (k - 2)) for k, c in enumerate(coef) if k >= 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = dp.reciprocal()
        u = p * inv
        x = -u if order == 1 else -u - (ddp * 0.5) * (u * u) * inv
    x = x + x0
    x.v = x0  # the root itself
    return x


def curve_foot(curve, y, order):
    """ξ (Jet) of the point y projected onto the curve along its normals:
    (x(ξ) − y)·x′(ξ) = 0, a cubic; inf where Newton's method does not reach a root."""
    c, d, e = curve
    r = (c[0] - y[0], c[1] - y[1])
    coef = (dot(r, d), dot(r, e) * 2.0 + dot(d, d), dot(d, e) * 3.0, dot(e, e) * 2.0)
    v = [k.v for k in coef]
    with np.errstate(divide="ignore", invalid="ignore"):
        xi = -v[0] / v[1]
        for _ in range(_NEWTON):
            p = v[0] + xi * (v[1] + xi * (v[2] + xi * v[3]))
            step = p / (v[1] + xi * (2.0 * v[2] + 3.0 * xi * v[3]))
            xi = xi - step
            if not np.any(np.abs(step) > 1e-15 * (1.0 + np.abs(xi))):
                break
        ok = np.isfinite(xi) & (np.abs(step) <= 1e-12 * (1.0 + np.abs(xi)))
    xi = np.where(ok, xi, np.inf)
    root = _root(coef, np.where(ok, xi, 0.0), order)
    root.v = xi
    return root


def curve_meet(master, x, t, order):
    """η (Jet) of the master point met from x along the normal of the tangent t:
    (y(η) − x)·t = a0 + a1 η + a2 η² = 0, the root nearest the straight master's."""
    c, d, e = master
    coef = (dot((c[0] - x[0], c[1] - x[1]), t), dot(d, t), dot(e, t))
    a0, a1, a2 = (k.v for k in coef)
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = np.sqrt(np.maximum(a1 * a1 - 4.0 * a0 * a2, 0.0))
        eta = -2.0 * a0 / (a1 + np.where(a1 < 0.0, -1.0, 1.0) * disc)
    return _root(coef, np.where(np.isfinite(eta), eta, 0.0), order)
