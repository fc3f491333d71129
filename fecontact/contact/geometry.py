r"""Distances and projections of the contact kinematics, in one place.

Points against segments and lines (2D and 3D), planes of triangles, and convex polygons.
Signed distances carry their derivatives where a gap needs them: the gradient and Hessian
with respect to the coordinates that move. The plane gap g = n·(x − a) of a point x from a
triangle (a, b, c), n = N/|N|, N = (b − a) × (c − a), with r = x − a, u = b − a, w = c − a,
s = r·N and ν = |N|: g = s/ν and

    ∇²g = ∇²s/ν − (∇s ∇νᵀ + ∇ν ∇sᵀ)/ν² + s (2 ∇ν ∇νᵀ/ν³ − ∇²ν/ν²),

where ∂N_k/∂u_i = ε_kij w_j, ∂N_k/∂w_j = ε_kij u_i, ∂²N_k/∂u_i∂w_j = ε_kij (ε the
permutation symbol), ∇ν = (∂N)ᵀ n and ∇²ν = (∂N)ᵀ (I − n nᵀ)/ν (∂N) + n_k ∇²N_k.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = [
    "closest_facet_distance",
    "closest_on_segments",
    "distance_curvature",
    "edge_folds",
    "facet_plane_gap",
    "point_line_distance",
    "polygon_distance",
    "segment_distance",
    "triangle_plane_distance",
    "unit",
]

_PERP = np.array([[0.0, -1.0], [1.0, 0.0]])  # rotation by +90°
_FLIP = np.array([1.0, -1.0])  # (w_y, w_x) ↦ (w_y, −w_x)
# (d, w) = T (P, x1, x2): d = x2 − x1, w = P − x1
_LINE_MAP = np.kron([[0.0, -1.0, 1.0], [1.0, -1.0, 0.0]], np.eye(2))


def unit(x: np.ndarray, what: str) -> tuple[np.ndarray, float]:
    """x/|x| and |x|; ``what`` names the two points whose difference x is, should they meet."""
    d = float(np.linalg.norm(x))
    if d == 0.0:
        raise InputError(f"{what} coincide: contact normal undefined")
    return x / d, d


def distance_curvature(e: np.ndarray, d: float) -> np.ndarray:
    """Hessian (I − e eᵀ)/d of the distance |x| at x = d e."""
    return (np.eye(len(e)) - np.outer(e, e)) / d


def closest_on_segments(x: np.ndarray, a: np.ndarray, b: np.ndarray):
    """Projections of points x on the segments (a, b), all (m, d) or x (d,): the parameter
    ξ ∈ [0, 1] of the closest point a + ξ(b − a) and the distance (m,) to it."""
    d = b - a
    w = x - a
    xi = np.clip(np.einsum("mi,mi->m", w, d) / np.einsum("mi,mi->m", d, d), 0.0, 1.0)
    return xi, np.linalg.norm(w - xi[:, None] * d, axis=1)


def segment_distance(x: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distances (m,) from points x to the segments (a, b), all (m, d)."""
    return closest_on_segments(x, a, b)[1]


def point_line_distance(P: np.ndarray, x1: np.ndarray, x2: np.ndarray, hessian: bool = True):
    """Signed distances f = (d × w)/|d| of points P from the lines through x1 and x2
    (d = x2 − x1, w = P − x1; positive on the left of d), all (m, 2), with their gradients
    (m, 6) and Hessians (m, 6, 6; None unless ``hessian``) with respect to (P, x1, x2).

    With c = d × w: ∂c/∂d = (w_y, −w_x), ∂c/∂w = J d, ∂²c/∂d∂w = −J, and f = c/|d|.
    """
    d, w = x2 - x1, P - x1
    # (|d| as np.linalg.norm sums it, and c_d by a product with ±1: the same numbers, without
    # those functions' call overhead on the few rows of a step)
    L = np.sqrt((d * d).sum(axis=1))[:, None, None]
    c = (d[:, 0] * w[:, 1] - d[:, 1] * w[:, 0])[:, None, None]
    c_d = w[:, ::-1] * _FLIP
    c_w = d @ _PERP.T
    f_d = c_d / L[:, 0] - c[:, 0] * d / L[:, 0] ** 3
    f_w = c_w / L[:, 0]
    G = np.concatenate([f_d, f_w], axis=1) @ _LINE_MAP
    if not hessian:
        return c[:, 0, 0] / L[:, 0, 0], G, None
    dd = d[:, :, None] * d[:, None, :]
    f_dd = -(c_d[:, :, None] * d[:, None, :] + d[:, :, None] * c_d[:, None, :]) / L**3
    f_dd += c * (3.0 * dd / L**5 - np.eye(2) / L**3)
    f_dw = -_PERP / L - d[:, :, None] * c_w[:, None, :] / L**3
    H_dw = np.zeros((len(d), 4, 4))
    H_dw[:, :2, :2] = f_dd
    H_dw[:, :2, 2:] = f_dw
    H_dw[:, 2:, :2] = f_dw.transpose(0, 2, 1)
    T = _LINE_MAP
    return c[:, 0, 0] / L[:, 0, 0], G, np.einsum("ai,mab,bj->mij", T, H_dw, T)


def polygon_distance(vertices: np.ndarray, normals: np.ndarray, x: np.ndarray):
    """Signed distance s (m) from point ``x`` to a convex counter-clockwise polygon (negative
    inside), with its gradient (2,) and Hessian (2, 2) on the piece that contains ``x``.

    ``normals[i]`` is the outward unit normal of the edge from vertex i to vertex i + 1.
    """
    rel = x - vertices
    s_edge = np.einsum("ij,ij->i", normals, rel)
    if np.all(s_edge < 0.0):  # inside: the nearest edge (largest s) gives the distance
        i = int(np.argmax(s_edge))
        return float(s_edge[i]), normals[i], np.zeros((2, 2))
    t, dist = closest_on_segments(x, vertices, np.roll(vertices, -1, axis=0))
    i = int(np.argmin(dist))
    if 0.0 < t[i] < 1.0:
        return float(s_edge[i]), normals[i], np.zeros((2, 2))
    k = i if t[i] == 0.0 else (i + 1) % len(vertices)
    e, d = unit(x - vertices[k], "the disk centre and a polygon vertex")
    return d, e, distance_curvature(e, d)


def closest_facet_distance(x: np.ndarray, xf: np.ndarray):
    """Distances (m,) from points x (m, d) to the facets xf (m, k, d) themselves (the closest
    point clipped to the segment or triangle), and the signed plane gaps (m,)."""
    if x.shape[1] == 2:
        a, b = xf[:, 0], xf[:, 1]
        t = b - a
        w = x - a
        g = (t[:, 1] * w[:, 0] - t[:, 0] * w[:, 1]) / np.linalg.norm(t, axis=1)
        return segment_distance(x, a, b), g
    a, b, c = xf[:, 0], xf[:, 1], xf[:, 2]
    u, w, v = b - a, c - a, x - a
    N = np.cross(u, w)
    g = np.einsum("mi,mi->m", v, N) / np.linalg.norm(N, axis=1)
    d00, d01, d11 = (np.einsum("mi,mi->m", p, s) for p, s in ((u, u), (u, w), (w, w)))
    d20, d21 = np.einsum("mi,mi->m", v, u), np.einsum("mi,mi->m", v, w)
    den = d00 * d11 - d01 * d01
    beta = (d11 * d20 - d01 * d21) / den
    gamma = (d00 * d21 - d01 * d20) / den
    inside = (beta >= 0.0) & (gamma >= 0.0) & (beta + gamma <= 1.0)
    dist = np.abs(g)
    out = ~inside
    if out.any():
        xo, ao, bo, co = x[out], a[out], b[out], c[out]
        dist[out] = np.minimum(
            np.minimum(segment_distance(xo, ao, bo), segment_distance(xo, bo, co)),
            segment_distance(xo, co, ao),
        )
    return dist, g


# permutation symbol ε_kij
_EPS = np.zeros((3, 3, 3))
_EPS[0, 1, 2] = _EPS[1, 2, 0] = _EPS[2, 0, 1] = 1.0
_EPS[0, 2, 1] = _EPS[2, 1, 0] = _EPS[1, 0, 2] = -1.0
# (r, u, w) = T (x_s, x_a, x_b, x_c): r = x_s − x_a, u = x_b − x_a, w = x_c − x_a
_TRIANGLE_MAP = np.kron(
    [[1.0, -1.0, 0.0, 0.0], [0.0, -1.0, 1.0, 0.0], [0.0, -1.0, 0.0, 1.0]], np.eye(3)
)


def triangle_plane_distance(x, a, b, c, hessian: bool = True):
    """Signed distances g = n·(x − a) (m) of points x from the planes of triangles (a, b, c),
    n = (b − a) × (c − a) normalised (right-hand rule), all (m, 3); with the gradients (m, 12)
    and Hessians (m, 12, 12; None unless ``hessian``) with respect to (x, a, b, c)."""
    r, u, w = x - a, b - a, c - a
    N = np.cross(u, w)
    nu = np.linalg.norm(N, axis=1)
    n = N / nu[:, None]
    s = np.einsum("mk,mk->m", r, N)
    Au = np.einsum("kij,mj->mki", _EPS, w)  # ∂N_k/∂u_i
    Aw = np.einsum("kij,mi->mkj", _EPS, u)  # ∂N_k/∂w_j
    m = len(x)
    J = np.zeros((m, 3, 9))  # ∂N/∂(r, u, w)
    J[:, :, 3:6], J[:, :, 6:] = Au, Aw
    s_z = np.concatenate(
        [N, np.einsum("mk,mki->mi", r, Au), np.einsum("mk,mkj->mj", r, Aw)], axis=1
    )
    nu_z = np.einsum("mk,mkz->mz", n, J)
    g = s / nu
    g_z = s_z / nu[:, None] - (s / nu**2)[:, None] * nu_z
    if not hessian:
        return g, g_z @ _TRIANGLE_MAP, None
    s_zz = np.zeros((m, 9, 9))
    s_zz[:, :3, 3:6], s_zz[:, :3, 6:] = Au, Aw
    s_zz[:, 3:6, 6:] = np.einsum("kij,mk->mij", _EPS, r)
    s_zz += s_zz.transpose(0, 2, 1)
    proj = (np.eye(3) - n[:, :, None] * n[:, None, :]) / nu[:, None, None]
    nu_zz = np.einsum("mkz,mkl,mly->mzy", J, proj, J)
    En = np.einsum("kij,mk->mij", _EPS, n)
    nu_zz[:, 3:6, 6:] += En
    nu_zz[:, 6:, 3:6] += En.transpose(0, 2, 1)
    i1, i2, i3 = 1.0 / nu, 1.0 / nu**2, 1.0 / nu**3
    cross = s_z[:, :, None] * nu_z[:, None, :]
    g_zz = (
        s_zz * i1[:, None, None]
        - (cross + cross.transpose(0, 2, 1)) * i2[:, None, None]
        + s[:, None, None]
        * (
            2.0 * i3[:, None, None] * nu_z[:, :, None] * nu_z[:, None, :]
            - nu_zz * i2[:, None, None]
        )
    )
    T = _TRIANGLE_MAP
    return g, g_z @ T, np.einsum("ai,mab,bj->mij", T, g_zz, T)


def facet_plane_gap(x: np.ndarray, xf: np.ndarray, hessian: bool = True):
    """Signed gaps (m,) of points x (m, d) from the planes of facets with vertices xf (m, k, d)
    along their outward normals (see the module docstring), with the gradients (m, d + k d) and
    Hessians (None unless ``hessian``) with respect to (x, facet vertices)."""
    if x.shape[1] == 2:
        f, G, H = point_line_distance(x, xf[:, 0], xf[:, 1], hessian)
        return -f, -G, None if H is None else -H
    return triangle_plane_distance(x, xf[:, 0], xf[:, 1], xf[:, 2], hessian)


def edge_folds(X: np.ndarray, tri: np.ndarray):
    """The edges two boundary triangles ``tri`` (T, 3; numbered outward) share, with
    reference node positions ``X`` (n, 3): ``edges`` (E, 2) node indices, ``opposite`` (E, 2)
    the third vertices of the two triangles, ``owners`` (E, 2) the triangles, and ``below``
    (E,) (m) how far the second triangle's third vertex lies below the first one's plane
    (> 0: the edge is convex, 0: the two are coplanar)."""
    pairs = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    third = np.concatenate([tri[:, 2], tri[:, 0], tri[:, 1]])
    owner = np.tile(np.arange(len(tri)), 3)
    key = np.sort(pairs, axis=1)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key, third, owner = key[order], third[order], owner[order]
    twin = np.flatnonzero(np.all(key[1:] == key[:-1], axis=1))  # two triangles share it
    edges, opposite = key[twin], np.stack([third[twin], third[twin + 1]], axis=1)
    t = tri[owner[twin]]  # the first triangle, numbered outward
    n = np.cross(X[t[:, 1]] - X[t[:, 0]], X[t[:, 2]] - X[t[:, 0]])
    n /= np.linalg.norm(n, axis=1)[:, None]
    below = -np.einsum("mi,mi->m", X[opposite[:, 1]] - X[edges[:, 0]], n)
    return edges, opposite, np.stack([owner[twin], owner[twin + 1]], axis=1), below
