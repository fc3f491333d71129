r"""Disk pairs of one kind evaluated together: every array over the pairs at once.

A model of many rigid disks (a pile in a box) holds a contact per pair of disks and per disk
and wall: hundreds of one-row pairs whose per-pair evaluation is mostly call overhead (a
4 × 4 Hessian built with ``np.block`` cost 0.28 ms a pair). The contact set gives a run of
consecutive pairs of one ``batch_key`` to one of these, which returns the pairs' rows stacked
in their order, number for number those of the pairs themselves: the distances and plane
gaps are the same per-row products (``np.matmul`` over a stack of 1 × 2 rows, as
``np.linalg.norm`` and the plane's product take them per pair), so no result moves.

==========================  ==================================================================
batch                       pairs (see :mod:`.rigid_pairs` for the gaps and slips)
==========================  ==================================================================
``DiskDiskBatch``           ``DiskDiskContact``: g = |c_b − c_a| − r_a − r_b
``DiskPlaneBatch``          ``DiskObstacleContact`` on a fixed ``Plane``: g = n·(c − p) − r
==========================  ==================================================================
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .pair_batches import PairBatch, dot_rows, frozen

__all__ = ["DiskDiskBatch", "DiskPlaneBatch"]

_XY = np.arange(2)
_XYT = np.arange(3)


class DiskDiskBatch(PairBatch):
    """``DiskDiskContact`` pairs together: gaps, gradients (m, 4), Hessians (m, 4, 4) over
    (x, y) of a then b, and slip rows over (x, y, θ) of a then b."""

    def __init__(self, pairs):
        super().__init__(pairs)
        a = [pair.bodies[0] for pair in self.pairs]
        b = [pair.bodies[1] for pair in self.pairs]
        oa = np.array([pair.offsets[0] for pair in self.pairs], int)[:, None]
        ob = np.array([pair.offsets[1] for pair in self.pairs], int)[:, None]
        self._xa, self._xb = oa + _XY, ob + _XY
        self._pa = np.array([body.position for body in a], float)
        self._pb = np.array([body.position for body in b], float)
        self._ra = np.array([body.shape.radius for body in a], float)
        self._rb = np.array([body.shape.radius for body in b], float)
        self._dofs = frozen(np.hstack([self._xa, self._xb]))
        self._slip_dofs = frozen(np.hstack([oa + _XYT, ob + _XYT]))

    def _normals(self, q: np.ndarray):
        """Unit normals e (m, 2) from a's centre to b's and the distances d (m,)."""
        x = (self._pb + q[self._xb]) - (self._pa + q[self._xa])
        d = np.sqrt(dot_rows(x, x))
        if not d.all():
            raise InputError("disk centres coincide: contact normal undefined")
        return x / d[:, None], d

    def gaps(self, q: np.ndarray) -> np.ndarray:
        d = self._normals(q)[1]
        return d - self._ra - self._rb

    def evaluate(self, q: np.ndarray):
        e, d = self._normals(q)
        K = (np.eye(2) - e[:, :, None] * e[:, None, :]) / d[:, None, None]
        H = np.empty((self.size, 4, 4))
        H[:, :2, :2] = H[:, 2:, 2:] = K
        H[:, :2, 2:] = H[:, 2:, :2] = -K
        return d - self._ra - self._rb, self._dofs, np.hstack([-e, e]), H

    def tangents(self, q: np.ndarray):
        e = self._normals(q)[0]
        t = np.stack([e[:, 1], -e[:, 0]], axis=1)
        GT = np.hstack([-t, self._ra[:, None], t, self._rb[:, None]])
        return self._slip_dofs, GT[:, None, :], t[:, None, :]


class DiskPlaneBatch(PairBatch):
    """``DiskObstacleContact`` pairs on fixed ``Plane`` obstacles together: gaps, gradients
    (m, 2) over the centre, no curvature, slip rows over (x, y, θ) of the disk."""

    def __init__(self, pairs):
        super().__init__(pairs)
        offsets = np.array([pair.offsets[0] for pair in self.pairs], int)[:, None]
        self._x = offsets + _XY
        self._p = np.array([pair.body.position for pair in self.pairs], float)
        self._r = np.array([pair.body.shape.radius for pair in self.pairs], float)
        self._point = np.array([pair.obstacle.point for pair in self.pairs], float)
        self._normal = np.array([pair.obstacle.normal for pair in self.pairs], float)
        self._dofs = frozen(self._x.copy())
        self._slip_dofs = frozen(offsets + _XYT)
        t = np.stack([self._normal[:, 1], -self._normal[:, 0]], axis=1)[:, None, :]
        self._T = frozen(t)
        self._GT = frozen(np.concatenate([t, self._r[:, None, None]], axis=2))

    def gaps(self, q: np.ndarray) -> np.ndarray:
        c = self._p + q[self._x]
        return dot_rows(c - self._point, self._normal) - self._r

    def evaluate(self, q: np.ndarray):
        return self.gaps(q), self._dofs, self._normal.copy(), None

    def tangents(self, q: np.ndarray):
        return self._slip_dofs, self._GT, self._T
