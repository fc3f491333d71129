"""The release of frictionless solids is read from sub-steps taken aside
(:class:`fecontact.time.substeps.Releases`): reading it does not move the run. The sub-steps
work on a copy of the contact set, leave the run's caches and ladder as they were
(:mod:`fecontact.time.aside`), and a sub-step that fails reads nothing instead of failing
the run's step."""

import numpy as np
import pytest

from fecontact.contact.body_pairs import NodeSurfaceContact
from fecontact.contact.mortar_interface import MortarInterface
from fecontact.contact.mortar_safeguard import DeepNodeRows
from fecontact.scenes import wave_step
from fecontact.testing import case
from fecontact.time import StepStats, simulate, substeps
from fecontact.time.substeps import READ_RELEASE, Releases


def fast_disks(stats):
    """The node-to-surface disks of tests/test_fast_approach.py at 30 m/s each, Δx/c: their
    probes start in halved steps, fail there, and read releases that pressed nodes make."""
    sim = case("two_disks").build(
        velocity=30.0, refinements=2, gap=0.0005, t_end=0.003, method="node-to-surface"
    )
    model = sim.model
    dt = wave_step(model.bodies[0], 1)
    return model, simulate(model, dt, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0, stats=stats)


def mortar_disks(stats):
    """The default two disks (one mortar interface) past their release (4.38 ms)."""
    sim = case("two_disks").build(t_end=0.0048)
    model = sim.model
    return model, simulate(model, sim.dt, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0, stats=stats)


def search_state(model):
    """What each pair keeps of its search for the run's next evaluations: the margin, and the
    kept search itself (the same object while no new search replaces it)."""
    state = []
    for pair in model.contacts.pairs:
        if isinstance(pair, MortarInterface):
            state.append((pair.margin, pair.searched))
        elif isinstance(pair, NodeSurfaceContact):
            state.append((pair.margin, pair.search.kept))
    return state


@pytest.mark.parametrize("run", [fast_disks, mortar_disks])
def test_a_probe_leaves_the_pairs_searches_as_the_run_had_them(run, monkeypatch):
    probe, seen = Releases._probe, []

    def watched(self, model, st, h, opts, timer):
        contacts, before = model.contacts, search_state(model)
        reading = probe(self, model, st, h, opts, timer)
        seen.append((model.contacts is contacts, before, search_state(model), reading[0]))
        return reading

    monkeypatch.setattr(Releases, "_probe", watched)
    stats = StepStats()
    for _ in run(stats)[1]:  # (the run to its end)
        pass
    assert seen and stats.localization.release_probes == len(seen)
    assert any(release is not None for *_, release in seen)  # (a release read by a probe)
    for same, before, after, _ in seen:
        assert same and before
        for (margin, kept), (margin_after, kept_after) in zip(before, after, strict=True):
            assert margin_after == margin and kept_after is kept


@pytest.mark.parametrize("run", [fast_disks, mortar_disks])
def test_a_run_that_reads_its_releases_is_the_run_without_probes(run, monkeypatch):
    """The whole run with its probes equals, to the bit, the run without them (no sub-step
    ever taken aside; its steps retaken in sub-steps where a closing is unrefined, as the
    run's own), the releasing steps taken whole (their split at the reading is the one use
    of a probe that moves the run: tests/test_release_split.py)."""
    monkeypatch.setattr(substeps, "split_at_release", lambda *args: None)
    stats = StepStats()
    read = [np.concatenate([st.q, st.v]) for st in run(stats)[1]]
    assert stats.localization.release_probes > 0
    # (no force ever falls to zero: no probe; the steps as the run's)
    monkeypatch.setattr(Releases, "_releasing", lambda self, st, within, settled=None: False)
    plain = StepStats()
    alone = [np.concatenate([st.q, st.v]) for st in run(plain)[1]]
    assert plain.localization.release_probes == 0
    assert len(read) == len(alone)
    for a, b in zip(read, alone, strict=True):
        np.testing.assert_array_equal(a, b)  # (bit for bit: nothing of a probe is left)


def dropped_ball(stats):
    """The elastic ball of ``ball_drop`` (one refinement) falling, striking, pressed, its
    release read by a probe, and flying again."""
    sim = case("ball_drop").build(refinements=1, t_end=0.02)
    model = sim.model
    return model, simulate(model, sim.dt, sim.t_end, sim.options, q0=sim.q0, v0=sim.v0, stats=stats)


@pytest.mark.parametrize("run", [fast_disks, dropped_ball])
def test_a_state_taken_as_in_flight_presses_nothing(run, monkeypatch):
    """A step that starts from a state the step before noted as pressing nothing
    (:meth:`Releases._note_flight`) skips its test: every such state presses nothing, and the
    run equals, to the bit, the run that tests every state (the disks fly, press, are halved
    and let go; the ball flies, strikes, is let go and flies)."""
    call, flights = Releases.__call__, []

    def watched(self, model, st, h, opts, timer):
        free, impulse = self.flying
        if st is free and st.impulse is impulse:
            flights.append(bool(st.pressed().any()))
        return call(self, model, st, h, opts, timer)

    monkeypatch.setattr(Releases, "__call__", watched)
    stats = StepStats()
    noted = [np.concatenate([st.q, st.v, st.impulse]) for st in run(stats)[1]]
    assert flights and not any(flights)
    assert stats.localization.impacts and stats.localization.release_probes
    monkeypatch.setattr(Releases, "_note_flight", lambda self, out, unsplit: None)
    tested = [np.concatenate([st.q, st.v, st.impulse]) for st in run(StepStats())[1]]
    assert len(noted) == len(tested)
    for a, b in zip(noted, tested, strict=True):
        np.testing.assert_array_equal(a, b)  # (bit for bit: the same decisions)


class MeanForces:
    """A state as :meth:`Releases._releasing` reads it: its contacts' mean forces (N)."""

    def __init__(self, force: np.ndarray):
        self.force, self.impulse = force, np.zeros(force.size)

    def mean_force(self) -> np.ndarray:
        return self.force


def test_a_safeguard_row_unloading_reads_no_release():
    """A mortar node's own row (the safeguard's pointwise rows, the master's nodes' too) whose
    force falls to zero is the node back within its allowance, held by the interface's
    weighted rows: no release of the balls, so no probe starts from it (two_balls at 10 m/s
    took 10 probes, 70 s of its 280 s, on the master's rows while the balls were pressed
    harder every step; none read a release). The same fall on a weighted row still does."""
    model = case("two_balls").build(velocity=10.0).model
    contacts = model.contacts
    pointwise = np.array([isinstance(pair, DeepNodeRows) for pair in contacts.pairs])
    rows = {kind: np.flatnonzero(pointwise[contacts.owner] == kind)[0] for kind in (True, False)}
    assert pointwise.sum() == 2  # (the slave's nodes against the master, and the master's)
    for safeguard, row in rows.items():
        releases = Releases(model, split=True)
        before, after = np.zeros(contacts.size), np.zeros(contacts.size)
        before[row], after[row] = 10.0, 4.0  # (zero 2/3 of a step ahead along that line)
        releases._releasing(MeanForces(before), READ_RELEASE, releases._aside())
        reads = releases._releasing(MeanForces(after), READ_RELEASE, releases._aside())
        assert reads is not safeguard


def laid_box(stats, steps=5):
    """A rigid box 2 × 2 × 1 cm laid on a clamped rubber slab under gravity (the row of
    benchmarks/rigid_mortar.py): its ringing forces start probes of all the contacts, and
    then, where the pair's total force falls, of the pair's rows."""
    from fecontact import Model
    from fecontact.bodies import RigidBody3D, Solid
    from fecontact.bodies.materials import NeoHookean
    from fecontact.bodies.shapes3d import Box
    from fecontact.contact import Contact
    from fecontact.time.settings import IntegratorOptions

    rubber = NeoHookean(1e7, 0.3, 1000.0)
    slab = Solid.box([-0.06, -0.04, -0.01], [0.06, 0.04, 0.0], (6, 4, 1), rubber)
    slab.fix(slab.nodes_where(lambda x: x[2] <= -0.01 + 1e-9))
    box = RigidBody3D.of_density(1000.0, [0.0, 0.0, 0.005], Box(0.02, 0.02, 0.01))
    model = Model([slab, box], [Contact(slab, box, method="mortar")], (0.0, 0.0, -9.81))
    dt = 8.61892e-5  # (Δx/c of the box in rubber)
    return model, simulate(model, dt, steps * dt, IntegratorOptions(), stats=stats)


def test_a_pending_probe_of_other_contacts_is_replaced_untaken(monkeypatch):
    """Where a step's pair lets go while a probe of all contacts is pending, that probe's
    reading would be replaced unread: it is not taken, and the run is the run that took it
    (bit for bit), with fewer probes."""
    stats = StepStats()
    states = [np.concatenate([st.q, st.v, st.impulse]) for st in laid_box(stats)[1]]
    falling = Releases._falling

    def taken_first(self, model, st, h, opts, timer):  # (every pending probe taken)
        self._reading(model, opts, timer)
        return falling(self, model, st, h, opts, timer)

    monkeypatch.setattr(Releases, "_falling", taken_first)
    every = StepStats()
    taken = [np.concatenate([st.q, st.v, st.impulse]) for st in laid_box(every)[1]]
    assert stats.localization.release_splits == every.localization.release_splits == 1
    assert 0 < stats.localization.release_probes < every.localization.release_probes
    assert len(states) == len(taken)
    for a, b in zip(states, taken, strict=True):
        np.testing.assert_array_equal(a, b)
