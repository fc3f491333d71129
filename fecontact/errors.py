"""Errors raised by fecontact.

``InputError`` is raised before any work starts when a user passes data outside its allowed
range; ``SolverError`` is raised when the time integration cannot proceed.

Every number given in SI units must be finite and at most ``MAX_MAGNITUDE`` = 1e30 in
magnitude, and a strictly positive one at least ``MIN_MAGNITUDE`` = 1e-30: squares and
products of a few such values (strain energies, stiffnesses, gap gradients) stay far from
overflow and underflow, and no quantity of an impact problem is within many decades of
either bound.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "InputError",
    "SolverError",
    "check_count",
    "check_finite",
    "check_kind",
    "check_positive",
    "check_vector",
    "check_range",
    "did_you_mean",
    "MAX_MAGNITUDE",
    "MIN_MAGNITUDE",
]

MAX_MAGNITUDE = 1e30
MIN_MAGNITUDE = 1e-30


class InputError(ValueError):
    """A parameter is outside its allowed range (raised before any computation)."""


def did_you_mean(name: str, known) -> str:
    """' (did you mean "x"?)' for the name of ``known`` closest to a misspelt ``name``
    (difflib's ratio ≥ 0.6, its default), else ""."""
    import difflib

    close = difflib.get_close_matches(str(name), [str(k) for k in known], n=1)
    return f" (did you mean {close[0]!r}?)" if close else ""


class SolverError(RuntimeError):
    """Newton did not converge; carries the time, step and residual where it stopped."""

    def __init__(
        self, message: str, time: float = math.nan, step: int = -1, residual: float = math.nan
    ):
        super().__init__(message)
        self.time = time
        self.step = step
        self.residual = residual


def _shown(value) -> str:
    """``value`` as an error message shows it: whole when short, else its shape."""
    text = repr(value)
    if len(text) <= 60:
        return text
    shape = np.shape(value) if not isinstance(value, (str, bytes)) else (len(value),)
    return f"an array of shape {shape}"


def check_finite(name: str, value) -> np.ndarray:
    """Return ``value`` as a float array, raising ``InputError`` unless every entry is a
    finite real number of magnitude at most ``MAX_MAGNITUDE``."""
    try:
        if isinstance(value, (str, bytes)):
            raise TypeError
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be real numbers, got {_shown(value)}") from None
    bad = ~np.isfinite(arr)
    if np.any(bad):
        index = tuple(int(i) for i in np.unravel_index(np.argmax(bad), arr.shape))
        where = "" if arr.ndim == 0 else f" (entry {index[0] if len(index) == 1 else index})"
        raise InputError(f"{name} must be finite, got {_shown(value)}{where}")
    if arr.size and np.max(np.abs(arr)) > MAX_MAGNITUDE:
        raise InputError(
            f"{name} must be at most {MAX_MAGNITUDE:g} in magnitude, got {_shown(value)}"
        )
    return arr


def check_kind(name: str, value, kind, what: str):
    """Return ``value`` if it is an instance of ``kind`` (a class or a tuple of them), else
    raise ``InputError`` naming ``name``, ``what`` it takes and the type it got: a material of
    a solid given to a beam, a number where a body is due."""
    if not isinstance(value, kind):
        raise InputError(f"{name} must be {what}, got {type(value).__name__}")
    return value


def check_vector(name: str, value, size: int) -> np.ndarray:
    """Return ``value`` as a float vector of ``size`` finite components."""
    x = check_finite(name, value).ravel()
    if x.shape != (size,):
        raise InputError(f"{name} must have {size} components, got {x.size}")
    return x


def _number(name: str, value) -> float:
    """``value`` as a float; only real numbers are accepted (not strings, not booleans)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.number)):
        if not (isinstance(value, np.ndarray) and value.shape == () and value.dtype.kind in "iuf"):
            raise InputError(f"{name} must be a number, got {_shown(value)}")
    return float(value)


def check_positive(name: str, value, allow_zero: bool = False) -> float:
    """Return ``value`` as a float after checking it is finite and > 0 (or >= 0), within
    [MIN_MAGNITUDE, MAX_MAGNITUDE] (or [0, MAX_MAGNITUDE] with ``allow_zero``)."""
    x = _number(name, value)
    if not math.isfinite(x):
        raise InputError(f"{name} must be finite, got {_shown(value)}")
    if x < 0 or (x == 0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise InputError(f"{name} must be {bound}, got {_shown(value)}")
    if x > MAX_MAGNITUDE or (x < MIN_MAGNITUDE and not allow_zero):
        low = 0.0 if allow_zero else MIN_MAGNITUDE
        raise InputError(f"{name} must be in [{low:g}, {MAX_MAGNITUDE:g}], got {_shown(value)}")
    return x


def check_count(name: str, value, low: int = 1, high: int = 10**6) -> int:
    """Return ``value`` as an int after checking it is an integer in [low, high] (an integral
    float such as 4.0 is accepted; booleans and strings are not)."""
    ok = isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(
        value, (bool, np.bool_)
    )
    ok = ok and math.isfinite(value) and int(value) == value and low <= int(value) <= high
    if not ok:
        raise InputError(f"{name} must be an integer in [{low}, {high}], got {_shown(value)}")
    return int(value)


def check_range(name: str, value, low: float, high: float, closed: tuple = (True, True)) -> float:
    """Return ``value`` as a float after checking it lies in the interval [low, high].

    ``closed`` says whether each end belongs to the interval.
    """
    x = _number(name, value)
    lo_ok = x >= low if closed[0] else x > low
    hi_ok = x <= high if closed[1] else x < high
    if not (math.isfinite(x) and lo_ok and hi_ok):
        interval = ("[" if closed[0] else "(") + f"{low:g}, {high:g}" + ("]" if closed[1] else ")")
        raise InputError(f"{name} must be in {interval}, got {_shown(value)}")
    return x
