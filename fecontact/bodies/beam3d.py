r"""Spatial geometrically exact (Simo–Reissner) beam: axial, two shears, torsion and two
bendings, with large rotations.

Each node carries its displacement (u_x, u_y, u_z) in m and its rotation vector ψ (rad,
|ψ| ≤ π) from the reference configuration, R = exp(ψ̃); the section frame is R Λ₀, Λ₀ the
reference triad of an element (tangent, section axis 2, axis 3). Rotation increments and the
angular velocities Ω of the nodes are in the frame R (right composition, R exp(Δ̃)), the
convention of :mod:`fecontact.rotations`; moments on the rotation dofs are in that frame too.

Linear two-node elements with the one-point rule for the stiffness (free of shear locking, as
:class:`~fecontact.bodies.beam.Beam2D`), with Crisfield & Jelenić's objective interpolation of
the rotations (:mod:`.beam3d_kernels`). The mass matrix is constant and consistent, as Beam2D's:
ρA on the translations and Λ₀ diag(J₁, J₂, J₃) Λ₀ᵀ per length on the rotations (by default
ρ(I₂ + I₃, I₂, I₃)), plus point masses and inertias. A beam in the x–y plane (section axis 3
along z) moving in that plane has Beam2D's strains, energy, in-plane mass blocks and internal
force.

The velocity-dependent inertial force of the rotations, the gyroscopic term, is the one of
that consistent rotational mass M: Ω_a × (M Ω)_a on node a (:mod:`.beam3d_inertia`), so that
the pair conserves the kinetic energy and the angular momentum of the mass matrix.
"""

from __future__ import annotations

import importlib.util
import os

import numpy as np
import scipy.sparse as sp

from ..errors import InputError, check_count, check_finite, check_kind, check_positive
from ..linalg import DENSE_LIMIT
from .beam import BEAM_MATERIAL, BEAM_SECTION, Material, Section
from .beam3d_inertia import Gyroscopic, consistent_mass, lumped_inertias
from .beam3d_kernels import (
    Beam3DElements,
    beam3d_energy,
    beam3d_internal,
    beam3d_strains,
    reference_triads,
    rotation_matrices,
)
from .centreline import Centreline, centreline_nodes

__all__ = ["KERNELS", "Beam3D", "kernel_choice"]

_EYE3 = np.eye(3)[None]
KERNELS = ("auto", "numpy", "jit")


def _numba_installed() -> bool:
    """Whether numba can be found (it is imported only where a beam runs the jit kernel)."""
    try:
        return importlib.util.find_spec("numba") is not None
    except ImportError:  # a finder that refuses it (an environment that hides the extras)
        return False


_NUMBA = _numba_installed()


def kernel_choice(kernel: str | None) -> str:
    """The element kernel a beam runs, "numpy" or "jit" (:mod:`.beam3d_jit`), of ``kernel``
    ("auto": jit where numba is installed; None: the environment's
    ``FECONTACT_BEAM3D_KERNEL``, else "auto"). Raises InputError for another name, or for
    "jit" without numba."""
    if kernel is None:
        kernel = os.environ.get("FECONTACT_BEAM3D_KERNEL", "auto")
    if kernel not in KERNELS:
        raise InputError(f"kernel must be one of {KERNELS}, got {kernel!r}")
    if kernel == "jit" and not _NUMBA:
        raise InputError('kernel "jit" needs numba; it comes with: pip install "fecontact[jit]"')
    if kernel == "auto":
        return "jit" if _NUMBA else "numpy"
    return kernel


def _kernel_functions(kernel: str):
    """(internal, energy) of the kernel "numpy" or "jit"."""
    if kernel == "numpy":
        return beam3d_internal, beam3d_energy
    from .beam3d_jit import jit_energy, jit_internal  # (numba imported only when used)

    return jit_internal, jit_energy


class Beam3D(Centreline):
    """Spatial Simo–Reissner beam through ``nodes`` (an (n, 3) array in m, in order).

    ``orientation``: a vector fixing each section's axis 2 (its part normal to the element);
    default e_z × tangent, so that a beam in the x–y plane has axis 2 in the plane and axis 3
    along z (the section's ``inertia`` bends it in the plane, as Beam2D). ``rotary_inertia``:
    the section's rotary inertia per length about its axes 1, 2, 3 (kg·m), default
    ρ(I₂ + I₃, I₂, I₃). ``kernel``: the element kernel, "numpy", "jit" (compiled with numba:
    :mod:`.beam3d_jit`) or "auto" (jit where numba imports), decided here for the beam's life
    (None: the environment's ``FECONTACT_BEAM3D_KERNEL``, else "auto"). Supports (``pin``,
    ``clamp``, ``fix``) and point masses (``add_mass``) are chainable; node indices may be
    negative. Dofs node by node: (u_x, u_y, u_z, ψ_x, ψ_y, ψ_z).
    """

    dim = 3
    dofs_per_node = 6
    components = ("x", "y", "z", "rx", "ry", "rz")
    slender = True
    linear_kinematics = True

    def __init__(
        self,
        nodes,
        material: Material,
        section: Section,
        orientation=None,
        rotary_inertia=None,
        kernel: str | None = None,
    ):
        X, seg = centreline_nodes(nodes, 3)
        check_kind("material", material, Material, BEAM_MATERIAL)
        check_kind("section", section, Section, BEAM_SECTION)
        if orientation is not None:
            orientation = check_finite("orientation", orientation)
            if orientation.shape != (3,) or not np.linalg.norm(orientation) > 0:
                raise InputError(f"orientation must be a nonzero 3-vector, got {orientation!r}")
        try:
            triads = reference_triads(X, orientation)
        except ValueError:
            raise InputError("orientation must not be parallel to an element") from None
        self.X, self.material, self.section = X, material, section
        self.length = float(seg.sum())
        self.fixed: set[int] = set()
        self.point_masses = np.zeros(len(X))
        self.point_inertias = np.zeros((len(X), 3, 3))
        m, s = material, section
        GA = m.G * s.area * s.shear_factor
        C = (m.E * s.area, GA, GA, m.G * s.torsion, m.E * s.inertia_2, m.E * s.inertia)
        self._el = Beam3DElements.of(X, triads, C)
        self._node_triads = np.concatenate([triads, triads[-1:]])  # (section_frames)
        # Λ₀ diag(J₁, J₂, J₃) Λ₀ᵀ per element: the rotary inertia per length in frame R
        J = np.diag(self._section_inertia(rotary_inertia))
        self._J = np.einsum("eij,jk,elk->eil", triads, J, triads)
        self._gyroscopic = Gyroscopic(self._el, len(X), dense=6 * len(X) <= DENSE_LIMIT)
        self._rotary = None  # the rotary mass (Gyroscopic.mass), made when first asked
        self.kernel = kernel_choice(kernel)  # "numpy" or "jit", for the beam's life
        self._internal, self._energy = _kernel_functions(self.kernel)

    def _section_inertia(self, given) -> np.ndarray:
        """Rotary inertia per length (kg·m) about the section axes: ``given`` (3 values ≥ 0),
        or ρ(I₂ + I₃, I₂, I₃) of the section."""
        s, rho = self.section, self.material.rho
        if given is None:
            return rho * np.array([s.inertia_2 + s.inertia, s.inertia_2, s.inertia])
        J = check_finite("rotary_inertia", given)
        if J.shape != (3,) or np.any(J < 0):
            raise InputError(f"rotary_inertia must be 3 values >= 0 (kg·m), got {given!r}")
        return J

    @classmethod
    def straight(
        cls,
        start,
        end,
        n_elements: int,
        material,
        section,
        orientation=None,
        rotary_inertia=None,
        kernel=None,
    ):
        """Straight beam from ``start`` to ``end`` (m) with ``n_elements`` equal elements
        (``rotary_inertia`` and ``kernel`` as the constructor's)."""
        n = check_count("n_elements", n_elements)
        a, b = check_finite("start", start), check_finite("end", end)
        if a.shape != (3,) or b.shape != (3,):
            raise InputError("start and end must be 3-vectors (x, y, z) in m")
        if np.linalg.norm(b - a) == 0.0:
            raise InputError("length must be > 0: start and end coincide")
        s = np.linspace(0.0, 1.0, n + 1)[:, None]
        return cls(a + s * (b - a), material, section, orientation, rotary_inertia, kernel)

    @classmethod
    def arc(cls, radius, angle, n_elements, material, section, orientation=None):
        """Circular arc of ``radius`` (m) and ``angle`` (rad) in the x–y plane about the
        origin, from (R, 0, 0) counter-clockwise, with ``n_elements`` equal chords."""
        r = check_positive("radius", radius)
        a = check_positive("angle", angle)
        t = np.linspace(0.0, a, check_count("n_elements", n_elements) + 1)
        nodes = np.column_stack([r * np.cos(t), r * np.sin(t), np.zeros_like(t)])
        return cls(nodes, material, section, orientation)

    # -- supports and masses ---------------------------------------------------------------
    def pin(self, node: int) -> Beam3D:
        """Spherical support: fix the displacement of ``node``, its rotation free."""
        return self.fix(node, "x", "y", "z")

    def add_mass(self, node: int, mass: float, inertia=0.0) -> Beam3D:
        """Attach a point mass (kg) to the translations of ``node`` and a rotary ``inertia``
        (kg·m², a scalar for a sphere's or a (3, 3) tensor in the reference frame)."""
        i = self.node_index(node)
        self.point_masses[i] += check_positive("mass", mass, allow_zero=True)
        J = check_finite("inertia", inertia)
        J = float(J) * np.eye(3) if J.ndim == 0 else J
        if J.shape != (3, 3) or np.any(np.linalg.eigvalsh(0.5 * (J + J.T)) < 0):
            raise InputError("inertia must be >= 0, or a symmetric positive (3, 3) tensor")
        self.point_inertias[i] += J
        self._rotary = None
        return self

    # -- sizes ------------------------------------------------------------------------------
    @property
    def elements(self) -> Beam3DElements:
        """The elements' kernel data (:mod:`fecontact.bodies.beam3d_kernels`)."""
        return self._el

    @property
    def element_dofs(self) -> np.ndarray:
        """(n_elements, 12) local dof indices of each element."""
        return self._el.dofs

    @property
    def rotation_triples(self) -> np.ndarray:
        """(n, 3) local indices of the nodes' rotation dofs ψ: composed on the right."""
        return 6 * np.arange(self.n_nodes)[:, None] + np.arange(3, 6)

    # -- mechanics --------------------------------------------------------------------------
    def strains(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Γ (axial, shear 2, shear 3) and K (torsion, bending 2, bending 3; 1/m) of every
        element, (E, 3) each, in its section frame at the midpoint."""
        return beam3d_strains(self._el, self.X, q)

    def energy(self, q: np.ndarray) -> float:
        """Strain energy W(q) in J."""
        return self._energy(self._el, self.X, q)

    def internal(self, q: np.ndarray, tangent: bool = True):
        """Strain energy (J), internal force (N; N·m in the nodes' frames R) and the element
        tangents ∂f(q ⊕ Δ)/∂Δ (E, 12, 12), not symmetric away from equilibrium."""
        return self._internal(self._el, self.X, q, self.ndof, tangent)

    def mass_matrix(self) -> sp.csr_matrix:
        """Constant consistent mass (kg, kg·m²): ρA and ρJ_e (frame R) with the P1 mass ℓ/6
        [[2, 1], [1, 2]] per element, plus the point masses and inertias."""
        rhoA = self.material.rho * self.section.area
        return consistent_mass(self._el, rhoA, self._J, self.point_masses, self.point_inertias)

    def nodal_inertias(self) -> np.ndarray:
        """(n, 3, 3) lumped rotary inertias of the nodes in their frames R (kg·m²): the rows of
        the consistent rotational mass summed, plus the point inertias."""
        return lumped_inertias(self._el, self._J, self.point_inertias)

    def inertial(self, q: np.ndarray, v: np.ndarray):
        """Gyroscopic force Ω_a × (M Ω)_a on the rotation dofs (N·m, frame R; zero on
        translations), M the consistent rotational mass, and its tangent ∂f/∂v (sparse,
        ndof × ndof)."""
        if self._rotary is None:
            self._rotary = self._gyroscopic.mass(self._el, self._J, self.point_inertias)
        return self._gyroscopic(self._rotary, np.asarray(v, float))

    def translation_field(self, vector) -> np.ndarray:
        """Nodal dof vector with ``vector`` on every translation and 0 on the rotations."""
        f = np.zeros((self.n_nodes, 6))
        f[:, :3] = vector
        return f.ravel()

    def rigid_modes(self) -> np.ndarray:
        """(ndof, 6) rigid motions: translations along x, y, z, then the rotations about the
        axes through the node centroid (u = e_k × (X − X̄), ψ = e_k)."""
        Xc = self.X - self.X.mean(axis=0)
        T = [self.translation_field(e) for e in np.eye(3)]
        R = []
        for e in np.eye(3):
            f = np.zeros((self.n_nodes, 6))
            f[:, :3], f[:, 3:] = np.cross(e, Xc), e
            R.append(f.ravel())
        return np.column_stack([*T, *R])

    # -- geometry and output ----------------------------------------------------------------
    def positions(self, q: np.ndarray) -> np.ndarray:
        """Current node coordinates X + u (m), shape (n, 3)."""
        return self.X + q.reshape(-1, 6)[:, :3]

    def point_kinematics(self, q: np.ndarray, nodes: np.ndarray):
        """Positions x (m, 3) of ``nodes``, their local dofs (m, 3), ∂x/∂q (m, 3, 3) and
        ∂²x/∂q² (None: linear)."""
        dofs = 6 * nodes[:, None] + np.arange(3)
        return self.X[nodes] + q[dofs], dofs, np.repeat(_EYE3, len(nodes), axis=0), None

    def section_turns(self, q: np.ndarray, nodes: np.ndarray, arms: np.ndarray):
        """Local dofs (m, 3) of the rotations at ``nodes`` and ∂ẋ_p/∂Ω (m, 3, 3) of the
        material points x_p = x + arm of their sections (``arms`` (m, 3), m): the spatial
        angular velocity is RΩ (Ω the velocities of the rotation dofs, composed on the
        right), so ẋ_p = ẋ + RΩ × arm and the block is −arm̃ R, whose columns are R_k × arm."""
        dofs = 6 * nodes[:, None] + np.arange(3, 6)
        R = rotation_matrices(q.reshape(-1, 6)[nodes, 3:])
        return dofs, np.cross(R.transpose(0, 2, 1), arms[:, None, :]).transpose(0, 2, 1)

    def section_points_before(self, q, q_n, nodes: np.ndarray, arms: np.ndarray) -> np.ndarray:
        """Where the material points now at x + arm (``arms`` (m, 3)) of the sections at
        ``nodes`` were at q_n: x_n + R_n Rᵀ arm (m, 3), exact for a rigid turn of the section."""
        Q, Qn = q.reshape(-1, 6)[nodes], q_n.reshape(-1, 6)[nodes]
        R, Rn = rotation_matrices(Q[:, 3:]), rotation_matrices(Qn[:, 3:])
        back = np.einsum("mij,mkj,mk->mi", Rn, R, arms)
        return self.X[nodes] + Qn[:, :3] + back

    def node_translation_dofs(self, nodes) -> np.ndarray:
        """(len(nodes), 3) local dof indices of (u_x, u_y, u_z) at ``nodes``."""
        return 6 * self.contact_nodes(nodes)[:, None] + np.arange(3)

    def nodal(self, x: np.ndarray, q: np.ndarray | None = None) -> np.ndarray:
        """Translation part (n, 3) of a nodal dof vector (displacement, velocity, force)."""
        return x.reshape(-1, 6)[:, :3]

    def section_frames(self, q: np.ndarray) -> np.ndarray:
        """(n, 3, 3) section frames R Λ₀ of the nodes (columns: tangent, axis 2, axis 3),
        Λ₀ that of the element starting at the node (the last element's at the last node)."""
        return rotation_matrices(q.reshape(-1, 6)[:, 3:]) @ self._node_triads

    def point_data(self, q: np.ndarray, v: np.ndarray) -> dict[str, np.ndarray]:
        """Nodal output: displacement, velocity (m, m/s), rotation vector ψ (rad), angular
        velocity Ω (rad/s, frame R) and the section axes 2 and 3 (unit vectors)."""
        Q, V = q.reshape(-1, 6), v.reshape(-1, 6)
        F = self.section_frames(q)
        return {
            "displacement": Q[:, :3],
            "velocity": V[:, :3],
            "rotation": Q[:, 3:],
            "angular_velocity": V[:, 3:],
            "axis_2": F[:, :, 1],
            "axis_3": F[:, :, 2],
        }
