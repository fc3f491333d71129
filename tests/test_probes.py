"""Node probes read one dof where a body's positions are X + u: the same floats, to the bit,
as the body's own ``positions`` and ``point_data`` give (what the probes returned before)."""

from types import SimpleNamespace

import numpy as np
import pytest
from test_body_protocol import bodies

from fecontact import Model, PointMass, node_probe
from fecontact.errors import InputError

QUANTITIES = ("x", "y", "z", "ux", "uy", "vx", "vy", "vz", "rotation")


def from_body(body, q, v, node: int, quantity: str) -> float:
    """The probe's value from the body's arrays, as a history row held it before."""
    if quantity in ("x", "y", "z"):
        return float(body.positions(q)[node, "xyz".index(quantity)])
    data = body.point_data(q, v)
    if quantity == "rotation":
        return float(data["rotation"][node])
    field = data["displacement" if quantity[0] == "u" else "velocity"]
    return float(field[node, "xyz".index(quantity[1])])


def bits(x: float) -> bytes:
    return np.float64(x).tobytes()  # (a negative zero is not a zero here)


@pytest.mark.parametrize("body", bodies(), ids=lambda b: type(b).__name__)
def test_probes_give_the_bodys_own_values_to_the_bit(body):
    model = Model([body])
    rng = np.random.default_rng(3)
    n = body.ndof
    checked = 0
    for q, v in [
        (rng.normal(size=n) * 1e-2, rng.normal(size=n)),
        (np.full(n, -0.0), np.full(n, -0.0)),  # negative zeros are written as such
    ]:
        st = SimpleNamespace(q=q, v=v)
        for node in {0, body.n_nodes - 1}:
            for quantity in QUANTITIES:
                try:
                    probe = node_probe(model, body, node, quantity)
                except InputError:  # (a quantity this kind has not: z in the plane, ...)
                    continue
                expected = from_body(body, q, v, node, quantity)
                assert bits(probe.fn(model, st)) == bits(expected), (quantity, node)
                checked += 1
    assert checked >= 8  # x, y and vx, vy at least, at two states


class Lever(PointMass):
    """A point whose position moves twice its dofs: affine kinematics other than X + u."""

    def positions(self, q):
        return (self.position + 2.0 * q[:2])[None, :]

    def point_kinematics(self, q, nodes):
        x, dofs, J, H = super().point_kinematics(q, nodes)
        return self.positions(q).repeat(len(nodes), axis=0), dofs, 2.0 * J, H


def test_a_body_whose_positions_are_not_x_plus_u_is_probed_through_its_positions():
    body = Lever(1.0, [0.5, 0.25])
    model = Model([body])
    st = SimpleNamespace(q=np.array([0.1, -0.2]), v=np.array([1.0, 2.0]))
    assert node_probe(model, body, 0, "x").fn(model, st) == 0.5 + 2.0 * 0.1
    assert node_probe(model, body, 0, "y").fn(model, st) == 0.25 - 2.0 * 0.2
