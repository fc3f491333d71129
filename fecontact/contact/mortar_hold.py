"""The rows of a mortar interface held through a Newton loop.

A mortar interface decides at each evaluation which of its slave nodes take part: those
whose covered weight carries at least the share ``taking_part`` of their covered elements'
(:mod:`.mortar_interface`). A node whose share sits at that threshold crosses it between the
iterates of a Newton loop with the motion the loop itself makes: its row read a finite gap
at one iterate and +inf (no row) at the next, and came back at the one after. Two P1 cubes
thrown at each other with their edges crossed stopped so: the node at the crossing held a
share of 0.250 (the threshold ¼), and the position correction's active set cycled between
none and that row (docs/explanation/mortar.md, *Rows held through a Newton loop*).

Held from the loop's first configuration (:meth:`HeldRows.hold_rows`), a row that takes
part there, or at any later iterate, keeps its row while it keeps a covered weight: its
weighted gap g̃_j = ∫ Φ_j g_N dA is continuous in q and falls to 0 with the covered weight,
so the row releases continuously instead of jumping to +inf.
"""

from __future__ import annotations

import numpy as np

__all__ = ["HeldRows"]


class HeldRows:
    """What a mortar interface adds to hold its rows; it has ``size`` rows, ``gaps(q)``, and
    keeps the gaps of one q in ``_last`` and ``_last_gaps`` (q's bytes first, ``_same``)."""

    holds_rows = True  # (ContactSet holds them through its Newton loops: rows_held)
    _held = None  # (m,) bool: the rows held since hold_rows (None: decided at each evaluation)
    _beyond = False  # whether an evaluation since hold_rows kept a row the rule would not

    def hold_rows(self, q: np.ndarray) -> None:
        """Hold the rows that take part at q, and those that take part at any later
        evaluation while they keep a covered weight, until :meth:`release_rows`."""
        self._held, self._beyond = None, False
        self._held = np.isfinite(self.gaps(q))  # (the gaps kept at q, if any, hold there)
        if self._last is not None and not self._same(q, self._last[0]):
            self._last = None  # (decided without the hold at another q)
        if self._last_gaps is not None and not self._same(q, self._last_gaps[0]):
            self._last_gaps = None

    def release_rows(self) -> None:
        """Decide the rows at each evaluation again; the gaps kept stand where the hold kept
        no row beyond the rule (the next step's first evaluation is at the same q)."""
        self._held = None
        if self._beyond:
            self._last = self._last_gaps = None  # (they may have held rows)

    def held_valid(self, valid: np.ndarray, weight: np.ndarray) -> np.ndarray:
        """The rows (m,) that take part: ``valid`` as decided at this evaluation, and while
        held those held with a covered ``weight`` (m,) W_j > 0."""
        if self._held is None:
            return valid
        if (valid & ~self._held).any():  # (a row gained: the gaps kept at another q lack it)
            self._held |= valid
            self._last = self._last_gaps = None
        out = self._held & (weight > 0.0)
        self._beyond = self._beyond or bool(np.any(out != valid))
        return out
