"""What a step leaves for the energy ledger (:mod:`fecontact.ledger`) about its smooth step:
the energies of its end (ṽ, q̃) before a contact phase moved them, the smooth friction's
work, a velocity jump's works, and the records of steps made of parts."""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "NOTHING_MOVED",
    "JoinedRecord",
    "SmoothRecord",
    "joined_record",
    "pending_record",
    "smooth_end",
    "smooth_record",
]

# the record of a step whose contact phase moved neither q nor v and did no work
NOTHING_MOVED = np.array([math.nan, math.nan, 0.0, 0.0, 0.0, 0.0])
NOTHING_MOVED.flags.writeable = False


def smooth_record(
    model, contact_phase, v_tilde, q_tilde=None, friction_work=0.0, works=None, release=0.0,
    held=None,
) -> np.ndarray | None:  # fmt: skip
    """What a stepper leaves in its state (``State.ledger``) for the ledger after its smooth
    step, when a ``contact_phase`` (correction or jump) may follow: the kinetic energy of
    ṽ (NaN when ``v_tilde`` is None: no correction and no jump moved v, then it is that of
    the step's end), the potential (strain + gravity) energy of q̃ (NaN when no correction
    moved q: then it is that of the step's end), the work the smooth step's friction forces
    dissipated, the velocity jump's ``works`` (normal, tangential, joints;
    :func:`fecontact.ledger_works.jump_work`) and the energy the smooth step's retake
    without the forces of the contacts it releases added over its first try (``release``)
    and the momentum hold's change of T, T(ṽ + ``held``) − T(ṽ) (J). Without a contact
    phase, None."""
    if not contact_phase:
        return None
    V = math.nan
    if q_tilde is not None:
        V = model.strain_energy(q_tilde) + model.potential_energy(q_tilde)
    works = (0.0, 0.0, 0.0) if works is None else works
    T = math.nan if v_tilde is None else model.kinetic_energy(v_tilde)
    record = [T, V, friction_work, *works]
    hold = 0.0 if held is None else model.kinetic_energy(v_tilde + held) - T
    tail = [release, hold] if hold else [release] if release else []
    return np.array(record + tail)


class SmoothRecord:
    """The record of :func:`smooth_record` for the state of one step, made when it is first
    read (``State.ledger`` calls it): the energies of ṽ and q̃ are sparse products and
    element sums that a run which never reads the ledger (``simulate`` without the recorder)
    need not pay for. q̃ and ṽ are the step's own arrays, which no later phase changes, and
    a body's energy is a function of its q alone, so the values are the same numbers at
    whatever time they are made."""

    __slots__ = ("model", "v_tilde", "q_tilde", "friction_work", "works", "release", "held")

    def __init__(self, model, v_tilde, q_tilde, friction_work: float, works, release, held):
        self.model, self.v_tilde, self.q_tilde = model, v_tilde, q_tilde
        self.friction_work, self.works, self.release = friction_work, works, release
        self.held = held

    def __call__(self) -> np.ndarray:
        return smooth_record(
            self.model,
            True,
            self.v_tilde,
            self.q_tilde,
            self.friction_work,
            self.works,
            self.release,
            self.held,
        )


def pending_record(
    model, contact_phase, v_tilde, q_tilde=None, friction_work=0.0, works=None, release=0.0,
    held=None,
):  # fmt: skip
    """:func:`smooth_record` of the same arguments, its energies made when it is first read:
    a :class:`SmoothRecord` where it has an energy to compute, else the record itself (None
    without a contact phase)."""
    if not contact_phase or (v_tilde is None and q_tilde is None):
        # (a +0.0 friction work: a −0.0 the record keeps)
        plus_zero = friction_work == 0.0 and math.copysign(1.0, friction_work) > 0.0
        if contact_phase and works is None and not release and plus_zero:
            return NOTHING_MOVED  # (most steps with candidates: shared, read-only)
        return smooth_record(model, contact_phase, None, None, friction_work, works, release)
    return SmoothRecord(model, v_tilde, q_tilde, friction_work, works, release, held)


def smooth_end(record) -> tuple | None:
    """(q̃ or None, ṽ) of a step's ledger record not yet made (``deferred_ledger``), where a
    correction or a jump moved v after the smooth step; None where it does not keep them."""
    if isinstance(record, SmoothRecord) and record.v_tilde is not None:
        return record.q_tilde, record.v_tilde
    return None


def joined_record(model, first, second) -> np.ndarray | None:
    """The record (:func:`smooth_record`) of one step made of the steps that end in
    ``first`` and ``second`` (a halved step, an impact located inside a step): the contact
    phases of both are the step's, so that the ledger charges them as such. With the first
    part's end energies T_1, V_1 and T̃_i, Ṽ_i the parts' smooth ends, T̃ = T̃_2 − (T_1 − T̃_1),
    Ṽ = Ṽ_2 − (V_1 − Ṽ_1); the smooth friction and the jumps' works add."""
    return _joined(model, first, second.ledger, second.v, second.q)


class JoinedRecord:
    """:func:`joined_record` of the parts ``first`` and ``second``, made when it is first
    read (``State.ledger`` calls it), as :class:`SmoothRecord`: a run that never reads the
    ledger does not pay the parts' energies. ``record``: ``second``'s record as it was set
    (a deferred one not yet made; the part's ``ledger`` becomes this one); the parts'
    arrays are kept, which no later phase changes."""

    __slots__ = ("model", "first", "record", "v", "q")

    def __init__(self, model, first, second, record):
        self.model, self.first, self.v, self.q = model, first, second.v, second.q
        self.record = record

    def __call__(self) -> np.ndarray | None:
        record = self.record
        if record is not None and not isinstance(record, np.ndarray):
            record = record()
        return _joined(self.model, self.first, record, self.v, self.q)


def _joined(model, first, r2, v2, q2) -> np.ndarray | None:
    """:func:`joined_record` of ``first`` and a second part with the record ``r2`` that
    ends at (``q2``, ``v2``)."""
    r1 = first.ledger
    if r1 is None:
        return r2
    # T_1 − T̃_1 and V_1 − Ṽ_1: zero, not evaluated, where the first part ends where its
    # smooth step does (NaN)
    dT = 0.0 if math.isnan(r1[0]) else model.kinetic_energy(first.v) - r1[0]
    dV = 0.0
    if not math.isnan(r1[1]):
        dV = model.strain_energy(first.q) + model.potential_energy(first.q) - r1[1]
    if r2 is None:  # the second part has no contact phase: it ends where its smooth step does
        r2 = smooth_record(model, True, v2, q2)
    else:  # (NaN: the smooth step's end is the part's end, and stays the step's where d = 0)
        r2 = r2.copy()
        if math.isnan(r2[0]) and dT:
            r2[0] = model.kinetic_energy(v2)
        if math.isnan(r2[1]) and dV:
            r2[1] = model.strain_energy(q2) + model.potential_energy(q2)
    out = np.zeros(max(r1.size, r2.size, 6))
    out[: r2.size] = r2
    out[0] = r2[0] - dT
    out[1] = r2[1] - dV
    out[2] = r1[2] + r2[2]
    out[3:6] += r1[3:6] if r1.size >= 6 else 0.0
    if r1.size > 6:  # the first part's release and momentum hold
        out[6 : r1.size] += r1[6:]
    return out
