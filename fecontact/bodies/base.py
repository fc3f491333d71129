"""What every body provides to the model, the contacts and the output.

A body owns ``ndof`` consecutive dofs of the model. ``Body`` is the protocol the rest of the
package relies on; ``BodyDefaults`` supplies the answers of a body that lacks a feature (no
elements that can invert, no cell data, not a rigid frame), so that no caller has to ask
whether a method exists.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

from ..errors import InputError, check_count

__all__ = ["BODY", "Body", "BodyDefaults", "EnergyConsistentBody", "RigidDefaults"]

BODY = "a body (Solid, Beam2D, Beam3D, RigidBody2D, RigidBody3D, PointMass, ...)"
"""What an argument that takes a body is, as its error names it."""


@runtime_checkable
class Body(Protocol):
    """The interface of a body: every member the model, the contacts, the steppers, the
    output and the scenes use on a body of any kind (a test checks each body class against
    it). Members a contact pair uses only on the kinds it is registered for (a beam's
    ``segments``, a solid's ``contact_facets``, a rigid body's ``center``) are not part of it.
    """

    # -- sizes and traits, fixed when the body is built
    dim: int  # 2 or 3
    ndof: int
    dofs_per_node: int
    n_nodes: int  # nodes (output points of a rigid body)
    mass: float  # kg, point masses included
    stiffness_volume: float  # ∫E dV (J): Young's modulus over the elastic volume, 0 if rigid
    characteristic_length: float  # m: the size of the body (beam length, box diagonal, ...)
    linear: bool  # internal force affine in q: the iteration matrix is constant
    linear_kinematics: bool  # node positions affine in q
    rigid_frame: bool  # positions x = c + R(φ) r of a rigid frame
    continuum: bool  # an elastic continuum, whose contact zones last over many wave transits
    slender: bool  # a beam: rotations and stretching far above any step it takes (hω ≫ 1)
    energy_consistent: bool  # an ``EnergyConsistentBody`` (the energy-decaying smooth step)
    element_dofs: np.ndarray
    center_index: int | None  # output point of a rigid body's centre of mass
    components: tuple[str, ...]  # names of a node's dofs, in order: x, y, (z | theta)
    fixed: set[int]  # supported dofs, held at zero
    rotation_triples: np.ndarray  # (k, 3) local dofs of rotation vectors ψ (SO(3)), often none

    # -- mechanics
    def internal(self, q: np.ndarray, tangent: bool = True): ...
    def energy(self, q: np.ndarray) -> float: ...
    def mass_matrix(self): ...
    def translation_field(self, vector) -> np.ndarray: ...
    def rigid_modes(self) -> np.ndarray: ...
    def inverted(self, q: np.ndarray) -> bool: ...
    def inertial(self, q: np.ndarray, v: np.ndarray): ...

    # -- nodes, supports and contact points
    def node_index(self, node: int) -> int: ...
    def support(self, node: int, components) -> None: ...
    def contact_nodes(self, nodes=None) -> np.ndarray: ...
    def positions(self, q: np.ndarray) -> np.ndarray: ...
    def point_kinematics(self, q: np.ndarray, nodes: np.ndarray): ...
    def point_positions(self, q: np.ndarray, nodes: np.ndarray) -> np.ndarray: ...
    def nodal(self, x: np.ndarray, q: np.ndarray | None = None) -> np.ndarray: ...

    # -- output
    def point_data(self, q: np.ndarray, v: np.ndarray) -> dict[str, np.ndarray]: ...
    def cell_data(self, q: np.ndarray) -> dict[str, np.ndarray]: ...
    def cells(self) -> list[tuple[str, np.ndarray]]: ...


@runtime_checkable
class EnergyConsistentBody(Body, Protocol):
    """A body whose ``energy_consistent`` is True: the energy-decaying step asks it for the
    force whose work over a step is the change of its strain energy."""

    def element_strains(self, q: np.ndarray) -> np.ndarray: ...
    def algorithmic_force(self, q0, q1, chi: float = 0.0, d=0.0, tangent: bool = True): ...


class BodyDefaults:
    """Defaults of the ``Body`` protocol for bodies without the feature."""

    dim = 2
    linear = False
    rigid_frame = False
    continuum = False
    slender = False
    energy_consistent = False  # has algorithmic_force (the energy-decaying smooth step)
    stiffness_volume = 0.0  # no elastic volume
    center_index = None
    # no rotation vectors: every dof adds (planar rotations, displacements)
    rotation_triples = np.zeros((0, 3), dtype=int)

    def inertial(self, q: np.ndarray, v: np.ndarray):
        """The velocity-dependent inertial force f(q, v) (the gyroscopic Ω × JΩ of rotating
        frames, in the body frame) and its tangent ∂f/∂v, as (f, C_v) on the body's dofs; None:
        the body has no such term (its inertial force is M v̇ alone)."""
        return None

    @property
    def ndof(self) -> int:
        """Dofs of the body: those of a node times the nodes (rigid bodies say their own)."""
        return self.dofs_per_node * self.n_nodes

    def support(self, node: int, components) -> None:
        """Hold ``components`` (names from ``self.components``, or their indices; all when
        empty) of ``node`` at zero: the one vocabulary of every body's ``fix``."""
        names = self.components
        chosen = range(len(names)) if len(components) == 0 else components
        for c in chosen:
            if isinstance(c, str) and c in names:
                c = names.index(c)
            if (
                not isinstance(c, (int, np.integer))
                or isinstance(c, bool)
                or not (0 <= int(c) < len(names))
            ):
                raise InputError(f"components must be among {', '.join(names)}, got {c!r}")
            self.fixed.add(len(names) * node + int(c))

    def point_positions(self, q: np.ndarray, nodes: np.ndarray) -> np.ndarray:
        """Positions (m) of ``nodes``; bodies with a cheaper path than the kinematics override."""
        return self.point_kinematics(q, nodes)[0]

    def inverted(self, q: np.ndarray) -> bool:
        """Whether q inverts an element (only materials that forbid it can say yes)."""
        return False

    def cell_data(self, q: np.ndarray) -> dict[str, np.ndarray]:
        """Per-cell output (stress, strain); none by default."""
        return {}

    def rigid_modes(self) -> np.ndarray:
        """(ndof, k) rigid motions of the body, the near-null space of its stiffness: the d
        translations, then the rotations (1 in 2D, 3 in 3D), here zero columns (bodies with a
        rotation field override)."""
        T = np.column_stack([self.translation_field(e) for e in np.eye(self.dim)])
        return np.hstack([T, np.zeros((T.shape[0], 1 if self.dim == 2 else 3))])


class RigidDefaults(BodyDefaults):
    """Defaults of a rigid body with a ``shape``: no strain energy, and its output points
    (the shape's points and the centre of mass) as its nodes."""

    @property
    def characteristic_length(self) -> float:
        """Size of the shape (m): a disk's or ball's diameter, a polygon's or box's largest
        vertex distance."""
        return self.shape.size

    def node_index(self, node: int) -> int:
        n = self.n_nodes
        return check_count("point", node, -n, n - 1) % n

    def internal(self, q: np.ndarray, tangent: bool = True):
        """No strain energy: (0, zero force, no element tangents)."""
        n = self.ndof
        return 0.0, np.zeros(n), (np.zeros((0, n, n)) if tangent else None)

    def energy(self, q: np.ndarray) -> float:
        return 0.0

    round_contact = "its shape"

    def contact_nodes(self, nodes=None) -> np.ndarray:
        """Validated indices of the shape's vertices that touch (all by default)."""
        n = len(self.shape.vertices)
        if n == 0:
            raise InputError(
                f"a {type(self.shape).__name__} has no vertices: contact it through "
                f"Contact(body, partner), which uses {self.round_contact}"
            )
        if nodes is None:
            return np.arange(n)
        idx = np.atleast_1d(np.asarray(nodes))
        if idx.dtype.kind not in "iu" or np.any(idx < -n) or np.any(idx >= n):
            raise InputError(f"nodes must be vertices of the shape, in [{-n}, {n - 1}]")
        return idx.astype(int) % n
