r"""Two ``Beam3D`` tubes, segment against segment (:class:`TubeBeamContact`).

Three groups of contacts: each segment of the first beam against the second's closest
segment (the tubes crossing), then each node of the first and each node of the second
against the other beam's closest segment (point to segment); ``clearance`` is the sum of the
two radii. Two segments within ``LINE`` (sin² of their angle) of parallel touch along a line,
where their closest pair is ill-posed (it jumps between the ends of their overlap): that
segment-to-segment contact is left out (g = +inf, zero rows), and the nodes, which end every
overlap, hold the tubes apart there.

**Valleys.** Where the partner beam kinks at a node k between its segments k − 1 and k, the
distance along it from a segment or a node of the other beam has one minimum on the convex
side (the node itself, the end of both segments) but two on the side it turns toward: the
closest points on both segments lie inside them (η < 1 on k − 1, η > 0 on k), and the tube
may press both. One row against the closer of the two cannot carry that: its partner
changed with round-off between the iterates of a correction and each choice had its own
gradient, so that a rod crossing another over a node, which the impact bends into such a
valley, cycled (the update flipped by 6e-9 m at gaps of 3e-14 m) and halved its steps. So
every row of the three groups has a second: in a valley, the first row takes segment k − 1
and the second segment k, in the order of their indices whichever is closer; elsewhere the
first row takes the closest segment and the second is left out (+inf), as
:mod:`.beam_sides` does for a point against a planar beam. The two rows of a segment or a
node take one impact law in the velocity jump (``points``). At a valley under a node the
rows of the segments and of the nodes there hold nearly one motion: the pair declares
``redundant_rows`` (least-norm multipliers), without which the scale k chose their split
(k ÷ 100 turned the sections by 4.8e-5 rad more in the first step of such a contact).
A second row left out keeps the gradient of the row its valley would make, against the
neighbour segment at the end its closest point is nearer (``hidden_partners``), and is a
candidate of the correction when its first row is (``reach``): a correction that itself
bends the valley (a thin rod struck over the node of a held one at 10 m/s) then holds it;
before, the row read +inf at the predictor, was no candidate, and ended 2.6e-7 m inside.

**Friction.** Each contact slips at its two touching points, P's at −r_P e from its
centreline point and Q's at +r_Q e (e from Q's point to P's), each moved by its section's
turn (:mod:`.section_segments`): a rod lying across another rolls. The pair is given the sum
of the radii (``clearance``) and shares it in proportion to the radii of the sections'
circles of equal area (a circular section's own radius).
"""

from __future__ import annotations

import numpy as np

from ..bodies.beam3d import Beam3D
from ..errors import InputError
from ..rotations import cross
from .beam3d_pairs import TubeContact
from .friction import tangent_basis
from .geometry import closest_on_segments
from .registry import register_pair
from .section_segments import segment_point_moves, segment_turns
from .segment3d import closest_parameters, closest_segments, tube_distance

__all__ = ["LINE", "TubeBeamContact", "hidden_partners", "valley_partners"]

LINE = 1e-6
"""sin² of the angle below which two segments touch along a line (about 1 mrad): their
segment-to-segment contact is left out and the nodes hold them (:class:`TubeBeamContact`)."""


class TubeBeamContact(TubeContact):
    """Two ``Beam3D`` tubes; the ``clearance`` is the sum of their radii (m, > 0). Rows
    ``[0, first)``: the segments of the first beam, then its nodes, then the second's nodes,
    each against its closest partner segment (in a valley the lower of two); rows
    ``[first, 2 first)`` the same features against the valley's other segment, +inf
    elsewhere (module docstring)."""

    frictional = True
    shared_points = True  # rows i and i + first hold one segment or node
    redundant_rows = True  # (the rows of a valley and of the nodes there hold nearly one motion)
    hides_rows = True  # (a second row outside a valley: ``reach``)

    def __init__(self, body: Beam3D, other: Beam3D, restitution=0.0, clearance=0.0):
        if other is body:
            raise InputError("a beam cannot contact itself (self-contact is not supported)")
        if not clearance > 0.0:
            raise InputError("clearance: two Beam3D touch through their tubes; give r1 + r2 > 0")
        super().__init__(body, restitution, clearance)
        self.other = other
        self.bodies = (body, other)
        self.other_segments = other.segments()
        self.other_offset = 0
        self.first = len(self.segments) + body.n_nodes + other.n_nodes
        self.size = 2 * self.first
        # closest distances this near (m) are ties: round-off of the two beams' sizes
        self.tie = 1e-12 * max(body.characteristic_length, other.characteristic_length)
        # where between the centrelines the surfaces touch: the clearance shared in
        # proportion to the radii of the sections' circles of equal area (a circle's own)
        rho = np.sqrt([body.section.area, other.section.area])
        self.radii = clearance * rho / rho.sum()

    def bind(self, model) -> None:
        super().bind(model)
        self.other_offset = model.offset_of(self.other)

    def points(self) -> np.ndarray:
        """The segment or node each row holds: rows i and i + ``first`` share it."""
        return np.tile(np.arange(self.first), 2)

    def _groups(self, q):
        """(P, Q, partner segment, dofs, absent) of the groups of the class docstring, the
        first rows' three groups, then the second rows' three: P the segments (m, 2, 3), Q
        the partners' segments or nodes (m, k, 3), the dofs of P's ends then of Q (a node's
        padded to 12 by its own, whose rows stay zero), and the rows left out."""
        o = self.other_offset
        xa = self.body.positions(q[self.offset : self.offset + self.body.ndof])
        xb = self.other.positions(q[o : o + self.other.ndof])
        A, B = xa[self.segments], xb[self.other_segments]
        a_dofs = self._beam_dofs()
        b_dofs = o + self.other.node_translation_dofs(self.other_segments.ravel()).reshape(-1, 6)

        def crossing(j):  # η and distance of A's segments from B's segments j
            xi, eta = closest_parameters(A, B[j])
            x1 = A[:, 0] + xi[:, None] * (A[:, 1] - A[:, 0])
            x2 = B[j, 0] + eta[:, None] * (B[j, 1] - B[j, 0])
            return eta, np.linalg.norm(x1 - x2, axis=1)

        wb = valley_partners(self.other_segments, closest_segments(A, B, self.tie), crossing)
        wb = (wb[0], hidden_partners(self.other_segments, *wb, crossing), wb[2])
        firsts = [(A, B[wb[0]], wb[0], np.concatenate([a_dofs, b_dofs[wb[0]]], axis=1))]
        seconds = [(A, B[wb[1]], wb[1], np.concatenate([a_dofs, b_dofs[wb[1]]], axis=1))]
        absent = [np.zeros(len(A), bool)]
        lost = [wb[2]]
        for x, segs, seg_dofs, beam, offset, nodes in (
            (xa, B, b_dofs, self.body, self.offset, self.other_segments),
            (xb, A, a_dofs, self.other, o, self.segments),
        ):
            own = offset + beam.node_translation_dofs(np.arange(beam.n_nodes))

            def along(j, x=x, segs=segs):  # ξ and distance of the points from segments j
                return closest_on_segments(x, segs[j, 0], segs[j, 1])

            which = valley_partners(nodes, _closest_to_points(x, segs, self.tie), along)
            which = (which[0], hidden_partners(nodes, *which, along), which[2])
            for rows, k in ((firsts, 0), (seconds, 1)):
                dofs = np.concatenate([seg_dofs[which[k]], own, own], axis=1)
                rows.append((segs[which[k]], x[:, None], which[k], dofs))
            absent.append(np.zeros(len(x), bool))
            lost.append(which[2])
        return [(*g, out) for g, out in zip(firsts + seconds, absent + lost, strict=True)]

    def _distances(self, q, hessian: bool):
        """Per contact: f, e, (ξ, η, left out, group), the partner segment, dofs (m, 12),
        G (m, 12), H (m, 12, 12) or None; group 0 a segment pair (η on the partner segment),
        1 and 2 a node of the first beam, of the second; left out: a segment pair near
        parallel, or a second row outside a valley."""
        out = [[] for _ in range(10)]
        for k, (P, Q, which, dofs, absent) in enumerate(self._groups(q)):
            f, e, params, G, H = tube_distance(P, Q, hessian)
            # (group 0: a segment pair; 1, 2: a node of the first, of the second; its number)
            pair = np.stack([np.full(len(f), k % 3), np.arange(len(f))])
            flat = _near_parallel(P, Q) if k % 3 == 0 else np.zeros(len(f), bool)
            out_ = absent | flat
            if k % 3:  # a node: pad its columns to the segment pair's 12
                G = np.concatenate([G, np.zeros((len(G), 3))], axis=1)
                H = None if H is None else np.pad(H, ((0, 0), (0, 3), (0, 3)))
            for part, value in zip(
                out, (f, e, params, which, dofs, G, H, out_, pair, flat), strict=True
            ):
                part.append(value)
        f, e, which, dofs, G, line, flat = (np.concatenate(out[i]) for i in (0, 1, 3, 4, 5, 7, 9))
        pair = np.concatenate(out[8], axis=1)
        xi = np.concatenate([p[0] for p in out[2]])
        eta = np.concatenate([p[1] for p in out[2]])
        H = None if not hessian else np.concatenate(out[6])
        return f, e, (xi, eta, line, pair, flat), which, dofs, G, H

    def look_ahead(self, q: np.ndarray, v: np.ndarray, h: float) -> None:
        """Keep the normals at the start of the coming step (the sides follow the motion)."""
        _, e, _, which, _, _, _ = self._distances(q, False)
        self._start = (e * self._sides(e, which)[:, None], which)

    def gaps(self, q: np.ndarray) -> np.ndarray:
        f, e, (_, _, line, _, _), which, _, _, _ = self._distances(q, False)
        return np.where(line, np.inf, self._sides(e, which) * f - self.radius)

    def reach(self, q: np.ndarray) -> np.ndarray:
        """The rows' gaps (m,), a second row left out outside a valley taking its first
        row's: the position correction can bend the partner into a valley under the feature
        (a rod struck over a node), and the second row, a candidate, is then held."""
        g = self.gaps(q)
        first, second = g[: self.first], g[self.first :]
        return np.concatenate([first, np.where(np.isinf(second), first, second)])

    def evaluate(self, q: np.ndarray):
        """Gaps (m,), dofs (m, 12), gradients (m, 12) and curvatures (m, 12, 12)."""
        f, e, (_, _, line, _, flat), which, dofs, G, H = self._distances(q, True)
        sigma = self._sides(e, which)
        # (a second row outside a valley keeps its gradient at g = +inf: should a position
        # correction bend a valley under it, the row enters with the effective mass there)
        scale = np.where(flat, 0.0, sigma)
        g = np.where(line, np.inf, sigma * f - self.radius)
        return g, dofs, scale[:, None] * G, scale[:, None, None] * H

    def tangents(self, q: np.ndarray):
        """Slip rows of the two touching points of each contact, T (ẋ_P − ẋ_Q), each point
        on its tube's surface (P's at −r_P e from its centreline, Q's at +r_Q e) and moved by
        its section's turn (:mod:`.section_segments`)."""
        _, e, (xi, eta, line, group, _), which, dofs, _, _ = self._distances(q, False)
        T = tangent_basis(e)
        pair = group[0] == 0
        w = np.zeros((len(e), 4))
        w[:, 0], w[:, 1] = 1.0 - xi, xi
        w[:, 2] = np.where(pair, eta - 1.0, -1.0)
        w[:, 3] = np.where(pair, -eta, 0.0)
        w[line] = 0.0
        GT = [np.concatenate([w[:, j, None, None] * T for j in range(4)], axis=2)]
        cols = [dofs]
        for sign, point in zip((1.0, -1.0), self._touching(e, group, which, xi, eta), strict=True):
            turns, B = self._turns(q, *point)
            cols.append(turns)
            GT.append(np.where(line, 0.0, sign)[:, None, None] * np.einsum("mti,mik->mtk", T, B))
        return np.concatenate(cols, axis=1), np.concatenate(GT, axis=2), T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """T·(Δx_P − Δx_Q) of the two touching points over the step, each turned back with
        its section (the linear form is not exact for a turn)."""
        _, e, (xi, eta, line, group, _), which, _, _, _ = self._distances(q, False)
        P, Q = (self._moves(q, q_n, *p) for p in self._touching(e, group, which, xi, eta))
        return np.where(line[:, None], 0.0, np.einsum("mtd,md->mt", T, P - Q))

    def _touching(self, e, group, which, xi, eta):
        """P's and Q's touching points per contact: (on the second beam, their segments
        (m, 2) as node numbers (a node twice), the parameter on them, the arm (m, 3) from
        the centreline to the surface)."""
        kind, own = group
        own2 = np.stack([own, own], axis=1)
        seg_a = self.segments[np.where(kind == 1, 0, np.where(kind == 0, own, which))]
        seg_b = self.other_segments[np.where(kind == 2, 0, which)]
        P_on_b = kind == 1  # (a node of the first beam: P is the second's segment)
        Q_on_b = kind != 1
        r_a, r_b = self.radii
        P = (P_on_b, np.where(P_on_b[:, None], seg_b, seg_a), xi)
        Q = (Q_on_b, np.where((kind == 0)[:, None], seg_b, own2), np.where(kind == 0, eta, 0.0))
        arm_P = -np.where(P_on_b, r_b, r_a)[:, None] * e
        arm_Q = np.where(Q_on_b, r_b, r_a)[:, None] * e
        return (*P, arm_P), (*Q, arm_Q)

    def _turns(self, q, on_b, nodes, at, arms):
        """Global dofs (m, 6) of the rotations of the points' segment ends and
        ∂ẋ_p/∂(their rates) (m, 3, 6), rows on either beam."""
        dofs, B = np.zeros((len(at), 6), int), np.zeros((len(at), 3, 6))
        for body, o, rows in (
            (self.body, self.offset, ~on_b),
            (self.other, self.other_offset, on_b),
        ):
            if rows.any():
                local, B[rows] = segment_turns(
                    body, q[o : o + body.ndof], nodes[rows], at[rows], arms[rows]
                )
                dofs[rows] = o + local
        return dofs, B

    def _moves(self, q, q_n, on_b, nodes, at, arms):
        """The motion (m, 3) over the step of the touching points, rows on either beam."""
        out = np.zeros((len(at), 3))
        for body, o, rows in (
            (self.body, self.offset, ~on_b),
            (self.other, self.other_offset, on_b),
        ):
            if rows.any():
                s = slice(o, o + body.ndof)
                out[rows] = segment_point_moves(
                    body, q[s], q_n[s], nodes[rows], at[rows], arms[rows]
                )
        return out


def valley_partners(segs: np.ndarray, closest: np.ndarray, near):
    """The partner segments of the first and second rows and the second rows left out
    (module docstring): ``segs`` (n, 2) the partner beam's segments as node numbers,
    ``closest`` (m,) each row's closest of them, ``near(j) -> (η, distance)`` (m,) of each
    row's closest point on its segment j[i] (η ∈ [0, 1] along it). A valley with the lower
    neighbour k − 1 of k = ``closest``: the two share a node, η < 1 on k − 1 and η > 0 on k;
    with the upper neighbour likewise; where both are valleys, the nearer neighbour's.
    Returns (first, second, left out) (m,)."""
    n = len(segs)
    lo, hi = np.maximum(closest - 1, 0), np.minimum(closest + 1, n - 1)
    eta, _ = near(closest)
    eta_lo, d_lo = near(lo)
    eta_hi, d_hi = near(hi)
    valley_lo = (closest > 0) & (segs[lo, 1] == segs[closest, 0]) & (eta_lo < 1.0) & (eta > 0.0)
    valley_hi = (closest < n - 1) & (segs[hi, 0] == segs[closest, 1]) & (eta < 1.0)
    valley_hi &= eta_hi > 0.0
    take_lo = valley_lo & ~(valley_hi & (d_hi < d_lo))
    first = np.where(take_lo, lo, closest)
    second = np.where(take_lo, closest, np.where(valley_hi, hi, closest))
    return first, second, ~(take_lo | valley_hi)


def hidden_partners(segs, first, second, lost, near) -> np.ndarray:
    """``second`` (of :func:`valley_partners`) with each row ``lost`` outside a valley given
    the neighbour of its ``first`` segment that shares the end its closest point is nearer
    (η < ½: the start): the segment its valley would take, whose gradient the row keeps at
    g = +inf (:meth:`TubeBeamContact.evaluate`)."""
    n = len(segs)
    eta, _ = near(first)
    lo, hi = np.maximum(first - 1, 0), np.minimum(first + 1, n - 1)
    lo_ok = (first > 0) & (segs[lo, 1] == segs[first, 0])
    hi_ok = (first < n - 1) & (segs[hi, 0] == segs[first, 1])
    toward_lo = np.where(lo_ok, lo, np.where(hi_ok, hi, first))
    toward_hi = np.where(hi_ok, hi, np.where(lo_ok, lo, first))
    return np.where(lost, np.where(eta < 0.5, toward_lo, toward_hi), second)


def _near_parallel(P: np.ndarray, Q: np.ndarray) -> np.ndarray:
    d1, d2 = P[:, 1] - P[:, 0], Q[:, 1] - Q[:, 0]
    c = cross(d1, d2)
    sin2 = np.einsum("mi,mi->m", c, c)
    return sin2 < LINE * np.einsum("mi,mi->m", d1, d1) * np.einsum("mi,mi->m", d2, d2)


def _closest_to_points(x: np.ndarray, segs: np.ndarray, tie: float) -> np.ndarray:
    """For each point x (n, 3), the index of the closest segment of ``segs`` (m, 2, 3);
    distances within ``tie`` (m) of the least by the first index (a point facing a kink of
    the other beam is as close to both its segments, and round-off chose afresh)."""
    n, m = len(x), len(segs)
    a, b = np.tile(segs[:, 0], (n, 1)), np.tile(segs[:, 1], (n, 1))
    dist = closest_on_segments(np.repeat(x, m, axis=0), a, b)[1].reshape(n, m)
    return np.argmax(dist <= dist.min(axis=1)[:, None] + tie, axis=1)


@register_pair(Beam3D, Beam3D)
def _beam3d_beam3d(beam, other, nodes, restitution, clearance):
    """Two tubes, segment against segment; ``clearance`` the sum of their radii."""
    if nodes is not None:
        raise InputError("nodes: two Beam3D meet through their segments; give no nodes")
    return TubeBeamContact(beam, other, restitution, clearance)
