"""Bodies on a centreline of nodes, the beams in the plane and in space: node lookup, supports,
contact nodes and line cells, shared by :class:`~fecontact.bodies.Beam2D` and
:class:`~fecontact.bodies.Beam3D`."""

from __future__ import annotations

import numpy as np

from ..errors import InputError, check_count, check_finite
from .base import BodyDefaults

__all__ = ["Centreline", "centreline_nodes"]


def centreline_nodes(nodes, dim: int) -> tuple[np.ndarray, np.ndarray]:
    """The nodes (n ≥ 2, ``dim``) of a centreline, checked finite and distinct in sequence,
    and its element lengths (m)."""
    X = check_finite("nodes", nodes)
    if X.ndim != 2 or X.shape[1] != dim or X.shape[0] < 2:
        raise InputError(f"nodes must be an (n >= 2, {dim}) array, got shape {X.shape}")
    seg = np.linalg.norm(np.diff(X, axis=0), axis=1)
    if np.any(seg <= 1e-12 * seg.sum()):
        k = int(np.argmin(seg))
        raise InputError(f"nodes: element {k} has zero length (nodes {k} and {k + 1})")
    return X, seg


class Centreline(BodyDefaults):
    """A body whose nodes ``X`` (n, d), m, lie along a centreline cut into elements ``_el``
    (node indices ``n0``, ``n1``); every node carries translations and a rotation."""

    X: np.ndarray
    length: float  # m, of the centreline
    slender = True

    @property
    def n_nodes(self) -> int:
        return len(self.X)

    @property
    def beam_mass(self) -> float:
        """Mass of the beam without point masses, kg."""
        return self.material.rho * self.section.area * self.length

    @property
    def stiffness_volume(self) -> float:
        """∫E dV of the beam (J)."""
        return self.material.E * self.section.area * self.length

    @property
    def mass(self) -> float:
        """Mass of the beam with its point masses, kg."""
        return self.beam_mass + float(self.point_masses.sum())

    @property
    def characteristic_length(self) -> float:
        """Length of the centreline, m."""
        return self.length

    def node_index(self, node: int) -> int:
        n = len(self.X)
        return check_count("node", node, -n, n - 1) % n

    def fix(self, node: int, *components):
        """Hold ``components`` (names from ``components`` or their indices; all when none are
        given) of ``node`` at zero."""
        self.support(self.node_index(node), components)
        return self

    def clamp(self, node: int):
        """Fix the displacement and the rotation of ``node``: ``fix(node)``."""
        return self.fix(node)

    def contact_nodes(self, nodes=None) -> np.ndarray:
        """Validated node indices (all nodes when ``nodes`` is None)."""
        if nodes is None:
            return np.arange(self.n_nodes)
        return np.array([self.node_index(i) for i in np.atleast_1d(nodes)], dtype=int)

    def segments(self) -> np.ndarray:
        """(n_elements, 2) node indices of the centreline segments."""
        return np.stack([self._el.n0, self._el.n1], axis=1)

    def cells(self) -> list[tuple[str, np.ndarray]]:
        """Cells for VTU output: the centreline as ``line`` cells."""
        return [("line", self.segments())]
