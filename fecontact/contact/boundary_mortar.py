r"""What a dual mortar pair of a 3D solid's boundary against a master with an exact distance field
shares, whatever the master: the slave rows over the boundary triangles.

The solid's boundary triangles (:meth:`~fecontact.Solid.contact_facets`) are the slave surface.
Each slave boundary node j carries one multiplier and one row, its weighted gap

    g̃_j = Σ_e ∫_e Φ_j D(x) dA₀,   rows g_j = g̃_j / L_j,

with D the master's distance (less the clearance), Φ_j = 4λ_j − 1 the dual functions of the
linear triangle (∫_e Φ_j λ_k dA₀ = δ_jk |e|₀/3) and L_j = Σ_e |e|₀/3 the reference area node j
carries: λ_j / L_j is the nominal pressure. A row's columns are the nodes of its triangles (its
star) and the master's dofs. :class:`BoundaryRows` keeps the triangles, the stars, the areas,
the margin and the rule, sums the triangles' end integrals into rows and caches them; a
subclass gives the integrals (``integrals(q, order, tris)``).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError, check_positive, check_range
from .base import PairDefaults
from .rigid_distance import triangle_rule

__all__ = ["BoundaryRows", "row_stars", "triangle_areas"]


def triangle_areas(t: np.ndarray) -> np.ndarray:
    """Areas (T,) of triangles t (T, 3, 3), m²."""
    return 0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1)


def row_stars(rows: np.ndarray, m: int):
    """Each row's star, the nodes of its triangles: (m, K) node rows padded with the row's own
    node, and the positions (E, 3 ends, 3 nodes) of each triangle's nodes in the star of the
    row of each of its ends (``rows`` (E, 3) the triangles' rows, m the number of rows)."""
    j = np.repeat(rows, 3, axis=1).ravel()  # (e, k, a) -> rows[e, k]
    a = np.tile(rows, (1, 3)).ravel()  # (e, k, a) -> rows[e, a]
    uniq, inv = np.unique(j * m + a, return_inverse=True)
    uj, ua = np.divmod(uniq, m)
    pos = np.arange(len(uniq)) - np.searchsorted(uj, uj)
    K = int(np.bincount(uj, minlength=m).max())
    star = np.repeat(np.arange(m)[:, None], K, axis=1)
    star[uj, pos] = ua
    return star, pos[inv].reshape(len(rows), 3, 3)


class BoundaryRows(PairDefaults):
    """The slave rows of a 3D solid ``body``'s boundary (module docstring): ``restitution``
    Newton's e_N in [0, 1], ``clearance`` (m) already checked by the pair, ``margin`` (m; None:
    the integrator's detection distance), ``subdivisions`` s ≥ 1 of the sub-triangles per edge
    of a triangle the master's region boundaries cross."""

    linear = False
    lazy_hessians = True

    def __init__(self, body, restitution, clearance, margin, subdivisions: int):
        self.body = body
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self.clearance = clearance
        self.own_margin = margin is not None
        self.margin = check_positive("margin", 0.05 * body.characteristic_length
                                     if margin is None else margin)  # fmt: skip
        if int(subdivisions) != subdivisions or subdivisions < 1:
            raise InputError(f"subdivisions must be an integer ≥ 1, got {subdivisions!r}")
        self.rules = (triangle_rule(1), triangle_rule(int(subdivisions)))
        self.facets = body.contact_facets()
        self.nodes, rows = np.unique(self.facets, return_inverse=True)
        self.element_rows = rows.reshape(self.facets.shape)
        self.area0 = triangle_areas(body.X[self.facets])  # |e|₀ (m²)
        self.length = np.bincount(rows.ravel(), np.repeat(self.area0 / 3.0, 3), len(self.nodes))
        """Reference area L_j (m²) each slave node carries: its rows are g̃_j / L_j."""
        self.area = self.length
        self.star, self.star_positions = row_stars(self.element_rows, len(self.nodes))
        self.cached = self.cached_gaps = None

    @property
    def size(self) -> int:
        return len(self.nodes)

    def reset(self) -> None:
        self.cached = self.cached_gaps = None

    def detect_within(self, distance: float) -> None:
        """Rows within ``distance`` (m, the integrator's detection distance) are integrated."""
        if not self.own_margin and distance > 0.0 and distance != self.margin:
            self.margin = distance
            self.reset()

    def integrals(self, q: np.ndarray, order: int, tris=None):
        """(near (m,) bool, triangles (T,), their end integrals ∫ Φ_i D dA₀ (T, 3), and what
        the subclass's derivatives need)."""
        raise NotImplementedError

    def reach(self, x: np.ndarray) -> np.ndarray:
        """Each row's reach (m,): the longest edge of its triangles at positions x (the solid's
        nodes), within which every point of its triangles lies from its node."""
        t = x[self.facets]
        edge = np.linalg.norm(t - np.roll(t, 1, axis=1), axis=2).max(axis=1)
        reach = np.zeros(self.size)
        for k in range(3):
            np.maximum.at(reach, self.element_rows[:, k], edge)
        return reach

    def rule_points(self, tris: np.ndarray, cut: np.ndarray):
        """The triangles ``tris`` reordered (plain ones first, then those ``cut`` by a region
        boundary, on s² sub-triangles), and their points: the index of each point's triangle
        in that order, area coordinates λ (P, 3), weights w (P,) and each triangle's first
        point."""
        tris = np.concatenate([tris[~cut], tris[cut]])
        n_plain, n_cut = int((~cut).sum()), int(cut.sum())
        (l1, w1), (ls, ws) = self.rules
        counts = np.concatenate([np.full(n_plain, len(w1)), np.full(n_cut, len(ws))])
        which = np.repeat(np.arange(len(tris)), counts)
        lam = np.concatenate([np.tile(l1, (n_plain, 1)), np.tile(ls, (n_cut, 1))])
        w = np.concatenate([np.tile(w1, n_plain), np.tile(ws, n_cut)])
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(int)
        return tris, which, lam, w, starts

    def weighted_rows(self, tris, values) -> np.ndarray:
        """The weighted gaps g̃_j / L_j (m,) from the end integrals ``values`` (T, 3) of the
        triangles ``tris``."""
        g = np.zeros(self.size)
        for k in range(3):
            g += np.bincount(self.element_rows[tris, k], values[:, k], self.size)
        return g / self.length

    def sum_rows(self, near, tris, values) -> np.ndarray:
        """The rows g_j (m,) from the triangles' end integrals, +inf where not ``near``."""
        return np.where(near, self.weighted_rows(tris, values), np.inf)

    def gaps(self, q: np.ndarray) -> np.ndarray:
        """The rows g_j (m) alone (+inf for rows that take no part)."""
        for cached in (self.cached, self.cached_gaps):
            if cached is not None and np.array_equal(cached[0], q):
                return cached[1].copy()
        g = self.sum_rows(*self.integrals(q, 0)[:3])
        self.cached_gaps = (q.copy(), g)
        return g.copy()

    def nodal_pressure(self, forces: np.ndarray):
        """The slave nodes (indices in the body) and their nominal pressure z_j = λ_j / L_j
        (Pa, per reference area) from the rows' normal forces λ_j (N)."""
        forces = np.asarray(forces, dtype=float)
        if forces.shape != (self.size,):
            raise InputError(f"forces must have {self.size} entries, got {forces.shape}")
        return self.nodes, forces / self.length
