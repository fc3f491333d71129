"""The compiled Beam3D kernel (:mod:`fecontact.bodies.beam3d_jit`) against the numpy kernel:
the same formulas, so the same force, tangent and energy to round-off."""

import json
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from conftest import ROOT

from fecontact import Model, Simulation, run
from fecontact.bodies import Beam3D, Material, Section
from fecontact.bodies.beam3d import kernel_choice
from fecontact.errors import InputError

ALUMINIUM = Material(7e10, nu=0.33, rho=2700.0)
STRIP = Section.rectangle(0.02, 0.002)


def _beams():
    """The same oblique rod of 6 elements with the numpy kernel and with the jit kernel."""
    ends = [0.0, 0.0, 0.0], [0.4, 0.15, -0.2]
    return [Beam3D.straight(*ends, 6, ALUMINIUM, STRIP, kernel=k) for k in ("numpy", "jit")]


def _states(beam, n: int):
    """Random states: displacements of 1 cm, a large rotation of the whole rod (up to 3 rad)
    and relative rotations of its elements from 1e-3 to 1.5 rad, so that the rotation
    coefficients are taken both by their series (θ² < 1) and by their closed forms."""
    rng = np.random.default_rng(32)
    for _ in range(n):
        Q = np.zeros((beam.n_nodes, 6))
        Q[:, :3] = 1e-2 * rng.normal(size=(beam.n_nodes, 3))
        spread = 10.0 ** rng.uniform(-3, np.log10(1.5 / np.sqrt(3)))
        Q[:, 3:] = rng.uniform(-1.7, 1.7, size=3) + spread * rng.normal(size=(beam.n_nodes, 3))
        yield Q.ravel()


def test_choice_of_kernel(monkeypatch):
    assert kernel_choice("numpy") == "numpy"
    assert kernel_choice("auto") in ("numpy", "jit")
    with pytest.raises(InputError, match="kernel"):
        kernel_choice("fortran")
    monkeypatch.setenv("FECONTACT_BEAM3D_KERNEL", "numpy")  # the default where none is given
    assert kernel_choice(None) == "numpy"
    assert Beam3D.straight([0, 0, 0], [1, 0, 0], 2, ALUMINIUM, STRIP).kernel == "numpy"


def test_summary_records_the_kernel(tmp_path):
    beam = Beam3D.straight([0, 0, 0], [0.4, 0, 0], 2, ALUMINIUM, STRIP, kernel="numpy").pin(0)
    sim = Simulation(Model([beam], [], gravity=(0.0, -9.81, 0.0)), dt=1e-3, t_end=2e-3)
    summary = run(sim, tmp_path, frames=False, checkpoint_every=0)
    assert summary["beam3d_kernel"] == "numpy"


def test_jit_kernel_equals_the_numpy_kernel():
    pytest.importorskip("numba")
    numpy_beam, jit_beam = _beams()
    assert (numpy_beam.kernel, jit_beam.kernel) == ("numpy", "jit")
    for q in _states(numpy_beam, 300):
        W, f, K = numpy_beam.internal(q)
        Wj, fj, Kj = jit_beam.internal(q)
        # double-precision sums of O(10) terms in another order, through the rotation
        # coefficients: measured at most 4e-15 (force), 6e-16 (tangent), 7e-16 (energy)
        # relative over these states (2.6e-14 on rods turned at random, whose elements
        # come near π, where T(ρ)⁻¹ amplifies round-off); 1e-12 is far above that and far
        # below a wrong term (a sign or a factor: O(1))
        assert abs(Wj - W) <= 1e-12 * abs(W)
        assert np.max(np.abs(fj - f)) <= 1e-12 * np.max(np.abs(f))
        assert np.max(np.abs(Kj - K)) <= 1e-12 * np.max(np.abs(K))
        _, fj_alone, none = jit_beam.internal(q, tangent=False)
        assert none is None and np.array_equal(fj_alone, fj)
        # (the energies are of one formula in two orders of summation: as the force's)
        assert abs(jit_beam.energy(q) - numpy_beam.energy(q)) <= 1e-12 * abs(W)


def test_without_numba_the_numpy_kernel_runs(tmp_path):
    """In an interpreter where numba cannot be imported, "auto" takes the numpy kernel."""
    script = textwrap.dedent(
        """
        import importlib.abc, sys

        class Blocker(importlib.abc.MetaPathFinder):
            def find_spec(self, name, path=None, target=None):
                if name.split(".")[0] in ("numba", "llvmlite"):
                    raise ModuleNotFoundError(f"No module named {name!r}", name=name)

        sys.meta_path.insert(0, Blocker())
        from fecontact.cli import main
        status = main(["run", "spatial_pendulum", "--t-end", "0.003", "--quiet"])
        print(status, "numba" in sys.modules)
        """
    )
    env = {"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin", "OPENBLAS_NUM_THREADS": "1"}
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, cwd=tmp_path, env=env
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.split("\n")[0] == "0 False"
    summary = json.loads((tmp_path / "out" / "spatial_pendulum" / "summary.json").read_text())
    assert summary["beam3d_kernel"] == "numpy"
