"""The settings of one run: the integrator options with what the run owns besides them."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from .state import IntegratorOptions
from .stats import StepStats

__all__ = ["RunSettings", "run_settings"]


@dataclass
class RunSettings(IntegratorOptions):
    """The :class:`IntegratorOptions` of one run and its statistics ``stats``, which the
    phases of its steps fill."""

    stats: StepStats = field(default_factory=StepStats, repr=False, compare=False)

    def __post_init__(self):
        pass  # the values are those of options already checked, taken as they are


def run_settings(opts: IntegratorOptions, stats: StepStats | None = None) -> RunSettings:
    """``opts`` as the settings of a run that counts into ``stats`` (default: new counts);
    settings already made are returned as they are."""
    if isinstance(opts, RunSettings):
        return opts
    values = {f.name: getattr(opts, f.name) for f in dataclasses.fields(IntegratorOptions)}
    return RunSettings(**values, stats=StepStats() if stats is None else stats)
