"""A safeguard for the smooth step's primal–dual active set: one row per update once the
sets stall or cycle.

The smooth step (:mod:`fecontact.time.smooth_contact`) changes every violating row of its
persistent contacts at once: rows that penetrate enter, rows whose force turns negative
leave. On rows coupled through a rigid body's six dofs this can wander without end: a rigid
box landing flat on an elastic cube went between sets of 12 and 17 of 23 rows for 40
updates, six halvings, and the run stopped. Once the sets cycle (a set already solved with
comes back) or stall (``STALL`` updates change no fewer rows than the fewest before), both
counted on updates that change several rows (a change of one row is a pivot already: a
single contact that enters and leaves as its Newton iteration settles, the founding
pendulum's tip, is left alone), each
update changes only the lowest-numbered row that the proposed set changes: Murty's
least-index rule, which ends in finitely many updates on the linearised law, whose Schur
matrix G_A S⁻¹ G_Aᵀ is positive definite (Murty 1974; the switch after a stall is Júdice &
Pires 1994's hybrid).
"""

from __future__ import annotations

import numpy as np

# updates of the active set without fewer rows changed than before, after which one row
# changes per update (Júdice & Pires take 10 on linear complementarity problems; the smooth
# Newton's iterations allow fewer)
STALL = 5


class LeastIndexPivot:
    """The active set's safeguard in one smooth step. ``floor`` (m): the penetration beyond
    which a row enters once pivoting; ``stats``: the run's contact counts, where
    ``smooth_active_set_pivots`` counts the steps that switched."""

    def __init__(self, floor: float, stats):
        self.floor, self.stats = floor, stats
        self.seen, self.pivoting = set(), False
        self.fewest, self.stalled = np.inf, 0  # (the fewest rows changed at once, since when)

    def __call__(self, proposed, current, solved, g) -> np.ndarray:
        """The set of the next update: ``proposed`` (from the set ``current`` after the
        update that enforced ``solved``, None: none yet, at gaps ``g``), or one row of it."""
        if solved is None:
            return proposed
        changed = np.flatnonzero(proposed != current)
        if not changed.size:
            return proposed
        if changed.size > 1:  # (a change of one row is already a least-index step)
            self._watch(proposed, current, changed.size)
        if not self.pivoting:
            return proposed
        if not (current == solved).all():  # (a row just entered holds no force yet)
            return current
        # (a row enters only beyond the gap tolerance: the coplanar rows of a flat landing
        # sit at g = ±1e-18 and would enter and leave by round-off alone)
        changed = changed[current[changed] | (g[changed] < -self.floor)]
        out = current.copy()
        out[changed[:1]] = proposed[changed[:1]]
        return out

    def _watch(self, proposed, current, n_changed: int) -> None:
        """Record ``current`` and switch to pivoting where the sets cycle or stall."""
        self.seen.add(current.tobytes())
        if n_changed < self.fewest:
            self.fewest, self.stalled = n_changed, 0
        else:
            self.stalled += 1
        if not self.pivoting and (proposed.tobytes() in self.seen or self.stalled >= STALL):
            self.pivoting = True
            self.stats.smooth_active_set_pivots += 1
