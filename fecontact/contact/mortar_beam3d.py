r"""Dual mortar contact of a 3D :class:`~fecontact.Solid` against the tube of a
:class:`~fecontact.bodies.beam3d.Beam3D`.

The solid's boundary triangles (:meth:`~fecontact.Solid.contact_facets`) are the slave surface,
the beam's tube of radius r (the ``clearance``) about its centreline polyline the master. Each
slave boundary node j carries one multiplier and one row, its weighted gap

    g̃_j = Σ_e ∫_e Φ_j D(x) dA₀,   D(x) = d(x) − r,   rows g_j = g̃_j / L_j,

with d the distance of the current point x = Σ λ_k x_k to the centreline (the least distance to
its segments between consecutive nodes, :mod:`fecontact.contact.polyline_distance`),
Φ_j = 4λ_j − 1 the dual functions of the linear triangle and L_j = Σ_e |e|₀/3 the reference
area node j carries: the same dual basis, reference-area integral and rule as the mortar
against a rigid body (:mod:`fecontact.contact.mortar_rigid3d`), whose multipliers λ_j / L_j
are the nominal pressure. A circular tube's surface does not depend on the sections'
rotations: D is a function of the solid's nodes and the beam's node positions only.

Integration: the degree-5 rule of :func:`~fecontact.contact.rigid_distance.triangle_rule` on
each triangle, on s² sub-triangles where the triangle's vertices have their closest points in
different regions of the centreline (a segment's interior, a node: the end caps, the switch
between neighbouring segments at a joint turning by more than
:data:`~fecontact.contact.polyline_distance.KINK`), where the curvature of D jumps (and on the
concave side of a bend, its gradient). The sub-triangles are fixed in area coordinates: they do not
follow the region's boundary, whose kink they integrate to a smaller error only.

Gradients and curvature over a triangle's 9 node coordinates and the 3 n_b beam node
translations (zero on the section rotations): at a point x with closest point p on segment
(a, b) at ξ, n = (x − p)/|x − p| and ∂D/∂(x, a, b) = (n, −(1 − ξ) n, −ξ n), x = Σ λ_k x_k;
the curvature is that of the segment's distance (held parameter for a closest point inside the
segment, :func:`~fecontact.contact.segment3d.tube_distance`) through the same chain. The
closest segment is chosen per point and held: at a joint it changes where both segments' fields
meet, with equal values (and, on the convex side, equal gradients).

Rows of nodes farther than the margin plus ``REACH`` times their triangles' longest edge from the
tube report +inf and a zero gradient: d is 1-Lipschitz, so D ≥ D_j − |x − x_j| and
D ≤ D_j + |x − x_j| over the node's triangles, and with ∫|Φ_j| = 2.375 L_j (the negative lobes
weigh 0.229 |e|₀ on each triangle) the row is at least D_j − 2.375 reach_j. (A polyline is not
convex, so the sharper bound of the rigid pair does not hold.)

What the rows do not hold one by one: a slave node may sit inside the tube by the
discretization's own amount; :class:`TubeDepths` measures every slave node's exact distance.
No friction: a frictional pair between a solid and a beam is node-to-surface.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..bodies.beam3d import Beam3D
from ..bodies.solid import Solid
from ..errors import InputError, check_positive, check_range
from .base import PairDefaults
from .polyline_distance import closest_on_polyline, region_labels, straight_runs
from .rigid_distance import SUBDIVISIONS, triangle_rule
from .segment3d import tube_distance

__all__ = ["REACH", "MortarBeam3D", "TubeDepths"]

REACH = 2.4
"""A node's row is at least D_j − 2.375 reach_j (module docstring): a node farther than the
margin plus ``REACH`` times its triangles' longest edge has a row beyond the margin."""


def _stars(rows: np.ndarray, m: int):
    """Each row's star, the nodes of its triangles: (m, K) node rows padded with the row's own
    node, and the positions (E, 3 ends, 3 nodes) of each triangle's nodes in the star of the
    row of each of its ends."""
    j = np.repeat(rows, 3, axis=1).ravel()  # (e, k, a) -> rows[e, k]
    a = np.tile(rows, (1, 3)).ravel()  # (e, k, a) -> rows[e, a]
    uniq, inv = np.unique(j * m + a, return_inverse=True)
    uj, ua = np.divmod(uniq, m)
    pos = np.arange(len(uniq)) - np.searchsorted(uj, uj)
    K = int(np.bincount(uj, minlength=m).max())
    star = np.repeat(np.arange(m)[:, None], K, axis=1)
    star[uj, pos] = ua
    return star, pos[inv].reshape(len(rows), 3, 3)


def _areas(t: np.ndarray) -> np.ndarray:
    """Areas (T,) of triangles t (T, 3, 3), m²."""
    return 0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1)


def _local(lam: np.ndarray, G: np.ndarray, H: np.ndarray | None):
    """The gradients (P, 15) and, from H, the curvatures (P, 15, 15) over (x₁, x₂, x₃, a, b)
    of a segment's distance with gradient G (P, 9) and curvature H (P, 9, 9) over (a, b, x):
    the chain through x = Σ λ_k x_k."""
    P = len(lam)
    grad = np.empty((P, 15))
    grad[:, :9] = (lam[:, :, None] * G[:, None, 6:]).reshape(P, 9)
    grad[:, 9:] = G[:, :6]
    if H is None:
        return grad, None
    curv = np.empty((P, 15, 15))
    ll = lam[:, :, None] * lam[:, None, :]
    curv[:, :9, :9] = (ll[:, :, None, :, None] * H[:, None, 6:, None, 6:]).reshape(P, 9, 9)
    cross = (lam[:, :, None, None] * H[:, None, 6:, :6]).reshape(P, 9, 6)
    curv[:, :9, 9:] = cross
    curv[:, 9:, :9] = cross.transpose(0, 2, 1)
    curv[:, 9:, 9:] = H[:, :6, :6]
    return grad, curv


class MortarBeam3D(PairDefaults):
    """Dual mortar contact of the boundary of a 3D :class:`~fecontact.Solid` (``body``, the
    slave) with the tube of radius ``clearance`` (m, > 0) about the centreline of a
    :class:`~fecontact.bodies.beam3d.Beam3D`; see the module docstring. One contact per slave
    boundary node; ``restitution`` Newton's e_N in [0, 1]; ``margin`` (m) the search distance
    (default: the integrator's detection distance); ``subdivisions`` (s ≥ 1) the sub-triangles
    per edge of a triangle across a region boundary of the centreline."""

    linear = False
    lazy_hessians = True
    frictional = False

    def __init__(self, body, beam, restitution=0.0, clearance=0.0, margin=None,
                 subdivisions: int = SUBDIVISIONS):  # fmt: skip
        if not isinstance(body, Solid) or body.dim != 3 or not isinstance(beam, Beam3D):
            raise InputError("mortar contact with a Beam3D's tube needs a 3D Solid")
        self.body, self.beam, self.bodies = body, beam, (body, beam)
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self.clearance = check_positive("clearance (the tube's radius)", clearance)
        self._own_margin = margin is not None
        self.margin = check_positive("margin", 0.05 * body.characteristic_length
                                     if margin is None else margin)  # fmt: skip
        if int(subdivisions) != subdivisions or subdivisions < 1:
            raise InputError(f"subdivisions must be an integer ≥ 1, got {subdivisions!r}")
        self.rules = (triangle_rule(1), triangle_rule(int(subdivisions)))
        self.facets = body.contact_facets()
        self.nodes, rows = np.unique(self.facets, return_inverse=True)
        self.element_rows = rows.reshape(self.facets.shape)
        self.area0 = _areas(body.X[self.facets])  # |e|₀ (m²)
        self.length = np.bincount(rows.ravel(), np.repeat(self.area0 / 3.0, 3), len(self.nodes))
        """Reference area L_j (m²) each slave node carries: its rows are g̃_j / L_j."""
        self.area = self.length
        self._star, pos = _stars(self.element_rows, len(self.nodes))
        self.segments = beam.segments()
        # each triangle end's node columns in its row (the beam's follow the star's 3K)
        self._node_cols = (3 * pos[..., None] + np.arange(3)).reshape(len(self.facets), 3, 9)
        self._beam_col0 = 3 * self._star.shape[1]
        self._node_dofs = body.node_translation_dofs(self.nodes)
        self._beam_dofs = beam.node_translation_dofs(np.arange(beam.n_nodes))
        self.offsets = (0, 0)
        self.dofs = np.zeros((len(self.nodes), self._beam_col0 + self._beam_dofs.size), int)
        self._last = self._last_gaps = None

    @property
    def size(self) -> int:
        return len(self.nodes)

    def bind(self, model) -> None:
        """Place the pair in the global dof vector of ``model``."""
        oa, ob = self.offsets = (model.offset_of(self.body), model.offset_of(self.beam))
        m, K = self._star.shape
        nodes = (oa + self._node_dofs[self._star]).reshape(m, 3 * K)
        beam = np.broadcast_to(ob + self._beam_dofs.ravel(), (m, self._beam_dofs.size))
        self.dofs = np.concatenate([nodes, beam], axis=1)
        self.dofs.flags.writeable = False
        self.reset()

    def reset(self) -> None:
        self._last = self._last_gaps = None

    def detect_within(self, distance: float) -> None:
        """Rows within ``distance`` (m, the integrator's detection distance) are integrated."""
        if not self._own_margin and distance > 0.0 and distance != self.margin:
            self.margin = distance
            self.reset()

    # -- geometry ---------------------------------------------------------------------------
    def _frame(self, q: np.ndarray):
        """Every node's position (m) of the solid, and the beam's segments' ends (S, 2, 3)."""
        (oa, ob), body, beam = self.offsets, self.body, self.beam
        x = body.positions(q[oa : oa + body.ndof])
        return x, beam.positions(q[ob : ob + beam.ndof])[self.segments]

    def node_distances(self, q: np.ndarray) -> np.ndarray:
        """D(x_j) (m): every slave node's distance to the centreline less the tube's radius."""
        x, ends = self._frame(q)
        return closest_on_polyline(x[self.nodes], ends)[2] - self.clearance

    def _near(self, x, ends):
        """The rows that take part (m,) bool, those whose bound from below D_j − REACH reach_j
        is within the margin, the triangles (T,) to integrate for them, and the region label of
        every slave node."""
        which, xi, d = closest_on_polyline(x[self.nodes], ends)
        t = x[self.facets]
        edge = np.linalg.norm(t - np.roll(t, 1, axis=1), axis=2).max(axis=1)
        reach = np.zeros(self.size)
        for k in range(3):
            np.maximum.at(reach, self.element_rows[:, k], edge)
        near = d - self.clearance - REACH * reach <= self.margin
        tris = np.flatnonzero(near[self.element_rows].any(axis=1))
        runs = straight_runs(ends, self.segments, self.beam.n_nodes)
        return near, tris, region_labels(which, xi, self.segments, runs)

    def _points(self, tris, labels):
        """The triangles reordered (plain ones first), and their points: the index of each
        point's triangle in that order, area coordinates λ (P, 3), weights w (P,) and the
        start of each triangle's points."""
        lab = labels[self.element_rows[tris]]
        cut = (lab[:, 0] != lab[:, 1]) | (lab[:, 0] != lab[:, 2])
        tris = np.concatenate([tris[~cut], tris[cut]])
        n_plain, n_cut = int((~cut).sum()), int(cut.sum())
        (l1, w1), (ls, ws) = self.rules
        counts = np.concatenate([np.full(n_plain, len(w1)), np.full(n_cut, len(ws))])
        which = np.repeat(np.arange(len(tris)), counts)
        lam = np.concatenate([np.tile(l1, (n_plain, 1)), np.tile(ls, (n_cut, 1))])
        w = np.concatenate([np.tile(w1, n_plain), np.tile(ws, n_cut)])
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(int)
        return tris, which, lam, w, starts

    def _integrals(self, q: np.ndarray, order: int, tris=None):
        """The triangles' end integrals ∫ Φ_i D dA₀ (T, 3) over the triangles of the rows that
        take part (or ``tris``), and for ``order`` ≥ 1 their derivatives by groups, the points
        of one triangle closest to one segment (whose 15 local dofs (x₁, x₂, x₃, a, b) have the
        same columns): (index of the triangle in tris (n,), segment (n,), the gradients
        (n, 3 ends, 15) and with ``order`` 2 the curvatures (n, 3, 15, 15)). Returns (near,
        tris, values, groups or None)."""
        x, ends = self._frame(q)
        near, found, labels = self._near(x, ends)
        tris = found if tris is None else tris
        if len(tris) == 0:
            return near, tris, np.zeros((0, 3)), None
        tris, which, lam, w, starts = self._points(tris, labels)
        xp = (lam[:, None, :] @ x[self.facets[tris]][which])[:, 0]
        seg = closest_on_polyline(xp, ends)[0]
        f, _, _, G, H = tube_distance(ends[seg], xp[:, None, :], hessian=order == 2)
        wphi = w[:, None] * (4.0 * lam - 1.0) * self.area0[tris][which, None]  # (P, 3)
        values = np.add.reduceat(wphi * (f - self.clearance)[:, None], starts, axis=0)
        if order == 0:
            return near, tris, values, None
        S, P = len(self.segments), len(which)
        keys, group = np.unique(which * S + seg, return_inverse=True)
        n = len(keys)
        # W (3n, P): the weights w Φ_i |e|₀ of each point in its group's end rows
        W = sp.csr_matrix((wphi.ravel(), ((3 * group)[:, None] + np.arange(3)).ravel(),
                           np.arange(0, 3 * P + 1, 3)), shape=(P, 3 * n)).T.tocsr()  # fmt: skip
        grad, curv = _local(lam, G, H if order == 2 else None)
        grads = (W @ grad).reshape(n, 3, 15)
        curvs = None if curv is None else (W @ curv.reshape(P, 225)).reshape(n, 3, 15, 15)
        return near, tris, values, (keys // S, keys % S, grads, curvs)

    def _columns(self, tris, groups) -> np.ndarray:
        """The columns (n, 3 ends, 15) of each group's 15 local dofs in the row of each end of
        its triangle."""
        tri, seg = groups[:2]
        nodes = self.segments[seg]
        beam = self._beam_col0 + 3 * nodes[:, :, None] + np.arange(3)  # (n, 2, 3)
        cols = np.empty((len(tri), 3, 15), dtype=int)
        cols[:, :, :9] = self._node_cols[tris[tri]]
        cols[:, :, 9:] = beam.reshape(-1, 1, 6)
        return cols

    # -- rows -------------------------------------------------------------------------------
    def _rows(self, near, tris, values) -> np.ndarray:
        g = np.zeros(self.size)
        for k in range(3):
            g += np.bincount(self.element_rows[tris, k], values[:, k], self.size)
        return np.where(near, g / self.length, np.inf)

    def gaps(self, q: np.ndarray) -> np.ndarray:
        """The rows g_j (m) alone (+inf for rows that take no part)."""
        for cached in (self._last, self._last_gaps):
            if cached is not None and np.array_equal(cached[0], q):
                return cached[1].copy()
        g = self._rows(*self._integrals(q, 0)[:3])
        self._last_gaps = (q.copy(), g)
        return g.copy()

    def evaluate(self, q: np.ndarray):
        """Rows (m,) in m, dofs (m, k), gradients (m, k), no curvature (:meth:`hessians`)."""
        if self._last is not None and np.array_equal(self._last[0], q):
            return self._last[1].copy(), self.dofs, self._last[2], None
        near, tris, values, groups = self._integrals(q, 1)
        g = self._rows(near, tris, values)
        k = self.dofs.shape[1]
        G = np.zeros(self.dofs.shape)
        if groups is not None:
            r = self.element_rows[tris[groups[0]]]  # (n, 3)
            scale = np.where(near, 1.0 / self.length, 0.0)[r]
            at = r[:, :, None] * k + self._columns(tris, groups)
            vals = scale[:, :, None] * groups[2]
            G = np.bincount(at.ravel(), vals.ravel(), G.size).reshape(G.shape)
        G.flags.writeable = False
        self._last = (q.copy(), g, G)
        return g.copy(), self.dofs, G, None

    def hessians(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """∇²g_j (len(rows), k, k) of the rows ``rows`` at q, in the layout of
        :meth:`evaluate`."""
        rows = np.asarray(rows, dtype=int)
        k = self.dofs.shape[1]
        where = np.full(self.size, -1)
        where[rows] = np.arange(len(rows))
        tris = np.flatnonzero((where[self.element_rows] >= 0).any(axis=1))
        near, tris, _, groups = self._integrals(q, 2, tris)
        if groups is None:
            return np.zeros((len(rows), k, k))
        r = self.element_rows[tris[groups[0]]]  # (n, 3)
        scale = np.where(near, 1.0 / self.length, 0.0)[r]
        g, end = np.nonzero(where[r] >= 0)
        c = self._columns(tris, groups)[g, end]  # (N, 15)
        at = (where[r[g, end]][:, None, None] * k + c[:, :, None]) * k + c[:, None, :]
        vals = scale[g, end, None, None] * groups[3][g, end]
        return np.bincount(at.ravel(), vals.ravel(), len(rows) * k * k).reshape(len(rows), k, k)

    # -- what the rows do not hold ----------------------------------------------------------
    def watch(self) -> TubeDepths:
        return TubeDepths(self)

    def nodal_pressure(self, forces: np.ndarray):
        """The slave nodes (indices in the body) and their nominal pressure z_j = λ_j / L_j
        (Pa, per reference area) from the rows' normal forces λ_j (N)."""
        forces = np.asarray(forces, dtype=float)
        if forces.shape != (self.size,):
            raise InputError(f"forces must have {self.size} entries, got {forces.shape}")
        return self.nodes, forces / self.length


class TubeDepths:
    """The deepest slave node of a :class:`MortarBeam3D` inside the tube, by its exact
    distance to the centreline, over the shortest reference boundary edge at that node."""

    def __init__(self, pair: MortarBeam3D):
        self.pair = pair
        t = pair.body.X[pair.facets]
        edge = np.linalg.norm(t - np.roll(t, 1, axis=1), axis=2).min(axis=1)
        self.edge = np.full(pair.size, np.inf)
        for k in range(3):
            np.minimum.at(self.edge, pair.element_rows[:, k], edge)

    def depth(self, q: np.ndarray) -> tuple[float, float]:
        """(deepest node's depth in m, ≥ 0; the largest depth over the node's shortest edge)."""
        d = -self.pair.node_distances(q)
        return max(0.0, float(d.max())), max(0.0, float((d / self.edge).max()))
