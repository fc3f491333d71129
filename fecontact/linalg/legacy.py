"""The names that process-global solver state had, kept for old callers, per thread.

Counts once lived in module-level dicts that every run added to (``ITERATIVE``,
``SPARSE_FACTORIZATIONS`` here, ``NEWTON``, ``FOLLOW_UPS`` and ``RELEASES`` in
:mod:`fecontact.time`), and AMG's near-null space in a process-wide registry
(``set_near_null_space``). A run now owns its counts (``fecontact.time.StepStats``) and its
linear solver (:class:`~fecontact.linalg.LinearSolver`), so that two runs in two threads
neither share nor mix them. The old names remain, deprecated, with a meaning that holds under
threads:

- a counter name is a read-only mapping, with the old keys, of the counts of the most recent
  run that finished in the calling thread (``fecontact.time.simulate``, and so
  ``fecontact.run``, record it when the run ends; zeros before any). It is read at each
  access: a view, not a snapshot. Unlike the old dicts it is not cumulative over the
  process: an old caller that subtracted a snapshot taken before a run gets the difference
  between two runs, not the run's count; read the run's ``StepStats`` instead.
- :func:`set_near_null_space` registers modes for the runs the calling thread starts
  afterwards (:func:`registered_modes`, read once when a run makes its solver).
"""

from __future__ import annotations

import threading
import warnings
import weakref
from collections.abc import Callable, Iterator, Mapping

import numpy as np

from ..errors import InputError

__all__ = [
    "LastRunCounts",
    "deprecated",
    "latest_run",
    "record_run",
    "registered_modes",
    "set_near_null_space",
]

_THREAD = threading.local()  # per thread: ``stats`` (the latest run's), ``modes`` (by size)


def record_run(stats) -> None:
    """Record ``stats`` (a run's ``StepStats``) as the calling thread's most recent run."""
    _THREAD.stats = stats


def latest_run():
    """The ``StepStats`` of the most recent run that finished in the calling thread (None:
    none yet)."""
    return getattr(_THREAD, "stats", None)


class LastRunCounts(Mapping):
    """A deprecated counter name: the read-only mapping ``read(stats)`` of the calling
    thread's most recent run (:func:`latest_run`; ``stats`` None before any run, where
    ``read`` gives the zero counts), read again at every access."""

    def __init__(self, name: str, read: Callable[[object], dict]):
        self.name, self.read = name, read

    def _counts(self) -> dict:
        return self.read(latest_run())

    def __getitem__(self, key: str):
        return self._counts()[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._counts())

    def __len__(self) -> int:
        return len(self._counts())

    def __repr__(self) -> str:
        return f"{self.name}({self._counts()!r})"


def deprecated(old: str, instead: str) -> None:
    """Warn (``DeprecationWarning``) that the name ``old`` is read; ``instead`` says what to
    use."""
    warnings.warn(
        f"{old} is deprecated: it reads the most recent run in the calling thread; {instead}",
        DeprecationWarning,
        stacklevel=3,
    )


def set_near_null_space(modes: np.ndarray) -> None:
    """Deprecated: use ``modes`` (n × k, rigid motions on a model's n free dofs) as AMG's
    near-null space in the runs that the calling thread starts from now on on a model with n
    free dofs, in place of the model's own rigid motions (``Model.rigid_modes``, which a run
    uses by default), for as long as the caller keeps the array; the latest registration of
    a size wins. The modes only speed CG up; its answer holds to CG's tolerance."""
    if not isinstance(modes, np.ndarray) or modes.ndim != 2:
        raise InputError(f"modes: an n x k NumPy array, not {type(modes).__name__}")
    warnings.warn(
        "set_near_null_space is deprecated: a run hands its model's rigid_modes to AMG; the "
        "modes registered here replace them in the runs this thread starts",
        DeprecationWarning,
        stacklevel=2,
    )
    registry = getattr(_THREAD, "modes", None)
    if registry is None:
        registry = _THREAD.modes = {}
    registry[modes.shape[0]] = weakref.ref(modes)


def registered_modes(n: int) -> np.ndarray | None:
    """The modes the calling thread registered for n free dofs (:func:`set_near_null_space`)
    and still kept by its caller, or None."""
    ref = getattr(_THREAD, "modes", {}).get(n)
    return None if ref is None else ref()
