"""When a run writes its frames: at every multiple of the output interval, at the end and at
the first impact.

With fixed steps every state is a history row, and a frame is the first state at or after
its time (at most one step of the run's ``dt`` late). With ``rtol`` the rows are at the
multiples of ``dt`` and the steps between them at times the control chooses: a frame at the
first state at or after its time would be at such a time, off both the rows and the
interval (frames at 0.025, 0.0375 s for an interval of 0.01 s and rows every 0.05 s). There
a frame whose time falls inside a step is interpolated between the states at the step's
ends (:func:`state_between`), so that the frames keep the times asked for, and a frame at a
row's time is that row."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..time import State
from ..time.configuration import minus, plus
from .frames import bodies_box, frame_parts, static_parts

__all__ = ["RunFrames", "state_between"]


def state_between(model, before: State, after: State, t: float) -> State:
    """The state of ``model`` at ``t`` (s) inside the step from ``before`` to ``after``: q
    and v linear in time between the two (q on the configuration space: a rotation vector
    turns by the fraction of the step's rotation, :func:`~fecontact.time.configuration.plus`),
    and what belongs to the step (contact impulses and forces, friction, h) from ``after``.
    A frame's velocity through an impact is the chord's, not the jump."""
    s = (t - before.t) / (after.t - before.t)
    q = plus(model, before.q, s * minus(model, after.q, before.q)[model.free])
    held = np.ones(model.n, bool)
    held[model.free] = False  # (supported dofs, moved or not, between their two values)
    q[held] = before.q[held] + s * (after.q[held] - before.q[held])
    v = before.v + s * (after.v - before.v)
    return dataclasses.replace(after, t=t, q=q, v=v)


class RunFrames:
    """The run's frames, written by ``pvd`` (a ``.pvd`` or VTKHDF writer) where ``enabled``:
    at each multiple of the output interval (the first state at or after it; with ``rtol``,
    a state within 1e-9 of dt of it, else between the states around it:
    :func:`state_between`), at the end and at the first impact; and the box the bodies
    swept, under which the obstacles' outlines are drawn."""

    def __init__(self, sim, pvd, enabled: bool):
        self.sim, self.pvd, self.enabled = sim, pvd, enabled
        self.next_frame = 0.0  # time (s) of the next frame at the output interval
        self.box = None  # the bodies' box over the frames, for the obstacles' outlines
        self.last: State | None = None  # the state before the one written next
        # (decided once: the runs whose states between rows are at the control's times)
        self.between = sim.options.rtol is not None

    def begin(self) -> None:
        """The obstacles' outlines around the bodies at the start of a new run."""
        if not self.enabled:
            return
        model = self.sim.model
        self.box = bodies_box(model, np.zeros(model.n) if self.sim.q0 is None else self.sim.q0)
        for part, mesh in static_parts(model, self.box).items():
            self.pvd.write_static(part, mesh)

    def write(self, st: State, impact: bool) -> None:
        """The frames due up to the state ``st`` (``impact``: the first impact's, at ``st``)."""
        if not self.enabled:
            return
        sim, last = self.sim, self.last
        near = 1e-9 * sim.dt  # (a time n·dt and k·interval apart by round-off: the same)
        self.last = st
        while self.between and last is not None and last.t + near < self.next_frame < st.t - near:
            self._frame(state_between(sim.model, last, st, self.next_frame))
        due = st.t >= self.next_frame - near or st.t >= sim.t_end - 1e-12
        if impact or due:
            self._frame(st)

    def _frame(self, st: State) -> None:
        model = self.sim.model
        self.pvd.write_frame(st.t, frame_parts(model, st))
        now = bodies_box(model, st.q)
        box = self.box
        self.box = (
            now
            if box is None
            else np.stack([np.minimum(box[0], now[0]), np.maximum(box[1], now[1])])
        )
        interval = self.sim.output_interval
        self.next_frame = (math.floor(st.t / interval + 1e-6) + 1) * interval

    def end(self, completed: bool) -> None:
        """The outlines under the whole motion, after a completed run."""
        if self.enabled and self.box is not None and completed:
            for part, mesh in static_parts(self.sim.model, self.box).items():
                self.pvd.write_static(part, mesh)
