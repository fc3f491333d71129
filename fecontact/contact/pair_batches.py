"""The units in which a contact set evaluates its pairs: a pair alone, or a run of
consecutive pairs of one ``batch_key`` evaluated together (their rows stacked in order, the
numbers of the pairs themselves: :mod:`.disk_batches`). Decided once per model."""

from __future__ import annotations

import numpy as np

__all__ = ["evaluation_units"]


def evaluation_units(pairs):
    """(units, the unit of each contact, each contact's number within its unit, whether each
    unit is a batch): consecutive pairs whose ``batch_key()`` is equal and not None form one
    unit, made by the key's first item (a batch class) from those pairs; every other pair is
    a unit of its own."""
    units, run, key = [], [], None
    for pair in pairs:
        k = pair.batch_key()
        if run and (k is None or k != key):
            units.append(_unit(run, key))
            run = []
        run.append(pair)
        key = k
    if run:
        units.append(_unit(run, key))
    sizes = [unit.size for unit in units]
    owner = np.repeat(np.arange(len(units)), sizes).astype(int)
    local = np.concatenate([np.arange(s) for s in sizes] or [np.zeros(0, int)]).astype(int)
    alone = {id(pair) for pair in pairs}
    return units, owner, local, [id(unit) not in alone for unit in units]


def _unit(run, key):
    """A pair alone stays itself; two or more of one key become their batch."""
    return run[0] if len(run) == 1 or key is None else key[0](run)
