r"""Two-sided beams: the side of a beam's centreline a point is on, decided from its motion.

A beam's surface is its centreline offset by ± the ``clearance`` c (half the section height,
plus the half thickness of a strip whose nodes are the points). Against element e = (x₁, x₂)
a point x has the line coordinates

    t = (x − x₁)·d / |d|²,   f = d × (x − x₁) / |d|   (d = x₂ − x₁; f > 0 on the left),

and, where its closest point lies inside the element (0 < t < 1), the gap g = s f − c with
the side s = ±1; at an end the gap is the distance to the end node less c (a round cap, the
same from either side), unless the point went through the element in this step.

The side is not frozen when the run starts: it is decided over every step from the point's
motion relative to the element, from (t₀, f₀) at the start of the step (positions that the
constraints held) to (t, f) now. The straight path between them crosses the centreline when
f₀ f < 0 and the crossing t* = t₀ + (t − t₀) f₀/(f₀ − f) lies in [0, 1]: the point went
through the element, and keeps the side s = sign f₀ it came from (its gap is then negative
and the correction puts it back). Otherwise s = sign f: a point that went around the free end
of a cantilever is below it, and its gap is its distance. Before any step (no start known)
s = sign f.

Where two elements meet at a node the surface has a corner on each side. On the side the
beam turns away from (convex), the offset surface is a circle arc of radius c around the
beam node, the end caps of both elements: a point there is closest to the node, and its one
row (the distance to the node less c) turns smoothly across the kink. On the side the beam
turns toward (a valley), the offset lines meet in a sharp corner and the surface is the upper
envelope of the two lines; a point in the valley (projecting inside both elements) is held
by both lines, g₁ ≥ 0 and g₂ ≥ 0, and at the corner its force may lie anywhere between the
two normals, which one row cannot carry. Each node therefore has two rows: row i against its
closest element, and, in a valley, rows i and i + n against the two elements in the order of
their indices (row i + n has g = +inf elsewhere). A row keeps its element while the node
crosses the valley's bisector and the closest element changes: its multiplier, and the
pre-impact rate G_j(q_n) v_n of Newton's law, stay those of one line. (Rows that followed the
closest element swapped lines between iterates and between steps: over a kink of 5e-4 rad
the correction then cycled, and Newton's law at e_N = 0.5 asked impulses of 1e4 N·s.)

The two rows of a node hold one point, and take one impact law in the velocity jump
(``points``): where a smooth contact force presses one of them at the end of the step (it
keeps ġ = 0, an equality), the other, closing in that step, is held with it. Two nearly
parallel lines cannot give one node ġ = 0 along one and Newton's ġ⁺ = −e_N ġ⁻ > 0 along the
other: the jump met the two targets with impulses of ±2.2e4 N·s and the run blew up (a
re-strike of the node, 0.5 m/s, in a localized sub-step, at e_N = 0.5).

With ``friction`` μ a row slips as the point that touches: c_b n from the beam's centreline
(n the row's unit normal toward the node), on the section there, and −c_a n from the node,
on the node's section where the node is a strip's (c_a + c_b = c; a solid's node: c_a = 0).
The beam's point at the row's ξ on the element (a, b) moves at (1 − ξ) ẋ_a + ξ ẋ_b +
ω(ξ) e_z × c_b n, the sections' turns interpolated as the centreline
(:mod:`.section_segments`); the node's at ẋ + θ̇ e_z × (−c_a n). Between two strips the
clearance is split in proportion to the sections' thicknesses √(12 I/A) (:func:`strip_share`:
each rectangle's half thickness when c is their sum). Over a step each section point is
turned back with its section, so that a rigid motion of both bodies slips nothing.
"""

from __future__ import annotations

import numpy as np

from ..bodies.beam import Beam2D
from ..bodies.solid import Solid
from ..errors import InputError, check_positive, check_range
from .base import PairDefaults
from .friction import tangent_basis
from .geometry import point_line_distance
from .registry import register_pair
from .section_segments import segment_point_moves, segment_turns

__all__ = [
    "PointBeamContact",
    "StripNodeDepths",
    "closest_rows",
    "line_coordinates",
    "swept",
    "swept_sides",
]


def line_coordinates(x: np.ndarray, x1: np.ndarray, x2: np.ndarray):
    """Unclamped parameters t and signed distances f (m, left of x₁ → x₂ positive) of points
    x from the lines of the elements (x₁, x₂), broadcasting over leading axes (…, 2)."""
    d, w = x2 - x1, x - x1
    dd = np.sum(d * d, axis=-1)
    t = np.sum(w * d, axis=-1) / dd
    f = (d[..., 0] * w[..., 1] - d[..., 1] * w[..., 0]) / np.sqrt(dd)
    return t, f


def swept_sides(start, t: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Sides s = ±1 (same shape as f) of points against elements, from their line coordinates
    ``start`` = (t₀, f₀) at the start of the step (None: not known) and (t, f) now (see the
    module docstring)."""
    return swept(start, t, f)[0]


def swept(start, t: np.ndarray, f: np.ndarray):
    """Sides s = ±1 and whether the path crossed the element (both shaped as f): see
    :func:`swept_sides`. A point that crossed an element is held by the element's line even
    where its closest point is now an end node: it went through the beam there, not around
    it."""
    now = np.where(f < 0.0, -1.0, 1.0)
    if start is None:
        return now, np.zeros(np.shape(f), dtype=bool)
    t0, f0 = start
    crossing = f0 * f < 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        t_star = t0 + (t - t0) * f0 / (f0 - f)
    crossed = crossing & (t_star >= 0.0) & (t_star <= 1.0)
    came_from = np.where(f0 < 0.0, -1.0, 1.0)
    at_line = f == 0.0  # on the line now: the side it was on
    return np.where(crossed | at_line, came_from, now), crossed


class PointBeamContact(PairDefaults):
    """Nodes of a body (a ``Solid``'s boundary nodes, a ``Beam2D``'s nodes) against the
    two-sided surface of a ``Beam2D``: its centreline offset by ± ``clearance`` c (m). Two
    rows per node: against its closest element, g = s f − c inside the element, the distance
    to the end node − c at an end; in a valley between two elements, one row against each
    line (module docstring for the side s and the valley)."""

    linear = False
    looks_ahead = True
    shared_points = True  # rows i and i + n hold node i
    frictional = True

    def points(self) -> np.ndarray:
        """Node i's number for its rows i and i + n: they take one impact law (module
        docstring)."""
        return np.tile(np.arange(len(self.nodes)), 2)

    def __init__(self, body, beam, nodes=None, restitution: float = 0.0, clearance=0.0):
        if not isinstance(beam, Beam2D):
            raise InputError(f"the second body must be a Beam2D, got {type(beam).__name__}")
        if body is beam:
            raise InputError("a body cannot contact itself (self-contact is not supported)")
        if body.dim != 2:
            raise InputError("a beam's surface takes 2D bodies only")
        self.body, self.beam, self.bodies = body, beam, (body, beam)
        self.nodes = body.contact_nodes(nodes)
        if len(self.nodes) == 0:
            raise InputError("nodes must name at least one node")
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self.clearance = check_positive("clearance", clearance, allow_zero=True)
        self.segments = beam.segments()
        self._point_dofs = body.node_translation_dofs(self.nodes)
        self._segment_dofs = beam.node_translation_dofs(self.segments.ravel()).reshape(-1, 4)
        self.offsets = (0, 0)
        self._start = None  # (t₀, f₀) of every (node, element) at the start of the step
        # the arms of the touching point from the node and from the beam's centreline (m)
        self.node_arm = strip_share(body, beam, self.clearance)
        self.beam_arm = self.clearance - self.node_arm

    @property
    def size(self) -> int:
        return 2 * len(self.nodes)

    def reset(self) -> None:
        self._start = None

    def watch(self):
        """What these rows do not hold: two strips, the second's nodes against the first's
        surface (:class:`StripNodeDepths`); a solid's boundary against a beam holds the beam's
        nodes by rows of their own (:mod:`.beam_on_solid`)."""
        return StripNodeDepths(self) if isinstance(self.body, Beam2D) else None

    def _coordinates(self, q: np.ndarray):
        (oa, ob), (a, b) = self.offsets, self.bodies
        x = a.positions(q[oa : oa + a.ndof])[self.nodes]
        xb = b.positions(q[ob : ob + b.ndof])
        x1, x2 = xb[self.segments[:, 0]], xb[self.segments[:, 1]]
        t, f = line_coordinates(x[:, None, :], x1[None], x2[None])
        return x, x1, x2, t, f

    def look_ahead(self, q: np.ndarray, v: np.ndarray, h: float) -> None:
        """Keep the line coordinates at the start of the coming step, for the sides."""
        self._start = self._coordinates(q)[3:]

    def evaluate(self, q: np.ndarray):
        """Gaps (2n,) in m — rows i and i + n of node i, g = +inf for an unused row —,
        global dofs (2n, 6) — the node's (x, y), then the element's two nodes' —, gradients
        (2n, 6) and Hessians (2n, 6, 6)."""
        x, x1, x2, t, f = self._coordinates(q)
        e, side, line, xe, used = closest_rows(self.segments, self._start, x, x1, x2, t, f)
        x = np.concatenate([x, x])
        m = self.size
        g, G, H = np.full(m, np.inf), np.zeros((m, 6)), np.zeros((m, 6, 6))
        held = line & used
        if held.any():
            fi, Gi, Hi = point_line_distance(x[held], x1[e[held]], x2[e[held]])
            s = side[held]
            g[held], G[held], H[held] = s * fi, s[:, None] * Gi, s[:, None, None] * Hi
        end = ~line & used
        if end.any():
            k = np.where(xe[end] == 0.0, 0, 1)
            node = np.where(k[:, None] == 0, x1[e[end]], x2[e[end]])
            g[end] = _end_caps(x[end] - node, k, np.flatnonzero(end), G, H)
        return g - self.clearance, self.row_dofs(e), G, H

    def _touching(self, q: np.ndarray):
        """Each row's element (2n,), its parameter ξ, the nodes' positions (2n, 2), the
        row's unit normal n toward the node (2n, 2) and whether the row is used (2n,); the
        touching point lies at c_b n from the beam's centreline, −c_a n from a strip's node."""
        x, x1, x2, t, f = self._coordinates(q)
        e, side, line, xi, used = closest_rows(self.segments, self._start, x, x1, x2, t, f)
        x = np.concatenate([x, x])
        d = x2[e] - x1[e]
        across = np.stack([-d[:, 1], d[:, 0]], axis=1) / np.linalg.norm(d, axis=1)[:, None]
        rel = x - x1[e] - xi[:, None] * d
        r = np.linalg.norm(rel, axis=1)
        caps = rel / np.where(r > 0.0, r, 1.0)[:, None]
        n = np.where(line[:, None], side[:, None] * across, caps)
        return e, xi, x, n, used

    def tangents(self, q: np.ndarray):
        """Dofs (2n, k), slip rows (2n, 1, k) and tangents T (2n, 1, 2): the node's touching
        point against the beam's section point at the row's ξ (module docstring); columns 7
        and 8 are the element's end rotations, a strip's node's rotation the ninth (k = 9;
        a solid's node, k = 8). Unused rows slip nothing."""
        e, xi, _, n, used = self._touching(q)
        T = tangent_basis(n) * used[:, None, None]
        ob = self.offsets[1]
        qb = q[ob : ob + self.beam.ndof]
        turns, B = segment_turns(self.beam, qb, self.segments[e], xi, self.beam_arm * n)
        W = np.zeros((len(e), 2, 8))
        W[:, :, :2] = np.eye(2)
        W[:, :, 2:4] = -(1.0 - xi)[:, None, None] * np.eye(2)
        W[:, :, 4:6] = -xi[:, None, None] * np.eye(2)
        W[:, :, 6:] = -B
        dofs = np.concatenate([self.row_dofs(e), ob + turns], axis=1)
        if self.node_arm:  # a strip's node: its section's turn moves its touching point
            oa, nodes = self.offsets[0], np.tile(self.nodes, 2)
            qa = q[oa : oa + self.body.ndof]
            turn, Ba = self.body.section_turns(qa, nodes, -self.node_arm * n)
            W, dofs = np.concatenate([W, Ba], axis=2), np.concatenate([dofs, oa + turn], axis=1)
        return dofs, np.einsum("mti,mik->mtk", T, W), T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """The step's slip (2n, 1): the node's touching point's travel against the beam's
        section point's, each section point turned back with its section (exact for the
        beam's sections turning alike)."""
        e, xi, x, n, _ = self._touching(q)
        (oa, ob), body, beam = self.offsets, self.body, self.beam
        qa, qa_n = q[oa : oa + body.ndof], q_n[oa : oa + body.ndof]
        qb, qb_n = q[ob : ob + beam.ndof], q_n[ob : ob + beam.ndof]
        moves = segment_point_moves(beam, qb, qb_n, self.segments[e], xi, self.beam_arm * n)
        if self.node_arm:
            arms, nodes = -self.node_arm * n, np.tile(self.nodes, 2)
            travel = x + arms - body.section_points_before(qa, qa_n, nodes, arms)
        else:
            x_n = body.positions(qa_n)[self.nodes]
            travel = x - np.concatenate([x_n, x_n])
        return np.einsum("mtd,md->mt", T, travel - moves)

    def row_dofs(self, e: np.ndarray) -> np.ndarray:
        """Global dofs (2n, 6) of the rows on the elements e (2n,): the node's (x, y), then
        the element's two nodes'."""
        oa, ob = self.offsets
        return np.hstack([oa + np.tile(self._point_dofs, (2, 1)), ob + self._segment_dofs[e]])


def strip_share(body, beam, clearance: float) -> float:
    """The part c_a (m) of the ``clearance`` on the side of ``body``'s nodes: 0 for a body
    without sections, for a ``Beam2D`` the clearance split in proportion to the two sections'
    thicknesses √(12 I/A) (a rectangle's own: exact for two rectangular strips whose
    clearance is the sum of their half thicknesses; half each for equal sections)."""
    if not isinstance(body, Beam2D):
        return 0.0
    ta, tb = (np.sqrt(12.0 * b.section.inertia / b.section.area) for b in (body, beam))
    return float(clearance * ta / (ta + tb))


def closest_rows(segments, start, x, x1, x2, t, f):
    """Two rows per point x (n, 2) against the elements (x1, x2) (n_e, 2), t and f (n, n_e)
    its line coordinates, ``start`` those at the step's start (or None): the element (2n,) of
    every row, its side s, whether it is held by the element's line (else by the end cap at
    its parameter ξ), ξ, and whether the row is used (module docstring)."""
    nodes = np.arange(len(x))
    xi = np.clip(t, 0.0, 1.0)
    d = x2 - x1
    dist = np.linalg.norm(x[:, None, :] - x1[None] - xi[..., None] * d[None], axis=2)
    e = np.argmin(dist, axis=1)
    side, crossed = swept(start, t, f)
    s, through = side[nodes, e], crossed[nodes, e]
    inner = ((xi[nodes, e] > 0.0) & (xi[nodes, e] < 1.0)) | through
    other = valley_neighbours(segments, x1, x2, e, s, t, inner & ~through)
    n, two = len(e), other >= 0
    elem = np.concatenate([e, other])
    elem[:n][two] = np.minimum(e, other)[two]
    elem[n:][two] = np.maximum(e, other)[two]
    elem[n:][~two] = 0
    used = np.concatenate([np.ones(n, bool), two])
    rows = np.concatenate([nodes, nodes])
    return elem, np.concatenate([s, s]), np.concatenate([inner, two]), xi[rows, elem], used


def _end_caps(rel, k, rows, G, H):
    """Distances |rel| (m) of points from the end node k (0: first, 1: second) of their
    elements; fills their gradients and Hessians into the ``rows`` of G and H."""
    r = np.linalg.norm(rel, axis=1)
    if np.any(r == 0.0):
        raise InputError("a node lies on a beam's end node: contact normal undefined")
    u = rel / r[:, None]
    K = (np.eye(2) - u[:, :, None] * u[:, None, :]) / r[:, None, None]
    i, ax = rows, np.arange(2)
    c = 2 + 2 * k[:, None] + ax  # the end node's columns
    G[i, :2], G[i[:, None], c] = u, -u
    H[i, :2, :2] = K
    H[i[:, None, None], c[:, :, None], c[:, None, :]] = K
    H[i[:, None, None], ax[None, :, None], c[:, None, :]] = -K
    H[i[:, None, None], c[:, :, None], ax[None, None, :]] = -K
    return r


CONCAVE = 1e-6
"""Two elements form a valley on a side when the far node of one lies this fraction of the
other's length on that side of the other's line (a straight beam bent by round-off stays
straight: no second row)."""


def valley_neighbours(segments, x1, x2, e, s, t, inner):
    """The element next to each node's closest element e (sharing a node with it) that forms
    a valley with it on the node's side s, where the node projects inside both (``inner``: on
    e's line; t (n, n_e) its parameters on every element); −1 where there is none.

    ``segments`` (n_e, 2) the elements' node indices, x1 and x2 (n_e, 2) their ends (m)."""
    n_e, rows = len(segments), np.arange(len(e))
    out = np.full(len(e), -1)
    for step in (-1, 1):
        nb = np.clip(e + step, 0, n_e - 1)
        tn = t[rows, nb]
        # the neighbour shares e's first node (step −1) or its second (step +1)
        shared = (
            segments[nb, 1] == segments[e, 0] if step < 0 else segments[nb, 0] == segments[e, 1]
        )
        near = np.flatnonzero(inner & (out < 0) & (nb != e) & shared & (tn >= 0.0) & (tn <= 1.0))
        if near.size == 0:  # (most evaluations: no node projects inside a neighbour)
            continue
        ei, ni = e[near], nb[near]
        far = x1[ni] if step < 0 else x2[ni]
        height = line_coordinates(far, x1[ei], x2[ei])[1]
        length = np.linalg.norm(x2[ei] - x1[ei], axis=1)
        valley = s[near] * height > CONCAVE * length
        out[near[valley]] = ni[valley]
    return out


class StripNodeDepths:
    """The second strip's nodes against the first's two-sided surface, in a pair of two
    strips: the rows hold the first strip's nodes only, so the second's end can go through
    the first between its nodes (an end-first strike with the striker named second) unless
    the reversed pair is declared too. ``depth(q)``: the deepest of those nodes inside the
    first strip (the clearance less its distance to the first's centreline, m ≥ 0) and that
    depth over the first strip's shortest element; reported and warned, not retaken (no row
    holds it, and a smaller step does not take it out)."""

    def __init__(self, pair: PointBeamContact):
        self.pair = pair
        self.segments = pair.body.segments()
        X = pair.body.X[self.segments]
        self.edge = float(np.linalg.norm(X[:, 1] - X[:, 0], axis=1).min())

    def depth(self, q: np.ndarray) -> tuple[float, float]:
        """(depth in m ≥ 0, depth over the first strip's shortest element) at q."""
        (oa, ob), (a, b) = self.pair.offsets, self.pair.bodies
        xa = a.positions(q[oa : oa + a.ndof])
        x = b.positions(q[ob : ob + b.ndof])
        x1, d = xa[self.segments[:, 0]], xa[self.segments[:, 1]] - xa[self.segments[:, 0]]
        w = x[:, None, :] - x1[None]
        t = np.einsum("nmd,md->nm", w, d) / np.einsum("md,md->m", d, d)
        r = np.linalg.norm(w - np.clip(t, 0.0, 1.0)[..., None] * d[None], axis=2)
        depth = max(self.pair.clearance - float(r.min()), 0.0)
        return depth, depth / self.edge

    def entering(self, q: np.ndarray) -> str:
        """What enters the other strip (for a message)."""
        return "a strip's node that no row holds"


@register_pair(object, Beam2D)
def _points_on_beam(body, beam, nodes, restitution, clearance):
    """A body's ``nodes`` against the beam's two-sided surface (a 2D solid's pair, which holds
    the beam's nodes too, is :mod:`.beam_on_solid`'s)."""
    return PointBeamContact(body, beam, nodes, restitution, clearance)


@register_pair(Beam2D, Solid)
def _beam_on_solid(beam, solid, nodes, restitution, clearance):
    raise InputError("a beam against a solid: give it as Contact(solid, beam, clearance=c)")
