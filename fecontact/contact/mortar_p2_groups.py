r"""The pairs of curved 6-node triangles integrated in groups of equal overlap polygons.

The overlap of a pair is a convex polygon of 3 to 6 vertices cut into a fan of 1 to 4 cells
(:mod:`fecontact.contact.mortar_p2_overlap`), and a batch of pairs is integrated over as many
cells as its largest polygon has, the extra cells of the others with zero area. Their points
cost as much as real ones, and Hessians are (n × n) per point: on a P2 box laid on a P2 slab
the pairs of a Hessian pass had 88 real cells of 153. Integrated in groups of the same number
of cells, every point counts; :func:`merge` puts the groups' results back in the pairs'
order, as one pass over all would have given them (the sums per pair are those of the same
points: equal to round-off).
"""

from __future__ import annotations

import numpy as np

from .dual_numbers import Jet

__all__ = ["merge"]


def _jet(parts, index, P: int) -> Jet:
    """One Jet over P entries from Jets ``parts`` on the entries ``index`` (one array each)."""

    def put(arrays):
        out = np.empty((P, *arrays[0].shape[1:]))
        for a, i in zip(arrays, index, strict=True):
            out[i] = a
        return out

    g = None if parts[0].g is None else put([j.g for j in parts])
    h = None if parts[0].h is None else put([j.h for j in parts])
    return Jet(put([j.v for j in parts]), g, h)


def _padded(arrays, index, P: int) -> np.ndarray:
    """(P, Q, ...) from the groups' (P_i, Q_i, ...) quadrature arrays, zeros past Q_i (points
    of zero weight)."""
    Q = max(a.shape[1] for a in arrays)
    out = np.zeros((P, Q, *arrays[0].shape[2:]))
    for a, i in zip(arrays, index, strict=True):
        out[i, : a.shape[1]] = a
    return out


def merge(results, index, P: int):
    """The results (moments, mass_of, coverage, covered, quad) of
    :func:`~fecontact.contact.mortar_p2_triangles.p2_triangle_integrals` on the groups of
    pairs ``index`` (arrays of the P pairs' indices, together each pair once) as one."""
    moments = [_jet([r[0][k] for r in results], index, P) for k in range(6)]

    def mass_of(part):  # the groups' masses, in the order of the pairs ``part``
        rank = np.cumsum(part) - 1
        taken = [(r[1](part[i]), rank[i[part[i]]]) for r, i in zip(results, index, strict=True)
                 if part[i].any()]  # fmt: skip
        n, at = int(part.sum()), [at for _, at in taken]
        mass = [[None] * 6 for _ in range(6)]
        for k in range(6):
            for l in range(k, 6):  # (symmetric)
                mass[k][l] = mass[l][k] = _jet([m[k][l] for m, _ in taken], at, n)
        return mass

    coverage = np.empty(P)
    covered = np.empty((P, 6))
    for r, i in zip(results, index, strict=True):
        coverage[i], covered[i] = r[2], r[3]
    quad = tuple(_padded([r[4][k] for r in results], index, P) for k in range(3))
    return moments, mass_of, coverage, covered, quad
