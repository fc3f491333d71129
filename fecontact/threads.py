"""BLAS threads inside a run.

The dense systems of a step have tens of unknowns: a pool of BLAS threads only adds
synchronisation to them. A run limits the pool to one thread while it steps (threadpoolctl),
and gives the user's own matrix products back their pool afterwards. A thread count the user
set in the environment (``OPENBLAS_NUM_THREADS``, ``OMP_NUM_THREADS``, ``MKL_NUM_THREADS``)
wins.
"""

from __future__ import annotations

import os
from contextlib import contextmanager

__all__ = ["blas_threads"]

USER_SETTINGS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


@contextmanager
def blas_threads(limit: int = 1):
    """Limit the BLAS thread pools to ``limit`` threads inside the ``with`` block, unless the
    environment sets a thread count."""
    if any(os.environ.get(name) for name in USER_SETTINGS):
        yield
        return
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=limit, user_api="blas"):
        yield
