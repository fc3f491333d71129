"""Case parameters, each declared once: default, unit, meaning and allowed values.

A case declares its parameters as the defaults of ``build`` and wraps it with :func:`case`::

    @case
    def build(
        length=Param.positive(0.3, "m", "beam length"),
        n_elements=Param.count(4, "number of beam elements"),
        restitution=Param.fraction(0.0, "Newton's coefficient of restitution e_N"),
    ):
        ...

``build()`` then runs with the defaults, checks every value it is given against its
declaration (one ``InputError`` naming the parameter and its range, before any work), and
records every value used in the ``Simulation`` (``summary.json``). ``fecontact info`` and
``--set`` read the same declarations.

Parameters that several cases share (a material, a mesh, an impact) are declared once in a
group, a dict of name to ``Param``, and a case names the groups it draws on::

    @case(SOLID)
    def build(E, nu, rho, material, radius=Param.positive(0.05, "m", "disk radius")): ...

A parameter of a group is listed without a default, or with a plain value that replaces the
group's default (same unit, meaning and range).
"""

from __future__ import annotations

import functools
import inspect
import math
from dataclasses import dataclass, replace
from typing import Any

from .errors import InputError, check_count, check_positive, check_range, did_you_mean

__all__ = ["Param", "assignment", "case", "declared_parameters"]


@dataclass(frozen=True)
class Param:
    """A parameter of a case: ``default`` value, ``unit`` (SI, "-" if none), ``text`` (what it
    is) and its allowed values: the interval from ``low`` to ``high`` (``closed`` says which
    ends belong to it) for numbers, integers when the default is an int, or one of
    ``choices`` for strings."""

    default: Any
    unit: str = "-"
    text: str = ""
    low: float = -math.inf
    high: float = math.inf
    closed: tuple[bool, bool] = (True, True)
    choices: tuple = ()

    @classmethod
    def positive(cls, default: float, unit: str, text: str) -> Param:
        """A number > 0."""
        return cls(float(default), unit, text, 0.0, math.inf, (False, True))

    @classmethod
    def nonnegative(cls, default: float, unit: str, text: str) -> Param:
        """A number ≥ 0."""
        return cls(float(default), unit, text, 0.0)

    @classmethod
    def fraction(cls, default: float, text: str) -> Param:
        """A number in [0, 1]."""
        return cls(float(default), "-", text, 0.0, 1.0)

    @classmethod
    def count(cls, default: int, text: str, low: int = 1, high: int = 10**6) -> Param:
        """An integer in [low, high]."""
        return cls(int(default), "-", text, low, high)

    @classmethod
    def choice(cls, default: str, text: str, choices) -> Param:
        """One of the strings ``choices``."""
        return cls(default, "-", text, choices=tuple(choices))

    @property
    def allowed(self) -> str:
        """The allowed values, as ``fecontact info`` prints them."""
        if self.choices:
            return "|".join(self.choices)
        lo_in = self.closed[0] and math.isfinite(self.low)
        hi_in = self.closed[1] and math.isfinite(self.high)
        ends = ("[" if lo_in else "(", "]" if hi_in else ")")
        kind = "integer in " if isinstance(self.default, int) else ""
        return f"{kind}{ends[0]}{self.low:g}, {self.high:g}{ends[1]}"

    def check(self, name: str, value):
        """``value`` if it is allowed (ints as int, numbers as float), else ``InputError``."""
        if self.choices:
            if not isinstance(value, str) or value not in self.choices:
                raise InputError(f"{name} must be one of {', '.join(self.choices)}, got {value!r}")
            return value
        if isinstance(self.default, int):
            high = self.high if math.isfinite(self.high) else 10**6
            return check_count(name, value, int(self.low), int(high))
        if self.low == 0.0 and math.isinf(self.high):
            # the package's magnitude limits for physical quantities
            return check_positive(name, value, allow_zero=self.closed[0])
        return check_range(name, value, self.low, self.high, self.closed)


def declared_parameters(build) -> dict[str, Param]:
    """The ``Param`` declarations of a build function (or of its signature), in signature
    order."""
    signature = build if isinstance(build, inspect.Signature) else inspect.signature(build)
    return {n: p.default for n, p in signature.parameters.items() if isinstance(p.default, Param)}


def case(build=None, /, *groups: dict[str, Param]):
    """Wrap a case's ``build`` whose defaults are ``Param``: values checked against their
    declarations, defaults filled in, and every value used recorded in the Simulation.

    ``@case`` alone, or ``@case(GROUP, ...)`` with groups of shared declarations (see the
    module docstring)."""
    if build is None or isinstance(build, dict):
        shared = (build, *groups) if build is not None else groups
        return lambda f: _wrap(f, shared)
    return _wrap(build, groups)


def _wrap(build, groups):
    signature = _declared_signature(build, groups)
    params = declared_parameters(signature)
    names = set(signature.parameters)

    @functools.wraps(build)
    def wrapper(**values):
        unknown = sorted(set(values) - names)
        if unknown:
            hint = did_you_mean(unknown[0], names)
            raise InputError(f"unknown parameter {unknown[0]!r}{hint}; known: {', '.join(names)}")
        used = {n: p.check(n, values.get(n, p.default)) for n, p in params.items()}
        sim = build(**{**values, **used})
        from .simulation import Simulation  # the case layer sits above the simulation

        if not isinstance(sim, Simulation):
            raise InputError(f"build() must return a Simulation, got {type(sim).__name__}")
        return sim.replace(parameters={**used, **sim.parameters})

    wrapper.__signature__ = signature  # what ``fecontact info``, ``--set`` and tests read
    wrapper.parameters = params
    return wrapper


def _declared_signature(build, groups) -> inspect.Signature:
    """``build``'s signature with every default a ``Param``: its own, or a group's (whose
    default a plain value in the signature replaces)."""
    shared = {n: p for g in groups for n, p in g.items()}
    parameters = []
    for name, par in inspect.signature(build).parameters.items():
        default = par.default
        if not isinstance(default, Param):
            group = shared.get(name)
            if group is None:  # undeclared: passed on unchecked, as before Param
                parameters.append(par.replace(kind=inspect.Parameter.KEYWORD_ONLY))
                continue
            empty = default is inspect.Parameter.empty
            # a replaced default must itself be allowed (checked once, when the case loads)
            default = group if empty else replace(group, default=group.check(name, default))
        parameters.append(par.replace(default=default, kind=inspect.Parameter.KEYWORD_ONLY))
    return inspect.Signature(parameters)


def assignment(item: str, form: str = "NAME=VALUE") -> tuple[str, str]:
    """(name, value text) of a ``--set`` item; a one-line ``InputError`` naming ``form``
    when the item has no name or no ``=``."""
    name, sep, text = item.partition("=")
    name = name.strip()
    if not sep or not name:
        raise InputError(f"--set expects {form}, got {item!r}")
    return name, text
