r"""Pointwise rows that keep a mortar interface's nodes from sinking into the other solid.

A dual mortar interface holds the weighted gaps g̃_j = ∫ Φ_j g_N dA ≥ 0: an average over
each slave node's elements, not the node's own distance. Where the gap field is far from
linear over an element — a convex kink under a coarse pole, the bulge of a disk hit at tens
of m/s — a node can lie inside the other body while its weighted gap is positive. The
safeguard adds, for every boundary node of each solid of the interface (two passes: the
slave's nodes against the master's surface, the master's nodes against the slave's), a row
of its own, the node-to-surface gap of
:class:`~fecontact.contact.body_pairs.NodeSurfaceContact` shifted by an allowance δ:

    g_s = g_N(x) + δ ≥ 0,   δ = ``ALLOWANCE`` × the shortest boundary edge of the surface,

g_N the signed plane gap of the node from its closest facet (−distance inside a convex
surface). g_N is a smooth maximum of the plane gaps of the facets around the master vertex
nearest the node (:class:`DeepNodeRows3D`, in 2D :mod:`.mortar_safeguard2d`): at a ball's
coarse pole, the apex of four facets tilted 30°, one facet's plane gap pushes the node along
its normal, sideways by half the force (the turned coarsest balls then left the axis at 32 %
of the impact speed); the facets' weighted mean normal pushes it along the apex's axis. Each plane
gap is read deeper by how far the node's foot on the plane lies outside its facet: a master
node pressed into the slave's surface dents it, the vertices around the node are concave,
and there the largest plane gap is a neighbour's plane that the node is not behind (the
graded balls 0.7 R off-centre: a node 2.4 % of the shortest edge behind its facet read
0.45 %, held there, and sank on).

The row is a candidate only for a node deeper than δ/2 (elsewhere it reports a finite gap
beyond any detection distance and a zero gradient): a node that the weighted gaps keep out,
or let in by their usual few tenths of a per cent of an edge, never sees it, so that every
run in which no node sinks deeper is unchanged bit for bit, its symmetry included. A node
deeper than δ makes the row active at both levels of the step, as any contact: Signorini at
the position correction (g_s ≥ 0 with the Alart–Curnier multiplier), Newton's impact law on
the velocity jump (with the interface's e_N), and Coulomb's law with the interface's μ on
slip rows along the row's own normal (:mod:`fecontact.contact.safeguard_slip`): the normal
force a held node carries is a contact force as any other (frictionless, a rolling disk
whose master nodes these rows held kept that part of its weight without friction).

A slave node's weighted row and its own row are two constraints, g̃_j ≥ 0 and g_s ≥ 0,
each with its multiplier. Their minimum as one row describes the same admissible set, but
has a kink where the two cross: at three boundary edges a step (two disks at 43.5 m/s,
8 Δx/c) the pointwise gap rose and the weighted one fell along the smooth step's Newton
update, and the iterates jumped across the kink of their minimum without converging. Two
rows have no kink; each keeps its own smooth linearisation. But both push the same node
along nearly the same normal: in one active set they are a nearly redundant pair, whose
multipliers the Schur complement splits into large forces of opposite signs (there the
position correction cycled through three active sets). They are *twins*
(:func:`twin_rows`): an active set holds the deeper of the two, and the other enters only
in its place, when its own gap is the smaller (:func:`fecontact.contact.laws.one_of_twins`).

This is the active-set safeguard of segment-to-segment methods that complement a weighted
(integrated) constraint with pointwise checks where the integral lets a point through (the
two-pass node-to-segment rows of Puso & Laursen, Comput. Methods Appl. Mech. Engrg. 193,
2004, used here only where a node is found inside).
"""

from __future__ import annotations

import numpy as np

from .body_pairs import NodeSurfaceContact, triangle_plane_distance
from .facet_excess import edge_excess, edge_excess_jet
from .geometry import closest_facet_distance
from .inside import bounding_box
from .safeguard_slip import SafeguardSlip

__all__ = [
    "ALLOWANCE",
    "DeepNodeRows",
    "DeepNodeRows3D",
    "SMOOTHING",
    "edge_excess",
    "edge_excess_jet",
    "pointwise_pairs",
    "pointwise_row",
    "real_gaps",
    "real_starts",
    "safeguard_rows",
    "shortest_edge",
    "twin_rows",
    "twins_among",
]

ALLOWANCE = 0.005
"""δ over the shortest boundary edge of the surface a node is held out of: half the depth
(1 % of an edge) a node of a mortar interface may reach, so that a node held by its row ends
within it, and above the 0.03–0.3 % the weighted gaps let a node in when they hold."""


SMOOTHING = 0.1
"""ε over δ: the smoothing length of the 3D rows' maximum of plane gaps (:class:`DeepNodeRows3D`):
at a vertex where n planes tie the row reads the node ε ln n shallower (0.35 δ at four), and
the planes' weights trade over a sideways shift of about 2ε / sin θ (θ the planes' tilt)."""


def shortest_edge(body, facets: np.ndarray) -> float:
    """The shortest edge (m) of the boundary ``facets`` of ``body`` in its reference
    configuration."""
    x = body.positions(np.zeros(body.ndof))
    corners = x[facets]
    edges = corners - np.roll(corners, 1, axis=1)
    return float(np.sqrt((edges**2).sum(-1)).min())


class DeepNodeRows(SafeguardSlip, NodeSurfaceContact):
    """Every boundary node of the solid ``body`` against the surface of the solid ``master``,
    g_s = g_N + δ ≥ 0 for a node deeper than δ/2; the others report a gap ``far`` beyond any
    detection distance (twice the pair's), with a zero gradient: never a candidate, and
    finite, so that a row that a correction's iterate lifts out stays a number
    (module docstring). ``restitution``: e_N, as the interface's; the interface's μ on slip rows
    along the row's normal (:mod:`.safeguard_slip`)."""

    meets_back = False  # (the rows of one interface's nodes deep inside, each way)
    inside_test = False  # g_s is held to round-off like a signed distance
    # the base margin is enough: a node that sinks is found by the inside test however deep
    looks_ahead = False
    _far = None  # (margin and placement, the rows of a free flight)
    twin = None
    """The interface whose row j holds this pair's node j by its weighted gap (the slave's
    rows; None: the master's, whose nodes have no weighted row)."""

    def __init__(self, body, master, restitution: float = 0.0):
        super().__init__(body, master, restitution=restitution)
        # one row per node, its closest facet's (the rows of concave features are left out:
        # the row only has to stop a node that sinks, not balance it in a dent)
        self.extra = 0
        self._row_node = np.arange(len(self.nodes))
        self._slave_dofs = body.node_translation_dofs(self.nodes)
        self.selected = self.closest = np.full(self.size, -1)
        self.allowance = ALLOWANCE * shortest_edge(master, self.facets)
        """δ (m): how deep a node may sink before its row holds it."""

    def closest_facets(self, xs: np.ndarray, xm: np.ndarray):
        # a node farther than the margin from the master's bounding box has no facet within
        # it (the search would find none): bodies whose boxes are apart need no search
        lo, hi = bounding_box(xm)
        lo, hi = lo - self.margin, hi + self.margin
        if not np.any(np.all((xs >= lo) & (xs <= hi), axis=1)):
            empty = np.zeros(0, int)
            return empty, empty, np.zeros(0)
        return super().closest_facets(xs, xm)

    def evaluate(self, q: np.ndarray):
        xs, xm = self.positions(q)
        lo, hi = bounding_box(xm)
        lo, hi = lo - self.margin, hi + self.margin
        if np.any(np.all((xs >= lo) & (xs <= hi), axis=1)):
            return super().evaluate(q)
        # every node farther than the margin from the other body: the rows of a free flight,
        # made once per margin and placement (most steps of a run)
        key = (self.base_margin, self.offsets)
        if self._far is None or self._far[0] != key:
            far = self._shifted(q)  # (+inf: no facet within reach of any node)
            for array in far[1:3]:
                array.flags.writeable = False
            self._far = (key, far)
        self.selected = np.full(self.size, -1)
        g, dofs, G, H = self._far[1]
        return g.copy(), dofs, G, H

    def _shifted(self, q):
        """The node-to-surface rows at q with their gaps shifted by δ."""
        g, dofs, G, H = super()._evaluate(q)
        return g + self.allowance, dofs, G, H

    def _evaluate(self, q):
        g, dofs, G, H = self._shifted(q)
        shallow = ~(g < 0.5 * self.allowance)
        g[shallow] = 2.0 * self.base_margin
        G[shallow] = 0.0
        self.selected[shallow] = -1  # (no curvature either)
        return g, dofs, G, H

    def held(self, q: np.ndarray) -> int:
        """How many nodes lie deeper than δ/2 at q, so that their rows are candidates: a
        held node ends a step about δ deep."""
        return int(np.count_nonzero(self.gaps(q) < 0.5 * self.allowance))

    # what an evaluation leaves for the rows' curvature and the pair's search (kept by
    # :meth:`real`, which reads another configuration between the step's evaluations)
    _KEPT = ("selected", "closest", "_seen")

    def real(self, q: np.ndarray):
        """(g_s, dofs, G) of every node at q without the placeholder above δ/2: the gap a
        located closing needs at the start of the step, where the node was still shallow
        (+inf where no facet is within the margin, and in 3D where the node cannot be
        deep). What the pair keeps of its last evaluation is left as it was."""
        kept = [getattr(self, name) for name in self._KEPT]
        try:
            return self._shifted(q)[:3]
        finally:
            for name, value in zip(self._KEPT, kept, strict=True):
                setattr(self, name, value)


class DeepNodeRows3D(DeepNodeRows):
    """:class:`DeepNodeRows` of 3D solids: a deep node's row is the smooth maximum of the
    plane gaps g_k of the master facets around the vertex v (of its closest facet) nearest
    to it, each less the excess P_k of the node's foot beyond its facet's edges
    (:func:`edge_excess` with a ramp of width δ, ``reach``; zero on the facet),

        g_s = ε ln Σ_k exp((g_k − P_k) / ε) + δ,   ε = ``SMOOTHING`` δ,

    the node's depth behind the convex vertex (inside, minus the largest plane gap), read at
    most ε ln n shallower where n planes tie. Its gradient Σ_k w_k ∇g_k (w the planes'
    soft-max weights) is their weighted mean: a node at the apex of the master's facets is
    pushed along the apex's axis, not along one facet's normal. Behind a concave vertex the
    planes whose facets the node is not under read deeper by P_k, and the row is the depth
    behind the facet it is under (module docstring)."""

    def __init__(self, body, master, restitution: float = 0.0):
        super().__init__(body, master, restitution)
        ends = self.facets.ravel()
        count = np.bincount(ends)
        self.around = np.full((len(count), int(count.max())), -1)
        """The facets around each master node (padded with −1)."""
        order = np.argsort(ends, kind="stable")
        start = np.cumsum(count) - count
        slot = np.arange(len(ends)) - np.repeat(start, count)
        self.around[ends[order], slot] = order // self.facets.shape[1]
        self.width = self.dim + self._facet_dofs.shape[1] * self.around.shape[1]
        self.smoothing = SMOOTHING * self.allowance
        self.reach = self.allowance
        """The width (m) of the ramp of a plane's excess (:func:`edge_excess`): δ, not ε. A
        foot e beyond its facet puts the node √(g² + e²) − |g| farther from the facet than
        from its plane, a ramp of width |g|, and a held node lies δ deep; at ε the row's
        gradient turned sideways by e/ε, its force λ with it, and Newton's iterates crossed
        a shared edge of two facets back and forth (docs/explanation/mortar.md)."""
        self.vertex = np.full(self.size, -1)
        """The master vertex each deep row reads (−1: none), at the last evaluation."""

    _KEPT = (*DeepNodeRows._KEPT, "vertex")

    def _planes(self, x, xm, vertex, hessian: bool):
        """The plane gaps (n, K) of points x (n, 3) from the facets around ``vertex`` (n,),
        their gradients (n, K, 12) and Hessians (n, K, 12, 12; None unless ``hessian``) over
        (x, facet vertices), and the facets (n, K; −1 pads: gap −inf, zero derivatives); each
        gap less the excess of the point's foot beyond its facet (:func:`edge_excess`). Last,
        the floor of :meth:`_reading`: the deepest plane gap itself (n,), its plane (n,), its
        gradient (n, 12) and Hessian (n, 12, 12; None unless ``hessian``)."""
        facets = self.around[vertex]
        n, K = facets.shape
        real = facets >= 0
        tri = xm[self.facets[np.where(real, facets, 0)]]  # (n, K, corners, d)
        xk = np.repeat(x, K, axis=0)
        t = tri.reshape(n * K, *tri.shape[2:])
        g, G, H = self.plane_gaps(xk, t, hessian)
        w = G.shape[1]
        g = np.where(real, g.reshape(n, K), -np.inf)
        G = G.reshape(n, K, w) * real[:, :, None]
        if H is not None:
            H = H.reshape(n, K, w, w) * real[:, :, None, None]
        k = np.where(real, g, np.inf).argmin(axis=1)
        rows = np.arange(n)
        floor = (g[rows, k], k, G[rows, k], None if H is None else H[rows, k])
        # each plane read deeper by how far the node's foot lies outside its facet
        excess = np.where(real, self.excess(xk, t, self.reach).reshape(n, K), 0.0)
        g = g - excess
        # (its derivatives where they count: on a row deeper than δ/2, whose maximum is
        # below −δ/2, and on a plane within 50 ε of that maximum, the others' weights
        # below e⁻⁵⁰)
        top = g.max(axis=1, keepdims=True)
        need = (excess > 0.0) & (g > top - 50.0 * self.smoothing) & (top < -0.5 * self.allowance)
        if need.any():
            _, dP, d2P = self.excess_jet(xk[need.ravel()], t[need.ravel()], self.reach)
            G[need] -= dP
            if H is not None:
                H[need] -= d2P
        return g, G, H, facets, floor

    def _reading(self, gk, Gk, Hk, floor):
        """The row's reading g_s − δ (n,) of the planes ``gk`` (less their excess) and their
        weights (n, K): their smooth maximum, but never deeper than the deepest plane gap
        itself (``floor``, :meth:`_planes`), whose plane then alone carries the row (its
        gradient and Hessian put in ``Gk``, ``Hk``). A node in front of every plane around
        its vertex is outside the solid there, convex or concave; the excesses, larger than
        the plane gaps where the node's feet lie far beyond the facets (a node beside a
        box's corner, a few cm out), read it deep inside."""
        value, w = self._soft(gk)
        low, k, G_low, H_low = floor
        on = low > value
        if on.any():  # (elsewhere the reading is the smooth maximum to the bit)
            value = np.where(on, low, value)
            w[on] = 0.0
            w[on, k[on]] = 1.0
            Gk[on, k[on]] = G_low[on]
            if Hk is not None:
                Hk[on, k[on]] = H_low[on]
        return value, w

    @staticmethod
    def plane_gaps(x, tri, hessian: bool):
        """The plane gaps (m,) of points x (m, 3) from the triangles ``tri`` (m, 3, 3), their
        gradients (m, 12) and Hessians (m, 12, 12; None unless ``hessian``)."""
        return triangle_plane_distance(x, tri[:, 0], tri[:, 1], tri[:, 2], hessian)

    excess = staticmethod(edge_excess)
    excess_jet = staticmethod(edge_excess_jet)

    def _soft(self, g):
        """The smooth maximum (n,) of the plane gaps g (n, K) and the weights (n, K)."""
        top = g.max(axis=1)
        e = np.exp((g - top[:, None]) / self.smoothing)
        total = e.sum(axis=1)
        return top + self.smoothing * np.log(total), e / total[:, None]

    def _spread(self, w, G):
        """The row vectors (n, width) Σ_k w_k G_k of the planes' gradients G (n, K, d + facet's)."""
        n, K = w.shape
        d = self.dim
        out = np.zeros((n, self.width))
        out[:, :d] = np.einsum("nk,nkd->nd", w, G[:, :, :d])
        out[:, d:] = (w[:, :, None] * G[:, :, d:]).reshape(n, -1)
        return out

    def _shifted(self, q):
        xs, xm = self.positions(q)
        m, (oa, ob) = self.size, self.offsets
        g = np.full(m, np.inf)
        d = self.dim
        dofs = np.empty((m, self.width), dtype=int)
        dofs[:, :d] = oa + self._slave_dofs
        dofs[:, d:] = ob + np.tile(self._facet_dofs[0], self.around.shape[1])
        G = np.zeros((m, self.width))
        s, f, _ = self.closest_facets(xs, xm)
        self.selected = np.full(m, -1)
        self.selected[s] = f
        self.closest = self.selected.copy()
        self.vertex = np.full(m, -1)
        if s.size:
            corners = self.facets[f]  # the closest facet's vertex nearest to the node
            near = np.linalg.norm(xm[corners] - xs[s, None], axis=2).argmin(axis=1)
            self.vertex[s] = v = corners[np.arange(len(s)), near]
            facets = self.around[v]
            used = np.where(facets >= 0, facets, facets[:, :1])
            dofs[s, d:] = ob + self._facet_dofs[used].reshape(len(s), -1)
            # the planes of the rows that may be deep (the others keep g = +inf: shallow)
            deep = s[self._may_be_deep(xs[s], xm[corners])]
            if deep.size:
                gk, Gk, _, _, floor = self._planes(xs[deep], xm, self.vertex[deep], False)
                g[deep], w = self._reading(gk, Gk, None, floor)
                g[deep] += self.allowance
                G[deep] = self._spread(w, Gk)
        return g, dofs, G, None

    def _may_be_deep(self, x: np.ndarray, tri: np.ndarray) -> np.ndarray:
        """Which points x (n, 3) may have a row deeper than δ/2 (g_s < δ/2) for their closest
        facets ``tri`` (n, 3, 3): those with g − 3 √(d² − g²) < −δ/4, g the plane gap and d
        the distance to the facet. The facet is one of the planes of the row (its vertex is
        the facet's), the foot of x lies √(d² − g²) from the facet in its plane, and each of
        the three edges' excesses is at most that far beyond its edge: g_s − δ ≥ g − P ≥
        g − 3 √(d² − g²). Elsewhere g_s ≥ 3δ/4, δ/4 above the threshold: far beyond the
        round-off of the two computations of g (|δ|/4 for a δ set negative)."""
        d, g = closest_facet_distance(x, tri)
        bound = -0.5 * self.allowance + 0.25 * abs(self.allowance)
        edges = tri.shape[1]  # (a segment's two ends)
        return g - edges * np.sqrt(np.maximum(d * d - g * g, 0.0)) < bound

    def hessians(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """∇²g_s of the rows at q: Σ_k w_k ∇²g_k + (Σ_k w_k ∇g_k ∇g_kᵀ − ∇g_s ∇g_sᵀ) / ε."""
        g, _, _, _ = self.evaluate(q)  # (the vertices and the shallow rows at q)
        rows = np.asarray(rows)
        H = np.zeros((len(rows), self.width, self.width))
        mask = (self.vertex[rows] >= 0) & (self.selected[rows] >= 0)
        if not mask.any():
            return H
        held = rows[mask]
        xs, xm = self.positions(q)
        gk, Gk, Hk, _, floor = self._planes(xs[held], xm, self.vertex[held], hessian=True)
        _, w = self._reading(gk, Gk, Hk, floor)
        n, K = w.shape
        d, f = self.dim, self._facet_dofs.shape[1]
        big = np.zeros((n, K, self.width))  # each plane's gradient in the row's columns
        big[:, :, :d] = Gk[:, :, :d]
        for k in range(K):
            big[:, k, d + f * k : d + f * (k + 1)] = Gk[:, k, d:]
        mean = np.einsum("nk,nki->ni", w, big)
        Hs = np.einsum("nk,nki,nkj->nij", w, big, big) - mean[:, :, None] * mean[:, None, :]
        Hs /= self.smoothing
        for k in range(K):
            cols = np.r_[0:d, d + f * k : d + f * (k + 1)]
            Hs[:, cols[:, None], cols] += w[:, k, None, None] * Hk[:, k]
        H[mask] = Hs
        return H


def safeguard_rows(interface, kind):
    """The pointwise rows of a mortar ``interface``: those of its slave's nodes against the
    master's surface (row j the twin of the interface's row j, the same node), and those of
    the master's nodes against the slave's (module docstring); ``kind`` the rows' class
    (:class:`DeepNodeRows3D` in 3D, its 2D form for P1 segments, a P2 interface's own)."""
    body, master, restitution = interface.body, interface.master, interface.restitution
    rows = kind(body, master, restitution)
    if not np.array_equal(rows.nodes, interface.nodes):
        raise ValueError("the mortar rows' nodes must be the slave body's boundary nodes")
    rows.twin = interface
    return rows, kind(master, body, restitution)


def twin_rows(pairs) -> np.ndarray | None:
    """For each contact of ``pairs`` (numbered in their order), its twin: the contact that
    holds the same node by the other constraint (a slave node's weighted gap and its own
    gap, module docstring), −1 for none; None when no pair has twins (decided once per
    run)."""
    start = np.cumsum([0] + [pair.size for pair in pairs])
    first = {id(pair): s for pair, s in zip(pairs, start[:-1], strict=True)}
    twins = np.full(start[-1], -1)
    found = False
    for pair, s in zip(pairs, start[:-1], strict=True):
        if isinstance(pair, DeepNodeRows) and pair.twin is not None:
            rows, t = np.arange(pair.size), first[id(pair.twin)]
            twins[s + rows], twins[t + rows] = t + rows, s + rows
            found = True
    return twins if found else None


def pointwise_pairs(pairs) -> np.ndarray:
    """For each of ``pairs``, whether it is a safeguard's pointwise rows (:class:`DeepNodeRows`,
    the slave's or the master's): their force falls to zero where the node is back within its
    allowance, held by the interface's weighted rows, not where the solids part."""
    return np.array([isinstance(pair, DeepNodeRows) for pair in pairs], dtype=bool)


def twins_among(twins: np.ndarray | None, rows: np.ndarray, extra: int = 0) -> np.ndarray | None:
    """Each of the contacts ``rows``' twin (``twins``: :func:`twin_rows`) as an index into
    ``rows`` (−1: none, or not among them), then ``extra`` rows without (joints); None in a
    model without twins."""
    if twins is None:
        return None
    where = np.full(len(twins), -1)
    where[rows] = np.arange(len(rows))
    twin = twins[rows]
    local = np.where(twin >= 0, where[np.maximum(twin, 0)], -1)
    return np.concatenate([local, np.full(extra, -1)])


def real_gaps(contacts, q: np.ndarray, rows: np.ndarray):
    """(g, G) of the contacts ``rows`` of a model's ``contacts`` (a ContactSet) at q: the real
    gaps g_s (m) of the pointwise rows (:meth:`DeepNodeRows.real`) with their dense gradient
    on the free dofs (len(rows) × n_free); NaN and zeros for the other rows."""
    g = np.full(len(rows), np.nan)
    G = np.zeros((len(rows), contacts.n_free))
    owner = contacts.owner[rows]
    for p in np.unique(owner):
        pair = contacts.pairs[p]
        if not isinstance(pair, DeepNodeRows):
            continue
        at = np.flatnonzero(owner == p)
        local = contacts.local[rows[at]]
        gs, dofs, Gv = pair.real(q)
        g[at] = gs[local]
        cols = contacts.free_index[np.broadcast_to(dofs, Gv.shape)[local]]
        fixed = cols < 0  # (a fixed dof: no column)
        values = np.where(fixed, 0.0, Gv[local])
        np.add.at(
            G, (np.repeat(at, cols.shape[1]), np.where(fixed, 0, cols).ravel()), values.ravel()
        )
    return g, G


def pointwise_row(contacts, j: int) -> bool:
    """Whether contact ``j`` of ``contacts`` (a ContactSet) is a pointwise row."""
    return isinstance(contacts.pairs[contacts.owner[j]], DeepNodeRows)


def real_starts(contacts, q, rows, g0, G0):
    """(g0, G0) with the pointwise rows among ``rows`` whose gap at the step's start ``q`` is
    a placeholder (no gradient: the node above half its allowance) read from their node's
    real gap (:func:`real_gaps`), where it is finite, for the instants of
    :mod:`fecontact.time.localize`: a node that sinks through its allowance within a step
    is then stopped at its instant. Its row surfaced only once the node was deeper than
    δ/2, the instant of another row was taken, and the correction pushed the node out
    against the body's stress at the step's end (a coarse disk's vertex between two block
    nodes at 3 m/s: 1.9e-4 m beyond its allowance, +0.16 J of strain, 0.45 % of the scale,
    docs/validation/stress_2d.md)."""
    flat = np.flatnonzero(~G0.any(axis=1))
    g, G = real_gaps(contacts, q, rows[flat])
    known = np.isfinite(g)
    if not known.any():
        return g0, G0
    g0, at = g0.copy(), flat[known]
    g0[rows[at]], G0[at] = g[known], G[known]
    return g0, G0
