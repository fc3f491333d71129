"""Heavy symmetric top on a fixed point (Lagrange's top).

A uniform disk (``Cylinder`` of ``radius`` and ``thickness``) on an axle: its centre of mass
lies ``arm`` from the fixed point O at the origin, on its symmetry axis, and a ``BallJoint``
holds O in space. It starts tilted by ``tilt`` from the vertical, spinning at ``spin`` about
its axis and precessing at ``precession`` about the vertical, without nutation rate (the top
of a nutation). Gravity acts along −z.

With Euler angles (φ precession, θ nutation, ψ spin; ZXZ) and the moments A_O = A + m ℓ² about
O (transverse) and C (axial), the angular momenta about the vertical, L_z = A_O φ̇ sin²θ +
C ω₃ cos θ, and about the axis, L₃ = C ω₃, are conserved with the energy; u = cos θ obeys
u̇² = f(u), a cubic whose roots u₁ < u₂ < 1 < u₃ bound the nutation, of period 4K(k)/√(b(u₃ −
u₁)), b = 2mgℓ/A_O, k² = (u₂ − u₁)/(u₃ − u₁) (Goldstein, Classical Mechanics, §5.7).

Probes: ``L_vertical`` and ``L_axis`` (kg·m²/s, about O), ``theta`` (rad, the axis from the
vertical) and ``phi`` (rad, the azimuth of the axis: the precession).
"""

import numpy as np

from fecontact import Cylinder, Model, Param, Probe, RigidBody3D, Simulation, case, run_cli
from fecontact.joints3d import BallJoint
from fecontact.rotations import exp
from fecontact.scenes import GRAVITY


def top_axis(st) -> np.ndarray:
    """The symmetry axis R e₃ of the top at state ``st``."""
    return exp(st.q[3:6])[:, 2]


def angular_momentum(body, st) -> np.ndarray:
    """Angular momentum about the fixed point O (the origin), kg·m²/s, in space."""
    R = exp(st.q[3:6])
    c = body.center(st.q)
    return body.mass * np.cross(c, st.v[:3]) + R @ (body.J @ st.v[3:6])


@case(GRAVITY)  # along -z
def build(
    mass=Param.positive(1.0, "kg", "mass of the top"),
    radius=Param.positive(0.05, "m", "radius of the disk"),
    thickness=Param.positive(0.01, "m", "thickness of the disk"),
    arm=Param.positive(0.05, "m", "distance from the fixed point to the centre of mass"),
    tilt=Param(0.5, "rad", "initial angle of the axis from the vertical", 0.0, 3.0, (False, True)),
    spin=Param(100.0, "rad/s", "initial spin about the axis (psi dot)", -1e4, 1e4),
    precession=Param(
        0.0, "rad/s", "initial precession rate about the vertical (phi dot)", -1e4, 1e4
    ),
    gravity=9.81,
    t_end=Param.positive(5.0, "s", "end time"),
    dt=Param.positive(5e-5, "s", "time step (L_vertical to 1e-6 over 5 s)"),
):
    # upright in the pose q = 0: the axis along +z, O at the origin
    top = RigidBody3D.uniform(mass, [0.0, 0.0, arm], Cylinder(radius, thickness))
    model = Model([top], gravity=(0.0, 0.0, -gravity), joints=[BallJoint(top, [0.0, 0.0, 0.0])])
    # tilted about x by θ₀: ω = φ̇ e_z + ψ̇ R e₃, body frame Ω = Rᵀω; the centre moves with it
    R0 = exp(np.array([tilt, 0.0, 0.0]))
    Omega = R0.T @ (precession * np.eye(3)[2]) + spin * np.eye(3)[2]
    r = np.array([0.0, 0.0, arm])
    q0 = np.concatenate([R0 @ r - r, [tilt, 0.0, 0.0]])
    v0 = np.concatenate([R0 @ np.cross(Omega, r), Omega])

    def momentum(i):
        def probe(m, st):
            L = angular_momentum(top, st)
            return float(L[2] if i == 2 else L @ top_axis(st))

        return probe

    probes = {
        "L_vertical": Probe(momentum(2), "kg m^2/s", "angular momentum about the vertical"),
        "L_axis": Probe(momentum(3), "kg m^2/s", "angular momentum about the top's axis"),
        "theta": Probe(
            lambda m, st: float(np.arccos(top_axis(st)[2])), "rad", "axis from the vertical"
        ),
        "phi": Probe(
            lambda m, st: float(np.arctan2(top_axis(st)[0], -top_axis(st)[1])),
            "rad",
            "azimuth of the axis (precession)",
        ),
    }
    return Simulation(model, dt=dt, t_end=t_end, probes=probes, q0=q0, v0=v0, name="heavy_top")


if __name__ == "__main__":
    run_cli(build)
