r"""Ball pairs in space of one kind evaluated together: the gaps, gradients and curvatures over
the pairs at once, the slip rows of the asked rows only, pair by pair.

A heap of rigid balls holds a contact per two balls and per ball and floor, most of them far
apart: the contact set measures every gap at every iteration, and per pair that is mostly
call overhead. The contact set gives a run of consecutive pairs of one ``batch_key`` to one
of these, which returns the pairs' rows stacked in their order, number for number those of
the pairs themselves: the distances and plane gaps are the same per-row products
(:func:`.pair_batches.dot_rows`), the normals and curvatures the same element-wise operations.

The slip rows turn each ball's arm by its rotation, R = exp(ψ̃) per ball, then take a few
3 × 3 products per pair, each of which a stacked form would have to match bit for bit. So
the batch asks its pairs for the slip rows of the rows asked for (the active contacts, a few
of the many pairs) and for nothing else: the numbers are the pairs' own, and no more
rotations are made than by the pairs alone.

==========================  ==================================================================
batch                       pairs (see :mod:`.rigid3d_pairs` for the gaps and slips)
==========================  ==================================================================
``BallBallBatch``           ``BallBallContact``: g = |c_b − c_a| − ρ_a − ρ_b
``BallPlaneBatch``          ``BallsPlaneContact`` of a ``Ball`` on a fixed ``Plane``:
                            g = n·(c − p) − ρ
==========================  ==================================================================
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .pair_batches import PairBatch, dot_rows, frozen

__all__ = ["BallBallBatch", "BallPlaneBatch"]

_XYZ = np.arange(3)
_SIX = np.arange(6)
_EYE3 = np.eye(3)


class _AskedRows(PairBatch):
    """A batch whose slip rows and slips are its pairs', asked for the given rows only."""

    def tangents(self, q: np.ndarray):
        return self.tangent_rows(q, np.arange(self.size))

    def tangent_rows(self, q: np.ndarray, rows: np.ndarray):
        parts = [self.pairs[j].tangents(q) for j in rows]
        return tuple(np.concatenate(p) for p in zip(*parts, strict=True))

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        return self.slip_rows(q, q_n, T, np.arange(self.size))

    def slip_rows(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray, rows: np.ndarray):
        pairs = self.pairs
        return np.concatenate([pairs[j].slips(q, q_n, T[i : i + 1]) for i, j in enumerate(rows)])


class BallBallBatch(_AskedRows):
    """``BallBallContact`` pairs together: gaps, gradients (m, 12), curvatures (m, 12, 12) over
    (u, Θ) of a then b; the curvature acts on the centres alone."""

    def __init__(self, pairs):
        super().__init__(pairs)
        oa = np.array([pair.offsets[0] for pair in self.pairs], int)[:, None]
        ob = np.array([pair.offsets[1] for pair in self.pairs], int)[:, None]
        self._xa, self._xb = oa + _XYZ, ob + _XYZ
        self._pa = np.array([pair.bodies[0].position for pair in self.pairs], float)
        self._pb = np.array([pair.bodies[1].position for pair in self.pairs], float)
        self._radii = np.array([pair.radii for pair in self.pairs], float)
        self._dofs = frozen(np.hstack([oa + _SIX, ob + _SIX]))

    def _normals(self, q: np.ndarray):
        """Unit normals n (m, 3) from a's centre to b's and the distances d (m,)."""
        x = (self._pb + q[self._xb]) - (self._pa + q[self._xa])
        d = np.sqrt(dot_rows(x, x))
        if not d.all():
            raise InputError("two balls share their centre: no contact normal")
        return x / d[:, None], d

    def gaps(self, q: np.ndarray) -> np.ndarray:
        return self._normals(q)[1] - self._radii

    def evaluate(self, q: np.ndarray):
        n, d = self._normals(q)
        K = (_EYE3 - n[:, :, None] * n[:, None, :]) / d[:, None, None]
        G = np.zeros((self.size, 12))
        G[:, :3], G[:, 6:9] = -n, n
        H = np.zeros((self.size, 12, 12))
        H[:, :3, :3] = H[:, 6:9, 6:9] = K
        H[:, :3, 6:9] = H[:, 6:9, :3] = -K
        return d - self._radii, self._dofs, G, H


class BallPlaneBatch(_AskedRows):
    """``BallsPlaneContact`` pairs of ``Ball`` bodies (one ball at the centre) on fixed
    ``Plane`` obstacles together: gaps, gradients (m, 6) over (u, Θ), no curvature (the
    pairs' is zero: the ball's centre is its body's)."""

    def __init__(self, pairs):
        super().__init__(pairs)
        offsets = np.array([pair.offset for pair in self.pairs], int)[:, None]
        self._x = offsets + _XYZ
        self._p = np.array([pair.body.position for pair in self.pairs], float)
        self._r = np.array([pair.radius for pair in self.pairs], float)
        self._point = np.array([pair.obstacle.point for pair in self.pairs], float)
        self._normal = np.array([pair.obstacle.normal for pair in self.pairs], float)
        self._dofs = frozen(offsets + _SIX)
        G = np.zeros((self.size, 6))
        G[:, :3] = self._normal
        self._G = frozen(G)

    def gaps(self, q: np.ndarray) -> np.ndarray:
        c = self._p + q[self._x]
        return dot_rows(c - self._point, self._normal) - self._r

    def evaluate(self, q: np.ndarray):
        return self.gaps(q), self._dofs, self._G.copy(), None
