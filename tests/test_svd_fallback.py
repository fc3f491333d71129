"""Singular value decompositions where LAPACK's divide and conquer (gesdd, gelsd) does not
converge: taken again by the QR iteration (:mod:`fecontact.linalg.svd`) and counted; what
no driver decomposes, and any LAPACK error left in a step, is the run's error with its time
and step, the states before it kept."""

import numpy as np
import pytest

import fecontact.time.stepper as stepper
from fecontact import Model, simulate
from fecontact.bodies import RigidBody3D
from fecontact.bodies.shapes3d import Box
from fecontact.errors import SolverError
from fecontact.linalg.svd import SVDFailure, lstsq, svd
from fecontact.time.settings import IntegratorOptions


def rank_deficient(n=12, rank=8, seed=3):
    rng = np.random.default_rng(seed)
    return rng.standard_normal((n, rank)) @ rng.standard_normal((rank, n))


def gesdd_fails(monkeypatch):
    """NumPy's svd and lstsq raising as gesdd and gelsd do where they do not converge."""

    def fail(*args, **kwargs):
        raise np.linalg.LinAlgError("SVD did not converge")

    monkeypatch.setattr(np.linalg, "svd", fail)
    monkeypatch.setattr(np.linalg, "lstsq", fail)


def test_the_qr_iteration_takes_over_where_divide_and_conquer_fails(monkeypatch):
    """The same decomposition and least-norm solution as NumPy's, flagged as a fallback
    (round-off of the two drivers: bound 1e-12 relative, measured ~1e-15)."""
    a = rank_deficient()
    b = np.arange(12.0)
    U0, s0, Vt0 = np.linalg.svd(a)
    x0 = np.linalg.lstsq(a, b, rcond=1e-10)[0]
    assert svd(a)[3] is False and lstsq(a, b, 1e-10)[1] is False
    gesdd_fails(monkeypatch)
    U, s, Vt, fell_back = svd(a)
    assert fell_back
    assert np.allclose(s, s0, rtol=0.0, atol=1e-12 * s0[0])
    assert np.allclose(U @ np.diag(s) @ Vt, a, rtol=0.0, atol=1e-12 * s0[0])
    x, fell_back = lstsq(a, b, 1e-10)
    assert fell_back
    assert np.allclose(x, x0, rtol=0.0, atol=1e-12 * np.linalg.norm(x0))


def test_a_matrix_with_nan_is_a_failure_not_a_lapack_error():
    a = rank_deficient()
    a[2, 3] = np.nan
    with pytest.raises(SVDFailure, match="NaN or inf"):
        svd(a)
    with pytest.raises(SVDFailure, match="NaN or inf"):
        lstsq(a, np.ones(12))


def test_a_lapack_error_in_a_step_stops_the_run_with_its_time_and_step(monkeypatch):
    """A LAPACK error the step's solvers did not catch is the step's failure: halved as any
    (max_halvings), then the run's ``SolverError`` at the step's start, the states before
    it yielded."""
    step = stepper.STEPPERS["nsga"]

    def failing_after(model, st, h, settings, timer):
        if st.t >= 2e-3 - 1e-12:
            raise np.linalg.LinAlgError("SVD did not converge")
        return step(model, st, h, settings, timer)

    monkeypatch.setitem(stepper.STEPPERS, "nsga", failing_after)
    box = RigidBody3D.uniform(0.5, [0.0, 0.0, 0.0], Box(0.03, 0.03, 0.01))
    model = Model([box], [], (0.0, 0.0, -9.81))
    states = []
    with pytest.raises(SolverError, match="linear algebra: SVD did not converge") as err:
        states.extend(simulate(model, 1e-3, 5e-3, IntegratorOptions(max_halvings=1)))
    assert [round(st.t * 1e3) for st in states] == [0, 1, 2]
    assert err.value.step == 3
    assert err.value.time == pytest.approx(2e-3, abs=1e-12)
