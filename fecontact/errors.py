"""Errors raised by fecontact.

``InputError`` is raised before any work starts when a user passes data outside its allowed
range; ``SolverError`` is raised when the time integration cannot proceed.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["InputError", "SolverError", "check_positive", "check_range", "check_finite"]


class InputError(ValueError):
    """A parameter is outside its allowed range (raised before any computation)."""


class SolverError(RuntimeError):
    """Newton did not converge; carries the time, step and residual where it stopped."""

    def __init__(
        self, message: str, time: float = math.nan, step: int = -1, residual: float = math.nan
    ):
        super().__init__(message)
        self.time = time
        self.step = step
        self.residual = residual


def check_finite(name: str, value) -> np.ndarray:
    """Return ``value`` as a float array, raising ``InputError`` if any entry is NaN or inf."""
    arr = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} must be finite, got {value!r}")
    return arr


def _number(name: str, value) -> float:
    """``value`` as a float; only real numbers are accepted (not strings, not booleans)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.number)):
        if not (isinstance(value, np.ndarray) and value.shape == () and value.dtype.kind in "iuf"):
            raise InputError(f"{name} must be a number, got {value!r}")
    return float(value)


def check_positive(name: str, value, allow_zero: bool = False) -> float:
    """Return ``value`` as a float after checking it is finite and > 0 (or >= 0)."""
    x = _number(name, value)
    if not math.isfinite(x):
        raise InputError(f"{name} must be finite, got {value!r}")
    if x < 0 or (x == 0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise InputError(f"{name} must be {bound}, got {value!r}")
    return x


def check_range(name: str, value, low: float, high: float, closed: tuple = (True, True)) -> float:
    """Return ``value`` as a float after checking it lies in the interval [low, high].

    ``closed`` says whether each end belongs to the interval.
    """
    x = _number(name, value)
    lo_ok = x >= low if closed[0] else x > low
    hi_ok = x <= high if closed[1] else x < high
    if not (math.isfinite(x) and lo_ok and hi_ok):
        interval = ("[" if closed[0] else "(") + f"{low:g}, {high:g}" + ("]" if closed[1] else ")")
        raise InputError(f"{name} must be in {interval}, got {value!r}")
    return x
