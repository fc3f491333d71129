"""What every contact pair provides to the contact set, and every obstacle to the output.

A pair holds ``size`` contacts; ``evaluate(q)`` gives their gaps g (m), dofs, gradients and
curvatures. ``PairDefaults`` answers for pairs without a rigid obstacle or without a cheaper
path to the gaps alone, so that the contact set never asks whether a method exists.
"""

from __future__ import annotations

import numpy as np

from ..bodies.solid import Solid
from ..errors import InputError

__all__ = ["PairDefaults", "at_beam_ends", "check_solid_pair"]


def at_beam_ends(body, nodes) -> bool:
    """Whether every node of ``nodes`` ends a beam ``body``'s centreline (lies on one of its
    segments only); False for a body that is not a beam."""
    if not body.slender:
        return False
    ends, count = np.unique(body.segments(), return_counts=True)
    return bool(np.isin(nodes, ends[count == 1]).all())


def check_solid_pair(body, master, kind: str) -> None:
    """An ``InputError`` unless ``body`` and ``master`` are two distinct solids of one
    dimension (``kind`` names the contact in the message)."""
    if not isinstance(body, Solid) or not isinstance(master, Solid):
        raise InputError(f"{kind} contact needs two Solid bodies")
    if body is master:
        raise InputError("a body cannot contact itself (self-contact is not supported)")
    if body.dim != master.dim:
        raise InputError("both solids must be 2D or both 3D")


class PairDefaults:
    """Defaults of a contact pair: no rigid obstacle, obstacles at rest."""

    obstacle = None
    bodies: tuple = ()  # the bodies whose dofs the rows move (empty: ``body`` alone)
    inside_test = False  # True: penetration(q) tests the nodes against a body's boundary
    looks_ahead = False  # True: look_ahead(q, v, h) is called before every step
    lazy_hessians = False  # True: evaluate() leaves H out; hessians(q, rows) gives it
    frictional = False  # True: tangents(q) gives the slip rows of Coulomb friction
    friction = 0.0  # Coulomb's μ of every contact of the pair (set by ``Contact``)
    redundant_rows = False  # True: rows can be redundant up to round-off (minimum-norm μ)
    duplicate_rows = False  # True: two segments clipped to their shared node: one row twice
    # True: declared with a pair of its kind the other way between the same two bodies
    # (two-pass), its rows and theirs can be redundant up to round-off where nodes meet
    meets_back = False
    at_beam_ends = False  # True: every contact is an end node of a beam (a tip, a bar's end)
    companions: tuple = ()  # pairs it brings into the model, bound with it (rows of its own)
    shared_points = False  # True: several rows can hold one point (``points()`` says which)
    # True: the pair decides which rows it has at each evaluation, and can hold that choice
    # from one configuration (``hold_rows(q)`` … ``release_rows()``: a Newton loop)
    holds_rows = False
    # True: some rows read +∞ (no row) where another row holds their point, and ``reach(q)``
    # gives each row's distance for the choice of candidates
    hides_rows = False

    def batch_key(self):
        """What lets consecutive pairs be evaluated together: (a batch class taking them, …)
        equal for pairs of one kind and setting, or None (evaluated alone)."""
        return None

    def points(self) -> np.ndarray:
        """The point (an int per row, the pair's own numbering) each row holds: rows of one
        point share its impact law in the velocity jump. Every row its own point here."""
        return np.arange(self.size)

    def bind(self, model) -> None:
        """Place the pair in the global dof vector of ``model``: the offsets of its two
        ``bodies``; what it kept of an earlier placement is forgotten (``reset``)."""
        self.offsets = (model.offset_of(self.bodies[0]), model.offset_of(self.bodies[1]))
        self.reset()

    def reset(self) -> None:
        """Forget what the pair keeps between evaluations (a new placement)."""

    def gaps(self, q: np.ndarray) -> np.ndarray:
        """The gaps g_j(q) (m) alone; pairs with a cheaper path than ``evaluate`` override."""
        return self.evaluate(q)[0]

    def reach(self, q: np.ndarray) -> np.ndarray:
        """Each row's distance (m) that decides whether it is a candidate: its gap, or for
        ``hides_rows`` pairs also a hidden row's distance (a row that can appear within a
        step's correction)."""
        return self.gaps(q)

    def admissible_gaps(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """The gaps (m) that admit a state at t = 0, from this pair's rows at q: the rows
        themselves; a pair whose rows are weighted gaps judges by its nodes' exact distances
        (a weighted gap can read below zero where no node is inside)."""
        return rows

    def penetration(self, q: np.ndarray) -> float:
        """How deep (m, ≥ 0) the deepest point of the pair lies on the wrong side: −min g
        where the gap is the signed distance itself (obstacles, bar ends); pairs with an
        ``inside_test`` measure it against the other body's boundary instead."""
        g = self.gaps(q)
        return float(max(0.0, -np.min(g, initial=np.inf)))

    def relative_depth(self, q: np.ndarray, g: np.ndarray) -> float:
        """Depth of the deepest point inside another body over that body's local facet size
        (0 for pairs whose gap is a signed distance: a projection on them is never lost)."""
        return 0.0

    def hessians(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """∇²g_j (len(rows), k, k) of the contacts ``rows`` (the pair's own numbering)."""
        return self.evaluate(q)[3][rows]

    def tangents(self, q: np.ndarray):
        """Slip rows of the contacts: dofs (m, k), T ∂x_rel/∂q (m, nt, k) and the unit
        tangents T (m, nt, d) of the contact planes, x_rel the motion of the body's contact
        point relative to the other's (``frictional`` pairs only)."""
        raise NotImplementedError(f"{type(self).__name__} has no friction")

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """The slip T·(x_rel(q) − x_rel(q_n)) (m, nt) of the contact points over a step,
        where the linear form G_T(q)(q − q_n) is not exact (points of rotating bodies); None:
        the linear form is."""
        return None

    def tangent_rows(self, q: np.ndarray, rows: np.ndarray):
        """``tangents`` of the contacts ``rows`` (the pair's own numbering) alone: dofs
        (len(rows), k), slip rows (len(rows), nt, k), tangents (len(rows), nt, d). A batch
        whose slip rows cost a rotation per pair computes the asked rows only."""
        dofs, G, T = self.tangents(q)
        return np.broadcast_to(dofs, (self.size, dofs.shape[1]))[rows], G[rows], T[rows]

    def slip_rows(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray, rows: np.ndarray):
        """``slips`` of the contacts ``rows`` alone (T (len(rows), nt, d) their tangents), or
        None where the linear form is exact."""
        full = np.zeros((self.size, *T.shape[1:]))
        full[rows] = T
        exact = self.slips(q, q_n, full)
        return None if exact is None else exact[rows]

    def detect_within(self, distance: float) -> None:
        """The integrator's detection distance (m), for pairs with a spatial search of their
        own: contacts farther than it are no candidates anyway."""

    def look_ahead(self, q: np.ndarray, v: np.ndarray, h: float) -> None:
        """Widen a spatial search of the pair's own to how far its bodies can close in the
        coming step h (s) from positions q and velocities v (pairs with one only)."""

    def watch(self):
        """What measures the nodes the pair's rows do not hold one by one (a mortar pair's
        weighted gaps): an object with ``depth(q) -> (m, depth over the local edge)``, or
        None when every row is a node's own gap."""
        return None

    def rate(self, q: np.ndarray) -> np.ndarray:
        """∂g_j/∂t (m/s) from a moving obstacle; zero for obstacles at rest."""
        return np.zeros(self.size)
