r"""Mortar (segment-to-segment) contact between two deformable solids, 2D.

The form chosen: dual mortar with weighted gaps (Wohlmuth 2000; Popp, Gee & Wall, IJNME 2009).
The slave body's boundary (the first body) carries one multiplier per node, interpolated by
dual shape functions Φ_j, biorthogonal to the nodal shape functions N_j; the constraint of node
j is its weighted gap

    g̃_j = ∫ Φ_j g_N ds ≥ 0  (m²),

integrated over the slave boundary segments, where g_N is the gap along the interpolated,
averaged slave normal to the master boundary (:mod:`fecontact.contact.mortar_segments`). The
rows handed to the Alart–Curnier laws are g_j = g̃_j / L_j (m), L_j the reference length the
node carries (half of each adjacent slave segment): a positive scaling, so 0 ≤ g_j ⊥ ν_j ≥ 0
is the same complementarity, and gaps, tolerances and the scale p_j keep their units. Biorthog-
onality keeps every multiplier a nodal unknown with its own complementarity — the contact set,
the NSGA position and velocity levels, the smooth contact force and friction take the rows as
they take a node's gap — and the discrete pressure field λ_h = Σ_j z_j Φ_j has nodal values

    z_j = λ_j / (L_j t)  (Pa),

λ_j the normal force of row j (N) and t the thickness of the 2D body (m).

Linearisation: the rows' gradients G_j = ∂g_j/∂q and curvatures ∇²g_j are exact, from a
second-order forward differentiation of the integral (:mod:`fecontact.contact.dual_numbers`):
through the averaged normals, the projections, the moving bounds of the overlaps and the
segment Jacobian. This is the consistent linearisation of Popp, Gee & Wall (2009) obtained
without deriving its terms by hand, so the position correction keeps Newton's quadratic rate.
The 3D form (Popp, Gitterle, Gee & Wall 2010: clipping of projected polygons) and quadratic
faces (the basis transformation of Popp, Wohlmuth, Gee & Wall 2012, needed because the corner
shape functions of a P2 face integrate to zero) are not implemented: P2 bodies are taken with
their boundary split into linear segments, like node-to-surface contact.

Contact rows are the slave boundary nodes. The master covers a part of a node's segments
(where the slave normals meet master segments facing them); a node takes part when the
covered part carries at least half of the dual weight of its covered segments,
∫_covered Φ_j ds ≥ ½ Σ_e |e|/2: where only the far end of a segment is covered, at the edge
of the zone the master faces, the negative lobe of Φ_j would turn g̃_j negative although the
surfaces are apart. Other rows report g = +inf with a zero gradient. A master segment whose
mean gap over its overlap is deeper than the margin behind the slave segment is a far part
of the master that happens to face it, not a contact partner, and is left out. The search
keeps the (slave, master) segment pairs whose midpoints are within the detection margin plus
both segment lengths, refreshed when a node has moved by more than an eighth of the margin.

Friction: the slip row of node j is the weighted relative motion t_j·∫ Φ_j (ẋ − ẏ) ds / L_j
along the slave node's tangent t_j, with the projections frozen over the step.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..bodies.solid import Solid
from ..errors import InputError, check_positive, check_range
from .base import PairDefaults
from .mortar_segments import segment_pair_integrals

__all__ = ["MortarContact", "merge_interfaces"]

_FULL = 1e-9  # a segment covered by less than this fraction counts as not covered (round-off)


def _neighbours(facets: np.ndarray):
    """For each segment (a, b) of an oriented boundary, the node before a and after b along
    the boundary (−1: none)."""
    n = facets.max() + 1
    ending, starting = np.full(n, -1), np.full(n, -1)
    ending[facets[:, 1]] = np.arange(len(facets))
    starting[facets[:, 0]] = np.arange(len(facets))
    e_prev, e_next = ending[facets[:, 0]], starting[facets[:, 1]]
    prev = np.where(e_prev >= 0, facets[np.maximum(e_prev, 0), 0], -1)
    nxt = np.where(e_next >= 0, facets[np.maximum(e_next, 0), 1], -1)
    return prev, nxt


def _tangent_of(X: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Unit tangents (X_b − X_a)/|X_b − X_a| (zero where a or b is −1)."""
    t = X[b] - X[a]
    norm = np.linalg.norm(t, axis=1)
    ok = (a >= 0) & (b >= 0) & (norm > 0.0)
    return np.where(ok[:, None], t / np.where(ok, norm, 1.0)[:, None], 0.0)


def _averaged_normals(x: np.ndarray, facets: np.ndarray, rows: np.ndarray, m: int):
    """Unit averaged normals (m, 2) of the slave nodes (rows of the segments' ends)."""
    t = x[facets[:, 1]] - x[facets[:, 0]]
    nu = np.stack([t[:, 1], -t[:, 0]], axis=1) / np.linalg.norm(t, axis=1)[:, None]
    n = np.zeros((m, 2))
    np.add.at(n, rows[:, 0], nu)
    np.add.at(n, rows[:, 1], nu)
    norm = np.linalg.norm(n, axis=1)
    return n / np.where(norm > 0.0, norm, 1.0)[:, None]


class _Layout:
    """Where the entries of the segment pairs land in the padded rows (m, k): ``dofs`` (m, k)
    and, for the slave ends a and b of each pair, the columns (P, 12) of its 12 dofs."""

    def __init__(self, ra, rb, dofs: np.ndarray, own: np.ndarray):
        m, d = own.shape
        rows = np.concatenate([np.repeat(ra, 12), np.repeat(rb, 12)])
        cols = np.concatenate([dofs.ravel(), dofs.ravel()])
        N = int(max(dofs.max(initial=0), own.max())) + 1
        uniq, inv = np.unique(rows * N + cols, return_inverse=True)
        ur, ud = np.divmod(uniq, N)
        pos = np.arange(len(uniq)) - np.searchsorted(ur, ur)
        k = max(int(np.bincount(ur, minlength=m).max(initial=0)), d)
        self.dofs = np.repeat(own[:, :1], k, axis=1)
        self.dofs[:, :d] = own
        self.dofs[ur, pos] = ud
        col = pos[inv].reshape(2, -1, 12)
        self.col_a, self.col_b = col[0], col[1]
        self.dofs.flags.writeable = False

    def rows(self, ra, rb, va: np.ndarray, vb: np.ndarray, m: int) -> np.ndarray:
        """Σ of the pairs' row vectors va, vb (P, 12) into (m, k)."""
        out = np.zeros(self.dofs.shape)
        np.add.at(out, (ra[:, None], self.col_a), va)
        np.add.at(out, (rb[:, None], self.col_b), vb)
        return out


class MortarContact(PairDefaults):
    """Dual mortar contact of the boundary of a 2D :class:`~fecontact.Solid` (the slave
    ``body``) with the boundary of another (the ``master``); see the module docstring.

    One contact per slave boundary node (``size``), with the weighted gap g_j (m);
    ``restitution`` is Newton's e_N in [0, 1]; ``margin`` (m) the search distance (default:
    the integrator's detection distance). Both directions are covered by one interface:
    the master's nodes cannot enter the slave either, to the discretization's accuracy.
    """

    linear = False
    lazy_hessians = True
    frictional = True

    def __init__(self, body, master, restitution: float = 0.0, margin=None):
        if not isinstance(body, Solid) or not isinstance(master, Solid):
            raise InputError("mortar contact needs two Solid bodies")
        if body is master:
            raise InputError("a body cannot contact itself (self-contact is not supported)")
        if body.dim != 2 or master.dim != 2:
            raise InputError("method='mortar' is available for 2D solids; use 'node-to-surface'")
        self.body, self.master = body, master
        self.bodies = (body, master)
        self.dim = 2
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self._own_margin = margin is not None
        if margin is None:
            margin = 0.05 * max(body.characteristic_length, master.characteristic_length)
        self.margin = check_positive("margin", margin)
        self.facets = body.contact_facets()
        self.master_facets = master.contact_facets()
        self.nodes, seg_rows = np.unique(self.facets, return_inverse=True)
        self.seg_rows = seg_rows.reshape(-1, 2)  # the contact rows of each segment's ends
        prev, nxt = _neighbours(self.facets)
        # a corner sharper than 60° (the faces of a block) splits the normal field: there each
        # segment keeps its own normal, so that a face's gap is measured along its normal
        X = body.X
        t = X[self.facets[:, 1]] - X[self.facets[:, 0]]
        t /= np.linalg.norm(t, axis=1)[:, None]
        smooth_prev = np.einsum("ij,ij->i", t, _tangent_of(X, prev, self.facets[:, 0])) > 0.5
        smooth_next = np.einsum("ij,ij->i", t, _tangent_of(X, self.facets[:, 1], nxt)) > 0.5
        self.has_prev, self.has_next = (prev >= 0) & smooth_prev, (nxt >= 0) & smooth_next
        self.local_nodes = np.stack(
            [np.where(self.has_prev, prev, self.facets[:, 0]), *self.facets.T,
             np.where(self.has_next, nxt, self.facets[:, 1])], axis=1
        )  # fmt: skip
        half = 0.5 * np.linalg.norm(X[self.facets[:, 1]] - X[self.facets[:, 0]], axis=1)
        self.length = np.bincount(self.seg_rows.ravel(), np.repeat(half, 2), len(self.nodes))
        """Reference length L_j (m) each slave node carries: its rows are g̃_j / L_j."""
        self.area = self.length * body.thickness
        self._dofs_s = body.node_translation_dofs(np.arange(body.n_nodes))
        self._dofs_m = master.node_translation_dofs(np.arange(master.n_nodes))
        self.offsets = (0, 0)
        self._last = self._search = None

    @property
    def size(self) -> int:
        return len(self.nodes)

    def bind(self, model) -> None:
        """Place the pair in the global dof vector of ``model``."""
        self.offsets = (model.offset_of(self.body), model.offset_of(self.master))
        self._last = self._search = None

    def detect_within(self, distance: float) -> None:
        """Search as far as the integrator's candidates reach (``distance`` m)."""
        if not self._own_margin and distance > 0.0 and distance != self.margin:
            self.margin = distance
            self._last = self._search = None

    def positions(self, q: np.ndarray):
        """Every node's position (m) of the slave and of the master at q."""
        (oa, ob), (a, b) = self.offsets, self.bodies
        return a.positions(q[oa : oa + a.ndof]), b.positions(q[ob : ob + b.ndof])

    def _pairs(self, xs: np.ndarray, xm: np.ndarray):
        """(slave segment, master segment) pairs near each other (module docstring)."""
        cache = self._search
        if cache is not None:
            xs0, xm0, pairs = cache
            moved = max(np.max(np.abs(xs - xs0)), np.max(np.abs(xm - xm0)))
            if moved <= 0.125 * self.margin:
                return pairs
        fs, fm = self.facets, self.master_facets
        cs, cm = 0.5 * (xs[fs[:, 0]] + xs[fs[:, 1]]), 0.5 * (xm[fm[:, 0]] + xm[fm[:, 1]])
        ls = np.max(np.linalg.norm(xs[fs[:, 1]] - xs[fs[:, 0]], axis=1))
        lm = np.max(np.linalg.norm(xm[fm[:, 1]] - xm[fm[:, 0]], axis=1))
        r = 1.25 * self.margin + ls + lm
        found = cKDTree(cs).sparse_distance_matrix(cKDTree(cm), r, output_type="ndarray")
        pairs = (found["i"].astype(int), found["j"].astype(int))
        self._search = (xs.copy(), xm.copy(), pairs)
        return pairs

    def _local(self, q: np.ndarray):
        """The slave segments e of the segment pairs, their local coordinates z (P, 12) and
        global dofs (P, 12), and the slave nodes' positions."""
        xs, xm = self.positions(q)
        e, f = self._pairs(xs, xm)
        z = np.concatenate([xs[self.local_nodes[e]], xm[self.master_facets[f]]], axis=1)
        oa, ob = self.offsets
        dofs = np.concatenate(
            [oa + self._dofs_s[self.local_nodes[e]], ob + self._dofs_m[self.master_facets[f]]],
            axis=1,
        )
        return e, z.reshape(len(e), 12), dofs.reshape(len(e), 12), xs

    def _integrate(self, e, z, hessian):
        return segment_pair_integrals(
            z, self.has_prev[e], self.has_next[e], hessian, depth=self.margin
        )

    def _valid(self, e, coverage, quad, xs) -> np.ndarray:
        """The rows (m,) whose covered support weighs at least half of the support of their
        segments that the master covers at all: W_j = ∫_covered Φ_j ds ≥ ½ Σ_e |e|/2."""
        xi, _, wJ = quad
        ra, rb = self.seg_rows[e, 0], self.seg_rows[e, 1]
        W = np.bincount(ra, ((0.5 - 1.5 * xi) * wJ).sum(1), self.size)
        W += np.bincount(rb, ((0.5 + 1.5 * xi) * wJ).sum(1), self.size)
        covered = np.bincount(e, coverage, len(self.facets)) > _FULL
        fs = self.facets[covered]
        half = 0.5 * np.linalg.norm(xs[fs[:, 1]] - xs[fs[:, 0]], axis=1)
        support = np.bincount(self.seg_rows[covered].ravel(), np.repeat(half, 2), self.size)
        return (W > 0.0) & (W >= 0.5 * support)

    def gaps(self, q: np.ndarray) -> np.ndarray:
        """The weighted gaps g_j (m) alone (+inf for the rows that take no part)."""
        last = self._last
        if last is not None and self._same(q, last[0]):
            return last[1][0].copy()
        e, z, _, xs = self._local(q)
        va, vb, coverage, quad = self._integrate(e, z, None)
        return self._gap_values(e, va.v, vb.v, coverage, quad, xs)

    def _gap_values(self, e, va, vb, coverage, quad, xs):
        ra, rb = self.seg_rows[e, 0], self.seg_rows[e, 1]
        g = np.bincount(ra, va, self.size) + np.bincount(rb, vb, self.size)
        return np.where(self._valid(e, coverage, quad, xs), g / self.length, np.inf)

    def _same(self, q, key) -> bool:
        (oa, ob), (a, b) = self.offsets, self.bodies
        now = (q[oa : oa + a.ndof], q[ob : ob + b.ndof])
        return all(np.array_equal(k, c) for k, c in zip(now, key, strict=True))

    def evaluate(self, q: np.ndarray):
        """Weighted gaps (m,) in m, dofs (m, k), gradients (m, k) and no Hessians (None:
        :meth:`hessians` gives them); rows that take no part have g = +inf and G = 0."""
        last = self._last
        if last is not None and self._same(q, last[0]):
            g, dofs, G = last[1][:3]
            return g.copy(), dofs, G, None
        e, z, dofs, xs = self._local(q)
        ga, gb, coverage, quad = self._integrate(e, z, False)
        g = self._gap_values(e, ga.v, gb.v, coverage, quad, xs)
        # the Hessians of the pairs that count only (the search also finds pairs that miss)
        ra, rb = self.seg_rows[e, 0], self.seg_rows[e, 1]
        counts = (coverage > 0.0) & (np.isfinite(g[ra]) | np.isfinite(g[rb]))
        own = self.offsets[0] + self._dofs_s[self.nodes]
        layout = _Layout(ra, rb, dofs, own)
        scale = np.where(np.isfinite(g), 1.0 / self.length, 0.0)
        G = layout.rows(ra, rb, ga.g * scale[ra, None], gb.g * scale[rb, None], self.size)
        G.flags.writeable = False
        (oa, ob), (a, b) = self.offsets, self.bodies
        key = (q[oa : oa + a.ndof].copy(), q[ob : ob + b.ndof].copy())
        self._last = (key, (g, layout.dofs, G, e, z, layout, scale, quad, counts))
        return g.copy(), layout.dofs, G, None

    def hessians(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """∇²g_j (len(rows), k, k) of the contacts ``rows`` at q, in the layout of
        :meth:`evaluate` at q."""
        self.evaluate(q)
        _, dofs, _, e, z, layout, scale, _, counts = self._last[1]
        rows = np.asarray(rows)
        H = np.zeros((len(rows), dofs.shape[1], dofs.shape[1]))
        where = np.full(self.size, -1)
        where[rows] = np.arange(len(rows))
        ra, rb = self.seg_rows[e, 0], self.seg_rows[e, 1]
        use = np.flatnonzero(counts & ((where[ra] >= 0) | (where[rb] >= 0)))
        if use.size == 0:
            return H
        ga, gb, _, _ = self._integrate(e[use], z[use], True)
        for r, col, jet in ((ra[use], layout.col_a[use], ga), (rb[use], layout.col_b[use], gb)):
            sel = where[r] >= 0
            w = where[r[sel]]
            c = col[sel]
            values = jet.h[sel] * scale[r[sel], None, None]
            np.add.at(H, (w[:, None, None], c[:, :, None], c[:, None, :]), values)
        return H

    def normals(self, q: np.ndarray) -> np.ndarray:
        """Averaged unit outward normals (m, 2) of the slave nodes at q."""
        return _averaged_normals(self.positions(q)[0], self.facets, self.seg_rows, self.size)

    def tangents(self, q: np.ndarray):
        """Slip rows (m, 1, k) of the weighted relative motion along each slave node's
        tangent t_j = (n_y, −n_x), in the layout of :meth:`evaluate`, and the tangents."""
        self.evaluate(q)
        _, dofs, _, e, _, layout, scale, (xi, eta, wJ), _ = self._last[1]
        t = self.normals(q) @ np.array([[0.0, -1.0], [1.0, 0.0]])
        ra, rb = self.seg_rows[e, 0], self.seg_rows[e, 1]
        Na, Nb = 0.5 * (1.0 - xi), 0.5 * (1.0 + xi)
        rows = []
        for r, phi in ((ra, 0.5 - 1.5 * xi), (rb, 0.5 + 1.5 * xi)):
            w = phi * wJ * scale[r, None]
            point = np.stack(
                [np.zeros(len(e)), (w * Na).sum(1), (w * Nb).sum(1), np.zeros(len(e)),
                 -(w * (1.0 - eta)).sum(1), -(w * eta).sum(1)], axis=1
            )  # fmt: skip
            rows.append((point[:, :, None] * t[r, None, :]).reshape(len(e), 12))
        GT = layout.rows(ra, rb, rows[0], rows[1], self.size)
        return dofs, GT[:, None, :], t[:, None, :]

    def nodal_pressure(self, forces: np.ndarray):
        """The slave nodes (indices in the slave body) and their contact pressure z_j (Pa)
        from the normal forces λ_j (N) of the pair's rows: z_j = λ_j / (L_j t)."""
        forces = np.asarray(forces, dtype=float)
        if forces.shape != (self.size,):
            raise InputError(f"forces must have {self.size} entries, got {forces.shape}")
        return self.nodes, forces / self.area


def merge_interfaces(pairs):
    """The pairs with each mortar interface once: a mortar pair declared both ways, (a, b)
    and (b, a), is one interface (the first declared); their restitution and friction must
    agree."""
    seen: dict = {}
    out = []
    for pair in pairs:
        if isinstance(pair, MortarContact):
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
    return out
