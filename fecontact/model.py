"""The model: bodies placed in one global dof vector, supports, gravity and contacts.

Each body owns a contiguous slice of the global vector q (displacements and rotations from the
reference configuration). Supports fix dofs at zero; the integrator works on the free dofs.
The mass matrix is constant and assembled once; the internal force and tangent are summed from
the bodies' element kernels into a sparsity pattern fixed at construction.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .bodies.base import BODY, BodyDefaults
from .contact import ContactSet
from .contact.base import PairDefaults
from .errors import InputError, check_finite, check_kind, check_positive, check_vector
from .linalg import DENSE_LIMIT, LinearSolver, Pattern, factorize
from .linalg.ladder import Ladder, iteration_solver, passing_matrix

__all__ = ["Model", "NodalLoad"]


class NodalLoad:
    """A load on ``node`` of ``body``: ``value`` is the nodal force vector (N, and N·m on a
    rotation dof), constant or a function of the time t (s) returning it."""

    def __init__(self, body, node: int, value):
        self.body, self.node, self.value = body, body.node_index(node), value
        if not callable(value):
            v = check_finite("value", value).ravel()
            if v.shape != (body.dofs_per_node,):
                raise InputError(f"value must have {body.dofs_per_node} components, got {v.size}")
            self.value = v
        self.dofs = np.zeros(0, int)
        self.n = 0

    def bind(self, model) -> None:
        o = model.offset_of(self.body)
        self.dofs = o + self.body.dofs_per_node * self.node + np.arange(self.body.dofs_per_node)
        self.n = model.n

    def __call__(self, t: float) -> np.ndarray:
        f = np.zeros(self.n)
        f[self.dofs] = self._at(t) if callable(self.value) else self.value
        return f

    def _at(self, t: float) -> np.ndarray:
        """The function's value at t, checked: a NaN or a wrong size would surface as a
        diverged step (an element said to invert) or a numpy broadcast error."""
        name = f"the load on node {self.node} at t = {t:g} s"
        return check_vector(name, self.value(t), self.body.dofs_per_node)


class Model:
    """Bodies, contact pairs and gravity.

    Parameters
    ----------
    bodies : the deformable (or rigid) bodies; each gets a slice of the global dofs.
    contacts : contact pairs built with :func:`fecontact.Contact`.
    gravity : acceleration of gravity in m/s², a vector with one component per space
        dimension (default: 9.81 m/s² along −y in 2D, along −z in 3D).
    joints : bilateral constraints (``fecontact.Pin``).
    damping : Rayleigh coefficients (α in 1/s, β in s): C = αM + βK_t.
    loads : time-dependent loads (:class:`NodalLoad`).
    """

    def __init__(self, bodies, contacts=(), gravity=None, joints=(), damping=(0.0, 0.0), loads=()):
        self.bodies = _distinct_bodies(_listed("bodies", bodies, BodyDefaults, BODY))
        pair = "a pair made by Contact(body, partner)"
        contacts = _listed("contacts", contacts, PairDefaults, pair)
        joints = _listed("joints", joints, PairDefaults, "a joint (Pin, BallJoint, ...)")
        loads = _listed("loads", loads, NodalLoad, "a NodalLoad")
        self.dim = dim = _common_dimension(self.bodies)
        self.gravity = _gravity(gravity, dim)
        self.continuum = any(b.continuum for b in self.bodies)
        self.slender = any(b.slender for b in self.bodies)
        self._place_dofs()
        self.rotations, self.inertial_bodies = _rotation_dofs(self)
        self._assemble_mass()
        self.f_gravity = self.M_full @ np.concatenate(
            [b.translation_field(self.gravity) for b in self.bodies]
        )
        for pair in contacts:
            pair.bind(self)
        self.contacts = ContactSet(contacts, self.free_index, len(self.free))
        for joint in joints:
            joint.bind(self)
        self.joints = ContactSet(joints, self.free_index, len(self.free))
        _check_joints_independent(self.joints, self.n)
        self.damping = _rayleigh(damping)
        self.loads = list(loads)
        for load in self.loads:
            load.bind(self)
        self._slices = [self.body_slice(i) for i in range(len(self.bodies))]
        self._measure_sizes(contacts)
        self.linear = all(b.linear for b in self.bodies)
        # rigid bodies and point masses only: no strain energy, no internal force
        self._elementless = not any(b.element_dofs.size for b in self.bodies)
        # (S_t, its solver, C) of a linear model per (β′, γ′): one factorization per step size
        self.iteration_cache: dict = {}
        self.column_cache: dict = {}  # H⁻¹G_jᵀ per metric and contact (linear models)
        # the solvers of S(a) = aM + K at sizes met once, and whether those met now are
        self.ladder: Ladder | None = None
        self.passing = False

    def _place_dofs(self) -> None:
        """The bodies' slices of the global vector (``offsets``, ``n``) and its free dofs,
        those no support holds (``free``, ``free_slice``, ``free_index``)."""
        sizes = [b.ndof for b in self.bodies]
        self.offsets = np.concatenate([[0], np.cumsum(sizes)]).astype(int)
        self.n = int(self.offsets[-1])
        fixed = np.zeros(self.n, dtype=bool)
        for b, o in zip(self.bodies, self.offsets, strict=False):
            fixed[o + np.fromiter(b.fixed, int, len(b.fixed))] = True
        self.free = np.flatnonzero(~fixed)
        if len(self.free) == 0:
            raise InputError("supports fix every dof: nothing can move")
        f = self.free
        # the free dofs as a slice when they are contiguous: views instead of copies
        self.free_slice = slice(int(f[0]), int(f[-1]) + 1) if f[-1] - f[0] + 1 == len(f) else f
        self.free_index = np.full(self.n, -1)
        self.free_index[self.free] = np.arange(len(self.free))
        self.dense = len(self.free) <= DENSE_LIMIT

    def _assemble_mass(self) -> None:
        """The constant mass matrix, the sparsity pattern of the iteration matrices over the
        free dofs, and the rigid motions."""
        self.M_full = sp.block_diag([b.mass_matrix() for b in self.bodies], format="csr")
        Mff = self.M_full[self.free][:, self.free]
        blocks = [o + b.element_dofs for b, o in zip(self.bodies, self.offsets, strict=False)]
        self.pattern = Pattern(blocks, self.free_index, len(self.free), extra=Mff)
        self.M = self.pattern.matrix(self.pattern.extra)
        # factorized in its own pattern: the shared one holds K's couplings (zeros in M,
        # e.g. between the components of a solid's displacement) and would fill them in
        self._M_own = Mff if not self.dense else self.M
        self._solve_M = None
        # rigid motions on the free dofs: the near-null space of AMG (sparse solver "amg")
        self.rigid_modes = np.vstack([b.rigid_modes() for b in self.bodies])[self.free]
        # the factorizations of M and S_t below; a run gives the model its own (use_solver)
        self.solver = LinearSolver(modes=self.rigid_modes)

    def _measure_sizes(self, contacts) -> None:
        """The model size ``length`` (m), the unit of each free dof's updates, the extent of
        the coordinates that gaps are computed from, ∫E dV (J; W's round-off, ``descent``)."""
        self.length = max(b.characteristic_length for b in self.bodies)
        self.stiffness_volume = float(sum(b.stiffness_volume for b in self.bodies))
        ones = np.ones(self.dim)  # (units: the model size for translations, 1 rad else)
        moves = np.concatenate([b.translation_field(ones) for b in self.bodies]) != 0
        self._update_unit = np.where(moves, self.length, 1.0)[self.free]
        self._reference = [b.positions(np.zeros(b.ndof)) for b in self.bodies]
        self._reference_extent = max(float(np.max(np.abs(X))) for X in self._reference)
        anchors = [p.obstacle.anchor for p in contacts if p.obstacle is not None]
        self._obstacle_extent = max((np.max(np.abs(a)) for a in anchors), default=0.0)

    def inverted(self, q: np.ndarray) -> bool:
        """Whether q inverts an element of a body whose material forbids it (Neo-Hookean)."""
        return any(b.inverted(q[self.body_slice(i)]) for i, b in enumerate(self.bodies))

    def coordinate_extent(self, q: np.ndarray) -> float:
        """max|X| + max|x − X| (m) over the bodies' points, reference X and current x at q, or
        the rigid obstacles' reference points if larger: a gap computed from x = X + u carries
        a round-off of about ε times it (a ball dropped from 5000 m, on the ground: 1e-12 m)."""
        u = 0.0
        for b, s, X in zip(self.bodies, self._slices, self._reference, strict=True):
            u = max(u, float(np.abs(b.positions(q[s]) - X).max()))
        return max(self._reference_extent + u, self._obstacle_extent)

    @property
    def solve_M(self):
        """M⁻¹ applied to a vector or to the columns of a matrix (factorized on first use)."""
        if self._solve_M is None:
            self._solve_M = factorize(self._M_own, symmetric=True, solver=self.solver)
        return self._solve_M

    def use_solver(self, solver: LinearSolver) -> None:
        """Factorize the model's matrices with ``solver`` (a run's, which counts their work)
        from now on; a run starts from caches emptied (:func:`~fecontact.time.make_stepper`)."""
        self.solver = solver

    def offset_of(self, body) -> int:
        """The first global dof of ``body``; ``InputError`` if it is not among the bodies
        (a contact, load, joint, probe or initial velocity of a body left out of the list)."""
        for b, o in zip(self.bodies, self.offsets, strict=False):
            if b is body:
                return int(o)
        raise InputError(
            f"a {type(body).__name__} that is not among the model's bodies: list it in "
            "Model([...], ...)"
        )

    def slice_of(self, body) -> slice:
        """The global dofs of ``body`` (checked as in :meth:`offset_of`)."""
        o = self.offset_of(body)
        return slice(o, o + body.ndof)

    def body_slice(self, i: int) -> slice:
        return slice(int(self.offsets[i]), int(self.offsets[i + 1]))

    @property
    def n_free(self) -> int:
        return len(self.free)

    def body_vector(self, body, values) -> np.ndarray:
        """Global dof vector holding ``values`` (the body's own dof vector, e.g. a rigid
        body's (v_x, v_y, ω)) on ``body`` and zero elsewhere."""
        x = np.zeros(self.n)
        o = self.offset_of(body)
        x[o : o + body.ndof] = check_finite("values", values).reshape(body.ndof)
        return x

    def translation(self, body, vector) -> np.ndarray:
        """Global dof vector with ``vector`` on every translation of ``body`` (a uniform
        initial velocity, say) and zero elsewhere."""
        x = np.zeros(self.n)
        o = self.offset_of(body)
        x[o : o + body.ndof] = body.translation_field(check_vector("vector", vector, self.dim))
        return x

    def internal(self, q: np.ndarray, tangent: bool = True):
        """Strain energy (J), internal force on all dofs and tangent on the free dofs."""
        if self._elementless and not tangent:
            return 0.0, np.zeros(self.n), None
        W, f, Ke = 0.0, np.zeros(self.n), []
        for b, s in zip(self.bodies, self._slices, strict=True):
            if not b.element_dofs.size:  # no elements (rigid bodies): no strain energy
                Ke.append(np.zeros((0,) + b.element_dofs.shape[1:] * 2))
                continue
            Wb, fb, Keb = b.internal(q[s], tangent)
            W += Wb
            f[s] = fb
            Ke.append(Keb)
        return W, f, (self.pattern.matrix(self.pattern.assemble(Ke)) if tangent else None)

    def element_strains(self, q: np.ndarray) -> np.ndarray:
        """The strains of every element of the bodies with elements, stacked (Σ E, 3)."""
        parts = [b.element_strains(q[s]) for b, s in self._strained()]
        return np.concatenate(parts) if parts else np.zeros((0, 3))

    def algorithmic_force(self, q0, q1, chi: float, d):
        """Force of the step q0 → q1 whose work is the strain energy's change plus χ's
        dissipation, on all dofs, and its tangent ∂/∂q1 on the free dofs (not symmetric);
        ``d`` (Σ E, 3) as :meth:`element_strains`, or None. Bodies without elements add
        nothing."""
        f, Ke, start = np.zeros(self.n), [], 0
        for b, s in zip(self.bodies, self._slices, strict=True):
            if not b.element_dofs.size:
                Ke.append(np.zeros((0,) + b.element_dofs.shape[1:] * 2))
                continue
            stop = start + len(b.element_dofs)
            db = 0.0 if d is None else d[start:stop]
            f[s], Keb = b.algorithmic_force(q0[s], q1[s], chi, db)
            Ke.append(Keb)
            start = stop
        return f, self.pattern.matrix(self.pattern.assemble(Ke))

    def _strained(self):
        pairs = zip(self.bodies, self._slices, strict=True)
        return [(b, s) for b, s in pairs if b.element_dofs.size]

    def iteration_sum(self, bp: float, K):
        """β′M + K in the shared structure (no sparse addition: one sum of data arrays)."""
        if self.dense:
            return bp * self.M + K
        return self.pattern.matrix(bp * self.pattern.extra + K.data)

    def iteration_matrix(self, bp: float, gp: float):
        """(S, solve, C) with the damping C = αM + βK and S = β′M + γ′C + K, for linear
        bodies (constant K): assembled and factorized once per step size, then reused. A size
        met while ``passing`` (used once) is solved by the ``ladder`` where one applies, C
        then None, S too where unread (:func:`fecontact.linalg.ladder.passing_matrix`)."""
        key = (bp, gp)
        if key not in self.iteration_cache:
            once = passing_matrix(self, bp) if self.passing else None
            if once is None:
                _, _, K = self.internal(np.zeros(self.n))
                alpha, beta = self.damping
                C = alpha * self.M + beta * K
                S = bp * self.M + K + gp * C
                once = (S, iteration_solver(self, bp, S, K), C)
            self.iteration_cache[key] = once
        return self.iteration_cache[key]

    def external(self, t: float) -> np.ndarray:
        """External force (N, N·m) on all dofs at time t (s): gravity plus the loads."""
        if not self.loads:
            return self.f_gravity
        return self.f_gravity + sum(load(t) for load in self.loads)

    def kinetic_energy(self, v: np.ndarray) -> float:
        return 0.5 * float(v @ (self.M_full @ v))

    def potential_energy(self, q: np.ndarray) -> float:
        """Gravitational potential energy (J), zero in the reference configuration."""
        return -float(self.f_gravity @ q)

    def update_size(self, dq: np.ndarray) -> float:
        """The size of an update dq of the free dofs in consistent units: max |dq_i| / s_i,
        s_i the model size (m) for a translation and 1 rad for a rotation."""
        return float(np.max(np.abs(dq) / self._update_unit, initial=0.0))

    def strain_energy(self, q: np.ndarray) -> float:
        return float(sum(b.energy(q[self.body_slice(i)]) for i, b in enumerate(self.bodies)))


def _rotation_dofs(model):
    """Decided once per model: the rotation vectors' dofs in free numbering ((k, 3), updated
    by composition in SO(3)) and the bodies with a velocity-dependent inertial force, as
    (body, its global slice)."""
    triples, inertial = [], []
    for i, (b, o) in enumerate(zip(model.bodies, model.offsets, strict=False)):
        t = model.free_index[o + np.asarray(b.rotation_triples, int).reshape(-1, 3)]
        if np.any((t < 0).any(axis=1) & (t >= 0).any(axis=1)):
            raise InputError(
                "supports: a rotation vector is held in some of its components only; "
                "hold all three (fix the rotation) or none"
            )
        triples.append(t[(t >= 0).all(axis=1)])
        zero = np.zeros(b.ndof)
        if b.inertial(zero, zero) is not None:
            inertial.append((b, model.body_slice(i)))
    return np.concatenate(triples).astype(int), inertial


_ONE = (str, bytes, BodyDefaults, PairDefaults, NodalLoad)


def _listed(name: str, values, kind: type, one: str) -> list:
    """``values`` as a list whose every entry is a ``kind``; else one ``InputError`` naming
    the argument and the entry: a lone body or pair where a list is due, an obstacle among
    the contacts (a Plane is a partner of a pair, not a pair), a number among the loads."""
    try:
        items = None if isinstance(values, _ONE) else list(values)
    except TypeError:
        items = None
    if items is None:
        raise InputError(f"{name} must be a list, each entry {one}; got {type(values).__name__}")
    for i, item in enumerate(items):
        check_kind(f"{name}[{i}]", item, kind, one)
    return items


def _distinct_bodies(bodies: list) -> list:
    if not bodies:
        raise InputError("bodies must contain at least one body")
    if len({id(b) for b in bodies}) < len(bodies):
        raise InputError("bodies: the same body is listed twice")
    return bodies


def _common_dimension(bodies) -> int:
    dims = {b.dim for b in bodies}
    if len(dims) > 1:
        raise InputError("bodies must all be 2D or all 3D")
    return dims.pop()


def _gravity(gravity, dim: int) -> np.ndarray:
    """The acceleration of gravity (m/s², ``dim`` components): 9.81 along the last axis
    downwards unless given."""
    if gravity is None:
        gravity = np.eye(dim)[-1] * -9.81
    g = check_finite("gravity", gravity).ravel()
    if g.shape != (dim,):
        raise InputError(f"gravity must have {dim} components for a {dim}D model")
    return g


def _rayleigh(damping) -> tuple[float, float]:
    """Rayleigh coefficients (α in 1/s, β in s), both ≥ 0."""
    alpha, beta = check_vector("damping", damping, 2)
    check_positive("damping alpha", alpha, allow_zero=True)
    check_positive("damping beta", beta, allow_zero=True)
    return float(alpha), float(beta)


def _check_joints_independent(joints, n: int) -> None:
    """Joints must hold what no other joint or support holds: redundant rows make the
    bordered matrices of every step singular. Those refused are named."""
    if joints.size == 0:
        return
    G = joints.jacobian(np.zeros(n), joints.all)[1]
    G = G.toarray() if sp.issparse(G) else np.asarray(G)
    rank = np.linalg.matrix_rank(G @ G.T) if G.size else 0
    if rank < joints.size:
        # the rows in a combination that vanishes: the left null space of G
        U = np.linalg.svd(G)[0]
        rows = np.abs(U[:, rank:]).max(axis=1) > 1e-8
        named = [f"{type(joints.pairs[i]).__name__} {i}" for i in np.unique(joints.owner[rows])]
        raise InputError(
            f"joints: {', '.join(named)} hold what their other rows already hold (a joint "
            "beside a support (pin, clamp, fix) or another joint, or a closed loop that "
            "holds one motion twice, as hinges on parallel axes all round); remove one, "
            "or let joints of the loop hold less (BallJoint, UniversalJoint) until no row "
            "is held twice"
        )
