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
discretization's own amount; the pair's watch measures every slave node's exact distance.
On triangles much wider than the tube the rows read millimetres below the nodes' own
distances (the negative lobes weigh the cone the distance makes across the face): there
``Contact`` builds the beam's rows instead (:mod:`fecontact.contact.tube_line_mortar`).

Friction: one slip row per slave node, the node's motion against the beam's material point
at its place, c_j T_j·(ẋ_j − ẏ_j) with ẏ_j = ṗ_j + ω_j × (x_j − p_j): p_j = (1 − ξ)a + ξb
the node's closest point on the centreline (ξ clamped), ω_j = (1 − ξ) R_a Ω_a + ξ R_b Ω_b
the sections' spatial angular velocity (Ω body-frame: a rolling rod turns its contact
point). T_j are the tangents of ν_j, the solid's outward normal at the node on its face
toward the tube (:func:`facing_normals`), turned across the segment's axis where the node's
closest point is inside a segment, and on an end cap by a share falling with the node's
angle off the end's plane (:func:`across_axis`: continuous there); c_j = max(0, ν_j·N_j),
N_j = Σ_beam ∂g_j/∂x_b the force the row puts on the beam per unit multiplier, so that
Coulomb's bound μλ_j acts on the row's load along that normal. Not the row's own normal N_j:
beside the line where a tube touches a face it is tilted by the node's offset, the rows
either side squeezing the tube sideways, so that Σλ_j exceeds the load and the tilted
tangents read the normal motion ahead of a rolling tube as slip (measured in the docs page
``explanation/mortar_beam3d``)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..bodies.beam3d import Beam3D
from ..bodies.solid import Solid
from ..errors import InputError, check_positive
from ..rotations import exp, hat
from .boundary_mortar import BoundaryRows
from .friction import tangent_basis
from .inside import Surface
from .mortar_rigid3d import NodeDepths
from .polyline_distance import closest_on_polyline, region_labels, straight_runs
from .rigid_distance import SUBDIVISIONS
from .segment3d import tube_distance

__all__ = ["REACH", "SAMPLES", "MortarBeam3D"]

REACH = 2.4
"""A node's row is at least D_j − 2.375 reach_j (module docstring): a node farther than the
margin plus ``REACH`` times its triangles' longest edge has a row beyond the margin."""


SAMPLES = 8
"""The start check measures the tube's depth in the solid at the beam's nodes and at
``SAMPLES`` − 1 points between each two (a straight segment's depth below a flat face is
linear: its deepest point is a node; across a solid's edge it is deepest at the edge, between
the samples, and read to within the sample spacing times the slope)."""


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


class MortarBeam3D(BoundaryRows):
    """Dual mortar contact of the boundary of a 3D :class:`~fecontact.Solid` (``body``, the
    slave) with the tube of radius ``clearance`` (m, > 0) about the centreline of a
    :class:`~fecontact.bodies.beam3d.Beam3D`; see the module docstring. One contact per slave
    boundary node; ``restitution`` Newton's e_N in [0, 1]; ``margin`` (m) the search distance
    (default: the integrator's detection distance); ``subdivisions`` (s ≥ 1) the sub-triangles
    per edge of a triangle across a region boundary of the centreline."""

    frictional = True

    def __init__(self, body, beam, restitution=0.0, clearance=0.0, margin=None,
                 subdivisions: int = SUBDIVISIONS):  # fmt: skip
        if not isinstance(body, Solid) or body.dim != 3 or not isinstance(beam, Beam3D):
            raise InputError("mortar contact with a Beam3D's tube needs a 3D Solid")
        clearance = check_positive("clearance (the tube's radius)", clearance)
        super().__init__(body, restitution, clearance, margin, subdivisions)
        self.beam, self.bodies = beam, (body, beam)
        self.segments = beam.segments()
        # each triangle end's node columns in its row (the beam's follow the star's 3K)
        cols = 3 * self.star_positions[..., None] + np.arange(3)
        self._node_cols = cols.reshape(len(self.facets), 3, 9)
        self._beam_col0 = 3 * self.star.shape[1]
        self._node_dofs = body.node_translation_dofs(self.nodes)
        self._beam_dofs = beam.node_translation_dofs(np.arange(beam.n_nodes))
        self._row_tris = row_triangles(self.element_rows, self.size)
        self.offsets = (0, 0)
        self.dofs = np.zeros((len(self.nodes), self._beam_col0 + self._beam_dofs.size), int)

    def bind(self, model) -> None:
        """Place the pair in the global dof vector of ``model``."""
        oa, ob = self.offsets = (model.offset_of(self.body), model.offset_of(self.beam))
        m, K = self.star.shape
        nodes = (oa + self._node_dofs[self.star]).reshape(m, 3 * K)
        beam = np.broadcast_to(ob + self._beam_dofs.ravel(), (m, self._beam_dofs.size))
        self.dofs = np.concatenate([nodes, beam], axis=1)
        self.dofs.flags.writeable = False
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
        near = d - self.clearance - REACH * self.reach(x) <= self.margin
        tris = np.flatnonzero(near[self.element_rows].any(axis=1))
        runs = straight_runs(ends, self.segments, self.beam.n_nodes)
        return near, tris, region_labels(which, xi, self.segments, runs)

    def integrals(self, q: np.ndarray, order: int, tris=None):
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
        lab = labels[self.element_rows[tris]]
        cut = (lab[:, 0] != lab[:, 1]) | (lab[:, 0] != lab[:, 2])
        tris, which, lam, w, starts = self.rule_points(tris, cut)
        xp = (lam[:, None, :] @ x[self.facets[tris]][which])[:, 0]
        seg, xi, f = closest_on_polyline(xp, ends)
        G = H = None
        if order == 2:
            f, _, _, G, H = tube_distance(ends[seg], xp[:, None, :])
        elif order == 1:  # the gradient ((1 − ξ)e, ξe, −e) over (a, b, x), e from x to p
            t = np.clip(xi, 0.0, 1.0)[:, None]
            a, b = ends[seg, 0], ends[seg, 1]
            e = ((1.0 - t) * a + t * b - xp) / f[:, None]
            G = np.concatenate([(1.0 - t) * e, t * e, -e], axis=1)
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
    def evaluate(self, q: np.ndarray):
        """Rows (m,) in m, dofs (m, k), gradients (m, k), no curvature (:meth:`hessians`)."""
        if self.cached is not None and np.array_equal(self.cached[0], q):
            return self.cached[1].copy(), self.dofs, self.cached[2], None
        near, tris, values, groups = self.integrals(q, 1)
        g = self.sum_rows(near, tris, values)
        k = self.dofs.shape[1]
        G = np.zeros(self.dofs.shape)
        if groups is not None:
            r = self.element_rows[tris[groups[0]]]  # (n, 3)
            scale = np.where(near, 1.0 / self.length, 0.0)[r]
            at = r[:, :, None] * k + self._columns(tris, groups)
            vals = scale[:, :, None] * groups[2]
            G = np.bincount(at.ravel(), vals.ravel(), G.size).reshape(G.shape)
        G.flags.writeable = False
        self.cached = (q.copy(), g, G)
        return g.copy(), self.dofs, G, None

    def hessians(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """∇²g_j (len(rows), k, k) of the rows ``rows`` at q, in the layout of
        :meth:`evaluate`."""
        rows = np.asarray(rows, dtype=int)
        k = self.dofs.shape[1]
        where = np.full(self.size, -1)
        where[rows] = np.arange(len(rows))
        tris = np.flatnonzero((where[self.element_rows] >= 0).any(axis=1))
        near, tris, _, groups = self.integrals(q, 2, tris)
        if groups is None:
            return np.zeros((len(rows), k, k))
        r = self.element_rows[tris[groups[0]]]  # (n, 3)
        scale = np.where(near, 1.0 / self.length, 0.0)[r]
        g, end = np.nonzero(where[r] >= 0)
        c = self._columns(tris, groups)[g, end]  # (N, 15)
        at = (where[r[g, end]][:, None, None] * k + c[:, :, None]) * k + c[:, None, :]
        vals = scale[g, end, None, None] * groups[3][g, end]
        return np.bincount(at.ravel(), vals.ravel(), len(rows) * k * k).reshape(len(rows), k, k)

    # -- friction ---------------------------------------------------------------------------
    def _slip_frame(self, q: np.ndarray):
        """Per row: the segment's node indices (m, 2), ξ clamped (m,), the arm x_j − p_j (m, 3),
        the scaled tangents c_j T_j (m, 2, 3) and the unit tangents T_j (module docstring)."""
        x, ends = self._frame(q)
        xj = x[self.nodes]
        seg, xi, _ = closest_on_polyline(xj, ends)
        t = np.clip(xi, 0.0, 1.0)
        arm = xj - (1.0 - t)[:, None] * ends[seg, 0] - t[:, None] * ends[seg, 1]
        G = self.evaluate(q)[2]
        N = G[:, self._beam_col0 :].reshape(self.size, -1, 3).sum(axis=1)
        nu = facing_normals(x, self.facets, self._row_tris, N)
        nu = across_axis(nu, ends[seg], xi, arm, self._cap(seg, xi))
        c = np.maximum(np.einsum("mi,mi->m", nu, N), 0.0)
        T = tangent_basis(nu)
        return self.segments[seg], t, arm, c[:, None, None] * T, T

    def _cap(self, seg: np.ndarray, xi: np.ndarray) -> np.ndarray:
        """Whether each closest point (segment, unclamped ξ) is a free end of the
        centreline (an end cap, not a joint)."""
        single = np.bincount(self.segments.ravel(), minlength=self.beam.n_nodes) == 1
        return np.where(xi <= 0.0, single[self.segments[seg, 0]],
                        (xi >= 1.0) & single[self.segments[seg, 1]])  # fmt: skip

    def tangents(self, q: np.ndarray):
        """Slip rows: dofs (m, 15), the node's translation and the 6 dofs of each of its
        segment's two beam nodes; c_j T_j ∂(x_j − y_j)/∂ (m, 2, 15); unit tangents T_j."""
        nodes, t, arm, cT, T = self._slip_frame(q)
        ob = self.offsets[1]
        R = exp(q[ob : ob + self.beam.ndof].reshape(-1, 6)[:, 3:])[nodes]  # (m, 2, 3, 3)
        W = np.empty((self.size, 2, 15))
        W[:, :, :3] = cT
        turn = np.einsum("mti,mij->mtj", cT, hat(arm))  # ∂(−ω × arm) = hat(arm) δω
        for k, s in enumerate((1.0 - t, t)):
            W[:, :, 3 + 6 * k : 6 + 6 * k] = -s[:, None, None] * cT
            W[:, :, 6 + 6 * k : 9 + 6 * k] = s[:, None, None] * turn @ R[:, k]
        beam = ob + 6 * nodes[:, :, None] + np.arange(6)
        dofs = np.concatenate([self.offsets[0] + self._node_dofs, beam.reshape(-1, 12)], 1)
        return dofs, W, T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """c_j T_j·(y_j,n − x_j,n) over the step: where the beam's material point now at x_j
        was at q_n, p_n + Σ_k s_k R_k,n R_kᵀ (x_j − p_j) (s = (1 − ξ, ξ), the same segment and
        ξ), against where the node was (exact for a rigid turn of the segment; the linear form
        on the rotation vectors is not)."""
        nodes, t, arm, cT, _ = self._slip_frame(q)
        ob = self.offsets[1]
        R = exp(q[ob : ob + self.beam.ndof].reshape(-1, 6)[:, 3:])[nodes]
        qn = q_n[ob : ob + self.beam.ndof].reshape(-1, 6)
        Rn, pn = exp(qn[:, 3:])[nodes], self.beam.X[nodes] + qn[nodes, :3]  # (m, 2, ...)
        y = np.zeros((self.size, 3))
        for k, s in enumerate((1.0 - t, t)):
            back = np.einsum("mji,mj->mi", R[:, k], arm)  # R_kᵀ arm
            y += s[:, None] * (pn[:, k] + np.einsum("mij,mj->mi", Rn[:, k], back))
        oa, body = self.offsets[0], self.body
        xn = body.positions(q_n[oa : oa + body.ndof])[self.nodes]
        return np.einsum("mti,mi->mt", cT, y - xn)

    # -- what the rows do not hold ----------------------------------------------------------
    def admissible_gaps(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """The gaps (m) that admit a state at t = 0 where the rows take part: each slave node's
        own distance D_j (a row reads a stand-off below it on triangles much larger than the
        tube, the dual functions' negative lobes, where no node is inside), and where the tube
        reaches into the solid (its centreline sampled, :data:`SAMPLES`; d − r, d the signed
        distance to the solid's boundary) where the rows of its closest triangle read below
        zero too, the shallower of the two: a tube resting on its rows (zero) dips between
        the nodes by their own stand-off and is admitted."""
        x, ends = self._frame(q)
        s = np.linspace(0.0, 1.0, SAMPLES + 1)[:, None, None]
        points = ((1.0 - s) * ends[:, 0] + s * ends[:, 1]).reshape(-1, 3)
        d, facet = Surface(self.facets).signed_distance(x, points, pad=self.clearance)
        tube = np.full(self.size, np.inf)
        hit = facet >= 0
        for k in range(3):
            np.minimum.at(tube, self.element_rows[facet[hit], k], d[hit] - self.clearance)
        # a row at zero holds its tube as in a run (dipping between the nodes by the rows'
        # stand-off; a settled state's rows are zero to round-off): a tube inside is refused
        # where its row reads below zero too, by the shallower of the two depths
        exact = np.minimum(self.node_distances(q), np.maximum(tube, rows))
        return np.where(np.isfinite(rows), exact, np.inf)

    def watch(self) -> NodeDepths:
        """The deepest slave node inside the tube, by its exact distance to the centreline."""
        return NodeDepths(self)


FACE = np.cos(np.pi / 4)
"""Triangles of a node whose normals lie within 45° of its triangle facing the tube most
squarely count as that node's face: at a box's edge the side face (90° away) is left out."""


def across_axis(nu: np.ndarray, ends: np.ndarray, xi: np.ndarray, arm: np.ndarray,
                cap: np.ndarray) -> np.ndarray:  # fmt: skip
    """The normals ν (m, 3) of the nodes turned toward the plane across their segment's axis
    e (``ends`` (m, 2, 3) the segments, ``xi`` the closest points' parameters, ``arm`` (m, 3)
    from the closest points to the nodes, ``cap``: the closest point is a free end of the
    centreline): ν − s(ν·e)e, normalised. A tube touches a face along a line only where the
    face contains the axis' direction; a face tilted along the axis (a block pitched by its
    load) touches it in the tube's own normal, across the axis: s = 1 where the closest
    point lies inside the segment (0 < ξ < 1). On an end cap the cap's normal turns from
    across the axis (on the end's plane) to along it, and s = 1 − |arm·e|/|arm| falls with it
    to 0, where ν is kept (a sphere's field): continuous across the end's plane. A turn
    switched off there instead tilted the slip rows of a node lying on it by the face's pitch
    (1.8e-4 rad), and the step's normal motion read through them as a slip that changed sign
    with the side of the plane the iterate fell on: the smooth step's Newton cycled. At a
    joint between two segments (the closest point a node of the beam) ν is kept."""
    e = ends[:, 1] - ends[:, 0]
    e /= np.linalg.norm(e, axis=1)[:, None]
    reach = np.linalg.norm(arm, axis=1)
    along = np.divide(np.abs(np.einsum("mi,mi->m", arm, e)), reach, out=np.ones_like(reach),
                      where=reach > 0.0)  # fmt: skip
    share = np.where((xi > 0.0) & (xi < 1.0), 1.0, np.where(cap, 1.0 - along, 0.0))
    across = nu - (share * np.einsum("mi,mi->m", nu, e))[:, None] * e
    size = np.linalg.norm(across, axis=1)
    turn = (share > 0.0) & (size > 1e-6)
    nu = nu.copy()
    nu[turn] = across[turn] / size[turn, None]
    return nu


def row_triangles(rows: np.ndarray, m: int) -> np.ndarray:
    """The triangles (m, K) of each of m rows, −1 padded (``rows`` (T, 3) the triangles'
    rows)."""
    r = rows.ravel()
    order = np.argsort(r, kind="stable")
    count = np.bincount(r, minlength=m)
    start = np.concatenate([[0], np.cumsum(count)[:-1]])
    table = np.full((m, int(count.max())), -1)
    table[r[order], np.arange(len(r)) - start[r[order]]] = order // 3
    return table


def facing_normals(x, facets, row_tris, N) -> np.ndarray:
    """Unit outward normals (m, 3) of the slave nodes' faces toward the tube: over each node's
    triangles ``row_tris`` (m, K; −1 pads) at positions x, the area-weighted normal of those
    within ``FACE`` of the one most along N (m, 3), the row's force on the beam."""
    t = x[facets]
    area = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    unit = area / np.linalg.norm(area, axis=1)[:, None]
    real = row_tris >= 0
    a, n = area[row_tris] * real[..., None], unit[row_tris] * real[..., None]
    score = np.where(real, np.einsum("mki,mi->mk", n, N), -np.inf)
    best = n[np.arange(len(N)), np.argmax(score, axis=1)]
    keep = real & (np.einsum("mki,mi->mk", n, best) >= FACE)
    nu = np.einsum("mk,mki->mi", keep.astype(float), a)
    return nu / np.linalg.norm(nu, axis=1)[:, None]
