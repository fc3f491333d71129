r"""Planar geometrically exact (Simo–Reissner) beam on a scikit-fem ``MeshLine``.

Total Lagrangian description. Each node carries the displacement (u_x, u_y) in m and the
rotation θ in rad (counter-clockwise positive) of its cross-section. The reference centreline
X(ξ) is parametrised by its arc length ξ, which is the coordinate of the ``MeshLine``; X itself
is a nodal field interpolated with the same shape functions, so inclined beams and polylines
need nothing special.

With J = |X'|, φ = atan2(X'_2, X'_1) + θ, t(φ) = (cos φ, sin φ), n(φ) = (−sin φ, cos φ) and
a = (X' + u')/J, the strains are

    axial  Γ = a·t − 1,    shear  γ = a·n,    curvature  κ = θ'/J,

and the strain energy is W = ½ ∫ (EA Γ² + G A_s γ² + EI κ²) J dξ. The internal force is ∂W/∂q
and the tangent its exact (symmetric) Hessian. A rigid motion leaves Γ, γ and κ at zero.

Stiffness is integrated with the one-point rule (reduced integration, free of shear locking for
linear elements); the mass needs the full rule, a one-point mass matrix being singular. In the
plane the mass matrix is constant: ρA on the translations, ρI on the rotation, plus point masses.

``linear=True`` gives the small-displacement (Timoshenko) beam instead: W = ½ qᵀ K₀ q with K₀ the
tangent above at q = 0, the second-order expansion of W about the reference configuration. Its
stiffness is constant, so the iteration matrix is factorized once. It is exact, not an
approximation, wherever the motion keeps Γ, γ, κ linear in q: a straight bar moving along its
axis (Γ = u′, γ = κ = 0) whatever the size of the strain. Rotations of the beam as a whole, on
the other hand, create spurious strain in it.
"""

from __future__ import annotations

from dataclasses import KW_ONLY, dataclass

import numpy as np
import scipy.sparse as sp
import skfem

from ..errors import (
    InputError,
    check_count,
    check_finite,
    check_kind,
    check_positive,
    check_range,
    check_vector,
)
from .beam_energy import beam_energy_force, element_strains
from .beam_kernels import BeamElements, beam_internal, beam_strains
from .centreline import Centreline, centreline_nodes

__all__ = ["Material", "Section", "Beam2D", "rectangle_torsion"]

_MIDPOINT = (np.array([[0.5]]), np.array([1.0]))
_EYE2 = np.eye(2)[None]


@skfem.BilinearForm
def _mass_form(u, v, _):
    return u * v


# what a beam's material and section are, as an error names them
BEAM_MATERIAL = "a beam Material(E, nu=..., rho=...) (LinearElastic and the others are solids')"
BEAM_SECTION = "a Section (Section.circle(radius), Section.rectangle(width, thickness), ...)"


@dataclass(frozen=True)
class Material:
    """Isotropic linear elastic material of a beam: ``Material(E, nu=..., rho=...)``.

    The arguments come in the order (E, nu, rho) of the solids' materials; those after E are
    keyword-only, so a call by position is an error rather than a density taken for ν.

    Parameters
    ----------
    E : Young's modulus in Pa (> 0).
    nu : Poisson's ratio, in (−1, 0.5); default 0.3.
    rho : density in kg/m³ (> 0).
    """

    E: float
    _: KW_ONLY
    nu: float = 0.3
    rho: float

    def __post_init__(self):
        object.__setattr__(self, "E", check_positive("E", self.E))
        object.__setattr__(self, "nu", check_range("nu", self.nu, -1.0, 0.5, (False, False)))
        object.__setattr__(self, "rho", check_positive("rho", self.rho))

    @property
    def G(self) -> float:
        """Shear modulus E / (2(1 + ν)) in Pa."""
        return self.E / (2.0 * (1.0 + self.nu))


@dataclass(frozen=True)
class Section:
    """Beam cross-section: area A in m², second moment I in m⁴ (bending in the beam's plane;
    about axis 3 of a ``Beam3D`` section), shear correction factor; for ``Beam3D`` also the
    second moment ``inertia_2`` about axis 2 (m⁴, default ``inertia``) and the torsion
    constant ``torsion`` J (m⁴, default the polar moment ``inertia`` + ``inertia_2``, exact for
    a circle)."""

    area: float
    inertia: float
    shear_factor: float = 5.0 / 6.0
    inertia_2: float | None = None
    torsion: float | None = None

    def __post_init__(self):
        object.__setattr__(self, "area", check_positive("area", self.area))
        object.__setattr__(self, "inertia", check_positive("inertia", self.inertia))
        object.__setattr__(self, "shear_factor", check_positive("shear_factor", self.shear_factor))
        i2 = self.inertia if self.inertia_2 is None else self.inertia_2
        object.__setattr__(self, "inertia_2", check_positive("inertia_2", i2))
        j = self.inertia + self.inertia_2 if self.torsion is None else self.torsion
        object.__setattr__(self, "torsion", check_positive("torsion", j))

    @classmethod
    def rectangle(cls, width: float, thickness: float) -> Section:
        """Solid rectangle ``width`` × ``thickness`` (m), bending about the width axis; in
        space the thickness lies along axis 2 and the width along axis 3."""
        b = check_positive("width", width)
        t = check_positive("thickness", thickness)
        area, inertia = b * t, b * t * t * t / 12.0
        if not (np.isfinite(inertia) and area > 0 and inertia > 0):
            raise InputError(f"width and thickness give no usable section: {b!r} x {t!r} m")
        return cls(
            area=area,
            inertia=inertia,
            shear_factor=5.0 / 6.0,
            inertia_2=t * b**3 / 12.0,
            torsion=rectangle_torsion(b, t),
        )

    @classmethod
    def circle(cls, radius: float) -> Section:
        """Solid circle of ``radius`` (m): I₂ = I₃ = πr⁴/4, J = πr⁴/2."""
        r = check_positive("radius", radius)
        area, inertia = np.pi * r * r, np.pi * r * r * r * r / 4.0
        if not (np.isfinite(inertia) and area > 0 and inertia > 0):
            raise InputError(f"radius gives no usable section: {r!r} m")
        return cls(area=area, inertia=inertia, shear_factor=0.9)


def rectangle_torsion(width: float, thickness: float) -> float:
    """Saint-Venant torsion constant J (m⁴) of a solid rectangle, by its series (Timoshenko &
    Goodier, Theory of Elasticity, 1951): with a ≥ b the long and short sides,
    J = a b³/3 [1 − (192/π⁵)(b/a) Σ_{n odd} tanh(nπa/2b)/n⁵]; 50 terms leave < 1e-12."""
    a, b = max(width, thickness), min(width, thickness)
    n = np.arange(1, 100, 2)
    series = np.sum(np.tanh(n * np.pi * a / (2.0 * b)) / n**5)
    return float(a * b**3 / 3.0 * (1.0 - 192.0 / np.pi**5 * (b / a) * series))


class Beam2D(Centreline):
    """Planar Simo–Reissner beam through ``nodes`` (an (n, 2) array in m, in order).

    Elements join consecutive nodes. Supports (``pin``, ``clamp``) and point masses
    (``add_mass``) are set with chainable methods; node indices may be negative (``-1`` is the
    last node). Dofs are ordered node by node as (u_x, u_y, θ). ``linear=True``: the
    small-displacement beam with the constant stiffness K₀ of the reference configuration (see
    the module docstring for when this is exact).
    """

    dofs_per_node = 3
    components = ("x", "y", "theta")
    slender = True

    def __init__(self, nodes, material: Material, section: Section, linear: bool = False):
        if not isinstance(linear, (bool, np.bool_)):
            raise InputError(f"linear must be True or False, got {linear!r}")
        X, seg = centreline_nodes(nodes, 2)
        self.X = X
        self.material = check_kind("material", material, Material, BEAM_MATERIAL)
        self.section = check_kind("section", section, Section, BEAM_SECTION)
        self.mesh = skfem.MeshLine(np.concatenate([[0.0], np.cumsum(seg)]))
        self.length = float(seg.sum())
        self.fixed: set[int] = set()
        self.point_masses = np.zeros(len(X))
        self._stiffness_basis = skfem.Basis(self.mesh, skfem.ElementLineP1(), quadrature=_MIDPOINT)
        self._mass_basis = skfem.Basis(self.mesh, skfem.ElementLineP1(), intorder=2)
        m, s = material, section
        rigidities = (m.E * s.area, m.G * s.area * s.shear_factor, m.E * s.inertia)
        self._el = BeamElements.of(X, self._stiffness_basis.element_dofs, rigidities)
        self.linear = bool(linear)
        """Constant stiffness K₀: internal(q) = K₀ q, the iteration matrix is factorized once."""
        self._K = self._Ke = None
        if self.linear:
            self._Ke = beam_internal(self._el, np.zeros(self.ndof), self.ndof, True)[2]
            rows = np.broadcast_to(self._el.dofs[:, :, None], self._Ke.shape)
            cols = np.broadcast_to(self._el.dofs[:, None, :], self._Ke.shape)
            self._K = sp.csr_matrix(
                (self._Ke.ravel(), (rows.ravel(), cols.ravel())), shape=(self.ndof, self.ndof)
            )

    # -- construction -----------------------------------------------------------------------
    @classmethod
    def straight(
        cls, start, end, n_elements: int, material: Material, section: Section, linear=False
    ):
        """Straight beam from ``start`` to ``end`` (m) with ``n_elements`` equal elements."""
        n = check_count("n_elements", n_elements)
        # a number would broadcast to the point (x, x)
        a, b = check_vector("start", start, 2), check_vector("end", end, 2)
        if np.linalg.norm(b - a) == 0.0:
            raise InputError("length must be > 0: start and end coincide")
        s = np.linspace(0.0, 1.0, n + 1)[:, None]
        return cls(a + s * (b - a), material, section, linear)

    @classmethod
    def polyline(cls, points, n_elements, material: Material, section: Section, linear=False):
        """Beam along the polyline ``points`` with ``n_elements`` per segment (int or list)."""
        P = check_finite("points", points)
        counts = np.broadcast_to(np.asarray(n_elements), (len(P) - 1,))
        parts = [P[:1]]
        for k, n in enumerate(counts):
            s = np.linspace(0.0, 1.0, check_count("n_elements", n) + 1)[1:, None]
            parts.append(P[k] + s * (P[k + 1] - P[k]))
        return cls(np.vstack(parts), material, section, linear)

    def pin(self, node: int) -> Beam2D:
        """Fix the displacement of ``node``; its rotation stays free: ``fix(node, "x", "y")``."""
        return self.fix(node, "x", "y")

    def add_mass(self, node: int, mass: float) -> Beam2D:
        """Attach a point mass (kg) to the translations of ``node``."""
        self.point_masses[self.node_index(node)] += check_positive("mass", mass, allow_zero=True)
        return self

    # -- sizes -------------------------------------------------------------------------------
    @property
    def elements(self) -> BeamElements:
        """The elements' kernel data (reference geometry, rigidities C, lengths ℓ, dofs) that
        the strain and force kernels of :mod:`fecontact.bodies.beam_kernels` take."""
        return self._el

    @property
    def element_dofs(self) -> np.ndarray:
        """(n_elements, 6) local dof indices of each element."""
        return self._el.dofs

    def strains(self, q: np.ndarray) -> tuple[np.ndarray, ...]:
        """Axial Γ, shear γ and curvature κ (1/m) at the element midpoints."""
        return beam_strains(self._el, q)[:3]

    def energy(self, q: np.ndarray) -> float:
        """Strain energy W(q) in J."""
        if self.linear:
            return 0.5 * float(q @ (self._K @ q))
        Gam, gam, kap = self.strains(q)
        C = self._el.C
        return 0.5 * float(self._el.ell @ (C[0] * Gam**2 + C[1] * gam**2 + C[2] * kap**2))

    def internal(self, q: np.ndarray, tangent: bool = True):
        """Strain energy (J), internal force ∂W/∂q (N, N·m) and element tangents (E, 6, 6)."""
        if self.linear:
            f = self._K @ q
            return 0.5 * float(q @ f), f, self._Ke if tangent else None
        return beam_internal(self._el, q, self.ndof, tangent)

    @property
    def energy_consistent(self) -> bool:
        """Whether :meth:`algorithmic_force` holds: the geometrically exact beam."""
        return not self.linear

    def algorithmic_force(self, q0, q1, chi: float = 0.0, d=0.0, tangent: bool = True):
        """The force (N, N·m) of the step q0 → q1 whose work is the strain energy's change,
        plus the dissipative stress χC(Δε − d), and its element tangents ∂/∂q1 (E, 6, 6)
        (:mod:`.beam_energy`); ``d`` (E, 3): the strain increment the stress subtracts."""
        return beam_energy_force(self._el, q0, q1, chi, d, self.ndof, tangent)

    def element_strains(self, q: np.ndarray) -> np.ndarray:
        """(Γ, γ, κ) of every element, (E, 3)."""
        return element_strains(self._el, q)

    def stiffness_matrix(self) -> sp.csr_matrix:
        """Constant stiffness K₀ (ndof × ndof, no supports) of a linear beam."""
        if not self.linear:
            raise InputError("stiffness_matrix: the beam is geometrically exact; use internal(q)")
        return self._K

    def mass_matrix(self) -> sp.csr_matrix:
        """Consistent mass (kg, kg·m²): kron(scalar P1 mass, diag(ρA, ρA, ρI)) + point masses."""
        rho = self.material.rho
        m1 = _mass_form.assemble(self._mass_basis)
        diag = np.array(
            [rho * self.section.area, rho * self.section.area, rho * self.section.inertia]
        )
        M = sp.kron(m1, sp.diags(diag), format="csr")
        M = M + sp.diags(np.repeat(self.point_masses, 3) * np.tile([1.0, 1.0, 0.0], self.n_nodes))
        return M.tocsr()

    def translation_field(self, vector) -> np.ndarray:
        """Nodal dof vector with ``vector`` on every translation and 0 on the rotations."""
        f = np.zeros((self.n_nodes, 3))
        f[:, :2] = vector
        return f.ravel()

    def rigid_modes(self) -> np.ndarray:
        """(ndof, 3) rigid motions: translations along x and y, and the rotation about the node
        centroid X̄ (u = e_z × (X − X̄) in m/rad, θ = 1)."""
        Xc = self.X - self.X.mean(axis=0)
        R = np.column_stack([-Xc[:, 1], Xc[:, 0], np.ones(len(Xc))]).ravel()
        T = [self.translation_field(e) for e in np.eye(2)]
        return np.column_stack([*T, R])

    # -- geometry and output -----------------------------------------------------------------
    def positions(self, q: np.ndarray) -> np.ndarray:
        """Current node coordinates X + u (m), shape (n, 2)."""
        return self.X + q.reshape(-1, 3)[:, :2]

    linear_kinematics = True
    """Node positions are linear in the dofs (x = X + u)."""

    def locate(self, point) -> int:
        """Index of the node at ``point`` (reference coordinates, m)."""
        d = np.linalg.norm(self.X - np.asarray(point, dtype=float), axis=1)
        i = int(np.argmin(d))
        if d[i] > 1e-9 * self.length:
            raise InputError(f"point {list(point)} is not a node of the beam")
        return i

    def point_kinematics(self, q: np.ndarray, nodes: np.ndarray):
        """Positions x (m, 2) of ``nodes``, their local dofs (m, 2), ∂x/∂q (m, 2, 2) and
        ∂²x/∂q² (None: linear)."""
        dofs = 3 * nodes[:, None] + np.arange(2)
        x = self.X[nodes] + q[dofs]
        return x, dofs, np.repeat(_EYE2, len(nodes), axis=0), None

    def section_turns(self, q: np.ndarray, nodes: np.ndarray, arms: np.ndarray):
        """Local dofs (m, 1) of the rotations θ at ``nodes`` and ∂ẋ_p/∂θ̇ = e_z × arm (m, 2, 1)
        of the material points x_p = x + arm of their sections (``arms`` (m, 2), m): where a
        section touches through its thickness, its turn moves the touching point."""
        dofs = 3 * nodes[:, None] + 2
        return dofs, np.stack([-arms[:, 1], arms[:, 0]], axis=1)[:, :, None]

    def section_points_before(self, q, q_n, nodes: np.ndarray, arms: np.ndarray) -> np.ndarray:
        """Where the material points now at x + arm (``arms`` (m, 2)) of the sections at
        ``nodes`` were at q_n: x_n + R(θ_n − θ) arm (m, 2)."""
        Q, Qn = q.reshape(-1, 3)[nodes], q_n.reshape(-1, 3)[nodes]
        c, s = np.cos(Qn[:, 2] - Q[:, 2]), np.sin(Qn[:, 2] - Q[:, 2])
        back = np.stack([c * arms[:, 0] - s * arms[:, 1], s * arms[:, 0] + c * arms[:, 1]], 1)
        return self.X[nodes] + Qn[:, :2] + back

    def node_translation_dofs(self, nodes) -> np.ndarray:
        """(len(nodes), 2) local dof indices of (u_x, u_y) at ``nodes``."""
        idx = np.array([self.node_index(i) for i in np.atleast_1d(nodes)], dtype=int)
        return 3 * idx[:, None] + np.arange(2)

    def nodal(self, x: np.ndarray, q: np.ndarray | None = None) -> np.ndarray:
        """Translation part (n, 2) of a nodal dof vector (displacement, velocity, force)."""
        return x.reshape(-1, 3)[:, :2]

    def point_data(self, q: np.ndarray, v: np.ndarray) -> dict[str, np.ndarray]:
        """Nodal fields for output: displacement, velocity (2D vectors) and rotation (rad)."""
        Q, V = q.reshape(-1, 3), v.reshape(-1, 3)
        return {
            "displacement": Q[:, :2],
            "velocity": V[:, :2],
            "rotation": Q[:, 2],
            "angular_velocity": V[:, 2],
        }
