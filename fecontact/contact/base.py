"""What every contact pair provides to the contact set, and every obstacle to the output.

A pair holds ``size`` contacts; ``evaluate(q)`` gives their gaps g (m), dofs, gradients and
curvatures. ``PairDefaults`` answers for pairs without a rigid obstacle or without a cheaper
path to the gaps alone, so that the contact set never asks whether a method exists.
"""

from __future__ import annotations

import numpy as np

__all__ = ["PairDefaults"]


class PairDefaults:
    """Defaults of a contact pair: no rigid obstacle, obstacles at rest."""

    obstacle = None
    lazy_hessians = False  # True: evaluate() leaves H out; hessians(q, rows) gives it

    def gaps(self, q: np.ndarray) -> np.ndarray:
        """The gaps g_j(q) (m) alone; pairs with a cheaper path than ``evaluate`` override."""
        return self.evaluate(q)[0]

    def hessians(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """∇²g_j (len(rows), k, k) of the contacts ``rows`` (the pair's own numbering)."""
        return self.evaluate(q)[3][rows]

    def rate(self, q: np.ndarray) -> np.ndarray:
        """∂g_j/∂t (m/s) from a moving obstacle; zero for obstacles at rest."""
        return np.zeros(self.size)
