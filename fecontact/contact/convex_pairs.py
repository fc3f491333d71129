r"""Contact of two convex rigid bodies in space by GJK/EPA and a face-clipping manifold.

The signed distance d of two shapes (their distance apart, minus the penetration depth when
they overlap) and its normal n, pointing from body a to body b, come from the GJK/EPA queries
of ``coal`` (the ``collision`` extra). One witness point per pair rocks a box lying on a face
from corner to corner, so polyhedra (``Box``, ``Cylinder`` as its rim prism, ``ConvexMesh``)
touch through a manifold instead, as physics engines build it: the face of either body most
aligned with n is the reference face, the other body's face most opposed to it the incident
face; the incident face clipped by the reference face's side planes (Sutherland–Hodgman) gives
the contact points x_b, each with its projection x_a on the reference plane. Where neither
face is within ``FACE_COS`` of n (an edge on an edge, a corner on an edge) and for a ``Ball``,
the pair holds the single witness pair of GJK/EPA. A ``Capsule`` on a polyhedron touches
along a segment where it lies on a face: its axis clipped by the face's side planes gives the
two ends of the contact (a cap, or the edge it overhangs); otherwise its caps' witnesses and,
where it lies below the line between them (an edge under the segment), its own.

Every contact point pair (r_a, r_b), body-frame points of a and b, has the gap
g = n·(x_b − x_a) and the gradient row, in the (u, Θ) of both bodies (Θ body-frame),

    G = [−n, −r_a × (R_aᵀ n), n, r_b × (R_bᵀ n)]

(δx = δu − R r̃ δΘ of :mod:`fecontact.bodies.rigid3d`); the curvature is left out (Newton's
rate, not its answer). A pair holds a fixed number of slots (the two largest faces' vertex
counts); slots the manifold leaves empty carry a gap of the bodies' size and a zero row, so
they stay open.

Coulomb friction acts at the same points, in the tangent basis T(n) of the analytic pairs
(:func:`fecontact.contact.friction.tangent_basis`): the slip rows are T applied to the
relative velocity of b's material point r_b against a's r_a,

    G_T = T [−I, R_a r̃_a, I, −R_b r̃_b],

and the slip over a step is T applied to the chord of those two material points from q_n to
q, (c_b + R_b r_b − c_a − R_a r_a)(q) − (…)(q_n), as for the vertices of a body on a plane
(:class:`fecontact.contact.NodeContact`): exact for a translating body, a rotating one's
points follow their chords.
"""

from __future__ import annotations

import importlib

import numpy as np

from ..bodies.rigid3d import RigidBody3D
from ..bodies.shapes3d import Ball, Capsule
from ..errors import InputError, check_range
from ..rotations import cross, exp, hat, log
from .base import PairDefaults
from .friction import tangent_basis

__all__ = ["ConvexContact", "hull_faces"]

FACE_COS = 0.95  # a face within ~18° of the normal is a reference face
_PLANE_DIGITS = 9  # Qhull's triangles of one face share their plane to round-off


def _coal():
    try:
        return importlib.import_module("coal")
    except ImportError as err:
        raise InputError(
            "convex-convex contact of RigidBody3D needs the 'collision' extra: "
            "pip install fecontact[collision] (coal)"
        ) from err


def hull_faces(vertices: np.ndarray):
    """The faces of the convex hull of ``vertices`` (n, 3): a list of vertex rows ordered
    counter-clockwise about the outward normal, the unit normals (F, 3) and offsets (F,) of
    their planes n·x = h."""
    from scipy.spatial import ConvexHull

    hull = ConvexHull(vertices)
    planes, group = np.unique(np.round(hull.equations, _PLANE_DIGITS), axis=0, return_inverse=True)
    faces, normals, offsets = [], [], []
    for f in range(len(planes)):
        ids = np.unique(hull.simplices[group.ravel() == f])
        n = hull.equations[group.ravel() == f][0, :3]
        P = vertices[ids]
        c = P.mean(0)
        e1 = P[0] - c
        e1 /= np.linalg.norm(e1)
        e2 = cross(n, e1)
        angle = np.arctan2((P - c) @ e2, (P - c) @ e1)
        faces.append(ids[np.argsort(angle)])
        normals.append(n)
        offsets.append(float(n @ P[0]))
    return faces, np.array(normals), np.array(offsets)


def _inward(poly: np.ndarray, n: np.ndarray) -> np.ndarray:
    """Unit inward side normals (m, 3) of the polygon ``poly`` (m, 3), counter-clockwise about
    ``n``."""
    m = cross(n, np.roll(poly, -1, axis=0) - poly)
    return m / np.linalg.norm(m, axis=1)[:, None]


def _inside(x: np.ndarray, poly: np.ndarray, n: np.ndarray, tol: float) -> np.ndarray:
    """Whether the points ``x`` (k, 3) lie over the polygon ``poly`` (about its normal n)."""
    return np.all(np.einsum("ej,kej->ke", _inward(poly, n), x[:, None] - poly[None]) >= -tol, 1)


def _crossings(ref, inc, nr, tol):
    """Crossings of the reference face's edges with the incident face's edges seen along nr:
    labels (i, j) of the edges and the points on both faces (every pair of edges at once)."""
    inc_p = inc - np.outer((inc - ref[0]) @ nr, nr)
    d1 = (np.roll(ref, -1, axis=0) - ref)[:, None]  # (m, 1, 3)
    d2 = (np.roll(inc_p, -1, axis=0) - inc_p)[None]  # (1, k, 3)
    r = inc_p[None] - ref[:, None]  # (m, k, 3)

    def along(a, b):  # (a × b)·nr, the signed area in the reference plane
        return np.einsum("...i,i->...", cross(a, b), nr)

    den = along(d1, d2)
    # parallel edges: their overlap ends at vertices, counted there
    ok = np.abs(den) > tol * np.linalg.norm(d1, axis=2) * np.linalg.norm(d2, axis=2)
    den = np.where(ok, den, 1.0)
    t, s = along(r, d2) / den, along(r, d1) / den
    i, j = np.nonzero(ok & (t >= 0.0) & (t <= 1.0) & (s >= 0.0) & (s <= 1.0))
    on_ref = ref[i] + t[i, j, None] * d1[i, 0]
    on_inc = inc[j] + s[i, j, None] * (np.roll(inc, -1, axis=0)[j] - inc[j])
    return list(zip(i.tolist(), j.tolist(), strict=True)), on_ref, on_inc


def face_manifold(ref, inc, nr, n_inc, tol):
    """The contact polygon of a reference face ``ref`` (m, 3, counter-clockwise about its
    outward normal ``nr``) and an incident face ``inc`` (k, 3, about ``n_inc``): the incident
    vertices over the reference face, the reference vertices under the incident face and the
    crossings of their edges. Returns, for each point, its label ("inc", vertex), ("ref",
    vertex) or ("cross", ref edge, incident edge), its point on the reference face and its
    point on the incident face (world, m); points within ``tol`` of an earlier one are left
    out (coincident corners would give equal rows)."""
    labels, x_ref, x_inc = [], [], []
    keep = np.flatnonzero(_inside(inc, ref, nr, tol))
    labels += [("inc", int(k)) for k in keep]
    x_inc.append(inc[keep])
    x_ref.append(inc[keep] - np.outer((inc[keep] - ref[0]) @ nr, nr))
    keep = np.flatnonzero(_inside(ref, inc, -nr, tol))
    t = (inc[0] - ref[keep]) @ n_inc / (nr @ n_inc)  # along nr up to the incident plane
    labels += [("ref", int(k)) for k in keep]
    x_ref.append(ref[keep])
    x_inc.append(ref[keep] + np.outer(t, nr))
    edges, on_ref, on_inc = _crossings(ref, inc, nr, tol)
    labels += [("cross", *c) for c in edges]
    x_ref, x_inc = np.vstack([*x_ref, on_ref]), np.vstack([*x_inc, on_inc])
    unique = [
        i for i in range(len(labels)) if np.all(np.linalg.norm(x_ref[:i] - x_ref[i], axis=1) > tol)
    ]
    return [labels[i] for i in unique], x_ref[unique], x_inc[unique]


def _increment(q: np.ndarray, q_n: np.ndarray, o: int) -> np.ndarray:
    """(Δu, log(R_nᵀR)) of the rigid body at dofs o … o + 5 from q_n to q."""
    psi, psi_n = q[o + 3 : o + 6], q_n[o + 3 : o + 6]
    return np.concatenate([q[o : o + 3] - q_n[o : o + 3], log(exp(psi_n).T @ exp(psi))])


def touching_face_normal(hulls, poses, d: float, tol: float):
    """The outward face normal (world, from a to b) of two polyhedra touching to round-off
    (|d| ≤ ``tol``, m) along which they are separated by no less than d − ``tol``, or None.

    At a distance of round-off GJK/EPA work on a polytope shrunk to a point and their normal
    is any direction (on a box resting flat on a box, corrected to d = −1.4e-17 m, EPA gave
    (0.71, 0.71, 1e-5)). The separating axes among the face normals hold it: the separation
    of the two vertex sets along a face normal is the signed distance where that face touches
    (the largest over all axes, edge pairs included), so a face whose separation is d to
    ``tol`` is a face contact and its normal the pair's."""
    (Ra, ca), (Rb, cb) = poses
    ha, hb = hulls
    xa, xb = ha.vertices @ Ra.T + ca, hb.vertices @ Rb.T + cb
    na, nb = ha.normals @ Ra.T, -(hb.normals @ Rb.T)  # candidate normals from a to b
    sep = np.concatenate(
        [(xb @ na.T).min(0) - (xa @ na.T).max(0), (xb @ nb.T).min(0) - (xa @ nb.T).max(0)]
    )
    best = int(np.argmax(sep))
    if sep[best] < d - tol:
        return None
    return np.vstack([na, nb])[best]


def _capsule_side(hulls) -> int | None:
    """Which of the two hulls is a capsule facing a polyhedron (None: neither)."""
    for side in (0, 1):
        if hulls[side].caps is not None and hulls[1 - side].faces is not None:
            return side
    return None


class _Hull:
    """A body's shape for the queries: the coal geometry and, for a polyhedron, its faces."""

    def __init__(self, body: RigidBody3D):
        coal = _coal()
        shape = body.shape
        self.faces = self.caps = None
        if isinstance(shape, Ball):
            self.geometry = coal.Sphere(shape.radius)
        elif isinstance(shape, Capsule):
            self.geometry = coal.Capsule(shape.radius, shape.length)
            self.caps, self.cap = shape.balls[0], coal.Sphere(shape.radius)
        else:
            V = np.asarray(shape.vertices, dtype=float)
            points = coal.StdVec_Vec3s()
            for p in V:
                points.append(p)
            self.geometry = coal.Convex.convexHull(points, False, "")
            self.vertices = V
            self.faces, self.normals, self.offsets = hull_faces(V)

    def face(self, k: int) -> np.ndarray:
        return self.vertices[self.faces[k]]


class ConvexContact(PairDefaults):
    """Two convex ``RigidBody3D`` (any shapes) by GJK/EPA, polyhedra through a face-clipping
    manifold, with Coulomb friction at the manifold's points."""

    linear = False
    frictional = True

    def __init__(self, a: RigidBody3D, b: RigidBody3D, restitution=0.0, clearance=0.0):
        if a is b:
            raise InputError("a body cannot contact itself")
        self.bodies = (a, b)
        self.body = a
        self.restitution = check_range("restitution", restitution, 0.0, 1.0)
        self.clearance = float(clearance)
        self.hulls = (_Hull(a), _Hull(b))
        polyhedra = all(h.faces is not None for h in self.hulls)
        # one slot per vertex of either body, then a pool for edge crossings (at most the
        # two faces' vertex counts) or for the single witness pair
        self.pool = sum(len(h.vertices) for h in self.hulls) if polyhedra else 0
        widest = sum(max(len(f) for f in h.faces) for h in self.hulls) if polyhedra else 1
        self.size = int(self.pool + widest)
        # a capsule on a polyhedron: its GJK witness and the witnesses of its two caps
        self.capsule = _capsule_side(self.hulls)
        self.round = not polyhedra  # a ball or a capsule: its points roll
        if self.capsule is not None:
            self.size = 3
        self.tol = 1e-9 * (a.shape.size + b.shape.size)  # coincident points, m
        self.far = a.shape.size + b.shape.size  # an empty slot's gap, m
        coal = _coal()
        self._request = coal.DistanceRequest()
        # GJK/EPA to 1e-10 m: the default 1e-6 reports touching below a micrometre
        self._request.gjk_tolerance = 1e-10
        self._request.epa_tolerance = 1e-10
        self._transform = coal.Transform3s
        self._result = coal.DistanceResult
        self._distance = coal.distance
        self.offsets = (0, 0)
        self._last = (None, None)  # (q of the two bodies, its contact points)

    def bind(self, model) -> None:
        self.offsets = tuple(model.offset_of(b) for b in self.bodies)

    def _poses(self, q):
        return [
            (exp(q[o + 3 : o + 6]), b.center(q[o : o + 6]))
            for b, o in zip(self.bodies, self.offsets, strict=True)
        ]

    def query(self, q: np.ndarray, cap: int | None = None):
        """Signed distance d (m), unit normal n from a to b and the witness points (world);
        ``cap`` (0, 1): the capsule's cap ball in place of the capsule."""
        poses = self._poses(q)
        geometry = [h.geometry for h in self.hulls]
        if cap is not None:
            side = self.capsule
            R, c = poses[side]
            geometry[side] = self.hulls[side].cap
            poses[side] = (R, c + R @ self.hulls[side].caps[cap])
        (Ra, ca), (Rb, cb) = poses
        res = self._result()
        d = self._distance(
            geometry[0],
            self._transform(Ra, ca),
            geometry[1],
            self._transform(Rb, cb),
            self._request,
            res,
        )
        n = np.array(res.normal, dtype=float)
        return (
            float(d),
            n / np.linalg.norm(n),
            np.array(res.getNearestPoint1()),
            np.array(res.getNearestPoint2()),
        )

    def manifold(self, q: np.ndarray):
        """Slots (k,), world points x_a (k, 3) on a and x_b (k, 3) on b, normal n from a to b
        (3,), or one per point (k, 3) (a capsule on a polyhedron)."""
        d, n, pa, pb = self.query(q)
        (Ra, ca), (Rb, cb) = self._poses(q)
        ha, hb = self.hulls
        if self.capsule is not None:
            return self._capsule_points(q, d, n, pa, pb)
        if ha.faces is None or hb.faces is None:
            return np.zeros(1, int), pa[None], pb[None], n
        fa, fb, cos_a, cos_b = self._faces(Ra, Rb, n)
        if max(cos_a, cos_b) < FACE_COS and abs(d) <= self.tol:
            face_n = touching_face_normal(self.hulls, self._poses(q), d, self.tol)
            if face_n is not None:  # (EPA's normal at a touch to round-off is arbitrary)
                n = face_n
                fa, fb, cos_a, cos_b = self._faces(Ra, Rb, n)
        if max(cos_a, cos_b) < FACE_COS:
            return np.array([self.pool]), pa[None], pb[None], n
        face_a, na = ha.face(fa) @ Ra.T + ca, Ra @ ha.normals[fa]
        face_b, nb = hb.face(fb) @ Rb.T + cb, Rb @ hb.normals[fb]
        flip = cos_a < cos_b - 1e-9  # b's face is the reference (ties go to a: no flip-flop)
        ref, inc, nr, ni = (face_b, face_a, nb, na) if flip else (face_a, face_b, na, nb)
        labels, x_ref, x_inc = face_manifold(ref, inc, nr, ni, self.tol)
        owner = {"ref": ("b" if flip else "a"), "inc": ("a" if flip else "b")}
        face_ids = {"a": ha.faces[fa], "b": hb.faces[fb]}
        first = {"a": 0, "b": len(ha.vertices)}
        slots, rank = [], self.pool
        for lab in labels:
            if lab[0] == "cross":
                slots.append(rank)
                rank += 1
            else:
                body = owner[lab[0]]
                slots.append(first[body] + int(face_ids[body][lab[1]]))
        if flip:
            return np.array(slots, int), x_inc, x_ref, -nr
        return np.array(slots, int), x_ref, x_inc, nr

    def _faces(self, Ra, Rb, n):
        """The faces of a and b most aligned with n and −n, and their cosines."""
        ha, hb = self.hulls
        fa = int(np.argmax(ha.normals @ (Ra.T @ n)))
        fb = int(np.argmax(hb.normals @ (Rb.T @ -n)))
        return fa, fb, ha.normals[fa] @ (Ra.T @ n), hb.normals[fb] @ (Rb.T @ -n)

    def _capsule_on_face(self, q, n):
        """A capsule lying on a face of the polyhedron (the face within ``FACE_COS`` of n, the
        axis within as much of its plane): its axis clipped by the face's side planes, the
        contact points at the two ends of the clipped axis (a cap, or where the capsule leaves
        the face over an edge) with their projections on the face. None where it does not
        lie on a face. Returns slots, x_a, x_b and the normals, as ``manifold``."""
        side, poly = self.capsule, 1 - self.capsule
        poses = self._poses(q)
        (Rp, cp), (Rc, cc) = poses[poly], poses[side]
        hull, capsule = self.hulls[poly], self.hulls[side]
        toward = n if poly == 0 else -n  # from the polyhedron to the capsule
        f = int(np.argmax(hull.normals @ (Rp.T @ toward)))
        nf = Rp @ hull.normals[f]
        ends = capsule.caps @ Rc.T + cc
        axis = ends[1] - ends[0]
        tilt = abs(axis @ nf) / np.linalg.norm(axis)
        if nf @ toward < FACE_COS or tilt > np.sqrt(1.0 - FACE_COS**2):
            return None
        face = hull.face(f) @ Rp.T + cp
        m = _inward(face, nf)
        a = np.einsum("ej,ej->e", m, ends[0] - face)  # side planes: a_e + s b_e ≥ 0
        b = m @ axis
        lo = max([0.0, *(-a[b > 0.0] / b[b > 0.0])])
        hi = min([1.0, *(-a[b < 0.0] / b[b < 0.0])])
        if lo > hi or np.any((b == 0.0) & (a < 0.0)):
            return None
        s = np.array([lo, hi]) if (hi - lo) * np.linalg.norm(axis) > self.tol else np.array([lo])
        centres = ends[0] + np.outer(s, axis)
        on_capsule = centres - capsule.cap.radius * nf
        on_face = centres - np.outer((centres - face[0]) @ nf, nf)
        pair = (on_face, on_capsule) if poly == 0 else (on_capsule, on_face)
        normals = np.repeat((nf if poly == 0 else -nf)[None], len(s), axis=0)
        return np.arange(1, 1 + len(s)), *pair, normals

    def _capsule_points(self, q, d, n, pa, pb):
        """A capsule on a polyhedron touches along a segment where it lies on a face: one
        witness anywhere along it would rock the capsule, so the witnesses of its two cap
        balls are slots 1 and 2, and the capsule's own witness is slot 0 where it lies below
        the line between theirs (an edge or a corner under the segment: the gap along a flat
        face is affine in the segment's parameter). Normals per slot (k, 3)."""
        flat = self._capsule_on_face(q, n)
        if flat is not None:
            return flat
        caps = [self.query(q, cap) for cap in (0, 1)]
        slots, xa, xb, normals = [1, 2], [c[2] for c in caps], [c[3] for c in caps], []
        normals = [c[1] for c in caps]
        R, c = self._poses(q)[self.capsule]
        ends = self.hulls[self.capsule].caps
        on_axis = (R.T @ ((pa, pb)[self.capsule] - c) - ends[0]) @ (ends[1] - ends[0])
        s = np.clip(on_axis / np.sum((ends[1] - ends[0]) ** 2), 0.0, 1.0)
        if d < (1.0 - s) * caps[0][0] + s * caps[1][0] - self.tol:
            slots, xa, xb, normals = [0, *slots], [pa, *xa], [pb, *xb], [n, *normals]
        return np.array(slots), np.array(xa), np.array(xb), np.array(normals)

    def _points(self, q: np.ndarray):
        """Slots k, world points x_a, x_b, the normal n and the poses at q, the manifold kept
        for the last q (the gaps, slip rows and slips of one iterate share one query)."""
        oa, ob = self.offsets
        key = np.concatenate([q[oa : oa + 6], q[ob : ob + 6]])
        if self._last[0] is not None and np.array_equal(self._last[0], key):
            return self._last[1]
        k, xa, xb, n = self.manifold(q)
        n = np.broadcast_to(n, xa.shape)  # (one normal for the pair but a capsule's points)
        keep = k < self.size  # more crossings than the pool holds: impossible for convex faces
        points = (k[keep], xa[keep], xb[keep], n[keep], self._poses(q))
        self._last = (key, points)
        return points

    def _arms(self, q: np.ndarray):
        """Slots k, the body-frame arms r_a, r_b (k, 3) of the contact points, n and poses."""
        k, xa, xb, n, poses = self._points(q)
        (Ra, ca), (Rb, cb) = poses
        return k, (xa - ca) @ Ra, (xb - cb) @ Rb, n, poses

    def _dofs(self):
        oa, ob = self.offsets
        row = np.concatenate([oa + np.arange(6), ob + np.arange(6)])
        return np.repeat(row[None], self.size, axis=0)

    def evaluate(self, q: np.ndarray):
        """Gaps (size,), dofs (size, 12), gradients (size, 12), no curvature."""
        k, xa, xb, n, ((Ra, _), (Rb, _)) = self._points(q)
        k, ra, rb = self._arms(q)[:3]  # body-frame arms Rᵀ(x − c)
        g = np.full(self.size, self.far)
        G = np.zeros((self.size, 12))
        g[k] = np.einsum("kd,kd->k", xb - xa, n) - self.clearance
        G[k, :3], G[k, 6:9] = -n, n
        G[k, 3:6] = -cross(ra, n @ Ra)  # (rows Rᵀn)
        G[k, 9:12] = cross(rb, n @ Rb)
        return g, self._dofs(), G, None

    def gaps(self, q: np.ndarray) -> np.ndarray:
        return self.evaluate(q)[0]

    def tangents(self, q: np.ndarray):
        """Slip rows (size, 2, 12) of b's contact points against a's, T (size, 2, 3): every
        slot in the basis of the pair's normal, zero rows in the empty slots."""
        k, ra, rb, n, ((Ra, _), (Rb, _)) = self._arms(q)
        T = np.zeros((self.size, 2, 3))
        if k.size:  # (the empty slots in the basis of the first point's normal)
            T[:] = tangent_basis(n[:1])
            T[k] = tangent_basis(n)
        rows = np.zeros((self.size, 3, 12))
        rows[k, :, :3], rows[k, :, 6:9] = -np.eye(3), np.eye(3)
        rows[k, :, 3:6] = Ra @ hat(ra)  # −∂x_a/∂Θ_a = R_a r̃_a
        rows[k, :, 9:12] = -Rb @ hat(rb)
        return self._dofs(), np.einsum("mti,mik->mtk", T, rows), T

    def slips(self, q: np.ndarray, q_n: np.ndarray, T: np.ndarray):
        """The slip over the step (size, 2), zero in the empty slots: between polyhedra
        T·(x_rel(q) − x_rel(q_n)) of the material points r_a, r_b found at q; with a round
        shape the slip rows applied to both bodies' increments (Δu, log(R_nᵀR)), zero for a
        ball or capsule rolling over the step (its material point's chord is O(Δθ³) off the
        rolling, and sticking held it: a capsule rolling at 20 rad/s on a face lagged its
        roll on a plane by 2e-8 m a step)."""
        if self.round:
            _, G, _ = self.tangents(q)
            return G @ np.concatenate([_increment(q, q_n, o) for o in self.offsets])
        k, ra, rb, _, ((Ra, ca), (Rb, cb)) = self._arms(q)
        (Ran, can), (Rbn, cbn) = self._poses(q_n)
        chord = (cb - cbn) - (ca - can) + rb @ (Rb - Rbn).T - ra @ (Ra - Ran).T
        out = np.zeros(T.shape[:2])
        out[k] = np.einsum("mtd,md->mt", T[k], chord)
        return out
