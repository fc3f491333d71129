"""Fixed gathers of the Beam3D kernel (:mod:`.beam3d_kernels`): where the rotation matrices of
an element sit in the derivatives of its tangent and in the matrix B of its force, and where the
blocks of the tangent's coefficient matrix come from. Made once per beam (per element count):
with a handful of elements a gather costs one numpy call, where placing blocks one by one costs
one call each."""

from __future__ import annotations

import numpy as np

__all__ = ["coefficient_sources", "element_gather"]


def _places() -> np.ndarray:
    """(46, 288): the flattened (exp(ρ̃), exp(½ρ̃), T(ρ)⁻¹, ½T(½ρ), R_m, 1) of an element @ it
    is Z = (Dρ, Dφ, (0, exp(−½ρ̃), 0, 0), (−R_mᵀ, 0, R_mᵀ, 0)), each (3, 12) flattened (the
    tangent's derivatives), then the (12, 12) matrix B that gives the element force from
    (n̂, p, t, t) and its tangent from their derivatives: their blocks are those matrices,
    transposed, negated, or I."""
    T = np.zeros((6, 3, 3, 4, 3, 12))  # (matrix, its row, column) -> (output, row, column)
    i, j = np.meshgrid(range(3), range(3), indexing="ij")
    T[2, j, i, 0, i, 3 + j] = -1.0  # Dρ = (0, −T(ρ)⁻ᵀ, 0, T(ρ)⁻¹)
    T[2, i, j, 0, i, 9 + j] = 1.0
    T[0, j, i, 1, i, 3 + j] = -1.0  # Dφ = (0, −exp(−ρ̃), 0, I)
    T[5, 0, 0, 1, range(3), range(9, 12)] = 1.0
    T[1, j, i, 2, i, 3 + j] = 1.0  # exp(½ρ̃)ᵀ at θ₀
    T[4, j, i, 3, i, j] = -1.0  # R_mᵀ at x₀ and x₁
    T[4, j, i, 3, i, 6 + j] = 1.0
    B = np.zeros((6, 3, 3, 12, 12))  # f = (−R_m n̂, exp(½ρ̃) p − exp(ρ̃) t, R_m n̂, t)
    B[4, i, j, i, j], B[4, i, j, 6 + i, j] = -1.0, 1.0
    B[1, i, j, 3 + i, 3 + j], B[0, i, j, 3 + i, 6 + j] = 1.0, -1.0
    B[5, 0, 0, range(9, 12), range(9, 12)] = 1.0
    return np.concatenate([T.reshape(54, 144), B.reshape(54, 144)], axis=1)[:46]


def _sources(places: np.ndarray) -> np.ndarray:
    """The places table as a gather: for each output column, the index in (x, 0, −x, −0)
    (x the 46 flattened inputs) of its one input, signed, or of the zero."""
    n = places.shape[0]
    out = np.full(places.shape[1], n)
    for c in range(places.shape[1]):
        (r,) = np.nonzero(places[:, c])
        if r.size:
            assert r.size == 1 and abs(places[r[0], c]) == 1.0
            out[c] = r[0] if places[r[0], c] > 0 else n + 1 + r[0]
    return out


def _signed(sources: np.ndarray, n: int):
    """The gather of :func:`_sources` as the columns of x with 0 appended (index n) and the
    signs to multiply them by (±1: exact): one gather and one product of one shape."""
    negative = sources > n
    return np.where(negative, sources - n - 1, sources), np.where(negative, -1.0, 1.0)


_PLACES, _PLACE_SIGNS = _signed(_sources(_places()), 46)


def element_gather(E: int):
    """The gather of :func:`_places` over E elements, as indices into their flattened inputs
    (E, 47) (the 46 of :func:`_places` and the 0) and its signs (±1), ordered as the
    derivatives Z (E, 12, 12), then B (E, 12, 12)."""
    rows = 47 * np.arange(E)[:, None]
    parts = (slice(None, 144), slice(144, None))
    index = np.concatenate([(rows + _PLACES[p]).ravel() for p in parts])
    return index, np.concatenate([np.tile(_PLACE_SIGNS[p], E) for p in parts])


def coefficient_sources() -> np.ndarray:
    """(144,): the tangent's coefficient matrix C (12, 12) of an element, (dn, dp, dt, Dt) =
    C Z with Z = (Dρ, Dφ, Z₃, Z₄) (the kernel's ``_tangent``), as the index of each entry in
    the element's flattened (C₁ (9, 3), A (9, 3), Q, V Q, −t̃, CG/ℓ, 0) (91 values; blocks
    (3, 3) row by row): the row blocks dn, dp, dt, Dt are

        dn: (C₁ᵈⁿ, 0, Aᵈⁿ, CG/ℓ),  dp: (C₁ᵈᵖ, 0, Aᵈᵖ, Q),
        dt: (C₁ᵗ, −t̃, Aᵗ, V Q),   Dt: (C₁ᵗ, 0, Aᵗ, V Q)."""

    def block(start):
        return start + 3 * np.arange(3)[:, None] + np.arange(3)

    zero = np.full((3, 3), 90)
    rows = [
        [block(0), zero, block(27), block(81)],
        [block(9), zero, block(36), block(54)],
        [block(18), block(72), block(45), block(63)],
        [block(18), zero, block(45), block(63)],
    ]
    return np.block(rows).ravel()
