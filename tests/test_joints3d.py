"""Joints in space: their rows against finite differences on the group, and a hinged body in
planar motion against the planar rigid body."""

import numpy as np
import pytest

from fecontact import Box, InputError, Model, Pin, Polygon, RigidBody2D, RigidBody3D
from fecontact.joints3d import BallJoint, FixedJoint, HingeJoint, PrismaticJoint, UniversalJoint
from fecontact.rotations import compose
from fecontact.time.simulate import simulate


def two_bodies():
    a = RigidBody3D.uniform(1.0, [0.0, 0.0, 0.0], Box(0.2, 0.1, 0.3))
    b = RigidBody3D.uniform(2.0, [0.3, 0.1, -0.2], Box(0.1, 0.4, 0.2))
    return a, b


def moved(q, d):
    """q ⊕ d on both bodies (6 dofs each)."""
    out = q + d
    for o in (3, 9):
        out[o : o + 3] = compose(q[o : o + 3], d[o : o + 3])
    return out


@pytest.mark.parametrize(
    "make",
    [
        lambda a, b: BallJoint(a, [0.1, 0.0, 0.0], b),
        lambda a, b: HingeJoint(a, [0.1, 0.0, 0.0], [1.0, 2.0, 0.5], b),
        lambda a, b: UniversalJoint(a, [0.1, 0.0, 0.0], [1, 0, 0], [0, 1, 0], b),
        lambda a, b: FixedJoint(a, [0.1, 0.0, 0.0], b),
        lambda a, b: HingeJoint(a, [0.1, 0.0, 0.0], [0.0, 0.0, 1.0]),
        lambda a, b: PrismaticJoint(a, [0.1, 0.0, 0.0], [1.0, 2.0, 0.5], b),
        lambda a, b: PrismaticJoint(a, [0.1, 0.0, 0.0], [1.0, 2.0, 0.5]),
    ],
    ids=["ball", "hinge", "universal", "fixed", "hinge-to-ground", "prismatic", "slider"],
)
def test_joint_rows_are_the_derivatives_along_the_group(make):
    """G is ∂g along body-frame rotations, H the derivative of Gᵀλ: central differences of
    step 1e-6 agree to their truncation error (1e-10 relative) with round-off (1e-9)."""
    a, b = two_bodies()
    joint = make(a, b)
    Model([a, b], gravity=(0.0, 0.0, 0.0), joints=[joint])
    rng = np.random.default_rng(3)
    q = np.r_[0.01, -0.02, 0.03, 0.4, -0.7, 0.2, -0.05, 0.02, 0.01, -1.1, 0.3, 0.6]
    g, dofs, G, H = joint.evaluate(q)
    lam = rng.normal(size=joint.size)
    k = G.shape[1]
    for j in range(k):
        d = np.zeros(12)
        d[dofs[0, j]] = 1e-6
        gp, _, Gp, _ = joint.evaluate(moved(q, d))
        gm, _, Gm, _ = joint.evaluate(moved(q, -d))
        assert np.allclose((gp - gm) / 2e-6, G[:, j], atol=1e-8)
        dF = (Gp.T @ lam - Gm.T @ lam) / 2e-6
        assert np.allclose(dF, np.einsum("i,ik->k", lam, H[:, :, j]), atol=1e-7)


def test_perpendicular_axes_of_a_universal_joint_are_checked():
    a, b = two_bodies()
    with pytest.raises(InputError, match="perpendicular"):
        UniversalJoint(a, [0, 0, 0], [1, 0, 0], [1, 1, 0], b)


def test_a_closed_loop_that_holds_a_motion_twice_names_its_joints():
    """A parallelogram four-bar of hinges on parallel axes (20 rows on 18 dofs: the loop
    holds its out-of-plane motion twice) is refused naming its joints (before: "a Pin holds
    what another Pin holds", for a model without a Pin); with the coupler on two ball joints
    (16 rows, independent) it swings, its energy held to 9.5e-7 J over 1 s at h = 1 ms
    (asked 1e-5, ten times over: the second-order step's drift on its 0.12 J)."""

    def four_bar(coupler):
        links = [
            RigidBody3D.uniform(1.0, centre, Box(0.02, 0.02, 0.02))
            for centre in ([0, 0, -0.1], [0.15, 0, -0.2], [0.3, 0, -0.1])
        ]
        a, c, b = links
        y = [0, 1, 0]
        joints = [HingeJoint(a, [0, 0, 0], y), HingeJoint(b, [0.3, 0, 0], y)]
        joints += [coupler(c, [0, 0, -0.2], a), coupler(c, [0.3, 0, -0.2], b)]
        return Model(links, [], gravity=(0, 0, -9.81), joints=joints), links

    with pytest.raises(InputError, match="HingeJoint 0, HingeJoint 1, HingeJoint 2"):
        four_bar(lambda c, p, o: HingeJoint(c, p, [0, 1, 0], o))
    model, (a, c, b) = four_bar(BallJoint)
    v0 = np.zeros(model.n)
    for body, v, w in ((a, -0.2, 2.0), (c, -0.4, 0.0), (b, -0.2, 2.0)):
        o = model.offset_of(body)
        v0[o], v0[o + 4] = v, w  # the crank and rocker turning at 2 rad/s about y
    energy = [
        model.kinetic_energy(st.v) + model.potential_energy(st.q)
        for st in simulate(model, 1e-3, 1.0, v0=v0)
    ]
    assert np.ptp(energy) < 1e-5


def test_a_hinged_bar_in_its_plane_swings_as_the_planar_rigid_pendulum():
    """The bar of ``rigid_pendulum`` (no stop) hinged about z and released horizontally: its
    angle follows the planar RigidBody2D with a Pin to round-off over 1 s at h = 1 ms
    (measured 4e-15 rad): about one axis the composition adds and T(D) is the identity."""
    L, m, h = 1.0, 1.0, 1e-3
    diamond = Polygon([[-L / 2, 0.0], [0.0, -0.01], [L / 2, 0.0], [0.0, 0.01]])
    bar2 = RigidBody2D(m, m * L**2 / 12.0, [L / 2, 0.0], shape=diamond)
    planar = Model([bar2], gravity=(0.0, -9.81), joints=[Pin(bar2, [0.0, 0.0])])
    # a thin box about its centre: J_z = m L²/12 (the thickness is tiny)
    J = [1e-3, m * L**2 / 12.0, m * L**2 / 12.0]
    bar3 = RigidBody3D(m, J, [L / 2, 0.0, 0.0], Box(L, 0.02, 0.02))
    hinge = HingeJoint(bar3, [0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    spatial = Model([bar3], gravity=(0.0, -9.81, 0.0), joints=[hinge])
    th2 = [st.q[2] for st in simulate(planar, h, 1.0)]
    s3 = list(simulate(spatial, h, 1.0))
    th3 = [st.q[5] for st in s3]
    assert np.max(np.abs(np.array(th2) - th3)) < 1e-12
    assert np.max(np.abs([st.q[[2, 3, 4]] for st in s3])) < 1e-12  # it stays in its plane


def test_a_slider_on_an_incline_accelerates_at_g_sin_alpha_and_keeps_its_spin_locked():
    """A box on a prismatic joint along a 30° incline, spun about every axis at the start
    (the joint must hold the rotation: v0 must satisfy it, so no spin), slides with
    s = ½ g sin α t² (constant force: the step is exact to round-off)."""
    axis = np.array([np.cos(np.pi / 6), 0.0, -np.sin(np.pi / 6)])
    box = RigidBody3D.uniform(2.0, [0.0, 0.0, 0.0], Box(0.2, 0.1, 0.1))
    slider = PrismaticJoint(box, [0.05, 0.02, 0.0], axis)
    model = Model([box], gravity=(0.0, 0.0, -9.81), joints=[slider])
    for st in simulate(model, 1e-3, 0.5):
        s = 0.5 * 9.81 * np.sin(np.pi / 6) * st.t**2
        assert np.allclose(st.q[:3], s * axis, rtol=0, atol=1e-12)
        assert np.abs(st.q[3:]).max() < 1e-12
