r"""Dual mortar contact of a :class:`~fecontact.bodies.beam3d.Beam3D`'s tube against a 3D
:class:`~fecontact.Solid` with the beam as the slave: the form for solids whose boundary
triangles are much larger than the tube's radius.

Rows: one per beam node i, the weighted gap of the centreline along its segments,

    g_i = Σ_s ∫_s Φ_i(ξ) φ(c(ξ)) ℓ_s dξ / L_i,   φ(c) = n_f·(c − x_f) − r,

with c(ξ) = (1 − ξ) a_s + ξ b_s the centreline point of segment s, ℓ_s its reference length,
Φ the dual functions of the linear segment (2 − 3ξ at the end a, 3ξ − 1 at the end b:
∫ Φ_a N_b dξ = 0, ∫ Φ_a N_a dξ = 1/2), L_i = Σ_s ℓ_s / 2 the reference length node i
carries, and φ the gap of c from the plane of its closest boundary triangle f of the solid
(outward normal n_f, the node-to-surface gap of :mod:`fecontact.contact.body_pairs`) less the
radius. Along a straight segment over a flat face φ is linear, so each row is the tube's own
gap at its node to round-off, wherever the tube lies on the face's triangles: no stand-off
and no dependence on where the tube crosses the mesh. The slave rows over the solid's
boundary (:mod:`fecontact.contact.mortar_beam3d`) integrate the tube's distance over the
face instead; on triangles much wider than the tube that distance is a cone whose dual
weights read millimetres below the nodes' own distances (the dual functions' negative
lobes), and the rows' rest height moves with the tube's place on the mesh.

The integral: a composite Gauss rule, :data:`PIECES` equal pieces of each segment with two
points each. Exact where φ is linear along a piece; where the closest triangle changes along
a segment of a deformed face, φ kinks, and the rule errs by the kink times the piece's
length squared.

Derivatives: at a point with facet f, ∂φ/∂(c, x_f) and ∂²φ are those of the plane gap
(:func:`~fecontact.contact.body_pairs.facet_plane_gap`), chained through c. A row's columns
are every beam node's translation and, per rule point of its segments, its triangle's three
nodes. Each point's triangle is chosen at the step's start and held over the step: chosen at
every iterate, a point over the edge two triangles share took either, as near, with their
planes tilted apart by the dent under the tube, and a rod laid flat along the diagonals of a
block's cells was pushed sideways one way and the other at alternate iterates of its position
correction, which never settled (explanation/contact_search.md in the docs).

Friction: one slip row per beam node, the tube's material point facing the solid at the
node, c_i − r n + (its section's turn), against the solid's material point under it (the
node's closest triangle, at its projection), tangent to that triangle's plane; scaled by
the row's load along the normal, n·N_i with N_i = Σ_beam ∂g_i/∂x_b (1 on a flat face), so that
Coulomb's bound μλ_i acts on the force the row puts across the face. A rod rolling on a face
slips at no row.

What the rows do not hold: the solid's nodes inside the tube (a face wrapping a tube thinner
than its triangles, or a solid's edge or corner under the tube between the rule's points);
the pair's watch measures every boundary node's distance to the centreline at every step.
Across a solid's convex edge φ bends (the larger of the two faces' plane gaps), and dual rows
would read below the tube's exact gap there (the dual functions' negative lobes again): a
segment over two faces of the solid at a step's start gives its rows its nodes' own gaps over
that step (:mod:`fecontact.contact.tube_line_rule`); the edge itself, between the nodes, is
held by the pair's companion rows (each segment against the solid's closest convex edge,
:mod:`fecontact.contact.beam3d_edges`, frictionless). Over a dent (a face node
pushed in) φ is the least of the dent's planes, kinked where the closest triangle changes,
and Newton's iteration can switch between them (step halvings, counted).
"""

from __future__ import annotations

import numpy as np

from ..errors import check_positive, check_range
from .base import PairDefaults
from .beam3d_edges import SolidEdges, TubeEdgeContact
from .body_pairs import facet_plane_gap
from .closest_facet import closest_among
from .facet_search import FacetSearch
from .inside import Surface
from .polyline_distance import closest_on_polyline
from .tube_line_friction import line_slips, line_tangents
from .tube_line_rule import StepRule
from .tube_plane import TangentPlaneRows, face_size

__all__ = [
    "LINE_RATIO",
    "PIECES",
    "SAMPLES",
    "TubeLineMortar",
    "TubeNodeDepths",
    "centreline_depths",
    "face_size",
    "tube_mortar",
]

PIECES = 4
"""Equal pieces of each segment in the rows' rule, two Gauss points each."""

SAMPLES = 8
"""The watch measures the tube's depth in the solid at the beam's nodes and at ``SAMPLES`` − 1
points between each two (the rows hold weighted integrals: between the nodes, where a segment
crosses a fold of a dented face, the centreline can dip below it)."""

_SAMPLE = np.linspace(0.0, 1.0, SAMPLES + 1)[:, None]

LINE_RATIO = 4.0
"""A solid whose boundary triangles are at least this many tube radii wide (:func:`face_size`)
meets a tube through the beam's rows (this module); finer solids through the solid's rows
(:mod:`fecontact.contact.mortar_beam3d`), which hold its nodes out of the tube where its face
wraps it."""


class TubeLineMortar(PairDefaults):
    """Dual mortar rows of a :class:`~fecontact.bodies.beam3d.Beam3D`'s tube of radius
    ``clearance`` (m, > 0) against the boundary of a 3D :class:`~fecontact.Solid` ``body``,
    one per beam node (module docstring); ``restitution`` Newton's e_N in [0, 1]; ``margin``
    (m) the search distance (default: the integrator's detection distance)."""

    linear = False
    lazy_hessians = True
    frictional = True
    looks_ahead = True  # (each step's rows: dual, or the nodes' own gaps over an edge)

    def __init__(self, body, beam, restitution=0.0, clearance=0.0, margin=None):
        self.body, self.beam, self.bodies = body, beam, (body, beam)
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self.clearance = check_positive("clearance (the tube's radius)", clearance)
        self.own_margin = margin is not None
        self.margin = check_positive("margin", 0.05 * body.characteristic_length
                                     if margin is None else margin)  # fmt: skip
        self.facets = body.contact_facets()
        self.surface = Surface(self.facets)  # (the start check's exact distances)
        self.search = FacetSearch(self.facets)  # of the rule's points
        self.node_search = FacetSearch(self.facets)  # of the beam's nodes (friction)
        # closest distances within this (m) are ties, decided by the plane gap
        self.tie = 1e-12 * max(body.characteristic_length, beam.characteristic_length)
        self.segments = beam.segments()
        S, n_b = len(self.segments), beam.n_nodes
        ends = beam.X[self.segments]
        self.ell = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1)  # ℓ_s (m)
        self.length = np.bincount(self.segments.ravel(), np.repeat(self.ell / 2, 2), n_b)
        self.rule = StepRule(body, self.facets, self.segments, self.ell, self.length, PIECES)
        self.xi, row = self.rule.xi, self.segments  # (S, 2): the row of each segment's end
        # the slot of each segment's end among its row's segments (its facet columns)
        order = np.argsort(row.ravel(), kind="stable")
        count = np.bincount(row.ravel(), minlength=n_b)
        slot = np.empty(2 * S, int)
        slot[order] = np.arange(2 * S) - np.repeat(np.cumsum(count) - count, count)
        self.slot = slot.reshape(S, 2)
        self.slots = int(count.max())
        P = len(self.xi)
        self.beam_cols = 3 * n_b
        self.width = 3 * n_b + 9 * P * self.slots
        self._beam_dofs = beam.node_translation_dofs(np.arange(n_b)).ravel()
        self.solid_dofs = body.node_translation_dofs(np.arange(body.n_nodes))
        # each point's facet columns in the row of each of its segment's ends (S, P, 2, 9)
        self._facet_cols = (self.beam_cols + 9 * (P * self.slot[:, None, :] +
                            np.arange(P)[None, :, None]))[..., None] + np.arange(9)  # fmt: skip
        self.offsets = (0, 0)
        self.cached = self.held = None  # (held: each rule point's triangle over the step)
        self.companions = _edge_rows(self)

    @property
    def size(self) -> int:
        return self.beam.n_nodes

    def bind(self, model) -> None:
        for pair in (super(), *self.companions):
            pair.bind(model)

    def reset(self) -> None:
        self.cached = self.held = None
        self.search.reset()
        self.node_search.reset()
        self.rule.reset()

    def look_ahead(self, q: np.ndarray, v: np.ndarray, h: float) -> None:
        """Before a step (or a placement's first evaluation): its rule (:class:`StepRule`)
        and each point's triangle, held over the step (module docstring)."""
        self.rule.choose(_triangles(self, q, np.broadcast_to(self.xi, self.rule.t.shape)))
        self.held, self.cached = _triangles(self, q, self.rule.t, self.search), None

    def detect_within(self, distance: float) -> None:
        """Rows within ``distance`` (m, the integrator's detection distance) are evaluated."""
        if not self.own_margin and distance > 0.0 and distance != self.margin:
            self.margin = distance
            self.reset()

    # -- geometry ---------------------------------------------------------------------------
    def frame(self, q: np.ndarray):
        """The solid's node positions (m) and the beam's node positions (n_b, 3)."""
        (oa, ob), body, beam = self.offsets, self.body, self.beam
        return body.positions(q[oa : oa + body.ndof]), beam.positions(q[ob : ob + beam.ndof])

    def points(self, q: np.ndarray):
        """The solid's node positions, the rule's centreline points (S, P, 3) and the closest
        boundary triangle of each (S, P; −1 beyond the margin plus the tube's radius and the
        longest segment: a row with a point within the margin has all of them)."""
        if not self.rule.decided:
            self.look_ahead(q, q, 0.0)
        x, c = _centreline(self, q, self.rule.t)
        return x, c, self.held

    def closest(self, search, points: np.ndarray, x: np.ndarray) -> np.ndarray:
        """The closest boundary triangle (P,) of each of ``points`` (−1: none within the
        search's reach), ties within round-off to the largest plane gap's magnitude (the
        node-to-surface choice, continuous outside a convex edge)."""
        reach = self.margin + self.clearance + float(self.ell.max())
        s, f, _ = search.found(points, x, reach)
        s, f, _ = closest_among(points, x, self.facets, s, f, reach, self.tie)
        out = np.full(len(points), -1)
        out[s] = f
        return out

    def _point_terms(self, q: np.ndarray, order: int):
        """At every rule point: φ (S, P), its facet (S, P), the near rows (m,) and, for
        ``order`` ≥ 1, the gradients (S, P, 15) over (a, b, x_f) and with 2 the curvatures."""
        x, c, f = self.points(q)
        S, P = f.shape
        found = f >= 0
        near = np.ones(self.size, bool)
        for e in range(2):  # a row takes part where every point of its segments has a facet
            np.logical_and.at(near, self.segments[:, e], found.all(axis=1))
        ok = found & found.all(axis=1)[:, None]  # (a near row's segments are all found)
        phi = np.full((S, P), np.inf)
        G = np.zeros((S, P, 15))
        H = np.zeros((S, P, 15, 15)) if order == 2 else None
        if ok.any():
            xf = x[self.facets[f[ok]]]
            g, Gp, Hp = facet_plane_gap(c[ok], xf, hessian=order == 2)
            phi[ok] = g - self.clearance
            t = self.rule.t[ok][:, None]
            G[ok] = np.concatenate([(1.0 - t) * Gp[:, :3], t * Gp[:, :3], Gp[:, 3:]], axis=1)
            if H is not None:
                T = np.zeros((len(t), 12, 15))  # (c, x_f) from (a, b, x_f)
                T[:, :3, :3] = (1.0 - t)[:, :, None] * np.eye(3)
                T[:, :3, 3:6] = t[:, :, None] * np.eye(3)
                T[:, 3:, 6:] = np.eye(9)
                H[ok] = np.einsum("pai,pab,pbj->pij", T, Hp, T)
        return f, phi, near, G, H

    def _dofs(self, f: np.ndarray) -> np.ndarray:
        """The rows' global dofs (m, width) with the points' facets f (S, P)."""
        oa, ob = self.offsets
        dofs = np.empty((self.size, self.width), int)
        dofs[:, : self.beam_cols] = ob + self._beam_dofs
        fill = oa + self.solid_dofs[self.facets[0]].ravel()  # columns no point uses (G = 0)
        dofs[:, self.beam_cols :] = np.tile(fill, (self.width - self.beam_cols) // 9)
        facet = oa + self.solid_dofs[self.facets[np.maximum(f, 0)]].reshape(*f.shape, 9)
        for e in range(2):
            rows = np.broadcast_to(
                self.segments[:, e, None, None], self._facet_cols[..., e, :].shape
            )
            dofs[rows, self._facet_cols[..., e, :]] = facet
        return dofs

    # -- rows -------------------------------------------------------------------------------
    def evaluate(self, q: np.ndarray):
        """Rows (m,) in m, dofs (m, width), gradients (m, width), no curvature."""
        if self.cached is not None and np.array_equal(self.cached[0], q):
            g, dofs, G = self.cached[1:]
            return g.copy(), dofs, G, None
        f, phi, near, Gp, _ = self._point_terms(q, 1)
        g = self._rows(phi, near)
        dofs = self._dofs(f)
        G = np.zeros((self.size, self.width))
        S, P = f.shape
        beam = np.broadcast_to(_beam_columns(self.segments)[:, None, :], (S, P, 6))
        for e in range(2):
            w = np.where(near[self.segments[:, e]][:, None], self.rule.weights[..., e], 0.0)
            row = self.segments[:, e, None, None]
            np.add.at(G, (np.broadcast_to(row, beam.shape), beam), w[..., None] * Gp[..., :6])
            G[np.broadcast_to(row, (S, P, 9)), self._facet_cols[..., e, :]] = (
                w[..., None] * Gp[..., 6:]
            )
        for array in (dofs, G):
            array.flags.writeable = False
        self.cached = (q.copy(), g, dofs, G)
        return g.copy(), dofs, G, None

    def _rows(self, phi: np.ndarray, near: np.ndarray) -> np.ndarray:
        """g_i (m,) from the points' φ (S, P), +inf where not ``near``."""
        g = np.zeros(self.size)
        fin = np.where(np.isfinite(phi), phi, 0.0)
        for e in range(2):
            g += np.bincount(self.segments[:, e], (self.rule.weights[..., e] * fin).sum(axis=1),
                             self.size)  # fmt: skip
        return np.where(near, g, np.inf)

    def gaps(self, q: np.ndarray) -> np.ndarray:
        """The rows g_i (m) alone (+inf for rows that take no part)."""
        if self.cached is not None and np.array_equal(self.cached[0], q):
            return self.cached[1].copy()
        _, phi, near, _, _ = self._point_terms(q, 0)
        return self._rows(phi, near)

    def hessians(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """∇²g_i (len(rows), width, width) of the rows ``rows`` at q, in the layout of
        :meth:`evaluate`."""
        rows = np.asarray(rows, dtype=int)
        k = self.width
        out = np.zeros((len(rows), k * k))
        _, phi, near, _, H = self._point_terms(q, 2)
        where = np.full(self.size, -1)
        where[rows] = np.arange(len(rows))
        beam = _beam_columns(self.segments)
        for e in range(2):
            r = where[self.segments[:, e]]
            s = np.flatnonzero((r >= 0) & near[self.segments[:, e]])
            if s.size == 0:
                continue
            cols = np.concatenate(
                [np.broadcast_to(beam[s, None, :], (len(s), len(self.xi), 6)),
                 self._facet_cols[s, :, e, :]], axis=2)  # fmt: skip
            at = (r[s, None, None, None] * k + cols[..., :, None]) * k + cols[..., None, :]
            vals = self.rule.weights[s, :, e, None, None] * H[s]
            out += np.bincount(at.ravel(), vals.ravel(), out.size).reshape(out.shape)
        return out.reshape(len(rows), k, k)

    # -- what the rows do not hold ----------------------------------------------------------
    def admissible_gaps(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """The gaps (m) that admit a state at t = 0 where the rows take part: where a row
        reads below zero, the least exact gap of its rule points (signed distance to the
        solid's boundary less r; across a solid's convex edge the rows read below it, the
        dual functions' negative lobes on a distance that bends there), the shallower of the
        two; and the depth in the tube of the boundary nodes nearest each row's segments."""
        x, c, _ = self.points(q)
        S, P = c.shape[:2]
        reach = self.margin + self.clearance + float(self.ell.max())  # (as the rows')
        d = self.surface.signed_distance(x, c.reshape(-1, 3), pad=reach)[0]
        least = np.full(self.size, np.inf)
        for e in range(2):
            np.minimum.at(least, self.segments[:, e], d.reshape(S, P).min(axis=1))
        exact = np.where(rows < 0.0, np.maximum(rows, least - self.clearance), rows)
        xb = self.frame(q)[1]
        seg, _, dist = closest_on_polyline(x[self.watched], xb[self.segments])
        for e in range(2):
            np.minimum.at(exact, self.segments[seg, e], dist - self.clearance)
        return np.where(np.isfinite(rows), exact, np.inf)

    def node_distances(self, q: np.ndarray) -> np.ndarray:
        """Every boundary node's distance (m) to the centreline less the tube's radius."""
        x, xb = self.frame(q)
        return closest_on_polyline(x[self.watched], xb[self.segments])[2] - self.clearance

    @property
    def watched(self) -> np.ndarray:
        return np.unique(self.facets)

    def watch(self):
        """The deepest boundary node of the solid inside the tube."""
        return TubeNodeDepths(self)

    # -- friction (:mod:`.tube_line_friction`) -----------------------------------------------
    def tangents(self, q: np.ndarray):
        """Slip rows: dofs (m, 15), c_i T_i ∂(x_i − y_i)/∂ (m, 2, 15), unit tangents T_i."""
        return line_tangents(self, q)

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """The exact slips c_i T_i·(x_rel(q) − x_rel(q_n)) (m, 2) over a step."""
        return line_slips(self, q, q_n, T)


def _beam_columns(segments: np.ndarray) -> np.ndarray:
    """The beam columns (S, 6) of each segment's two ends' translations."""
    return (3 * segments[:, :, None] + np.arange(3)).reshape(-1, 6)


def _edge_rows(pair: TubeLineMortar) -> tuple:
    """The pair's companion rows: each segment against the solid's closest convex edge
    (:mod:`fecontact.contact.beam3d_edges`, frictionless), which cuts into the tube between
    two nodes where no row of the pair holds it; none on a solid of one plane face."""
    if len(np.unique(pair.rule.face)) < 2:
        return ()
    edges = SolidEdges(pair.body)
    return (TubeEdgeContact(pair.beam, edges, pair.restitution, pair.clearance),)


def _triangles(pair: TubeLineMortar, q: np.ndarray, t: np.ndarray, search=None) -> np.ndarray:
    """The closest boundary triangle (S, P; −1: none) of the centreline points at ``t``
    (S, P) at q, by ``search`` (default: the rule's)."""
    x, c = _centreline(pair, q, t)
    search = pair.rule.search if search is None else search
    return pair.closest(search, c.reshape(-1, 3), x).reshape(c.shape[:2])


def _centreline(pair: TubeLineMortar, q: np.ndarray, t: np.ndarray):
    """The solid's node positions and the centreline points (S, P, 3) at ``t`` (S, P)."""
    x, xb = pair.frame(q)
    ends = xb[pair.segments]
    return x, (1.0 - t)[..., None] * ends[:, None, 0] + t[..., None] * ends[:, None, 1]


def centreline_depths(pair: TubeLineMortar, q: np.ndarray):
    """How deep (m, > 0 inside) the tube of ``pair`` lies in its solid at :data:`SAMPLES` + 1
    points of each segment (its ends included): r less the centreline point's signed distance
    to the solid's boundary, from the coordinates (no row's reading: between the beam's nodes
    a segment crossing a fold of a dented face dips below it while its rows hold); and the
    closest boundary triangle of each point (−1: farther than r outside the solid's box)."""
    x, xb = pair.frame(q)
    ends = xb[pair.segments]
    points = ((1.0 - _SAMPLE) * ends[:, None, 0] + _SAMPLE * ends[:, None, 1]).reshape(-1, 3)
    d, facet = pair.surface.signed_distance(x, points, pad=pair.clearance)
    return pair.clearance - d, facet


class TubeNodeDepths:
    """What the rows of a :class:`TubeLineMortar` do not hold, from the coordinates: the
    deepest boundary node of its solid inside the tube (by its distance to the centreline,
    over the shortest reference boundary edge at that node) and the deepest point of the
    tube inside the solid (the centreline sampled along each segment,
    :func:`centreline_depths`, over the shortest reference edge of the
    triangle it lies under)."""

    def __init__(self, pair: TubeLineMortar):
        self.pair = pair
        nodes = pair.watched
        t = pair.body.X[pair.facets]
        self.facet_edge = np.linalg.norm(t - np.roll(t, 1, axis=1), axis=2).min(axis=1)
        self.edge = np.full(pair.body.n_nodes, np.inf)
        for k in range(3):
            np.minimum.at(self.edge, pair.facets[:, k], self.facet_edge)
        self.edge = self.edge[nodes]

    def _depths(self, q: np.ndarray):
        """((nodes' depths, over their edges), (the centreline's depths, over theirs)) (m)."""
        d = -self.pair.node_distances(q)
        line, facet = centreline_depths(self.pair, q)
        line = np.where(facet >= 0, line, -np.inf)
        return (d, d / self.edge), (line, line / self.facet_edge[np.maximum(facet, 0)])

    def depth(self, q: np.ndarray) -> tuple[float, float]:
        """(deepest point's depth in m, ≥ 0; the largest depth over its local edge)."""
        (d, dr), (line, lr) = self._depths(q)
        deepest = max(0.0, float(d.max()), float(line.max()))
        return deepest, max(0.0, float(dr.max()), float(lr.max()))

    def entering(self, q: np.ndarray) -> str:
        """What enters the other body deepest over its local edge (for a message)."""
        (_, dr), (_, lr) = self._depths(q)
        return "the beam's tube" if lr.max() > dr.max() else "a node"


def tube_mortar(solid, beam, restitution=0.0, clearance=0.0):
    """The mortar pair of a 3D ``solid`` and a ``beam``'s tube of radius ``clearance`` (m),
    chosen once from the solid's face size (:func:`face_size`) over the radius: at least
    :data:`LINE_RATIO`, the beam's rows (:class:`TubeLineMortar`); finer, the solid's rows
    blended toward the tube's tangent plane
    (:class:`~fecontact.contact.tube_plane.TangentPlaneRows`)."""
    clearance = check_positive("clearance (the tube's radius)", clearance)
    if face_size(solid) >= LINE_RATIO * clearance:
        return TubeLineMortar(solid, beam, restitution, clearance)
    return TangentPlaneRows(solid, beam, restitution, clearance)
