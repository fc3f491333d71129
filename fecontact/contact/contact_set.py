"""``ContactSet``: every contact pair of a model, numbered globally over the free dofs, with
gaps, gradients and curvatures gathered into dense or sparse arrays."""

from __future__ import annotations

from contextlib import contextmanager

import numpy as np
import scipy.sparse as sp

from ..linalg import DENSE_LIMIT
from .friction_rows import FrictionRows
from .mortar_interface import merge_interfaces
from .mortar_safeguard import twin_rows
from .pair_batches import evaluation_units
from .watch import SolidWatch, solid_watches

__all__ = [
    "ContactSet",
    "admissible_gaps",
    "candidates",
    "held_together",
    "rows_held",
    "whole_points",
]


class ContactSet(FrictionRows):
    """All contact pairs of a model, numbered globally and restricted to the free dofs."""

    def __init__(self, pairs, free_index: np.ndarray, n_free: int):
        self.pairs = merge_interfaces(pairs)
        self.free_index = free_index
        self.n_free = n_free
        self.size = sum(pair.size for pair in self.pairs)
        self.restitution = _per_contact(self.pairs, [pair.restitution for pair in self.pairs])
        self.linear = all(pair.linear for pair in self.pairs)
        self.friction = _per_contact(self.pairs, [pair.friction for pair in self.pairs])
        self.frictional = bool(np.any(self.friction > 0.0))
        self.redundant_rows = _redundant(self.pairs)
        self.owner = _per_contact(self.pairs, range(len(self.pairs)), int)  # pair of a contact
        self.twins = twin_rows(self.pairs)  # two rows of one node (mortar_safeguard), or None
        # each contact's number within its pair
        self.local = _per_contact(self.pairs, [np.arange(pair.size) for pair in self.pairs], int)
        self.point = _points(self.pairs)
        self.units, self.unit_owner, self.unit_local, self._batched = evaluation_units(self.pairs)
        self._pair_roles()
        self._scatters: dict = {}
        self._last_scatter: dict = {}  # per pair: read-only (rows, dofs) and their _Scatter
        self._all = np.arange(self.size)
        self._all.flags.writeable = False
        obstacles = [pair.obstacle for pair in self.pairs if pair.obstacle is not None]
        self._moving = [o for o in obstacles if o.moving]
        # the gaps alone are cheaper where a pair can skip its derivatives
        self._gap_functions = [unit.gaps for unit in self.units]
        self._affine = _Affine(*self._affine_form()) if self._affine_and_small() else None

    def _pair_roles(self) -> None:
        """The pairs by role: measured by an inside/outside test (the others by their gaps),
        looking ahead, holding their rows through a Newton loop, hiding rows (their mask)."""
        self._holding = [p for p in self.pairs if p.holds_rows]  # rows_held
        self._hiding = [(p, self.owner == i) for i, p in enumerate(self.pairs) if p.hides_rows]
        self._inside = [i for i, pair in enumerate(self.pairs) if pair.inside_test]
        self._signed = ~np.isin(self.owner, self._inside)  # contacts whose gap is a distance
        self._all_signed = bool(self._signed.all())
        self._inside_rows = [np.flatnonzero(self.owner == i) for i in self._inside]
        self._looking = [pair for pair in self.pairs if pair.looks_ahead]
        self.watches = solid_watches(self.pairs)  # the mortar interfaces' nodes
        self.watches += [w for w in (pair.watch() for pair in self.pairs) if w is not None]

    def _affine_and_small(self) -> bool:
        """Affine gaps (constant gradients, fixed obstacles) of a small model: g(q) = g₀ + G q
        is then kept with G dense, so that a step without candidates costs one product."""
        affine = bool(self.pairs) and self.linear and not self.moving
        return affine and self.size * len(self.free_index) <= 2**16

    @property
    def all(self) -> np.ndarray:
        return self._all

    @property
    def moving(self) -> bool:
        return bool(self._moving)

    @property
    def affine(self) -> bool:
        """Whether every gap is affine in q (nodes against fixed planes): constant gradients,
        no curvature."""
        return self._affine is not None

    def detect_within(self, distance: float) -> None:
        """Give the pairs with a spatial search of their own the integrator's detection
        distance (m), so that one margin decides what is a candidate."""
        for pair in self.pairs:
            pair.detect_within(distance)

    def penetration(self, q: np.ndarray, gaps: np.ndarray | None = None) -> float:
        """How deep (m, ≥ 0) any point lies where a contact forbids it at q: the nodes of a
        solid inside another solid's discretized boundary by the inside/outside test
        (:mod:`fecontact.contact.inside`), whatever their constraint gap says; −min g for the
        other pairs, whose gap is the signed distance (``gaps``: g(q) of every contact, when
        known)."""
        if not self.pairs:
            return 0.0
        g = self.gaps(q) if gaps is None or gaps.size != self.size else gaps
        signed = g if self._all_signed else g[self._signed]
        depth = max(0.0, -float(signed.min())) if signed.size else 0.0
        for i in self._inside:
            depth = max(depth, self.pairs[i].penetration(q))
        return depth

    def look_ahead(self, q: np.ndarray, v: np.ndarray, h: float) -> None:
        """Before a step h (s) from (q, v): the solid pairs' searches reach as far as their
        bodies can close in it, and the beam pairs keep where the points start (their sides
        follow the motion over the step)."""
        for pair in self._looking:
            pair.look_ahead(q, v, h)

    def relative_depth(self, q: np.ndarray, gaps: np.ndarray) -> float:
        """The largest −g at q of a solid's node inside another solid over the size of the
        facet that holds it (``gaps``: every contact's g at q; 0 without solid–solid
        pairs)."""
        depth = 0.0
        for i, rows in zip(self._inside, self._inside_rows, strict=True):
            depth = max(depth, self.pairs[i].relative_depth(q, gaps[rows]))
        return depth

    def set_time(self, t: float) -> None:
        """Place the moving obstacles where they are at time t (s)."""
        for obstacle in self._moving:
            obstacle.time = t

    def rates(self, q: np.ndarray, select: np.ndarray) -> np.ndarray:
        """∂g_j/∂t of the contacts ``select`` (m/s): nonzero for moving obstacles only."""
        if not self.moving:
            return np.zeros(len(select))
        return np.concatenate([p.rate(q) for p in self.pairs])[select]

    def quadratic(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """vᵀ ∇²g_j v for every constraint j (the acceleration term of a holonomic one)."""
        if self._affine is not None:  # affine gaps: no curvature (and no pair evaluated)
            return np.zeros(self.size)
        out = []
        for g, dofs, _, H in self.evaluate(q):
            if H is None:
                out.append(np.zeros(len(g)))
            else:
                vd = v[np.broadcast_to(dofs, H.shape[:2])]
                out.append(np.einsum("mi,mij,mj->m", vd, H, vd))
        return np.concatenate(out) if out else np.zeros(0)

    def evaluate(self, q: np.ndarray):
        """Gaps (m,), dofs (list per pair), gradient values and Hessians of every contact."""
        return [pair.evaluate(q) for pair in self.pairs]

    def _affine_form(self):
        """(g₀, G on all dofs, G on the free dofs) of affine gaps g = g₀ + G q."""
        n = len(self.free_index)
        parts = self.evaluate(np.zeros(n))
        G = np.zeros((self.size, n))
        rows = np.split(self._all, np.cumsum([len(g) for g, _, _, _ in parts])[:-1])
        for r, (_, dofs, Gv, _) in zip(rows, parts, strict=True):
            dofs = np.broadcast_to(dofs, Gv.shape) if dofs.shape != Gv.shape else dofs
            np.add.at(G, (np.repeat(r, Gv.shape[1]), dofs.ravel()), Gv.ravel())
        g0 = np.concatenate([g for g, _, _, _ in parts])
        return g0, G, np.ascontiguousarray(G[:, self.free_index >= 0])

    def gaps(self, q: np.ndarray) -> np.ndarray:
        if not self.pairs:
            return np.zeros(0)
        if self._affine is not None:
            return self._affine.gaps(q)
        if len(self.units) == 1:
            return self._gap_functions[0](q)
        return np.concatenate([gaps(q) for gaps in self._gap_functions])

    def jacobian(self, q: np.ndarray, select: np.ndarray):
        """Gaps and dense gradient (len(select) × n_free) of the contacts ``select``."""
        return self.linearize(q, select)[:2]

    def curvature(self, q: np.ndarray, select: np.ndarray, weights: np.ndarray):
        """Σ_j weights_j ∇²g_j over ``select`` (n_free × n_free; see :meth:`linearize`)."""
        return self.linearize(q, select, weights)[2]

    def linearize(self, q: np.ndarray, select: np.ndarray, weights=None):
        """Gaps g (len(select),), their dense gradient G (len(select) × n_free) and, when
        ``weights`` are given, the curvature C = Σ_j weights_j ∇²g_j (n_free × n_free), from
        one evaluation of the pairs at q. C is dense like the model's matrices up to
        ``DENSE_LIMIT`` free dofs, else sparse (CSR) over the dofs of the contacts with a
        nonzero weight."""
        n = self.n_free
        C = _empty_curvature(weights, n)
        if not self.pairs or len(select) == 0:
            return np.zeros(0), np.zeros((len(select), n)), _curvature_matrix(C, n)
        if self._affine is not None:  # affine gaps: no curvature (no dense G to fill)
            return *self._affine.linearize(q, select), _curvature_matrix(C, n)
        G = np.zeros((len(select), n))
        parts = [unit.evaluate(q) for unit in self.units]
        single = len(parts) == 1
        g_all = _gaps_of(parts)
        owner = None if single else self.unit_owner[select]
        every = single and select is self._all  # no selection to copy
        for i, (_, dofs, Gv, H) in enumerate(parts):
            picked = self._picked(i, select, owner)
            if picked is None:
                continue
            rows, loc = picked
            if dofs.shape != Gv.shape:
                dofs = np.repeat(dofs.reshape(1, -1), len(Gv), axis=0)
            sc = self._scatter(i, rows, dofs if every else dofs[loc])
            if not every:  # the selected rows (linear kinematics carry no Hessian)
                Gv, H = Gv[loc], (None if H is None else H[loc])
            # each pair fills rows of its own: an assignment unless a row repeats a dof
            _add(G, sc.g_index, Gv.ravel()[sc.g_keep], sc.g_unique, assign=True)
            if C is not None:
                self._add_curvature(C, i, q, (rows, loc, dofs, sc), H, weights, single)
        return g_all[select], G, _curvature_matrix(C, n)

    def _picked(self, i: int, select: np.ndarray, owner):
        """The rows of ``select`` in unit i and their numbers there, or None when it has none
        (``owner``: each selected contact's unit; None for a single unit)."""
        if owner is None:
            if select is self._all:
                return self._all, self._all
            return np.arange(len(select)), select
        rows = np.flatnonzero(owner == i)
        if rows.size == 0:
            return None
        return rows, self.unit_local[select[rows]]

    def _add_curvature(self, C, i, q, placed, H, weights, single: bool) -> None:
        """C += Σ_r weights_r ∇²g_r over the selected rows of unit i; ``placed`` = (rows in
        the selection, their numbers within the unit, the unit's dofs, their scatter). A
        pair with ``lazy_hessians`` is asked for those of the rows with a weight only (the
        active contacts)."""
        rows, loc, dofs, sc = placed
        if self.units[i].lazy_hessians:
            act = np.flatnonzero(weights[rows])
            if act.size:
                w, Ha = weights[rows[act]], self.units[i].hessians(q, loc[act])
                sa = self._scatter(i, rows[act], dofs[loc[act]])
                _add_weighted(C, sa, w, Ha, assign=False)
        elif H is not None:
            # (a single pair writes into a C still zero)
            _add_weighted(C, sc, weights[rows], H, assign=single)

    def _scatter(self, i: int, rows: np.ndarray, dofs: np.ndarray):
        """Where the gradient rows and Hessians of unit i land in G and C (cached: the dofs
        of most pairs never change)."""
        last = self._last_scatter.get(i)
        if last is not None and last[0] is rows and last[1] is dofs:
            return last[2]  # the same unchangeable arrays as last time
        key = (i, rows.tobytes(), dofs.tobytes())
        sc = self._scatters.get(key)
        if sc is None:
            sc = _Scatter(rows, self.free_index[dofs], self.n_free, self._batched[i])
            if len(self._scatters) > 256:
                self._scatters.clear()
            self._scatters[key] = sc
        if not (rows.flags.writeable or dofs.flags.writeable):
            self._last_scatter[i] = (rows, dofs, sc)
        return sc

    def generalized_force(self, q: np.ndarray, select: np.ndarray, mult: np.ndarray, n: int):
        """Σ_j G_jᵀ mult_j over ``select`` on all n dofs (for output of nodal forces)."""
        parts = self.evaluate(q)
        f = np.zeros(n)
        wfull = np.zeros(self.size)
        wfull[select] = mult
        offset = 0
        for g, dofs, G, _ in parts:
            m = len(g)
            f += np.bincount(
                dofs.ravel(), (wfull[offset : offset + m, None] * G).ravel(), minlength=n
            )
            offset += m
        return f


def candidates(contacts: ContactSet, q: np.ndarray, g: np.ndarray, margin: float) -> np.ndarray:
    """The contacts within ``margin`` (m) at q (``g``: their gaps there), and the rows that a
    ``hides_rows`` pair leaves out at q with their distance within it: a correction can make
    them rows (a solid's node dented under a peg), and then holds them."""
    near = g <= margin
    for pair, rows in contacts._hiding:
        near[rows] |= pair.reach(q) <= margin
    return near.nonzero()[0]


def held_together(contacts: ContactSet, closed: np.ndarray, held: np.ndarray) -> np.ndarray:
    """``held`` (a mask over the ``closed`` contacts: those a smooth force presses) with
    every closed row of a point one of whose rows is held: a point's rows take one impact
    law (a node in a beam's valley held by one line's force while the nearly parallel other
    line closes on it: ġ = 0 on one row and Newton's ġ⁺ = −e ġ⁻ > 0 on the other ask the
    node for two velocities along almost one direction)."""
    if contacts.point is None or not held.any() or held.all():
        return held
    at = contacts.point[closed]
    return np.isin(at, at[held])


def whole_points(contacts: ContactSet, mask: np.ndarray) -> np.ndarray:
    """``mask`` (per contact) extended to every row of a point one of whose rows it marks
    (a node-to-surface node's rows at a concave feature)."""
    if contacts.point is None:
        return mask
    return np.isin(contacts.point, contacts.point[mask])


@contextmanager
def rows_held(contacts: ContactSet, q: np.ndarray, hold: bool = True):
    """Within it (where ``hold``), every pair of ``contacts`` that decides its rows at each
    evaluation keeps those it has at q, with their facets, and those it gains: no row of
    the iterates of a Newton loop (the smooth step, the position correction) vanishes
    (:mod:`.concave_rows`)."""
    holding = contacts._holding if hold else ()
    for pair in holding:
        pair.hold_rows(q)
    try:
        yield
    finally:
        for pair in holding:
            pair.release_rows()


def _points(pairs) -> np.ndarray | None:
    """The global number of the point each contact holds (rows of one point share it), or
    None where every row holds a point of its own (decided once per model)."""
    if not any(pair.shared_points for pair in pairs):
        return None
    out, base = [], 0
    for pair in pairs:
        own = pair.points() if pair.shared_points else np.arange(pair.size)
        out.append(base + np.asarray(own, int))
        base += pair.size
    return np.concatenate(out)


def _redundant(pairs) -> bool:
    """Whether some rows of ``pairs`` may hold one motion twice: a pair that declares it
    (``redundant_rows``), or two-pass node-to-surface (:func:`_both_ways`)."""
    return any(p.redundant_rows for p in pairs) or _both_ways(pairs)


def _both_ways(pairs) -> bool:
    """Whether two pairs of a kind that ``meets_back`` hold the same two bodies each way
    (two-pass node-to-surface): where the nodes of both bodies meet, a node's row on the
    other body's facet and the row of the node it meets on its own facet hold one relative
    motion. Two such rows pressed by a smooth force are equalities of the position correction
    (either sign): two disks at 30 m/s, one cell a step, took ±8e-3 multipliers on them,
    against 1e-5 on the others, and a 9 mm correction for a 0.2 mm overlap, 17 % of their
    energy created in the step. Their multipliers are the minimum-norm ones."""
    ways = {(type(p), id(p.body), id(p.master)) for p in pairs if p.meets_back}
    return any((kind, b, a) in ways for kind, a, b in ways)


def _per_contact(pairs, values, dtype=float) -> np.ndarray:
    """Each pair's value repeated over its contacts."""
    parts = [np.full(pair.size, v) for pair, v in zip(pairs, values, strict=True)]
    return np.concatenate(parts or [np.zeros(0, dtype)])


def _gaps_of(parts) -> np.ndarray:
    """The gaps of every contact from the pairs' evaluations (the one pair's own array when
    there is one)."""
    return parts[0][0] if len(parts) == 1 else np.concatenate([p[0] for p in parts])


def _empty_curvature(weights, n: int):
    """None without ``weights``; else a zero C, dense up to ``DENSE_LIMIT`` free dofs, or
    the list its sparse parts are gathered in."""
    if weights is None:
        return None
    return np.zeros((n, n)) if n <= DENSE_LIMIT else []


def _add_weighted(C, sc, w: np.ndarray, H: np.ndarray, assign: bool) -> None:
    """C += Σ_r w_r ∇²g_r placed by the scatter ``sc``: into a dense C, or as a part of a
    sparse one (a list of (values, flat indices))."""
    # rows on the same dofs (a joint's two equations): summed before the scatter
    Hw = w @ H.reshape(len(w), -1) if sc.shared else w[:, None, None] * H
    values = Hw.ravel()[sc.c_keep]
    if isinstance(C, list):
        C.append((values, sc.c_index))
    else:
        _add(C, sc.c_index, values, sc.c_unique, assign=assign)


def _curvature_matrix(C, n: int):
    """The curvature as it was gathered: dense, or sparse (COO, duplicates to be summed) from
    (values, (rows, cols)) parts (zero weights dropped: only the active contacts' dofs
    appear)."""
    if not isinstance(C, list):
        return C
    values = np.concatenate([v for v, _ in C] or [np.zeros(0)])
    flat = np.concatenate([i for _, i in C] or [np.zeros(0, int)])
    keep = values != 0.0
    rows, cols = np.divmod(flat[keep], n)
    return sp.coo_matrix((values[keep], (rows, cols)), shape=(n, n))


class _Affine:
    """Affine gaps g = g₀ + G q (``G`` on all dofs, ``Gf`` on the free ones, dense). Where
    every row of G has one entry (nodes on planes normal to an axis: most floors and walls)
    the gaps are g₀ + G_jk q_k gathered at that entry, the dense product's own numbers (its
    other terms are zeros) without reading G (66 × 387 floats on the elastic ball, 200 kB
    a product: a third of the cache a located impact step has besides its modes)."""

    __slots__ = ("g0", "G", "Gf", "at", "values")

    def __init__(self, g0: np.ndarray, G: np.ndarray, Gf: np.ndarray):
        self.g0, self.G, self.Gf = g0, G, Gf
        single = bool(G.size) and bool((np.count_nonzero(G, axis=1) == 1).all())
        self.at = np.argmax(G != 0.0, axis=1) if single else None
        self.values = G[np.arange(G.shape[0]), self.at] if single else None

    def gaps(self, q: np.ndarray) -> np.ndarray:
        if self.at is None:
            return self.g0 + self.G @ q
        return self.g0 + self.values * q[self.at]

    def linearize(self, q: np.ndarray, select: np.ndarray):
        """(g, G on the free dofs) of the rows ``select``."""
        if self.at is None:
            return self.g0[select] + self.G[select] @ q, self.Gf[select]
        at = self.at[select]
        return self.g0[select] + self.values[select] * q[at], self.Gf[select]


class _Scatter:
    """Index arrays that place gradient rows (r, k) and Hessians (r, k, k) of contacts into the
    dense G (rows × free dofs) and C (free × free), n free dofs; fixed dofs (index −1) are
    dropped. The indices are flat (row × n + column): a one-dimensional fancy assignment
    costs half of a two-dimensional one on these small arrays."""

    def __init__(self, rows: np.ndarray, fi: np.ndarray, n: int, batched: bool = False):
        k = fi.shape[1]
        r = np.repeat(rows, k)
        f = fi.ravel()
        self.g_keep = f >= 0
        self.g_index = r[self.g_keep] * n + f[self.g_keep]
        self.g_unique = _unique(self.g_index)
        a = np.repeat(fi, k, axis=1).ravel()
        b = np.tile(fi, (1, k)).ravel()
        # Hessians of a pair's rows on the same dofs are summed first: scattered as one row
        # (a batch's rows are added pair after pair, as the pairs alone would be)
        self.shared = len(fi) > 1 and not batched and bool(np.all(fi == fi[0]))
        if self.shared:
            a, b = np.repeat(fi[0], k), np.tile(fi[0], k)
        self.c_keep = (a >= 0) & (b >= 0)
        self.c_index = a[self.c_keep] * n + b[self.c_keep]
        self.c_unique = _unique(self.c_index)
        # no fixed dof: a view instead of a boolean selection
        self.g_keep = slice(None) if self.g_keep.all() else self.g_keep
        self.c_keep = slice(None) if self.c_keep.all() else self.c_keep


def _unique(index: np.ndarray) -> bool:
    return len(np.unique(index)) == len(index)


def _add(A: np.ndarray, index, values: np.ndarray, unique: bool, assign=False) -> None:
    """A.flat[index] += values (A C-contiguous); a plain fancy assignment when no index repeats
    (much cheaper), and ``assign`` when those entries of A are known to be zero."""
    flat = A.reshape(-1)  # a view
    if unique and assign:
        flat[index] = values
    elif unique:
        flat[index] += values
    else:
        np.add.at(flat, index, values)


def admissible_gaps(contacts: ContactSet, q: np.ndarray, g: np.ndarray) -> np.ndarray:
    """The gaps (m) by which a state at t = 0 is admitted, from the rows g of ``contacts`` at q
    (each pair's ``admissible_gaps``; a solid–solid mortar interface's by its watch,
    :meth:`~fecontact.contact.watch.SolidWatch.admissible_gaps`)."""
    owner = contacts.owner
    # a mortar interface between two solids: by its watch's nodes of either body
    judges = {id(w.pair): w for w in contacts.watches if isinstance(w, SolidWatch)}
    parts = [
        judges.get(id(pair), pair).admissible_gaps(q, g[owner == i])
        for i, pair in enumerate(contacts.pairs)
    ]
    return np.concatenate([np.zeros(0), *parts])
