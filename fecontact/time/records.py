"""What a step hands the next one besides q, v, v̇ and a: typed records of the smooth contact
forces, of friction and of the penalty law, each None where the run has none. A checkpoint
stores them as named arrays (:func:`record_arrays`, :func:`records_from_arrays`)."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

__all__ = [
    "FrictionRecord",
    "PenaltyRecord",
    "SmoothForces",
    "record_arrays",
    "records_from_arrays",
]


@dataclass
class SmoothForces:
    """The contact forces of the smooth step (:mod:`fecontact.time.smooth_contact`) at the
    end of a step: λ_N of every contact (m,) and, with friction, λ_T (m, nt) (N); and the
    forces (normal, tangential) (m, dim) (N) that v̇ and a carry, which a step that releases
    a contact takes out again; ``closing`` (m,), where the run's contacts settle a step after
    an impact (or would, in the decoupled step, whose next correction then has no slip rows
    for them): 1 for the contacts that closed within the step (open at its start), else 0."""

    normal: np.ndarray
    tangential: np.ndarray | None
    in_vd: np.ndarray
    in_a: np.ndarray
    closing: np.ndarray | None = None

    def without(self, rows: np.ndarray) -> SmoothForces:
        """A copy with the forces of the contacts ``rows`` set to zero."""
        out = dataclasses.replace(self)
        for name in ("normal", "tangential", "in_vd", "in_a", "closing"):
            x = getattr(self, name)
            if x is not None:
                x = x.copy()
                x[rows] = 0.0
                setattr(out, name, x)
        return out


@dataclass
class FrictionRecord:
    """The frictional record of a step: tangential multipliers of the position correction
    k ν_T and impulses k Λ_T (m, nt), stick/slip status (m,) (0 open, 1 stick, 2 slip) and
    the work friction has dissipated since t = 0 (J)."""

    nu: np.ndarray
    impulse: np.ndarray
    status: np.ndarray
    work: float

    @classmethod
    def start(cls, before: FrictionRecord | None, m: int, dim: int) -> FrictionRecord:
        """A step's record, zero but for the work done so far (``before``: the last step's)."""
        nt = dim - 1
        work = 0.0 if before is None else before.work
        return cls(np.zeros((m, nt)), np.zeros((m, nt)), np.zeros(m), work)


@dataclass
class PenaltyRecord:
    """The penalty law of a run (:mod:`fecontact.time.penalty`): stiffness k_j (N/m) and
    damping c_j (N·s/m) of every contact, NaN until it first closes, and the run's first
    step h₁ (s). One record serves the whole run: its arrays fill in as contacts close."""

    k: np.ndarray
    c: np.ndarray
    h1: float


# the arrays of a checkpoint: the name of each, and where it lives
_FIELDS = {
    "contact_force": ("smooth", "normal"),
    "friction_force": ("smooth", "tangential"),
    "force_in_vd": ("smooth", "in_vd"),
    "force_in_a": ("smooth", "in_a"),
    "contact_closing": ("smooth", "closing"),
    "friction_nu": ("friction", "nu"),
    "friction_impulse": ("friction", "impulse"),
    "friction_status": ("friction", "status"),
    "friction_work": ("friction", "work"),
    "penalty_k": ("penalty", "k"),
    "penalty_c": ("penalty", "c"),
    "penalty_h1": ("penalty", "h1"),
}
_RECORDS = {"smooth": SmoothForces, "friction": FrictionRecord, "penalty": PenaltyRecord}
_SCALARS = {"friction_work", "penalty_h1"}
_ARRAYS = ("strain_increment", "ledger")  # the state's fields that are arrays of their own


def record_arrays(st) -> dict[str, np.ndarray]:
    """The arrays of the records of the state ``st`` (its fields ``smooth``, ``friction``,
    ``penalty``, ``strain_increment`` and ``ledger``), by the names a checkpoint stores."""
    out = {}
    for name, (owner, field) in _FIELDS.items():
        record = getattr(st, owner)
        value = None if record is None else getattr(record, field)
        if value is not None:
            out[name] = np.atleast_1d(np.asarray(value, dtype=float))
    for name in _ARRAYS:
        if (value := getattr(st, name)) is not None:
            out[name] = value
    return out


def records_from_arrays(arrays: dict[str, np.ndarray]) -> dict:
    """The state's records (by field name) from a checkpoint's ``arrays``: the inverse of
    :func:`record_arrays`."""
    values: dict[str, dict] = {owner: {} for owner in _RECORDS}
    for name, (owner, field) in _FIELDS.items():
        if name in arrays:
            x = arrays[name]
            values[owner][field] = float(x.reshape(-1)[0]) if name in _SCALARS else x
    out = {}
    for owner, cls in _RECORDS.items():
        if values[owner]:
            fields = [f.name for f in dataclasses.fields(cls)]
            out[owner] = cls(**{f: values[owner].get(f) for f in fields})
    for name in _ARRAYS:
        if name in arrays:
            out[name] = arrays[name]
    return out
