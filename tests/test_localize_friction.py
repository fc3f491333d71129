"""Undamped frictional solids localized in whole steps (``FRICTIONAL_SOLIDS``, on by default:
docs/validation/localization.md, "Friction"): the closing's energy is gone, and a node of a
lasting contact that lifts and re-closes is left to the step's end (counted ``persistent``)."""

import dataclasses
import warnings

import numpy as np
from conftest import load_case
from test_localize_mixed import box_on_slab

from fecontact import Contact, IntegratorOptions, Model, Simulation, run
from fecontact.bodies import NeoHookean, RigidBody2D, Solid
from fecontact.bodies.rigid import Polygon
from fecontact.contact import Plane
from fecontact.ledger import CREATED
from fecontact.scenes import wave_step
from fecontact.time import localize, run_settings
from fecontact.time.substeps import Releases, localized_stepper


def struck_block(t_end=0.005, mu=0.2):
    """A Neo-Hookean block 20 × 4 cm (20 × 4 cells) resting on a floor with Coulomb's μ, under
    gravity, struck from 1 mm above by a rigid pentagon (1 kg, circumradius 3 cm) at 1.5 m/s
    spinning at 40 rad/s, e_N = 0.5, at twice the block's wave step Δx/c."""
    block = Solid.rectangle([-0.1, 0.0], [0.1, 0.04], (20, 4), NeoHookean(1e7, 0.3, 1000.0))
    pentagon = RigidBody2D.uniform(1.0, [0.01, 0.071], Polygon.regular(5, 0.03))
    floor = Contact(block, Plane([0.0, 0.0], [0.0, 1.0]), friction=mu)
    model = Model([block, pentagon], [floor, Contact(block, pentagon, restitution=0.5)],
                  (0.0, -9.81))  # fmt: skip
    v0 = np.zeros(model.n)
    v0[model.body_slice(1)] = [0.0, -1.5, 40.0]
    return Simulation(model, dt=wave_step(block, 2.0), t_end=t_end, v0=v0, name="struck")


def created(sim, out):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # (the end-of-step run warns: measured)
        summary = run(sim, out, frames=False, checkpoint_every=0)
    ledger = summary["energy_ledger"]
    return ledger["created"] / ledger["scale"], summary


def test_auto_takes_frictional_solids_in_whole_steps_unless_switched_off(monkeypatch):
    model = struck_block().model
    settings = run_settings(model, IntegratorOptions())
    assert localize.localizes(model, settings)
    assert isinstance(localized_stepper(model, settings), Releases)
    monkeypatch.setattr(localize, "FRICTIONAL_SOLIDS", False)
    assert not localize.localizes(model, run_settings(model, IntegratorOptions()))


def test_the_struck_block_on_a_frictional_floor_creates_no_energy(tmp_path):
    """The pentagon's closing at the end of its step pushes the block's nodes out: 5.4e-2 of
    the scale created (measured 0.0540, by 5 ms; h/4: 0). Located, 0 measured, as on the
    frictionless floor (0): bound the ledger's warning level, 1e-3 of the scale. The floor's
    nodes that lift and re-close under the ringing are left to the step's end."""
    sim = struck_block()
    off = sim.replace(options=dataclasses.replace(sim.options, localize=False))
    assert created(off, tmp_path / "off")[0] > 0.05
    auto, summary = created(sim, tmp_path / "auto")
    assert auto <= CREATED
    assert summary["localized_impacts"] >= 1
    assert summary["localization_fallbacks"]["persistent"] >= 1


def test_a_box_dropped_corner_first_on_a_frictional_slab_creates_no_energy(tmp_path):
    """The rigid box corner first on the elastic slab with μ = 0.3 (mortar): the end-of-step
    closing creates 2.66e-2 of the scale (measured 0.02656), located 0 measured; bound the
    ledger's warning level, 1e-3."""
    sim = box_on_slab(friction=0.3, method="mortar")
    off = sim.replace(options=dataclasses.replace(sim.options, localize=False))
    assert created(off, tmp_path / "off")[0] > 0.02
    auto, summary = created(sim, tmp_path / "auto")
    assert auto <= CREATED and summary["localized_impacts"] >= 1


def test_a_settled_floor_under_a_ringing_block_reads_no_release(tmp_path):
    """``elastic_block`` at its defaults (held on its 20° incline by μ = 0.5, 30 ms): the
    floor's node forces ring and fall towards zero again and again, and each fall read the
    release aside (26 probes: 0.77 → 2.79 s of CPU). A contact lasting for over
    CHATTER_WINDOW steps reads none: only the first landing's 2 probes are left, and the run
    is the same to the bit (history.csv, measured), with no energy created (0 measured; bound
    the ledger's warning level)."""
    sim = load_case("elastic_block").build(t_end=0.03)
    share, summary = created(sim, tmp_path / "auto")
    assert share <= CREATED
    assert summary["localization_cost"]["release_probes"] <= 2
