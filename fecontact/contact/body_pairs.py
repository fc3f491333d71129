r"""Contact between deformable bodies: node-to-surface for solids, node-to-node for bar ends.

Notation: a slave node at x_s (m) of one body against the boundary of another body (the
master), whose surface is cut into flat facets — segments (x_1, x_2) in 2D, triangles
(x_a, x_b, x_c) in 3D — with the outward unit normal n of the master body. Each slave node is
one contact, with the signed gap along the normal of its facet (m; > 0 open, < 0 inside the
master body):

=======  ==================================================================================
2D       g = n·(x_s − x_1),  n = (t_y, −t_x)/|t|,  t = x_2 − x_1  (the boundary runs
         counter-clockwise, the body on the left of t)
3D       g = n·(x_s − x_a),  n = N/|N|,  N = (x_b − x_a) × (x_c − x_a)
=======  ==================================================================================

The gap is the distance to the facet's plane (the line in 2D), extended beyond the facet. Its
gradient G = ∂g/∂(x_s, facet nodes) and Hessian ∇²g are exact
(:func:`fecontact.contact.geometry.facet_plane_gap`).

Choice of the facet: the one closest to x_s (Euclidean distance to the facet itself, its
projection clipped to the facet). Where several facets are equally close — the node lies in the
cone outside a convex vertex or edge of the master, or inside a concave one — the one with the
largest |g| is taken. Outside a convex corner this is the larger of the plane gaps, a lower
bound of the distance that is continuous across the cone; inside a convex body the closest
facet's plane gap is minus the distance to the surface, so g ≤ 0 exactly when the node has
entered the master body (the position correction then moves it back onto the nearest facet).
g is continuous and piecewise smooth; G and ∇²g are those of the selected facet.

Candidates: facets within the detection ``margin`` (m) of a slave node, from the broad phase
of :mod:`fecontact.contact.facet_search` (a k-d tree over the facet centroids and the slave
nodes in the master's box, kept while the nodes move little), so the work follows the contact
zone. Before every step the margin is widened to twice the distance the two bodies can close
in it (:meth:`NodeSurfaceContact.look_ahead`). A slave node already inside the master,
however deep, gets its closest facet from the inside/outside test of
:mod:`fecontact.contact.inside`. Any other slave node with no facet within the margin reports
g = +inf with zero gradient; the integrator only works on contacts with g below its own
detection margin. Near a concave feature of the master (a dent's vertex or valley) a node
gets a row for each facet of the feature too (:mod:`fecontact.contact.concave_rows`): 1 +
``extra`` rows per slave node, a fixed number of contacts.

Penetration (:meth:`NodeSurfaceContact.penetration`, every step): a node whose closest point
on the master lies strictly inside a facet is as deep inside the master as it lies behind
that facet's plane — the face's normal is the angle-weighted pseudo-normal there
(:func:`fecontact.contact.inside.face_depths`) —, and that facet is the one selected when any
lies within the margin; in 2D a node closest to a vertex and outside by the vertex's
pseudo-normal is outside (:func:`fecontact.contact.inside.segment_depths`); only the other
nodes the search watches take the full inside/outside test, and after an evaluation at the
same q only those the evaluation did not test already (it tests every watched node without
a facet within the margin, and keeps its positions and search for the record).

Bar ends (:class:`NodeNodeContact`): node i of body a against node j of body b along a fixed
unit axis n (from a towards b): g = (x_j − x_i)·n, linear in q. With ``friction`` μ the two
nodes slip across the axis, T·(ẋ_i − ẋ_j) with T ⊥ n: two bars' end faces touch at their
centres, the nodes, which their sections' turns do not move, so the linear form is the exact
slip of a step.
"""

from __future__ import annotations

import math

import numpy as np

from ..bodies.beam import Beam2D
from ..bodies.solid import Solid
from ..errors import InputError, check_finite, check_positive, check_range
from .base import PairDefaults, at_beam_ends, check_solid_pair
from .beam_sides import PointBeamContact
from .closest_facet import closest_among
from .concave_rows import ConcaveRows
from .facet_search import FacetSearch
from .friction import point_tangents
from .geometry import closest_facet_distance, facet_plane_gap, triangle_plane_distance
from .registry import pair_factory, register_pair

__all__ = [
    "NodeNodeContact",
    "NodeSurfaceContact",
    "body_pair",
    "closest_facet_distance",
    "facet_plane_gap",
    "triangle_plane_distance",
]


class NodeSurfaceContact(ConcaveRows, PairDefaults):
    """Nodes of a :class:`~fecontact.Solid` (the slave ``body``) against the boundary of
    another solid (the ``master``): node-to-segment in 2D, node-to-facet (triangles) in 3D.

    Parameters
    ----------
    body : the slave solid; ``nodes`` are its contact nodes (default: its boundary nodes).
    master : the solid whose boundary facets (:meth:`Solid.contact_facets`: P2 facets split
        through their mid nodes, quadrilaterals into two triangles) the nodes must not cross.
    restitution : Newton's coefficient e_N in [0, 1] of every contact of the pair.
    margin : detection distance (m) of the spatial search; default: the integrator's
        (``detection_margin`` × the model size), set when a run starts.

    One contact per slave node (``size``); see the module docstring for the gap. Only the
    slave nodes are kept out of the master: the master's nodes may enter the slave body
    unless the symmetric pair ``NodeSurfaceContact(master, body)`` is added too.
    """

    # a node of each body at the other's facet where they meet: the two passes' rows hold
    # one relative motion (ContactSet: minimum-norm multipliers)
    meets_back = True
    linear = False
    lazy_hessians = True
    inside_test = True
    looks_ahead = True

    def __init__(self, body, master, nodes=None, restitution: float = 0.0, margin=None):
        self.check_bodies(body, master)
        self.body, self.master = body, master
        self.bodies = (body, master)
        self.dim = body.dim
        self.nodes = body.contact_nodes(nodes)
        if len(self.nodes) == 0:
            raise InputError("nodes must name at least one node")
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self._own_margin = margin is not None
        if margin is None:
            margin = 0.05 * max(body.characteristic_length, master.characteristic_length)
        self.margin = self.base_margin = check_positive("margin", margin)
        self.facets = master.contact_facets()
        self.search = FacetSearch(self.facets)
        self.surface = self.search.surface
        # distances to the closest facets within this (m) are ties, decided by the gap
        self.tie_tolerance = 1e-12 * max(body.characteristic_length, master.characteristic_length)
        d = self.dim
        # rows per node beyond the closest facet's, at concave features (:mod:`.concave_rows`);
        # in 3D only: in 2D a node thrown deep into a disk kept the correction from settling
        self.extra = 0 if d == 2 else 6
        self._row_node = np.tile(np.arange(len(self.nodes)), 1 + self.extra)
        self.redundant_rows = self.extra > 0  # (six planes through a vertex)
        self._slave_dofs = body.node_translation_dofs(self.nodes)[self._row_node]
        self._facet_dofs = master.node_translation_dofs(self.facets.ravel()).reshape(
            len(self.facets), -1
        )
        self.width = d + self._facet_dofs.shape[1]
        self.offsets = (0, 0)
        self.selected = np.full(self.size, -1)
        """Facet of each row at the last evaluation (−1: none near)."""
        self.closest = self.selected[: len(self.nodes)]  # each node's closest facet
        self._last = None  # (the two bodies' dofs, result, ``_seen``) of the last evaluation
        self._seen = None  # (xs, xm, watched) of the last search by closest_facets

    @staticmethod
    def check_bodies(body, master) -> None:
        """An ``InputError`` unless the slave ``body`` and the ``master`` can be paired (two
        solids here; a pair of another slave kind overrides it)."""
        check_solid_pair(body, master, "node-to-surface")

    @property
    def size(self) -> int:
        return len(self._row_node)

    def reset(self) -> None:
        self._last = None
        self.search.reset()

    def positions(self, q):
        """The slave nodes' positions and every master node's position at q (m)."""
        (oa, ob), (a, b) = self.offsets, self.bodies
        xs = a.positions(q[oa : oa + a.ndof])[self.nodes]
        return xs, b.positions(q[ob : ob + b.ndof])

    def closest_facets(self, xs: np.ndarray, xm: np.ndarray):
        """(slave indices, facet indices, plane gaps in m) of the slave nodes (positions xs)
        with a facet of the master (node positions xm) within the margin, or inside it however
        deep: the closest facet and the node's signed gap from its plane."""
        tie = self.tie_tolerance  # (unwatched nodes: outside)
        s, f, watched = self.search.closest_candidates(xs, xm, self.margin, tie)
        s, f, g = closest_among(xs, xm, self.facets, s, f, self.margin, tie)
        self._seen = (xs, xm, watched)
        lost = watched.copy()
        lost[s] = False
        lost = np.flatnonzero(lost)
        if lost.size == 0:
            return s, f, g
        depth, fl = self.surface.signed_distance(xm, xs[lost], outside=False)
        inside = depth < 0.0
        if not inside.any():
            return s, f, g
        si, fi = lost[inside], fl[inside]
        gi = closest_facet_distance(xs[si], xm[self.facets[fi]])[1]
        return np.r_[s, si], np.r_[f, fi], np.r_[g, gi]

    def penetration(self, q: np.ndarray) -> float:
        """Depth (m, ≥ 0) of the deepest slave node inside the master by the inside/outside
        test, over the nodes the search cannot rule out (:mod:`.facet_search`)."""
        last = self._last
        if last is not None and last[2] is not None and last[0] == self._dofs_key(q):
            # the evaluation at q ran the search at q, and the full test on every watched
            # node without a facet within the margin: one it gave no facet is outside
            (xs, xm, watched), tested = last[2], True
        else:
            xs, xm = self.positions(q)
            watched, tested = self.search.watched(xs, xm, self.margin), False
        watched = np.flatnonzero(watched)  # (the others are outside)
        if watched.size == 0:
            return 0.0
        if not tested:  # the selected facets at q: the closest of all (module docstring)
            self.evaluate(q)
        f = self.closest[watched]
        near = f >= 0
        # on its facet's face, or (2D) outside beyond a vertex: known by proof, no full test
        on = watched[near]
        deepest, unknown = self.surface.settled_depth(xs[on], xm, f[near], self.tie_tolerance)
        rest = on[unknown] if tested else np.concatenate((watched[~near], on[unknown]))
        if rest.size == 0:
            return deepest
        return max(deepest, float(np.max(self.surface.depths(xm, xs[rest]), initial=0.0)))

    def relative_depth(self, q: np.ndarray, g: np.ndarray) -> float:
        """The largest −g of the slave nodes with a negative gap g (the pair's gaps at q) over
        the size (longest edge) of the facet that holds each."""
        rows = np.flatnonzero(g < 0.0)
        if rows.size == 0:
            return 0.0
        self.evaluate(q)  # the facets selected at q (kept from the gaps' evaluation)
        seen = self._last[2]  # (the positions of the evaluation at q, when it searched)
        xf = (self.positions(q) if seen is None else seen)[1][self.facets[self.selected[rows]]]
        if self.dim == 2:  # a segment's longest edge is itself (the same sum of squares)
            e = xf[:, 1] - xf[:, 0]
            return float(np.max(-g[rows] / np.sqrt((e * e).sum(axis=1))))
        size = np.max(np.linalg.norm(xf - np.roll(xf, 1, axis=1), axis=2), axis=1)
        return float(np.max(-g[rows] / size))

    def detect_within(self, distance: float) -> None:
        """Search as far as the integrator's candidates reach (``distance`` m), unless the
        pair was given a margin of its own: a node closing from beyond the search would
        report no facet."""
        if not self._own_margin and distance > 0.0 and distance != self.base_margin:
            self.base_margin = distance
            self._set_margin(distance)

    def look_ahead(self, q: np.ndarray, v: np.ndarray, h: float) -> None:
        """Search at least twice as far as the two bodies can close in a step h (s) from
        velocities v: h √d (max |v_a| + max |v_b|) over the velocity components of every node,
        in powers of two of the base margin so that the cached search is kept."""
        (oa, ob), (a, b) = self.offsets, self.bodies
        speed = np.abs(v[oa : oa + a.ndof]).max() + np.abs(v[ob : ob + b.ndof]).max()
        ratio = 2.0 * h * math.sqrt(self.dim) * speed / self.base_margin
        self._set_margin(self.base_margin * (2.0 ** np.ceil(np.log2(ratio)) if ratio > 1 else 1))

    def _set_margin(self, margin: float) -> None:
        if margin != self.margin:
            self.margin = margin
            self.search.reset()
            self._last = None

    def _dofs_key(self, q) -> tuple[bytes, bytes]:
        """The two bodies' dofs of q as bytes: equal bytes are the same q to the bit (a
        tenth of the cost of comparing the arrays), so the result kept for them holds."""
        (oa, ob), (a, b) = self.offsets, self.bodies
        return q[oa : oa + a.ndof].tobytes(), q[ob : ob + b.ndof].tobytes()

    def evaluate(self, q: np.ndarray):
        """Gaps (m,) in m, global dofs (m, k) — the slave node's d translations, then those of
        the facet's vertices —, gradients (m, k) and no Hessians (None: :meth:`hessians` gives
        those of the rows that need them); rows of nodes with no facet within the margin have
        g = +inf and zero derivatives.

        The integrator often evaluates twice at the same q (gaps, then gradients): the last
        result is kept and returned again (dofs and G read-only, g a fresh copy).
        """
        key = self._dofs_key(q)
        last = self._last
        if last is not None and last[0] == key:
            g, dofs, G, H = last[1]
            return g.copy(), dofs, G, H
        self._seen = None
        result = self._evaluate(q)
        for array in result[1:3]:
            array.flags.writeable = False
        self._last = (key, result, self._seen)
        return result[0].copy(), *result[1:]

    def _evaluate(self, q):
        xs, xm = self.positions(q)
        m, k = self.size, self.width
        oa, ob = self.offsets
        g = np.full(m, np.inf)
        dofs = np.empty((m, k), dtype=int)
        dofs[:, : self.dim] = oa + self._slave_dofs
        dofs[:, self.dim :] = ob + self._facet_dofs[0]
        G = np.zeros((m, k))
        s, f, _ = self.closest_facets(xs, xm)
        self.selected = np.full(m, -1)
        self.selected[s] = f
        self.closest = self.selected[: len(xs)].copy()
        if self.extra:
            s, f = self.node_rows(s, f, xs, xm)
            self.selected[: len(xs)] = -1
            self.selected[s] = f
        if s.size:
            x = xs[self._row_node[s]]
            g[s], G[s], _ = facet_plane_gap(x, xm[self.facets[f]], hessian=False)
            dofs[s, self.dim :] = ob + self._facet_dofs[f]
        return g, dofs, G, None

    frictional = True

    def tangents(self, q: np.ndarray):
        """Slip rows of each node against the facet's material point at its projection:
        the tangents with the gap's weights (1 for the node, −N_i(ξ) for the vertices)."""
        _, dofs, G, _ = self.evaluate(q)
        GT = point_tangents(G, self.dim)
        return dofs, GT, GT[:, :, : self.dim]

    def hessians(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """∇²g (len(rows), k, k) of the contacts ``rows`` at q, with the facets the last
        :meth:`evaluate` at q selected (zero for nodes with no facet near)."""
        self.evaluate(q)  # the selection at q (kept: no work when it was just evaluated)
        H = np.zeros((len(rows), self.width, self.width))
        f = self.selected[rows]
        near = f >= 0
        if near.any():
            seen = self._last[2]  # (the positions of the evaluation at q, when it searched)
            xs, xm = self.positions(q) if seen is None else seen[:2]
            x = xs[self._row_node[np.asarray(rows)[near]]]
            H[near] = facet_plane_gap(x, xm[self.facets[f[near]]])[2]
        return H


class NodeNodeContact(PairDefaults):
    """Node i of body a against node j of body b along a fixed unit ``axis`` n pointing from
    a towards b: g = (x_j − x_i)·n (m), linear in q (G = (−n, n) on the two nodes'
    translations, no curvature). Two bars end to end on one axis, say.

    For two :class:`~fecontact.Beam2D` bars, ``nodes`` = (i, j) must be end nodes (default:
    the two closest ends) and the axis defaults to the outward tangent of bar a at node i in
    the reference configuration.
    """

    linear = True
    obstacle = None
    size = 1
    frictional = True

    def __init__(self, a, b, nodes=None, restitution: float = 0.0, axis=None):
        if a is b:
            raise InputError("a body cannot contact itself")
        self.body, self.bodies = a, (a, b)
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        beams = isinstance(a, Beam2D) and isinstance(b, Beam2D)
        if nodes is None:
            if not beams:
                raise InputError("nodes: give the pair (node of a, node of b)")
            ends_a, ends_b = [0, a.n_nodes - 1], [0, b.n_nodes - 1]
            dist = np.linalg.norm(a.X[ends_a][:, None] - b.X[ends_b][None], axis=2)
            ia, ib = np.unravel_index(int(np.argmin(dist)), dist.shape)
            nodes = (ends_a[ia], ends_b[ib])
        pair = np.atleast_1d(nodes).ravel()
        if pair.size != 2:
            raise InputError(f"nodes must be a pair (node of a, node of b), got {nodes!r}")
        self.nodes = (a.node_index(pair[0]), b.node_index(pair[1]))
        i, j = self.nodes
        self.at_beam_ends = at_beam_ends(a, [i]) and at_beam_ends(b, [j])
        if axis is None:
            if not beams:
                raise InputError("axis: give the contact direction n (from a towards b)")
            if i not in (0, a.n_nodes - 1) or self.nodes[1] not in (0, b.n_nodes - 1):
                raise InputError("nodes: bar-end contact acts between end nodes of the bars")
            axis = a.X[i] - a.X[1 if i == 0 else i - 1]
        n = check_finite("axis", axis).ravel()
        norm = np.linalg.norm(n)
        if n.shape != (a.X.shape[1],) or norm == 0.0:
            raise InputError(f"axis must be a non-zero {a.X.shape[1]}-vector, got {axis!r}")
        self.axis = n / norm
        self._dofs = np.concatenate(
            [
                a.node_translation_dofs([self.nodes[0]])[0],
                b.node_translation_dofs([self.nodes[1]])[0],
            ]
        )
        self._G = np.concatenate([-self.axis, self.axis])[None, :]
        self.offsets = (0, 0)

    def bind(self, model) -> None:
        """Place the pair in the global dof vector of ``model``."""
        self.offsets = (model.offset_of(self.bodies[0]), model.offset_of(self.bodies[1]))

    def evaluate(self, q: np.ndarray):
        """Gap (1,) in m, global dofs (1, 2d), gradient (1, 2d), Hessian None (linear)."""
        d = len(self.axis)
        dofs = self._dofs.copy()
        dofs[:d] += self.offsets[0]
        dofs[d:] += self.offsets[1]
        (a, b), (i, j) = self.bodies, self.nodes
        xa = a.X[i] + q[dofs[:d]]
        xb = b.X[j] + q[dofs[d:]]
        return np.array([(xb - xa) @ self.axis]), dofs[None, :], self._G.copy(), None

    def tangents(self, q: np.ndarray):
        """Slip rows of node i against node j across the axis: T·(ẋ_i − ẋ_j), T ⊥ n (two bars'
        end faces touch at their centres, which their sections' turns do not move)."""
        _, dofs, G, _ = self.evaluate(q)
        GT = point_tangents(G, len(self.axis))
        return dofs, GT, GT[:, :, : len(self.axis)]


def body_pair(body, other, nodes=None, restitution: float = 0.0):
    """The contact pair between two deformable bodies: :class:`NodeSurfaceContact` for two
    solids (``nodes`` of ``body`` against the surface of ``other``), :class:`NodeNodeContact`
    for two beams (``nodes`` = their end nodes facing each other, default the closest ends)."""
    return pair_factory(body, other)(body, other, nodes, restitution, 0.0)


def _no_clearance(clearance) -> None:
    if clearance:
        raise InputError("clearance: not available between two deformable bodies; use 0")


@register_pair(Solid, Solid)
def _solid_solid(body, other, nodes, restitution, clearance):
    _no_clearance(clearance)
    return NodeSurfaceContact(body, other, nodes, restitution)


@register_pair(Beam2D, Beam2D)
def _bar_ends(body, other, nodes, restitution, clearance):
    """Two strips (``clearance`` > 0, the sum of their half thicknesses): the nodes of ``body``
    against the two-sided surface of ``other``; two bars (0): their facing ends."""
    if clearance:
        return PointBeamContact(body, other, nodes, restitution, clearance)
    return NodeNodeContact(body, other, nodes, restitution)
