r"""Inside or outside: signed distances of points to a body's closed, oriented boundary.

The boundary is cut into flat facets — segments (a, b) in 2D, running counter-clockwise (the
body on the left), triangles (a, b, c) in 3D with the outward normal by the right-hand rule —
at the current node positions. The signed distance of a point x is

    s(x) = ± min_f dist(x, facet f)    (m; < 0 inside the body, > 0 outside),

the distance to the facet itself (its closest point clipped to the segment or triangle), so it
is exact for a point already deep inside, where a facet's plane gap or a search margin tells
nothing. The sign:

=======  ==================================================================================
2D       the winding number w(x) = (1/2π) Σ_e atan2((a − x) × (b − x), (a − x)·(b − x)):
         1 inside a counter-clockwise boundary, 0 outside (and 0 in a hole, whose boundary
         runs clockwise); inside when w > 1/2.
3D       the angle-weighted pseudo-normal n_ψ of the closest feature (Bærentzen & Aanæs,
         IEEE TVCG 11(3), 2005): the facet's normal, the sum of the two normals of an edge,
         or Σ α_f n_f over the facets around a vertex (α_f the facet's angle there); then
         s = sign((x − c)·n_ψ) |x − c|, c the closest point. Exact for a closed 2-manifold.
=======  ==================================================================================

Broad phase: points outside the surface's bounding box (grown by ``pad``) are outside, and
get s = +inf; the others ask a k-d tree over the facet centroids for their k nearest
centroids, k doubled until the k-th lies farther than the best exact distance found plus the
largest centroid-to-vertex distance ρ: no facet beyond can be closer. The tree is built on
the current positions at every call, so it follows the bodies as they move; when points ×
facets are few (≤ 4096) every facet is tried instead, cheaper than building a tree.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial import cKDTree

from .geometry import closest_on_segments

__all__ = [
    "Surface",
    "bounding_box",
    "facet_distances",
    "face_depths",
    "segment_depths",
    "segment_neighbours",
    "triangle_closest",
    "winding_numbers",
]

_FIRST_K = 8  # centroids asked first: a point near a surface has its closest facet among them
_CHUNK = 2**22  # point × segment pairs of the 2D winding number evaluated at once
_BRUTE_FORCE = 4096  # point × facet pairs below which every facet is tried (no tree to build)
_FEW = 8  # points up to which plain floats settle them faster than numpy's per-call overhead


def winding_numbers(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Winding numbers (p,) of the closed polygon(s) of segments (a, b) (s, 2) around
    ``points`` (p, 2): +1 inside a counter-clockwise loop."""
    out = np.zeros(len(points))
    step = max(1, _CHUNK // max(len(a), 1))
    for i in range(0, len(points), step):
        x = points[i : i + step, None, :]
        u, w = a[None] - x, b[None] - x
        cross = u[..., 0] * w[..., 1] - u[..., 1] * w[..., 0]
        dot = np.einsum("psi,psi->ps", u, w)
        out[i : i + step] = np.arctan2(cross, dot).sum(axis=1) / (2.0 * np.pi)
    return out


def bounding_box(x: np.ndarray):
    """Lower and upper corners of the box of points x (n, d), per component: a reduction
    along the long axis of an (n, d) array costs a fraction of one across it."""
    d = range(x.shape[1])
    return np.array([x[:, k].min() for k in d]), np.array([x[:, k].max() for k in d])


def _triangle_closest(x, a, b, c):
    """Distances (m,) from points x to triangles (a, b, c) (all (m, 3)), with the closest
    feature: kind (0 face, 1 edge, 2 vertex), the local edge (0: ab, 1: bc, 2: ca) or corner
    (0, 1, 2), and the closest point (m, 3)."""
    u, w, v = b - a, c - a, x - a
    N = np.cross(u, w)
    n = N / np.linalg.norm(N, axis=1)[:, None]
    g = np.einsum("mi,mi->m", v, n)
    d00, d01, d11 = (np.einsum("mi,mi->m", p, s) for p, s in ((u, u), (u, w), (w, w)))
    d20, d21 = np.einsum("mi,mi->m", v, u), np.einsum("mi,mi->m", v, w)
    den = d00 * d11 - d01 * d01
    beta = (d11 * d20 - d01 * d21) / den
    gamma = (d00 * d21 - d01 * d20) / den
    face = (beta > 0.0) & (gamma > 0.0) & (beta + gamma < 1.0)
    dist = np.abs(g)
    kind = np.zeros(len(x), dtype=int)
    local = np.zeros(len(x), dtype=int)
    closest = x - g[:, None] * n
    out = ~face
    if out.any():
        ends = ((a, b), (b, c), (c, a))
        xo = x[out]
        t = np.empty((3, len(xo)))
        dd = np.empty((3, len(xo)))
        for k, (p, s) in enumerate(ends):
            t[k], dd[k] = closest_on_segments(xo, p[out], s[out])
        e = np.argmin(dd, axis=0)
        te = t[e, np.arange(len(xo))]
        dist[out] = dd[e, np.arange(len(xo))]
        p = np.stack([a[out], b[out], c[out]], axis=1)
        start, end = p[np.arange(len(xo)), e], p[np.arange(len(xo)), (e + 1) % 3]
        closest[out] = start + te[:, None] * (end - start)
        at_vertex = (te == 0.0) | (te == 1.0)
        kind[out] = np.where(at_vertex, 2, 1)
        local[out] = np.where(te == 1.0, (e + 1) % 3, e)
    return dist, kind, local, closest


def facet_distances(points: np.ndarray, xf: np.ndarray) -> np.ndarray:
    """Distances (m,) from points (m, d) to facets xf (m, k, d): segments in 2D, triangles in
    3D, the closest point clipped to the facet."""
    if points.shape[1] == 2:
        return closest_on_segments(points, xf[:, 0], xf[:, 1])[1]
    return _triangle_closest(points, xf[:, 0], xf[:, 1], xf[:, 2])[0]


def triangle_closest(points: np.ndarray, xf: np.ndarray):
    """Distances (m,) from points (m, 3) to triangles xf (m, 3, 3), whether the closest point
    lies off the face's interior (on an edge or a vertex) (m,) and the closest points (m, 3),
    clipped to the triangles."""
    dist, kind, _, closest = _triangle_closest(points, xf[:, 0], xf[:, 1], xf[:, 2])
    return dist, kind > 0, closest


def face_depths(points: np.ndarray, xf: np.ndarray):
    """Whether each of ``points`` (m, d) projects strictly inside its facet xf (m, k, d), and
    then how deep (m, ≥ 0) it lies behind the facet's plane (the outward normal of
    :class:`Surface`). When that facet is the surface's closest to the point, its closest
    feature is the face, whose pseudo-normal is the face normal: the depth is the point's
    depth inside the closed surface, with no test of the rest."""
    a, b = xf[:, 0], xf[:, 1]
    u, v = b - a, points - a
    if points.shape[1] == 2:
        xi = np.einsum("mi,mi->m", v, u) / np.einsum("mi,mi->m", u, u)
        # the body lies on the left of a counter-clockwise segment: inside is u × v > 0
        behind = (u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) / np.linalg.norm(u, axis=1)
        return (xi > 0.0) & (xi < 1.0), np.maximum(behind, 0.0)
    w = xf[:, 2] - a
    d00, d01, d11 = (np.einsum("mi,mi->m", p, s) for p, s in ((u, u), (u, w), (w, w)))
    d20, d21 = np.einsum("mi,mi->m", v, u), np.einsum("mi,mi->m", v, w)
    den = d00 * d11 - d01 * d01
    beta, gamma = (d11 * d20 - d01 * d21) / den, (d00 * d21 - d01 * d20) / den
    face = (beta > 0.0) & (gamma > 0.0) & (beta + gamma < 1.0)
    N = np.cross(u, w)
    behind = -np.einsum("mi,mi->m", v, N) / np.linalg.norm(N, axis=1)
    return face, np.maximum(behind, 0.0)


def segment_neighbours(facets: np.ndarray) -> np.ndarray | None:
    """For each segment (a, b) of a closed 2D boundary ``facets`` (n, 2): the segment that ends
    at a and the one that starts at b, (n, 2); None unless every node of the boundary starts
    exactly one segment and ends exactly one (a closed polygon, holes allowed)."""
    facets = np.asarray(facets, dtype=int)
    n_nodes = int(facets.max()) + 1
    starts = np.bincount(facets[:, 0], minlength=n_nodes)
    ends = np.bincount(facets[:, 1], minlength=n_nodes)
    if np.any(starts != ends) or np.any(starts > 1):
        return None
    of_start, of_end = np.full(n_nodes, -1), np.full(n_nodes, -1)
    of_start[facets[:, 0]] = of_end[facets[:, 1]] = np.arange(len(facets))
    return np.stack([of_end[facets[:, 0]], of_start[facets[:, 1]]], axis=1)


def segment_depths(points, x, facets, neighbours, f, slack: float):
    """2D: of ``points`` (m, 2) and their closest segments f (m,) of a closed boundary (node
    positions x, segments ``facets`` with their :func:`segment_neighbours`) — each the
    closest of the whole boundary within ``slack`` (m) —, which depths (m, ≥ 0) are known
    without the full test, and those depths: :func:`face_depths` where the point projects
    strictly inside its segment (the same numbers), 0 where the closest point is an end c of
    the segment and the point is certainly outside.

    Why a vertex's verdict is exact: with n1, n2 the outward unit normals of the two
    segments at c and r = x − c, the vertex's pseudo-normal n1 + n2 gives the side,
    s = r·(n1 + n2) > 0 outside and ≤ 0 inside when c is exactly the closest point
    (Bærentzen & Aanæs, IEEE TVCG 11(3), 2005, in 2D). Where c is only within ε = ``slack``
    of the closest distance d (|r| = D ≤ d + ε), the open disk of radius d about an inside x
    holds no boundary point, so each segment's direction e_i from c obeys r·e_i ≤ δ = √(2Dε)
    (segments are far longer than δ); inside the interior sector at c this bounds s ≤ 2δ. A
    point is certified only where s > 4δ, far above that bound and the round-off of s; the
    others are left to the full test.
    """
    a, b = x[facets[f, 0]], x[facets[f, 1]]
    u, v = b - a, points - a
    xi = np.einsum("mi,mi->m", v, u) / np.einsum("mi,mi->m", u, u)
    length = np.linalg.norm(u, axis=1)
    # as face_depths: the body lies on the left of a counter-clockwise segment
    depth = np.maximum((u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) / length, 0.0)
    known = (xi > 0.0) & (xi < 1.0)
    if known.all():
        return known, depth
    end = (xi > 0.5).astype(np.intp)  # the closest end: b where the projection passes it
    r = points - x[facets[f, end]]
    xo = x[facets[neighbours[f, end]]]  # the other segment at that end
    t = xo[:, 1] - xo[:, 0]
    # outward normals (t_y, −t_x)/|t| summed: the rotated sum of the unit tangents
    n = u / length[:, None] + t / np.sqrt(np.einsum("mi,mi->m", t, t))[:, None]
    s = r[:, 0] * n[:, 1] - r[:, 1] * n[:, 0]
    # s > 4 √(2 D ε), squared
    far = s * s > 32.0 * slack * np.sqrt(np.einsum("mi,mi->m", r, r))
    outside = ~known & (s > 0.0) & far
    depth[outside] = 0.0
    return known | outside, depth


def few_segment_depths(points: list, chains: list, slack: float):
    """:func:`segment_depths` of a few points in plain floats, the same operations in the same
    order (so the same numbers to the bit), without numpy's per-call overhead (about 1 µs a
    call, some forty calls). ``points``: [(x, y)] (m); ``chains``: per point the positions
    of the start of the segment before its closest segment (a, b), a, b, and the end of the
    segment after. The deepest of the settled depths (m, ≥ 0; 0 when none, NaN if one is
    NaN, as ``np.max(depth[known], initial=0)``) and the indices of the points not
    settled."""
    deepest, unsettled = 0.0, []
    for i, ((px, py), (p0, (ax, ay), (bx, by), p3)) in enumerate(zip(points, chains, strict=True)):
        ux, uy, vx, vy = bx - ax, by - ay, px - ax, py - ay
        xi = (vx * ux + vy * uy) / (ux * ux + uy * uy)
        length = math.sqrt(ux * ux + uy * uy)
        if 0.0 < xi < 1.0:  # on the face: behind the segment by the cross product
            d = (ux * vy - uy * vx) / length
            if d > deepest or d != d:
                deepest = d
            continue
        # beyond the end c: the vertex's pseudo-normal with the other segment's tangent t
        if xi > 0.5:
            rx, ry, tx, ty = px - bx, py - by, p3[0] - bx, p3[1] - by
        else:
            rx, ry, tx, ty = px - ax, py - ay, ax - p0[0], ay - p0[1]
        tl = math.sqrt(tx * tx + ty * ty)
        s = rx * (uy / length + ty / tl) - ry * (ux / length + tx / tl)
        if not (s > 0.0 and s * s > 32.0 * slack * math.sqrt(rx * rx + ry * ry)):
            unsettled.append(i)
    return deepest, unsettled


class Surface:
    """A body's closed, oriented boundary of flat ``facets`` (n, 2) segments or (n, 3)
    triangles of node indices, numbered with the outward normal (as
    :meth:`fecontact.bodies.Solid.contact_facets`): signed distances of points to it at any
    node positions. The topology (edges, vertices) is fixed; positions are given per call."""

    def __init__(self, facets: np.ndarray):
        self.facets = np.asarray(facets, dtype=int)
        self.dim = self.facets.shape[1]
        if self.dim == 3:
            pairs = self.facets[:, [[0, 1], [1, 2], [2, 0]]]  # (n, 3, 2)
            edges, self._edge_of = np.unique(
                np.sort(pairs, axis=2).reshape(-1, 2), axis=0, return_inverse=True
            )
            self._edge_of = self._edge_of.reshape(-1, 3)
            self._n_edges = len(edges)
        else:  # each segment's neighbours, for the vertex test of :meth:`settled`
            self.neighbours = nb = segment_neighbours(self.facets)
            if nb is not None:  # per segment: the nodes of the one before, its own, the next
                f = self.facets
                self._chains = np.stack([f[nb[:, 0], 0], f[:, 0], f[:, 1], f[nb[:, 1], 1]], 1)

    def settled(self, points: np.ndarray, x: np.ndarray, f: np.ndarray, slack: float):
        """Which of ``points`` (m, d), whose closest facets of the surface (node positions x)
        are f (m,) within ``slack`` (m), have a depth known without the full test, and those
        depths (m, ≥ 0): :func:`face_depths` in 3D, :func:`segment_depths` in 2D (none
        settled beyond a vertex where the boundary is not a closed polygon)."""
        if self.dim == 3 or self.neighbours is None:
            return face_depths(points, x[self.facets[f]])
        return segment_depths(points, x, self.facets, self.neighbours, f, slack)

    def settled_depth(self, points: np.ndarray, x: np.ndarray, f: np.ndarray, slack: float):
        """:meth:`settled`, reduced: the deepest of the depths it knows (m, ≥ 0; 0 when none)
        and the indices (into ``points``) of the points it leaves to the full test."""
        if self.dim == 2 and self.neighbours is not None and len(points) <= _FEW:
            deepest, rest = few_segment_depths(points.tolist(), x[self._chains[f]].tolist(), slack)
            return deepest, np.array(rest, dtype=np.intp)
        known, depth = self.settled(points, x, f, slack)
        return float(np.max(depth[known], initial=0.0)), np.flatnonzero(~known)

    def signed_distance(self, x: np.ndarray, points: np.ndarray, pad=0.0, outside=True):
        """Signed distances (p,) in m of ``points`` (p, d) to the surface with node positions
        ``x`` (n, d), negative inside, and the closest facet of each (p,). Points farther
        than ``pad`` (m) outside the bounding box of the nodes x, and with ``outside`` False every
        point outside (in 2D, where the sign comes first and costs no search): s = +inf,
        facet −1."""
        s = np.full(len(points), np.inf)
        facet = np.full(len(points), -1)
        if len(points) == 0:
            return s, facet
        # the box of every node (of a solid, the box of its boundary), before any gather
        lo, hi = bounding_box(x)
        lo, hi = lo - pad, hi + pad
        p_lo, p_hi = bounding_box(points)
        if np.any(p_hi < lo) or np.any(p_lo > hi):  # the boxes are apart: every point out
            return s, facet
        near = np.flatnonzero(((points >= lo) & (points <= hi)).all(axis=1))
        if near.size == 0:
            return s, facet
        xf = x[self.facets]
        if self.dim == 2:
            inside = winding_numbers(points[near], xf[:, 0], xf[:, 1]) > 0.5
            if not outside:
                near, inside = near[inside], inside[inside]
        if near.size == 0:
            return s, facet
        p = points[near]
        dist, f = self._closest_facets(xf, p)
        if self.dim == 3:
            inside = self._pseudo_normal_sign(xf, p, f) < 0.0
        s[near] = np.where(inside, -dist, dist)
        facet[near] = f
        return s, facet

    def depths(self, x: np.ndarray, points: np.ndarray) -> np.ndarray:
        """How deep (m, ≥ 0) each of ``points`` lies inside the surface (0 outside)."""
        return np.maximum(0.0, -self.signed_distance(x, points, outside=False)[0])

    def _facet_distances(self, points, xf):
        return facet_distances(points, xf)

    def _closest_facets(self, xf, p):
        """Distance to, and index of, the closest facet of each point (exact: see the module
        docstring for the stopping test of the k-d tree search; few pairs are all tried)."""
        n = len(xf)
        if len(p) * n <= _BRUTE_FORCE:
            d = self._facet_distances(np.repeat(p, n, axis=0), np.tile(xf, (len(p), 1, 1)))
            d = d.reshape(len(p), n)
            which = np.argmin(d, axis=1)
            return d[np.arange(len(p)), which], which
        centroid = xf.mean(axis=1)
        reach = float(np.sqrt(np.max(np.sum((xf - centroid[:, None]) ** 2, axis=2))))
        tree = cKDTree(centroid)
        best, which = np.full(len(p), np.inf), np.full(len(p), -1)
        pending = np.arange(len(p))
        k = min(_FIRST_K, n)
        while pending.size:
            dc, ic = tree.query(p[pending], k=k)
            dc, ic = dc.reshape(len(pending), k), ic.reshape(len(pending), k)
            d = self._facet_distances(np.repeat(p[pending], k, axis=0), xf[ic.ravel()])
            d = d.reshape(len(pending), k)
            j = np.argmin(d, axis=1)
            rows = np.arange(len(pending))
            best[pending], which[pending] = d[rows, j], ic[rows, j]
            done = (k == n) | (dc[:, -1] > best[pending] + reach)
            pending = pending[~done]
            k = min(2 * k, n)
        return best, which

    def _pseudo_normal_sign(self, xf, p, f):
        """(x − c)·n_ψ (m²-ish; only its sign counts) of each point against the angle-weighted
        pseudo-normal of the closest feature of its closest facet f."""
        a, b, c = xf[:, 0], xf[:, 1], xf[:, 2]
        normal = np.cross(b - a, c - a)
        normal /= np.linalg.norm(normal, axis=1)[:, None]
        _, kind, local, closest = _triangle_closest(p, a[f], b[f], c[f])
        n_psi = normal[f].copy()
        edge = kind == 1
        if edge.any():
            edge_normal = np.zeros((self._n_edges, 3))
            np.add.at(edge_normal, self._edge_of.ravel(), np.repeat(normal, 3, axis=0))
            n_psi[edge] = edge_normal[self._edge_of[f[edge], local[edge]]]
        vertex = kind == 2
        if vertex.any():
            corners = np.stack([a, b, c], axis=1)
            u = np.roll(corners, -1, axis=1) - corners  # to the next corner
            w = np.roll(corners, 1, axis=1) - corners  # to the previous corner
            angle = np.arctan2(np.linalg.norm(np.cross(u, w), axis=2), np.sum(u * w, axis=2))
            n_nodes = int(self.facets.max()) + 1
            vertex_normal = np.zeros((n_nodes, 3))
            weighted = angle[:, :, None] * normal[:, None, :]
            np.add.at(vertex_normal, self.facets.ravel(), weighted.reshape(-1, 3))
            n_psi[vertex] = vertex_normal[self.facets[f[vertex], local[vertex]]]
        return np.einsum("mi,mi->m", p - closest, n_psi)
