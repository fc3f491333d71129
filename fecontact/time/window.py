"""The crossings a located impact takes together: a step's closings at Hermite instants τ
(fractions of what is left of the step) within a window of the earliest are one impact, whose
correction closes the others with the last of them at its instant
(:mod:`fecontact.time.localize`, ``TOGETHER``)."""

from __future__ import annotations

import numpy as np

__all__ = ["instants", "last_together"]


def last_together(tau: np.ndarray, within: float) -> int:
    """Which of the crossings at ``tau`` (fractions of the step's rest) the step refines: the
    last of those within ``within`` of the earliest (the correction closes the others with
    it at its instant)."""
    if tau.size == 1:  # (one crossing: most located steps)
        return 0
    together = np.flatnonzero(tau <= tau.min() + within)
    return int(together[np.argmax(tau[together])])


def instants(tau: np.ndarray, within: float) -> int:
    """How many located impacts the crossings at ``tau`` (fractions of the step's rest) take,
    as :func:`last_together` takes them: the earliest with those within ``within`` of it, then
    the earliest left, and so on. Counted by chaining neighbours instead, a dense run of
    closings (a face landing on a slab that sags: 30 rows 1e-5 of the step apart) read as one
    instant where the step needed one for each window."""
    tau, count, start = np.sort(tau), 0, 0
    while start < tau.size:
        count, start = count + 1, int(np.searchsorted(tau, tau[start] + within, "right"))
    return count
