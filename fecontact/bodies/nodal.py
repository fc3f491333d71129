"""Bodies whose dofs are the translations of their nodes: x = X + u, node by node.

Node lookup, supports, positions and point kinematics of such a body, shared by every body
on a mesh whose unknowns are nodal displacements (elastic solids).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .base import BodyDefaults

__all__ = ["NodalTranslations"]


class NodalTranslations(BodyDefaults):
    """A body with reference node coordinates ``X`` (n, d) in m and the displacements u of its
    nodes as dofs, ordered node by node: dof = d·node + component."""

    X: np.ndarray
    dim: int
    fixed: set[int]
    linear_kinematics = True
    """Node positions are linear in the dofs (x = X + u)."""

    # -- nodes and supports ------------------------------------------------------------------
    def node_index(self, node: int) -> int:
        """Validated node index in [0, n_nodes); negative indices count from the end."""
        n = self.n_nodes
        if not _is_int(node) or not -n <= int(node) < n:
            raise InputError(f"node must be an integer in [{-n}, {n - 1}], got {node!r}")
        return int(node) % n

    def nodes_of(self, nodes) -> np.ndarray:
        """Validated node indices of one node or a sequence of them."""
        return np.array([self.node_index(i) for i in np.atleast_1d(nodes).ravel()], dtype=int)

    @property
    def components(self) -> tuple[str, ...]:
        return ("x", "y", "z")[: self.dim]

    def fix(self, nodes, *components, **keywords) -> NodalTranslations:
        """Hold the displacement ``components`` ("x", "y", "z", or 0, 1, 2; all when none are
        given) of ``nodes`` at zero. ``components=`` as a keyword takes one or a sequence."""
        if "components" in keywords:
            components = (*components, *np.atleast_1d(keywords.pop("components")).tolist())
        if keywords:
            raise InputError(f"fix: unknown argument {next(iter(keywords))!r}")
        for i in self.nodes_of(nodes):
            self.support(int(i), components)
        return self

    def nodes_where(self, condition) -> np.ndarray:
        """Nodes whose reference coordinates satisfy ``condition(x)``; x has shape (d, n) as in
        scikit-fem (``lambda x: x[1] < 1e-9``: the nodes on y = 0)."""
        mask = np.asarray(condition(self.X.T), dtype=bool)
        if mask.shape != (self.n_nodes,):
            raise InputError(f"condition must return {self.n_nodes} booleans, got {mask.shape}")
        return np.flatnonzero(mask)

    # -- sizes -------------------------------------------------------------------------------
    @property
    def dofs_per_node(self) -> int:
        return self.dim

    @property
    def n_nodes(self) -> int:
        return len(self.X)

    linear_kinematics = True
    """Node positions are linear in the dofs (x = X + u)."""

    @property
    def characteristic_length(self) -> float:
        """Diagonal of the bounding box of the reference configuration, m."""
        return float(np.linalg.norm(self.X.max(axis=0) - self.X.min(axis=0)))

    def positions(self, q: np.ndarray) -> np.ndarray:
        """Current node coordinates X + u (m), shape (n_nodes, d)."""
        return self.X + np.asarray(q).reshape(-1, self.dim)

    def nodal(self, x: np.ndarray, q: np.ndarray | None = None) -> np.ndarray:
        """A dof vector viewed per node, (n_nodes, d)."""
        return np.asarray(x).reshape(-1, self.dim)

    def node_translation_dofs(self, nodes) -> np.ndarray:
        """(len(nodes), d) local dof indices of the displacement of ``nodes``."""
        return self.dim * self.nodes_of(nodes)[:, None] + np.arange(self.dim)

    def point_kinematics(self, q: np.ndarray, nodes: np.ndarray):
        """Positions x (m, d) of ``nodes``, their local dofs (m, d), ∂x/∂q (m, d, d) and
        ∂²x/∂q² (None: linear)."""
        dofs = self.dim * nodes[:, None] + np.arange(self.dim)
        x = self.X[nodes] + q[dofs]
        return x, dofs, np.repeat(np.eye(self.dim)[None], len(nodes), axis=0), None

    def rigid_modes(self) -> np.ndarray:
        """(ndof, k) rigid motions: the d translations, then the rotations ω × (X − X̄) about
        the node centroid X̄ for ω = e_z (2D) or e_x, e_y, e_z (3D); dimensionless, m/rad."""
        Xc = self.X - self.X.mean(axis=0)
        n, d = Xc.shape
        T = np.tile(np.eye(d), (n, 1))
        if d == 2:
            R = np.column_stack([-Xc[:, 1], Xc[:, 0]]).reshape(-1, 1)
        else:
            R = np.stack([np.cross(w, Xc).ravel() for w in np.eye(3)], axis=1)
        return np.hstack([T, R])

    def point_data(self, q: np.ndarray, v: np.ndarray) -> dict[str, np.ndarray]:
        """Nodal fields for output: ``displacement`` (m) and ``velocity`` (m/s), (n_nodes, d)."""
        return {"displacement": self.nodal(q), "velocity": self.nodal(v)}


def _is_int(value) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))
