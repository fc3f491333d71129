r"""What the 2D and 3D dual mortar pairs share: rows, their assembly, the nodes that take part.

A mortar pair integrates, over entries (a slave element against a master element), the
contributions of each slave element's ends k to their weighted gaps g̃_j = ∫ Φ_j g_N dA, as
:class:`~fecontact.contact.dual_numbers.Jet` values with exact gradients and Hessians over the
entry's local coordinates. This module gathers them into the pair's rows g_j = g̃_j / L_j (m),
L_j = Σ_e |e|/n_e the reference measure (length in 2D, area in 3D) node j carries (n_e the
element's nodes; ∫_e Φ_j dA = |e|/n_e for the dual functions of linear elements), pads the rows
to one width, and decides which nodes take part: those whose covered support carries at least
the share s (``taking_part``: ½ in 2D, ¼ in 3D) of the weight of their covered elements,
W_j ≥ s Σ_e |e|/n_e, W_j the covered weight the subclass reports (2D: of the shape functions
N_j; 3D: of the dual functions Φ_j, equal to that of N_j since the dual functions of a partly
covered element are those of its covered part, ∫_C Φ_j dA = ∫_C N_j dA); a linear segment
counts from the node to the farthest point of its covered part (:func:`segment_reach`). The
others report g = +inf and a zero gradient; within a Newton loop the rows that took part are
held (:mod:`.mortar_hold`). The gaps of the last q are kept: the time loop
asks for them again at the same q (the correction, the probes, the summary).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError, check_positive, check_range
from .base import PairDefaults, check_solid_pair
from .friction import tangent_basis
from .mortar_hold import HeldRows
from .mortar_safeguard import DeepNodeRows3D, safeguard_rows
from .mortar_safeguard2d import DeepNodeRows2D

__all__ = [
    "MortarInterface",
    "covered_shares",
    "element_measures",
    "linear_faces",
    "linear_shares",
    "merge_interfaces",
    "node_normals",
    "segment_reach",
    "sharp_nodes",
    "slip_normals",
]

_COVERED = 1e-9  # an element covered by less than this fraction counts as not covered


def element_measures(x: np.ndarray, facets: np.ndarray) -> np.ndarray:
    """Lengths (2D segments) or areas (3D triangles) of the facets, m or m²."""
    if facets.shape[1] == 2:
        return np.linalg.norm(x[facets[:, 1]] - x[facets[:, 0]], axis=1)
    u, w = x[facets[:, 1]] - x[facets[:, 0]], x[facets[:, 2]] - x[facets[:, 0]]
    return 0.5 * np.linalg.norm(np.cross(u, w), axis=1)


def linear_faces(body) -> np.ndarray:
    """The boundary elements of ``body`` a mortar interface integrates over (rows of nodes):
    its flat contact facets."""
    return body.contact_facets()


def linear_shares(x: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """∫_e N_k dA (faces, nodes per face) of each face's nodes at positions x: |e|/n_e."""
    ends = faces.shape[1]
    return np.repeat(element_measures(x, faces) / ends, ends).reshape(-1, ends)


def covered_shares(pair, xs, e, dual, covered) -> np.ndarray:
    """The weight (C, ends) of the ``covered`` elements' ends that a node's covered weight is
    measured against: the shares ∫_e N_k dA at the positions ``xs``; those of a 2D pair's
    linear segments up to the farthest covered point (:func:`segment_reach`, from the
    entries' covered weights ``dual`` (P, 2) on their elements ``e``)."""
    share = pair.shares_of(xs, pair.facets[covered])
    if pair.dim != 2 or pair.facets.shape[1] != 2:
        return share
    weights = [np.bincount(e, dual[:, k], len(pair.facets))[covered] for k in (0, 1)]
    return share * segment_reach(share, *weights)


def segment_reach(share: np.ndarray, w0: np.ndarray, w1: np.ndarray) -> np.ndarray:
    """The part (S, 2) of each end's share of a linear segment (``share`` (S, 2), |e|/2)
    that lies between that end and the farthest point of the segment's covered part, from
    the covered weights ∫ N_0 ds and ∫ N_1 ds (S,): with the covered part [a, b] in ξ,
    ∫_{−1}^{b} N_0 dξ = (1 + b)(3 − b)/4 and ∫_{a}^{1} N_1 dξ = (1 − a)(3 + a)/4. The
    covered part's half length c and centre m follow from its weights: ∫ N_0 = c(1 − m)
    |e|/2, ∫ N_1 = c(1 + m) |e|/2 (a covered part in pieces: the interval of the same
    weights). 1 where the covered part reaches the far end; → 0 as a part that starts at
    the end shrinks to nothing, so a node is not dropped when its other segment begins to
    be covered from its side."""
    with np.errstate(divide="ignore", invalid="ignore"):
        u0, u1 = w0 / share[:, 0], w1 / share[:, 1]
        c, m = 0.5 * (u0 + u1), (u1 - u0) / (u0 + u1)
    a = np.clip(np.nan_to_num(m - c, nan=-1.0), -1.0, 1.0)
    b = np.clip(np.nan_to_num(m + c, nan=1.0), -1.0, 1.0)
    return np.stack([(1.0 + b) * (3.0 - b), (1.0 - a) * (3.0 + a)], axis=1) * 0.25


def facet_normals(x: np.ndarray, facets: np.ndarray) -> np.ndarray:
    """Unit outward normals (n_f, d) of the ``facets`` (their corners first) at node positions x."""
    f = facets
    if x.shape[1] == 2:
        t = x[f[:, 1]] - x[f[:, 0]]
        nu = np.stack([t[:, 1], -t[:, 0]], axis=1)
    else:
        nu = np.cross(x[f[:, 1]] - x[f[:, 0]], x[f[:, 2]] - x[f[:, 0]])
    return nu / np.linalg.norm(nu, axis=1)[:, None]


def node_normals(x: np.ndarray, facets: np.ndarray, rows: np.ndarray, m: int) -> np.ndarray:
    """Unit outward normals (m, d) of m nodes, the mean of the unit normals of the ``facets``
    (at node positions x) around each; ``rows`` (n_f, k) the facets' ends' node numbers."""
    nu = facet_normals(x, facets)
    n = np.zeros((m, x.shape[1]))
    for k in range(facets.shape[1]):
        np.add.at(n, rows[:, k], nu)
    norm = np.linalg.norm(n, axis=1)
    return n / np.where(norm > 0.0, norm, 1.0)[:, None]


SHARP = np.cos(np.radians(30.0))
"""A node is on an edge or a corner (``sharp_nodes``) where a facet's normal turns from the
node's mean normal by 30° or more: two faces meeting at 60° or more, the corner at which the
2D pair splits its normal field (``mortar.MortarContact``)."""


def sharp_nodes(x: np.ndarray, facets: np.ndarray, rows: np.ndarray, m: int) -> np.ndarray:
    """Whether each of m nodes is on an edge or a corner of the boundary (``SHARP``)."""
    nu, n = facet_normals(x, facets), node_normals(x, facets, rows, m)
    sharp = np.zeros(m, bool)
    for k in range(facets.shape[1]):
        turned = np.einsum("fd,fd->f", nu, n[rows[:, k]]) <= SHARP
        sharp[rows[turned, k]] = True
    return sharp


def slip_normals(pair, x, e, ends, weights) -> np.ndarray:
    """The normals (m, d) whose tangent planes carry the slip rows of a mortar ``pair`` at its
    slave's node positions x: the mean of each node's facets' unit normals, but on an edge or
    a corner (``pair.sharp``) the facets' own normals weighted by the node's covered dual
    weight ∫ Φ_j dA on each (−Σ of the master columns of the ``weights`` of the entries e,
    whose ends' rows are ``ends``). There each facet's gap is measured along the facet's
    normal, so the row's normal force on the slave is along that mean; a tangent from the
    mean of all the node's facets (45° at a block's edge) had a normal part, and the
    friction of a sliding block pressed it on (1.47 μ from the first step, 2.4 μ over 5 ms;
    docs/explanation/mortar.md, *Friction at edges and corners*)."""
    n = node_normals(x, pair.facets, pair.element_rows, pair.size)
    sharp, n_master = pair.sharp, pair.master_facets.shape[1]
    if not sharp.any():
        return n
    nf = facet_normals(x, pair.facets[e])
    acc = np.zeros_like(n)
    for end, w in zip(ends, weights, strict=True):
        np.add.at(acc, end, -w[:, -n_master:].sum(axis=1)[:, None] * nf)
    norm = np.linalg.norm(acc, axis=1)
    use = sharp & (norm > 0.0)
    n[use] = acc[use] / norm[use, None]
    return n


class _Layout:
    """Where the entries land in the padded rows (m, k): ``dofs`` (m, k) and, for each end of
    the entries' slave elements, the columns (P, W) of the entries' W local dofs."""

    def __init__(self, ends, dofs: np.ndarray, own: np.ndarray):
        m, d = own.shape
        P, W = dofs.shape
        rows = np.concatenate([np.repeat(r, W) for r in ends])
        cols = np.tile(dofs.ravel(), len(ends))
        N = int(max(dofs.max(initial=0), own.max())) + 1
        uniq, inv = np.unique(rows * N + cols, return_inverse=True)
        ur, ud = np.divmod(uniq, N)
        pos = np.arange(len(uniq)) - np.searchsorted(ur, ur)
        k = max(int(np.bincount(ur, minlength=m).max(initial=0)), d)
        self.dofs = np.repeat(own[:, :1], k, axis=1)
        self.dofs[:, :d] = own
        self.dofs[ur, pos] = ud
        self.cols = pos[inv].reshape(len(ends), P, W)
        self.dofs.flags.writeable = False

    def rows(self, ends, values) -> np.ndarray:
        """Σ of the entries' row vectors (one (P, ..., W) array per end) into (m, ..., k)."""
        out = np.zeros((self.dofs.shape[0], *values[0].shape[1:-1], self.dofs.shape[1]))
        for r, c, v in zip(ends, self.cols, values, strict=True):
            if v.ndim == 2:
                np.add.at(out, (r[:, None], c), v)
            else:  # (P, nt, W): the slip rows
                t = np.arange(v.shape[1])[None, :, None]
                np.add.at(out, (r[:, None, None], t, c[:, None, :]), v)
        return out


class MortarInterface(HeldRows, PairDefaults):
    """The rows of a dual mortar interface between the boundary of a :class:`~fecontact.Solid`
    (the slave ``body``) and the boundary of another (the ``master``); subclasses give the
    entries and their integrals (2D: :class:`~fecontact.contact.mortar.MortarContact`)."""

    linear = False
    faces_of, shares_of = staticmethod(linear_faces), staticmethod(linear_shares)
    """The elements a body's boundary is integrated over and their nodes' ∫_e N_k dA."""
    lazy_hessians = True
    coupled = False  # (Hessians coupling two entries of an element: _integrate's quad[-1])
    frictional = True
    partial = True
    """Whether a node whose elements the master covers in part may take part (2D and 3D: the
    dual functions of the covered part and the moving bounds of the overlaps are
    differentiated, so their gradients are exact)."""
    taking_part = 0.5
    """The least share W_j / Σ_e |e|/n_e of a node's covered weight for its row to take part:
    below it the covered part lies too far out on the node's elements for the weighted gap,
    extrapolated from there, to read the node's own gap."""

    def __init__(self, body, master, restitution: float = 0.0, margin=None):
        check_solid_pair(body, master, "mortar")
        self.body, self.master = body, master
        self.bodies = (body, master)
        self.dim = body.dim
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self._own_margin = margin is not None
        if margin is None:
            margin = 0.05 * max(body.characteristic_length, master.characteristic_length)
        self.margin = check_positive("margin", margin)
        self.facets = self.faces_of(body)
        self.master_facets = self.faces_of(master)
        self.nodes, rows = np.unique(self.facets, return_inverse=True)
        self.element_rows = rows.reshape(self.facets.shape)  # the rows of each element's ends
        share = self.shares_of(body.X, self.facets).ravel()
        self.length = np.bincount(self.element_rows.ravel(), share, len(self.nodes))
        self.sharp = sharp_nodes(body.X, self.facets, self.element_rows, len(self.nodes))
        """Reference measure L_j (m in 2D, m² in 3D) each slave node carries: its rows are
        g̃_j / L_j."""
        self.area = self.length * (body.thickness if self.dim == 2 else 1.0)
        self._dofs_s = body.node_translation_dofs(np.arange(body.n_nodes))
        self._dofs_m = master.node_translation_dofs(np.arange(master.n_nodes))
        self.offsets = (0, 0)
        self._last = self._last_gaps = self._search = self._layout_of = None
        kind = DeepNodeRows2D if self.dim == 2 else DeepNodeRows3D
        self.pointwise, self.master_rows = safeguard_rows(self, kind)
        """The rows of the slave's and (2D) of the master's nodes deep inside the other solid,
        contacts of the model after its declared pairs (:mod:`.mortar_safeguard`; None:
        none)."""

    @property
    def size(self) -> int:
        return len(self.nodes)

    def bind(self, model) -> None:
        """Place the pair in the global dof vector of ``model``."""
        self.offsets = (model.offset_of(self.body), model.offset_of(self.master))
        self._last = self._last_gaps = self._search = self._layout_of = None
        for rows in (self.pointwise, self.master_rows):
            if rows is not None:  # (not on quadratic faces; in 3D the slave's nodes only)
                rows.bind(model)

    def detect_within(self, distance: float) -> None:
        """Search as far as the integrator's candidates reach (``distance`` m)."""
        if not self._own_margin and distance > 0.0 and distance != self.margin:
            self.margin = distance
            self._last = self._last_gaps = self._search = None
        if self.pointwise is not None:
            self.pointwise.detect_within(distance)

    # the search kept for the next evaluations, None before one (time.aside leaves it be)
    searched = property(lambda self: self._search)

    def _kept_pairs(self, xs: np.ndarray, xm: np.ndarray):
        """The element pairs of the last search while no node has moved an eighth of the
        margin since (None: search again)."""
        if self._search is None:
            return None
        return self._search[2] if self._moved(xs, xm) <= 0.125 * self.margin else None

    def _moved(self, xs: np.ndarray, xm: np.ndarray) -> float:
        """The largest coordinate change (m) of a node of either body since the last search."""
        xs0, xm0 = self._search[:2]
        return max(np.max(np.abs(xs - xs0)), np.max(np.abs(xm - xm0)))

    def _keep_search(self, xs, xm, e, f, apart: np.ndarray):
        """Keep the pairs (e, f) found at xs, xm, with ``apart`` (P,) a lower bound (m) of the
        distance of each pair's elements (centres' distance less both elements' reach)."""
        self._search = (xs.copy(), xm.copy(), (e, f), float(np.min(apart, initial=np.inf)))
        return e, f

    def _near(self, xs: np.ndarray, xm: np.ndarray, e: np.ndarray, f: np.ndarray):
        """The candidate pairs (e, f), or none when every pair's elements are farther apart
        than the margin. A gap is measured from a slave point to a master point on the
        master element, so then every point's |g_N| exceeds the margin, and no row could be
        a candidate (g ≤ margin) but by extrapolating a gap from elsewhere: every row reports
        +inf, as when the search finds no pair, without the integrals (the steps of a free
        flight). The pairs' distances are bounded below at the search, less twice the
        largest displacement since (√d times its largest coordinate change)."""
        bound = self._search[3] - 2.0 * np.sqrt(self.dim) * self._moved(xs, xm)
        return (e[:0], f[:0]) if bound > self.margin else (e, f)

    def positions(self, q: np.ndarray):
        """Every node's position (m) of the slave and of the master at q."""
        (oa, ob), (a, b) = self.offsets, self.bodies
        return a.positions(q[oa : oa + a.ndof]), b.positions(q[ob : ob + b.ndof])

    def _global_dofs(self, slave_nodes: np.ndarray, master_nodes: np.ndarray) -> np.ndarray:
        """Global dofs (P, W) of the entries' local slave and master nodes."""
        oa, ob = self.offsets
        P, d = len(slave_nodes), self.dim
        return np.concatenate(
            [(oa + self._dofs_s[slave_nodes]).reshape(P, d * slave_nodes.shape[1]),
             (ob + self._dofs_m[master_nodes]).reshape(P, d * master_nodes.shape[1])], axis=1
        )  # fmt: skip

    def _valid(self, e, coverage, dual, xs) -> np.ndarray:
        """The rows (m,) that take part (module docstring); ``dual`` (P, ends) the covered
        dual weight of each entry's ends."""
        ends = self.facets.shape[1]
        W = np.zeros(self.size)
        for k in range(ends):
            W += np.bincount(self.element_rows[e, k], dual[:, k], self.size)
        fraction = np.bincount(e, coverage, len(self.facets))
        covered = fraction > _COVERED
        share = covered_shares(self, xs, e, dual, covered).ravel()
        support = np.bincount(self.element_rows[covered].ravel(), share, self.size)
        valid = (W > 0.0) & (W >= self.taking_part * support)
        if not self.partial:
            part = covered & (fraction < 1.0 - 1e-9)
            valid[self.element_rows[part].ravel()] = False
        return self.held_valid(valid, W)

    def _key(self, q):
        """The two bodies' dofs of q as bytes (the same bytes: the same q to the bit)."""
        (oa, ob), (a, b) = self.offsets, self.bodies
        return q[oa : oa + a.ndof].tobytes(), q[ob : ob + b.ndof].tobytes()

    def _same(self, q, key) -> bool:
        return self._key(q) == key

    def _gap_values(self, e, jets, coverage, dual, xs):
        if len(e) == 0:  # no entry: no row takes part
            return np.full(self.size, np.inf)
        g = np.zeros(self.size)
        for k, jet in enumerate(jets):
            g += np.bincount(self.element_rows[e, k], jet.v, self.size)
        return np.where(self._valid(e, coverage, dual, xs), g / self.length, np.inf)

    def gaps(self, q: np.ndarray) -> np.ndarray:
        """The weighted gaps g_j (m) alone (+inf for the rows that take no part); the last
        evaluation's when q has not changed since."""
        for cached in (self._last, self._last_gaps):
            if cached is not None and self._same(q, cached[0]):
                return cached[1]["g"].copy()
        g = self._gap_values(*self._values(q))
        self._last_gaps = (self._key(q), {"g": g})
        return g.copy()

    def _values(self, q: np.ndarray):
        """The entries e, the value Jets of their ends' weighted gaps, their coverage and
        covered weights, and the slave nodes' positions, at q."""
        e, z, _, xs = self._local(q)
        jets, coverage, dual, _ = self._integrate(e, z, None)
        return e, jets, coverage, dual, xs

    def evaluate(self, q: np.ndarray):
        """Weighted gaps (m,) in m, dofs (m, k), gradients (m, k) and no Hessians (None:
        :meth:`hessians` gives them); rows that take no part have g = +inf and G = 0."""
        last = self._last
        if last is not None and self._same(q, last[0]):
            r = last[1]
            return r["g"].copy(), r["layout"].dofs, r["G"], None
        e, z, dofs, xs = self._local(q)
        jets, coverage, dual, quad = self._integrate(e, z, False)
        g = self._gap_values(e, jets, coverage, dual, xs)
        ends = [self.element_rows[e, k] for k in range(len(jets))]
        valid = np.isfinite(g)
        # the Hessians of the entries that count only (the search also finds some that miss)
        counts = (coverage > 0.0) & np.any([valid[r] for r in ends], axis=0)
        layout = self._layout(ends, dofs)
        scale = np.where(valid, 1.0 / self.length, 0.0)
        G = layout.rows(ends, [j.g * scale[r, None] for r, j in zip(ends, jets, strict=True)])
        G.flags.writeable = False
        self._last = (self._key(q), dict(g=g, G=G, e=e, z=z, layout=layout, scale=scale, quad=quad,
                                counts=counts))  # fmt: skip
        return g.copy(), layout.dofs, G, None

    def _layout(self, ends, dofs: np.ndarray) -> _Layout:
        """The layout of these entries: the last one while the entries are the same (the
        iterates of a Newton solve mostly keep them)."""
        key = np.concatenate([np.stack(ends, axis=1), dofs], axis=1)
        if self._layout_of is not None and np.array_equal(self._layout_of[0], key):
            return self._layout_of[1]
        layout = _Layout(ends, dofs, self.offsets[0] + self._dofs_s[self.nodes])
        self._layout_of = (key, layout)
        return layout

    def hessians(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """∇²g_j (len(rows), k, k) of the contacts ``rows`` at q, in the layout of
        :meth:`evaluate` at q."""
        self.evaluate(q)
        r = self._last[1]
        e, layout, scale = r["e"], r["layout"], r["scale"]
        rows = np.asarray(rows)
        k = layout.dofs.shape[1]
        H = np.zeros((len(rows), k, k))
        where = np.full(self.size, -1)
        where[rows] = np.arange(len(rows))
        ends = [self.element_rows[e, j] for j in range(self.facets.shape[1])]
        use = np.flatnonzero(r["counts"] & np.any([where[x] >= 0 for x in ends], axis=0))
        if use.size == 0:
            return H
        jets, _, _, quad = self._integrate(e[use], r["z"][use], True)
        for end, cols, jet in zip(ends, layout.cols, jets, strict=True):
            rr = end[use]
            sel = where[rr] >= 0
            c = cols[use][sel]
            values = jet.h[sel] * scale[rr[sel], None, None]
            np.add.at(H, (where[rr[sel]][:, None, None], c[:, :, None], c[:, None, :]), values)
        if self.coupled and quad[-1] is not None:
            _add_coupled(H, quad[-1], (ends, layout.cols, use), (where, scale))
        return H

    def tangents(self, q: np.ndarray):
        """Slip rows (m, nt, k) of the weighted relative motion of each slave node,
        T_j·∫ Φ_j (ẋ − ẏ) dA / L_j with the projections frozen, in the layout of
        :meth:`evaluate`, and the unit tangents T_j (m, nt, d) of the slave nodes' planes."""
        self.evaluate(q)
        r = self._last[1]
        e, scale = r["e"], r["scale"]
        ends = [self.element_rows[e, k] for k in range(self.facets.shape[1])]
        ws = [self._slip_weights(r["quad"], k) * scale[end, None] for k, end in enumerate(ends)]
        T, values = tangent_basis(slip_normals(self, self.positions(q)[0], e, ends, ws)), []
        for w, end in zip(ws, ends, strict=True):  # w (P, local nodes)
            # nodes that only bound the covered part (2D) carry no slip weight
            w = np.pad(w, ((0, 0), (0, r["layout"].cols.shape[2] // self.dim - w.shape[1])))
            v = w[:, None, :, None] * T[end][:, :, None, :]  # (P, nt, nodes, d)
            values.append(v.reshape(len(e), T.shape[1], v.shape[2] * v.shape[3]))
        return r["layout"].dofs, r["layout"].rows(ends, values), T

    def nodal_pressure(self, forces: np.ndarray):
        """The slave nodes (indices in the slave body) and their contact pressure z_j (Pa)
        from the normal forces λ_j (N) of the pair's rows: z_j = λ_j / (L_j t), t the
        thickness of a 2D body (1 in 3D)."""
        forces = np.asarray(forces, dtype=float)
        if forces.shape != (self.size,):
            raise InputError(f"forces must have {self.size} entries, got {forces.shape}")
        return self.nodes, forces / self.area


def _add_coupled(H, coupled, entries, at) -> None:
    """Add the Hessians C (K, n, z, z) coupling the entries a and b of one element (over a's
    coordinates and b's; indices among ``use``) to the rows' Hessians H: ``entries`` the
    rows of the elements' ends, their columns and ``use``, the entries integrated; ``at``:
    the rows' places in H (−1: not asked) and their scales."""
    (where, scale), (a, b, C), (ends, cols, use) = at, coupled, entries
    for k, (end, col) in enumerate(zip(ends, cols, strict=True)):
        rr = end[use][a]
        sel = where[rr] >= 0
        ca, cb = col[use][a][sel], col[use][b][sel]
        values = C[sel, k] * scale[rr[sel], None, None]
        np.add.at(H, (where[rr[sel]][:, None, None], ca[:, :, None], cb[:, None, :]), values)


def merge_interfaces(pairs):
    """The pairs with each mortar interface once: a mortar pair declared both ways, (a, b)
    and (b, a), is one interface (the first declared); their restitution and friction must
    agree. The safeguard rows of the interfaces (their master's nodes, then their slave's)
    follow the declared pairs, then the pairs' ``companions`` (a solid–box pair's corner rows)."""
    seen: dict = {}
    out = []
    for pair in pairs:
        if isinstance(pair, MortarInterface):
            key = frozenset((id(pair.body), id(pair.master)))
            first = seen.get(key)
            if first is not None:
                if (first.restitution, first.friction) != (pair.restitution, pair.friction):
                    raise InputError(
                        "a mortar interface declared both ways needs the same restitution "
                        "and friction in both declarations"
                    )
                continue
            seen[key] = pair
        out.append(pair)
    companions = [c for p in out for c in p.companions]
    # (the master's rows first: the order before the slave's had rows of their own)
    deep = []
    for p in seen.values():
        for rows in (p.master_rows, p.pointwise):
            if rows is not None:
                rows.friction = p.friction  # (a held node's normal force rubs as any contact's)
                deep.append(rows)
    return out + deep + companions
