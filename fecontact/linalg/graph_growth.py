"""How fast the graph of a sparse matrix grows: the dimension its factorization behaves in.

A sparse factorization of a planar mesh (a 2D body, a thin slab) fills in far less than one of
a volume mesh: nested dissection costs n^{3/2} operations on a planar graph and n² on a 3D one,
and the sparse solver choice's estimate of a factorization (:mod:`.choice`) differs by that.
Which of the two a matrix is, the mesh's dimension does not say (a slab of two layers of
tetrahedra factorizes like a 2D mesh), its graph does: the unknowns within graph distance r of
an unknown grow like r^d on a d-dimensional mesh. :func:`graph_growth` counts them breadth
first from one row until ``GROWTH_UNKNOWNS`` are reached and returns d from the last doubling
of r. Measured (docs/validation/large_solids.md): 1.64–2.02 on 2D disks and squares in P1 and
P2 and on slabs of 2 and 5 layers of tetrahedra, 2.41–3.04 on a ball, cubes (tetrahedra in P1
and P2, hexahedra) and a slab of 10 layers, 20,577 to 66,050 unknowns, from any of four
starting rows; a few milliseconds (2–37 products with the matrix).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["GROWTH_UNKNOWNS", "PLANAR_GROWTH", "graph_growth"]

GROWTH_UNKNOWNS = 3000
"""Unknowns counted breadth first: at 1,000 the volume meshes' few levels (3–6) read 2.31–2.51,
too near the planar meshes' 2.0; at 3,000 (4–9 levels in 3D) the two groups lie 0.39 apart."""

PLANAR_GROWTH = 2.25
"""Growth below which a graph factorizes like a planar one: halfway between the largest reading
of a planar mesh (2.02) and the smallest of a volume one (2.41)."""


def graph_growth(A) -> float | None:
    """The growth exponent d of the graph of the structurally symmetric sparse A (CSR or CSC)
    around its middle row, or None when A is too small to tell (fewer than 4 ×
    ``GROWTH_UNKNOWNS`` rows: the count would reach the mesh's boundary) or the middle row's
    component holds fewer than ``GROWTH_UNKNOWNS`` (a small body's)."""
    n = A.shape[0]
    if n < 4 * GROWTH_UNKNOWNS:
        return None
    indptr, indices = A.indptr, A.indices
    seen = np.zeros(n, dtype=bool)
    front = np.array([n // 2])
    seen[front] = True
    within = [1]  # unknowns within distance 0, 1, 2, …
    while within[-1] < GROWTH_UNKNOWNS and front.size:
        starts, lengths = indptr[front], indptr[front + 1] - indptr[front]
        offsets = np.repeat(starts - np.cumsum(lengths) + lengths, lengths)
        near = np.unique(indices[offsets + np.arange(lengths.sum())])
        front = near[~seen[near]]
        seen[front] = True
        within.append(within[-1] + front.size)
    r = len(within) - 1
    if within[-1] < GROWTH_UNKNOWNS or r < 2:
        return None
    half = r // 2
    return math.log(within[r] / within[half]) / math.log(r / half)
