"""What a user's workflow around a run needs: the history as a pandas table, progress in logs
and notebooks, sweeps on any scheduler, BLAS threads limited inside a run only."""

import numpy as np
import pytest

from fecontact import load_run
from fecontact.cli import main


@pytest.fixture(scope="module")
def pendulum_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("pendulum")
    argv = ["run", "flexible_pendulum", "--t-end", "0.05", "--quiet", "--out", str(out)]
    assert main(argv) == 0
    return out


def test_history_and_probes_as_a_dataframe(pendulum_run):
    pd = pytest.importorskip("pandas")
    run = load_run(pendulum_run)
    frame = run.to_dataframe()
    assert isinstance(frame, pd.DataFrame) and frame.index.name == "t"
    np.testing.assert_array_equal(frame.index.to_numpy(), run.history["t"])
    for name in ("tip_x", "tip_y", "tip_vx", "tip_vy", "kinetic_energy"):
        np.testing.assert_array_equal(frame[name].to_numpy(), run.history[name])
    assert len(frame) == 51  # t = 0 and 50 steps of 1 ms
    assert frame.attrs["units"] == {"tip_x": "m", "tip_y": "m", "tip_vx": "m/s", "tip_vy": "m/s"}
