"""The energy ledger and impact localization carry over to the cases in space: the ledger's
``created`` and ``scale`` are filled and it closes at every step; a rigid ball in space on a
plane is localized by default and follows the exact parabolas as the planar one does."""

import numpy as np
import pytest
from conftest import ROOT

from fecontact import Model, load_run
from fecontact.bodies import RigidBody3D
from fecontact.bodies.shapes3d import Ball
from fecontact.cli.commands import main
from fecontact.contact import Contact, Plane
from fecontact.testing import ball_exact_gap
from fecontact.time import IntegratorOptions, StepStats, simulate
from fecontact.time.localize import localizes

TERMS = ("damping_dissipation", "friction_dissipation", "impact_dissipation")
# short runs through their first contacts (the heavy top has none)
RUNS = {
    "heavy_top": "0.02",
    "tumbling_box": "0.1",
    "spatial_pendulum": "0.02",
    "rod_drop": "0.02",
    "box_stack": "0.05",
    "rod_on_post": "0.1",
}


@pytest.mark.parametrize("name", sorted(RUNS))
def test_the_ledger_of_the_cases_in_space_is_filled_and_closes(name, tmp_path):
    """E(t) − E(0) − W + ΣD over the steps within 1e-9 of the energies (round-off of a sum
    of some thousand step terms ~1e-13); ``created`` and ``scale`` finite, scale > 0."""
    args = ["run", str(ROOT / "cases" / f"{name}.py"), "--quiet", "--out", str(tmp_path)]
    assert main([*args, "--checkpoint-every", "0", "--t-end", RUNS[name]]) == 0
    done = load_run(tmp_path)
    history, ledger = done.history, done.summary["energy_ledger"]
    E = history["total_energy"]
    D = sum(history[k] for k in (*TERMS, "numerical_dissipation"))
    residual = np.abs(E - E[0] - history["load_work"] + D)
    scale = max(ledger["scale"], np.max(np.abs(E)))
    assert residual.max() <= 1e-9 * scale
    assert ledger["scale"] > 0.0 and 0.0 <= ledger["created"] < np.inf


def test_a_rigid_ball_in_space_bounces_localized_by_default():
    """A RigidBody3D ``Ball`` dropped 1 m on a plane at e = 0.8, h = 1e-3 over 3 s, default
    options: localization is on ("auto": rigid bodies, frictionless, fixed obstacle) and the
    height follows the exact parabolas to round-off (measured 2.8e-14 m; the planar disk's
    bound 1e-9 m), six impacts located; without it the error is 3.1e-3 m."""
    ball = RigidBody3D.uniform(1.0, [0.0, 0.0, 1.1], Ball(0.1))
    model = Model([ball], [Contact(ball, Plane([0, 0, 0], [0, 0, 1]), restitution=0.8)])
    assert localizes(model, IntegratorOptions())
    stats = StepStats()
    states = list(simulate(model, 1e-3, 3.0, IntegratorOptions(), stats=stats))
    t = np.array([st.t for st in states])
    gap = np.array([st.q[2] for st in states]) + 1.0
    assert np.max(np.abs(gap - ball_exact_gap(t, e=0.8))) <= 1e-9
    assert min(float(st.gaps.min()) for st in states) >= -1e-12
    assert stats.localization.impacts == 6
