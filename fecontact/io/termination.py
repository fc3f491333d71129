"""A run stopped by SIGTERM ends as one stopped by Ctrl-C: its summary written (status
``interrupted``), its frame index listing every frame written, its lock released.

SIGTERM is how a cluster's scheduler ends a job at its time limit, and what ``kill``,
``docker stop`` and ``timeout`` send; Python's default action ends the process at once,
without the cleanup of a ``KeyboardInterrupt``.
"""

from __future__ import annotations

import signal
import threading
from contextlib import contextmanager

__all__ = ["Terminated", "terminate_as_interrupt"]


class Terminated(KeyboardInterrupt):
    """The process received SIGTERM during a run."""


def _raise_terminated(signum, frame):
    raise Terminated("terminated by SIGTERM")


@contextmanager
def terminate_as_interrupt():
    """Within the block, SIGTERM raises :class:`Terminated` (a ``KeyboardInterrupt``). Only the
    main thread may set a signal handler: elsewhere (a run in a worker thread) nothing
    changes."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    before = signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, before)
