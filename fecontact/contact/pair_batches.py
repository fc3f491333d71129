"""The units in which a contact set evaluates its pairs: a pair alone, or a run of
consecutive pairs of one ``batch_key`` evaluated together (their rows stacked in order, the
numbers of the pairs themselves: :mod:`.disk_batches`, :mod:`.ball_batches`). Decided once
per model."""

from __future__ import annotations

import numpy as np

from .base import PairDefaults

__all__ = ["PairBatch", "dot_rows", "evaluation_units", "frozen"]


class PairBatch(PairDefaults):
    """Consecutive one-row pairs of one kind: their rows stacked in order."""

    size = 0

    def __init__(self, pairs):
        self.pairs = tuple(pairs)
        self.size = len(self.pairs)
        self.friction = max(pair.friction for pair in self.pairs)


def dot_rows(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a_j·b_j (m,) of rows (m, d), each the product the pairs take one by one: ``np.matmul``
    over a stack of 1 × d rows gives, bit for bit, what ``np.linalg.norm`` and a row's ``@``
    give (``np.einsum`` and the plain sum of squares differ in the last bit on some rows)."""
    return np.matmul(a[:, None, :], b[:, :, None])[:, 0, 0]


def frozen(a: np.ndarray) -> np.ndarray:
    """``a`` made read-only: the same dofs at every evaluation (their scatter is kept)."""
    a.flags.writeable = False
    return a


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
