"""The recorder's energies (``fecontact.energy.StateEnergies``), resolved once per run, are
the model's own floats to the bit: kinetic, strain and gravity energy of every body kind,
alone and together, at states with negative zeros."""

import numpy as np
import pytest
from test_body_protocol import bodies

from fecontact import Model, PointMass
from fecontact.energy import StateEnergies


def bits(x: float) -> bytes:
    return np.float64(x).tobytes()  # (a negative zero is not a zero here)


def states(n: int):
    rng = np.random.default_rng(5)
    yield rng.normal(size=n) * 1e-2, rng.normal(size=n)
    yield np.zeros(n), np.full(n, -0.0)  # ½ vᵀMv of −0.0 velocities is +0.0
    yield np.full(n, -0.0), -rng.normal(size=n)


def check(model: Model) -> None:
    measure = StateEnergies(model)
    for q, v in states(model.n):
        expected = model.kinetic_energy(v), model.strain_energy(q), model.potential_energy(q)
        assert list(map(bits, measure(q, v))) == list(map(bits, expected))


@pytest.mark.parametrize("body", bodies(), ids=lambda b: type(b).__name__)
def test_energies_are_the_models_own(body):
    check(Model([body]))


def test_energies_of_bodies_together():
    dims = {2: [b for b in bodies() if b.dim == 2], 3: [b for b in bodies() if b.dim == 3]}
    for group in dims.values():
        check(Model(group))


def test_a_point_mass_takes_the_diagonal_path():
    # (so that the tests above check the diagonal product against the sparse one)
    assert StateEnergies(Model([PointMass(2.0, [0.0, 0.0])])).diagonal is not None
    beam = next(b for b in bodies() if type(b).__name__ == "Beam3D")
    assert StateEnergies(Model([beam])).diagonal is None  # consistent mass
