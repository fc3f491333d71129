r"""Mortar integrals over curved 6-node triangles (3D P2 solids): overlaps, projections, duals.

Slave face (x_1, ..., x_6), master face (y_1, ..., y_6), each x(s, t) = Σ_k N_k(s, t) x_k with
the P2 shape functions of :func:`fecontact.contact.mortar_p2.shape_functions` (corners, then
the edge nodes m12, m23, m31) over the reference triangle s, t ≥ 0, s + t ≤ 1, written once as
x = c_0 + c_s s + c_t t + c_ss s² + c_st s t + c_tt t².

Pairs face each other when their corner planes' normals stand at more than 90°; up to 104.5°
their integration weights are scaled by φ(c) = t²(3 − 2t), t = −n_s·n_m / ``mortar3d.TURNED``
(:func:`_facing_weight`), as on linear triangles, so that a pair enters the weighted gaps
continuously as its faces turn.

The gap is measured along the slave face's own normal n = x_s × x_t (outward): the master
point y(μ) = x + α n solves three equations in (μ₂, μ₃, α), and g_N dA = α |n|² ds dt (no
square root). The overlap is integrated in the slave face's parameter plane: the master's
corners are projected onto the slave surface along its normals, (x(s, t) − y_i)·x_s =
(x(s, t) − y_i)·x_t = 0, and the triangle of their feet is clipped to the reference triangle;
its vertices are feet, reference corners or crossings of the two triangles' edges, a convex
polygon cut into a fan of cells with the 7-point rule of degree 5 each. On flat faces with
straight edges (the patch test) the feet triangle is the master face's exact image and every
integrand a polynomial of degree ≤ 4 on each cell: the integrals are exact. On curved faces
the straight edges between the feet stand for the master's curved edges (an error of the
curvature's order).

The weighted gaps of the slave face's six nodes are g̃_j = ∫ Φ_j g_N dA with the dual
functions Φ = A Ñ of the transformed basis Ñ = T N (α = 1/5, Popp, Wohlmuth, Gee & Wall,
SIAM J. Sci. Comput. 2012; :func:`fecontact.contact.mortar_p2.dual_coefficients`): the
corner functions of the quadratic triangle integrate to zero, the transformed ones to
2/15 of the face. A is that of the flat reference face (biorthogonal in dA exactly on flat
faces), so that Σ_j Φ_j = 1 and a uniform pressure gives every node its consistent P2 load.

Linearisation: everything above is written in :class:`~fecontact.contact.dual_numbers.Jet`
arithmetic over the 36 coordinates z = (x_1..x_6, y_1..y_6). The projections' values come
from Newton's method. The feet take two Newton steps in Jet arithmetic from the converged
values (the error of the first step is second order in a change of z, of the second fourth
order); the master points at the integration points, the most numerous, are differentiated
implicitly (:func:`_master_alpha`), the same derivatives at a tenth of the products. The
polygon's vertices are rebuilt in Jets from what each one is (a foot, a corner, a crossing),
so the gradients and Hessians include the motion of the overlap's boundary: the
linearisation is consistent. The derivatives of the polynomials of the points (shape
functions, the slave surface) come by the chain rule from their own partials
(:mod:`fecontact.contact.mortar_p2_points`).
"""

from __future__ import annotations

import numpy as np

from .dual_numbers import Jet
from .mortar3d import TURNED
from .mortar_facets import FACING
from .mortar_p2 import dual_coefficients
from .mortar_p2_groups import merge
from .mortar_p2_overlap import polygon, vertex_jets
from .mortar_p2_points import polynomials, slave_surface

__all__ = [
    "DUALS",
    "TRANSFORM",
    "monomials",
    "p2_triangle_integrals",
    "quadratic_rule",
]

DUALS, TRANSFORM = dual_coefficients("triangle")
"""A (6, 6) and T (6, 6) of the reference triangle: Φ = A Ñ, Ñ = T N (α = 1/5)."""

# N_k = Σ_m C[m, k] monomial_m, monomials (1, s, t, s², s t, t²), nodes (1, 2, 3, m12, m23, m31)
_C = np.array([[1, 0, 0, 0, 0, 0], [-3, -1, 0, 4, 0, 0], [-3, 0, -1, 0, 0, 4],
               [2, 2, 0, -4, 0, 0], [4, 0, 0, -4, 4, -4],
               [2, 0, 2, 0, 0, -4]], dtype=float)  # fmt: skip


def quadratic_rule():
    """The 7-point rule of degree 5 on the reference triangle: barycentric points (7, 3) and
    weights (7,) summing to 1."""
    r = np.sqrt(15.0)
    a, b = (6.0 - r) / 21.0, (6.0 + r) / 21.0
    wa, wb = (155.0 - r) / 1200.0, (155.0 + r) / 1200.0
    pts = [[1 / 3, 1 / 3, 1 / 3]]
    for c in (a, b):
        pts += [[1 - 2 * c, c, c], [c, 1 - 2 * c, c], [c, c, 1 - 2 * c]]
    return np.array(pts), np.array([0.225] + [wa] * 3 + [wb] * 3)


_RULE, _RULE_W = quadratic_rule()


def monomials(s, t):
    """(1, s, t, s², s t, t²) of values or Jets."""
    return [s * 0.0 + 1.0, s, t, s * s, s * t, t * t]


# -- vectors of Jets ------------------------------------------------------------------------
def _dot(u, w):
    return u[0] * w[0] + u[1] * w[1] + u[2] * w[2]


def _cross(u, w):
    return (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])


def _sub(u, w):
    return tuple(a - b for a, b in zip(u, w, strict=True))


def _coefficients(nodes):
    """c_m = Σ_k C[m, k] x_k (6 monomials, each a 3-tuple) of six nodes' 3-tuples."""
    return [tuple(sum(nodes[k][d] * _C[m, k] for k in range(6) if _C[m, k] != 0.0)
                  for d in range(3)) for m in range(6)]  # fmt: skip


def _surface(c, s, t):
    """x, x_s, x_t and (x_ss, x_st, x_tt) at (s, t) of a face with coefficients c."""
    c0, cs, ct, css, cst, ctt = c
    x = tuple(c0[d] + s * (cs[d] + s * css[d] + t * cst[d]) + t * (ct[d] + t * ctt[d])
              for d in range(3))  # fmt: skip
    xs = tuple(cs[d] + s * (css[d] * 2.0) + t * cst[d] for d in range(3))
    xt = tuple(ct[d] + s * cst[d] + t * (ctt[d] * 2.0) for d in range(3))
    return x, xs, xt, (tuple(v * 2.0 for v in css), cst, tuple(v * 2.0 for v in ctt))


def _value_coefficients(V):
    """The monomials' coefficients (B, 6, 3) of faces with nodes V (B, 6, 3)."""
    return np.einsum("mk,bkd->bmd", _C, V)


def _value_surface(c, s, t):
    m = np.stack(monomials(s, t), axis=1)  # (B, 6)
    x = np.einsum("bm,bmd->bd", m, c)
    xs = c[:, 1] + 2.0 * s[:, None] * c[:, 3] + t[:, None] * c[:, 4]
    xt = c[:, 2] + s[:, None] * c[:, 4] + 2.0 * t[:, None] * c[:, 5]
    return x, xs, xt


def _solve(J, b):
    """Batched solve of J x = b (B, n, n), (B, n); NaN where J is singular."""
    det = np.linalg.det(J)
    ok = np.isfinite(det) & (np.abs(det) > 0.0)
    J = np.where(ok[:, None, None], J, np.eye(J.shape[1]))
    x = np.linalg.solve(J, np.where(np.isfinite(b), b, 0.0)[..., None])[..., 0]
    return np.where(ok[:, None], x, np.nan)


# -- the master corners' feet on the slave surface -----------------------------------------
def _feet_values(c, y):
    """(s, t) (B, 2) of the points y (B, 3) projected onto the slave faces (coefficients c,
    (B, 6, 3)) along their normals, by Newton's method from the flat face's projection."""
    u, v = c[:, 1] + c[:, 3], c[:, 2] + c[:, 5]  # start: the corners' plane
    r = y - c[:, 0]
    G = np.stack([np.stack([(u * u).sum(1), (u * v).sum(1)], 1),
                  np.stack([(u * v).sum(1), (v * v).sum(1)], 1)], 1)  # fmt: skip
    st = _solve(G, np.stack([(r * u).sum(1), (r * v).sum(1)], 1))
    for _ in range(30):
        s, t = st[:, 0], st[:, 1]
        x, xs, xt = _value_surface(c, s, t)
        d = x - y
        F = np.stack([(d * xs).sum(1), (d * xt).sum(1)], 1)
        J = np.empty((len(s), 2, 2))
        J[:, 0, 0] = (xs * xs).sum(1) + 2.0 * (d * c[:, 3]).sum(1)
        J[:, 0, 1] = J[:, 1, 0] = (xs * xt).sum(1) + (d * c[:, 4]).sum(1)
        J[:, 1, 1] = (xt * xt).sum(1) + 2.0 * (d * c[:, 5]).sum(1)
        step = _solve(J, F)
        st = st - step
        if not np.any(np.abs(step) > 1e-15):
            break
    return st


def _foot_jets(c, y, st, order):
    """The foot (s, t) Jets of the point y (a 3-tuple of Jets) from its values st (B, 2):
    ``order`` Newton steps in Jet arithmetic (2 for Hessians)."""
    s, t = c[0][0].constant_like(st[:, 0]), c[0][0].constant_like(st[:, 1])
    for _ in range(order):  # none for values alone
        x, xs, xt, (xss, xst, xtt) = _surface(c, s, t)
        d = _sub(x, y)
        F1, F2 = _dot(d, xs), _dot(d, xt)
        J11, J12 = _dot(xs, xs) + _dot(d, xss), _dot(xs, xt) + _dot(d, xst)
        J22 = _dot(xt, xt) + _dot(d, xtt)
        det = J11 * J22 - J12 * J12
        inv = det.where(np.abs(det.v) > 0.0, 1.0).reciprocal()
        s, t = s - (J22 * F1 - J12 * F2) * inv, t - (J11 * F2 - J12 * F1) * inv
    s.v, t.v = st[:, 0], st[:, 1]
    return s, t


def _gather(jets):
    """One Jet of the batches of ``jets`` in a row."""
    v = np.concatenate([j.v for j in jets])
    if jets[0].g is None:
        return Jet(v, None, None)
    g = np.concatenate([j.g for j in jets])
    h = None if jets[0].h is None else np.concatenate([j.h for j in jets])
    return Jet(v, g, h)


def _master_alpha(cm, x, n, mu, order):
    """The Jet of α of y(μ) = x + α n on the master faces (coefficients cm, Jets affine in z)
    from the converged values mu (B, 3), by implicit differentiation of F(μ, z) = y(μ) − x −
    α n = 0 with J = ∂F/∂μ = (y_s, y_t, −n): ∂μ = −J⁻¹ ∂F/∂z at fixed μ and, μ carrying these
    exact gradients and no curvature, ∂²μ = −J⁻¹ ∂²F (F and its gradient vanish along the
    solution, so what is left of F's curvature is −J ∂²μ). The same derivatives as Newton
    steps in Jet arithmetic from the converged values, at a fraction of their products."""
    if order == 0:
        return x[0].constant_like(mu[:, 2])
    s, t, a = mu.T
    m = [None, s, t, s * s, s * t, t * t]
    ys = tuple(cm[1][d].v + 2.0 * s * cm[3][d].v + t * cm[4][d].v for d in range(3))
    yt = tuple(cm[2][d].v + s * cm[4][d].v + 2.0 * t * cm[5][d].v for d in range(3))
    J = np.stack([np.stack(ys, 1), np.stack(yt, 1), -np.stack([v.v for v in n], 1)], axis=2)
    det = np.linalg.det(J)
    singular = ~(np.isfinite(det) & (det != 0.0))
    inv = np.linalg.inv(np.where(singular[:, None, None], np.eye(3), J))
    Fz = np.stack([cm[0][d].g + sum(m[k][:, None] * cm[k][d].g for k in range(1, 6))
                   - x[d].g - a[:, None] * n[d].g for d in range(3)], axis=1)  # fmt: skip
    du = -np.einsum("bkd,bdz->bkz", inv, Fz)
    if order == 1:
        return Jet(a, du[:, 2], None)
    zero = np.zeros_like(x[0].h)  # (exact zeros, never written: the Jets below are flat)
    u = [Jet(mu[:, k], du[:, k], zero, True) for k in range(3)]
    w = inv[:, 2]  # α'' = −w·∂²F: F's components combined first, on the affine coefficients
    c = [sum(cm[k][d] * w[:, d] for d in range(3)) for k in range(6)]
    y = c[0] + u[0] * (c[1] + u[0] * c[3] + u[1] * c[4]) + u[1] * (c[2] + u[1] * c[5])
    wx = sum(x[d] * w[:, d] for d in range(3))
    wn = sum(n[d] * w[:, d] for d in range(3))
    return Jet(a, du[:, 2], -(y - wx - u[2] * wn).h)


def _master_values(cm, x, n):
    """(μ₂, μ₃, α) (B, 3) of y(μ) = x + α n by Newton's method from the corners' plane."""
    u0, v0 = cm[:, 1] + cm[:, 3], cm[:, 2] + cm[:, 5]
    J = np.stack([u0, v0, -n], axis=2)
    with np.errstate(all="ignore"):
        mu = _solve(J, x - cm[:, 0])
        for _ in range(30):
            y, ys, yt = _value_surface(cm, mu[:, 0], mu[:, 1])
            F = y - x - mu[:, 2, None] * n
            step = _solve(np.stack([ys, yt, -n], axis=2), F)
            mu = mu - step
            if not np.any(np.abs(step) > 1e-15):
                break
    return np.where(np.isfinite(mu), mu, 0.0)


_ZEROS: dict = {}


def _spread(jet, G: int, cells: int):
    """Each batch entry G times in a row, the whole batch ``cells`` times (an affine jet keeps
    one shared zero Hessian: it is never written)."""
    v = np.tile(np.repeat(jet.v, G), cells)
    if jet.g is None:
        return Jet(v, None, None)
    g = np.tile(np.repeat(jet.g, G, axis=0), (cells, 1))
    if jet.h is None:
        return Jet(v, g, None)
    if jet.flat:
        shape = (len(v), *jet.h.shape[1:])
        if _ZEROS.get("h") is None or _ZEROS["h"].shape != shape:
            _ZEROS["h"] = np.zeros(shape)
        return Jet(v, g, _ZEROS["h"], True)
    return Jet(v, g, np.tile(np.repeat(jet.h, G, axis=0), (cells, 1, 1)))


def _per_pair(f: Jet, cells: int, P: int, G: int) -> Jet:
    """Σ over the cells and points of each of the P pairs (batch ordered cell, pair, point)."""
    g = None if f.g is None else f.g.reshape(cells, P, G, -1).sum(axis=(0, 2))
    h = None if f.h is None else f.h.reshape(cells, P, G, *f.h.shape[1:]).sum(axis=(0, 2))
    return Jet(f.v.reshape(cells, P, G).sum(axis=(0, 2)), g, h)


def _cells(slots, count, P):
    """The fan's integration points (s, t) and weights w (Jets, batch cell, pair, point)."""
    G = len(_RULE_W)
    ss, ts, ws = [], [], []
    b = [np.tile(_RULE[:, i], P) for i in range(3)]
    for k in range(1, len(slots) - 1):
        (s0, t0), (s1, t1), (s2, t2) = slots[0], slots[k], slots[k + 1]
        area = ((s1 - s0) * (t2 - t0) - (t1 - t0) * (s2 - s0)) * 0.5
        area = area.where(k + 1 < count, 0.0)
        ss.append(s0.repeat(G) * b[0] + s1.repeat(G) * b[1] + s2.repeat(G) * b[2])
        ts.append(t0.repeat(G) * b[0] + t1.repeat(G) * b[1] + t2.repeat(G) * b[2])
        ws.append(area.repeat(G) * np.tile(_RULE_W, P))
    return _gather(ss), _gather(ts), _gather(ws)


def _feet(z):
    """The master corners' feet (P, 3, 2) on the slave faces, and whether the faces face."""
    P = len(z)
    X, Y = z[:, :18].reshape(P, 6, 3), z[:, 18:36].reshape(P, 6, 3)
    cs_v = _value_coefficients(X)
    with np.errstate(all="ignore"):
        F = np.stack([_feet_values(cs_v, Y[:, i]) for i in range(3)], axis=1)
    ns, nm = (np.cross(V[:, 1] - V[:, 0], V[:, 2] - V[:, 0]) for V in (X, Y))
    size = np.linalg.norm(ns, axis=1) * np.linalg.norm(nm, axis=1)
    facing = np.einsum("pd,pd->p", ns, nm) < -FACING * size
    return np.where(np.isfinite(F), F, 10.0), facing


def _scatter(result, live, n: int, hessian):
    """The results of the live pairs placed among all (zeros elsewhere)."""
    moments, mass_of, coverage, covered, quad = result
    P = len(live)

    def put(a, fill=0.0):
        out = np.full((P, *a.shape[1:]), fill)
        out[live] = a
        return out

    def jet(j):
        g = None if j.g is None else put(j.g)
        return Jet(put(j.v), g, None if j.h is None else put(j.h))

    def mass_all(part):  # the pairs covered in part are live (they cover something)
        return mass_of(part[live])

    return [jet(j) for j in moments], mass_all, put(coverage), put(covered), tuple(map(put, quad))


def p2_triangle_integrals(z: np.ndarray, hessian=None, depth: float = np.inf):
    """Weighted-gap contributions of P (slave face, master face) pairs of 6-node triangles:
    ``z`` (P, 36) the coordinates (m) of x_1..x_6, y_1..y_6; ``hessian`` None (values), False
    (gradients) or True (Hessians too) over z; ``depth`` (m): a master face whose mean gap
    over the overlap is below −depth lies behind the slave face and is dropped.

    Returns (moments, mass_of, coverage, covered, quad): the Jets of m_k = ∫ Ñ_k g_N dA
    (m³), a function of a mask of the pairs giving their M_kl = ∫ Ñ_k Ñ_l dA (m², 6 × 6)
    over the overlap, the fraction of the slave face's
    parameter triangle the pair covers (P,), ∫ Ñ_k dA over the overlap (P, 6; m²) and the
    quadrature as values for the slip rows: (s, t) (P, Q, 2), μ (P, Q, 2) and the weights
    of dA (P, Q). The weighted gaps are g̃ = A m with the dual coefficients A of the
    covered part (:func:`fecontact.contact.mortar3d_p2.weighted_gaps`)."""
    F, facing = _feet(z)
    index, count, points = polygon(F)
    live = facing & (count >= 3)  # the pairs that face each other with an overlap of area
    if not live.all():
        return _scatter(p2_triangle_integrals(z[live], hessian, depth), live, z.shape[1], hessian)
    if count.min() < count.max():  # the same number of cells in a pass (mortar_p2_groups)
        groups = [np.flatnonzero(count == c) for c in np.unique(count)]
        return merge([p2_triangle_integrals(z[i], hessian, depth) for i in groups], groups, len(z))
    P, G = len(z), len(_RULE_W)
    order = 0 if hessian is None else (2 if hessian else 1)
    c = Jet.variables(z, hessian)
    nodes = [(c[3 * k], c[3 * k + 1], c[3 * k + 2]) for k in range(12)]
    cs, cm = _coefficients(nodes[:6]), _coefficients(nodes[6:])
    feet = [_foot_jets(cs, nodes[6 + i], F[:, i], order) for i in range(3)]
    s, t, w = _cells(vertex_jets(feet, index, points), count, P)
    cells = index.shape[1] - 2
    if (phi := _facing_weight(nodes)) is not None:
        w = w * _spread(phi, G, cells)
    cm_v = np.tile(
        np.repeat(_value_coefficients(z[:, 18:36].reshape(P, 6, 3)), G, 0), (cells, 1, 1)
    )
    X = np.tile(np.repeat(z[:, :18].reshape(P, 6, 3), G, 0), (cells, 1, 1))
    n, mu, alpha = _projection(X, cm, cm_v, s, t, order, (G, cells))
    nn = _dot(n, n)
    dA = np.sqrt(nn.v) * w.v
    gap = ((mu[:, 2] * nn.v * w.v).reshape(cells, P, G).sum((0, 2)),
           dA.reshape(cells, P, G).sum((0, 2)))  # fmt: skip
    behind = np.tile(np.repeat(gap[0] < -depth * gap[1], G), cells)  # deeper than depth
    w, dA = w.where(~behind, 0.0), np.where(behind, 0.0, dA)
    f = (alpha * nn * w).where(w.v != 0.0, 0.0)
    Nt = _jets(*polynomials(_C @ TRANSFORM.T, s, t))
    moments = [_per_pair(Nt[k] * f, cells, P, G) for k in range(6)]

    def mass_of(part):  # M_kl of the pairs ``part``: their points alone
        at = np.flatnonzero(np.tile(np.repeat(part, G), cells))
        w_ = w.take(at)
        dA_ = (nn.take(at).sqrt() * w_).where(w_.v != 0.0, 0.0)
        return _mass([N_.take(at) for N_ in Nt], dA_, (cells, int(part.sum()), G))

    coverage = 2.0 * w.v.reshape(cells, P, G).sum((0, 2))
    covered = np.stack([(Ntk.v * dA).reshape(cells, P, G).sum((0, 2)) for Ntk in Nt], axis=1)

    def per_pair(a):  # (cells P G, ...) values → (P, cells G, ...)
        a = np.moveaxis(a.reshape(cells, P, G, *a.shape[1:]), 1, 0)
        return a.reshape(P, cells * G, *a.shape[3:])

    quad = (per_pair(np.stack([s.v, t.v], 1)), per_pair(mu[:, :2]), per_pair(dA))
    return moments, mass_of, coverage, covered, quad


def _facing_weight(nodes):
    """The pairs' weights φ = t²(3 − 2t), t = min(c / ``mortar3d.TURNED``, 1), as Jets, of the
    cosine c = −n_s·n_m between the unit normals of the two faces' corner planes (those the
    facing cut of :func:`_feet` reads, so that φ → 0 where a pair stops facing): a box's side
    faces stand at 90° to the face it rests on, and with the cut alone their pairs entered and
    left the weighted gaps with the round-off of the normals. None where every pair faces by
    more than 104.5° (the weights as they were)."""
    ns = _cross(_sub(nodes[1], nodes[0]), _sub(nodes[2], nodes[0]))
    nm = _cross(_sub(nodes[7], nodes[6]), _sub(nodes[8], nodes[6]))
    t = -_dot(ns, nm) * ((_dot(ns, ns) * _dot(nm, nm)).sqrt() * TURNED).reciprocal()
    if np.all(t.v >= 1.0):
        return None
    return (t * t * (3.0 - t * 2.0)).where(t.v < 1.0, 1.0)


def _projection(X, cm, cm_v, s, t, order: int, spread):
    """The slave normal n = x_s × x_t at the points (s, t) of the slave faces with nodes X
    (B, 6, 3), the values (μ₂, μ₃, α) of the master points y(μ) = x + α n and the Jet of
    α; ``cm_v`` the master faces' coefficients at the points."""
    x, xs, xt = slave_surface(_C, X, s, t)
    n = _cross(xs, xt)
    mu = _master_values(cm_v, np.stack([v.v for v in x], 1), np.stack([v.v for v in n], 1))
    cmr = [[_spread(v, *spread) for v in cv] for cv in cm]
    return n, mu, _master_alpha(cmr, x, n, mu, order)


def _jets(v, g, h):
    """The columns of values (B, J), gradients (B, J, n) and Hessians (B, J, n, n) as J Jets."""
    return [Jet(v[:, j], None if g is None else g[:, j], None if h is None else h[:, j])
            for j in range(v.shape[1])]  # fmt: skip


def _mass(Nt, dA, shape_):
    """M_kl = ∫ Ñ_k Ñ_l dA per pair (6 × 6 Jets, symmetric)."""
    weighted = [Ntk * dA for Ntk in Nt]
    mass = [[None] * 6 for _ in range(6)]
    for k in range(6):
        for m in range(k, 6):
            mass[k][m] = mass[m][k] = _per_pair(weighted[k] * Nt[m], *shape_)
    return mass
