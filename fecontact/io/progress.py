"""How far a run is: a bar on a terminal and in a Jupyter notebook, plain lines in a log.

When standard error is not a terminal (a batch job's log, a pipe) a bar would write hundreds
of carriage returns that a log never shows; the run then prints one line at the start, one
each time it passes another tenth of its end time, and one at the end.
"""

from __future__ import annotations

import importlib.util
import math
import sys
import time

__all__ = ["RunProgress", "bar_class", "in_notebook", "is_terminal"]


def in_notebook() -> bool:
    """Whether this process is a Jupyter kernel (its standard error is not a terminal, yet a
    bar shows)."""
    shell = sys.modules.get("IPython")
    if shell is None or "ipykernel" not in sys.modules:
        return False
    ip = shell.get_ipython()
    return ip is not None and "IPKernelApp" in getattr(ip, "config", {})


class RunProgress:
    """Progress of the run ``name`` from ``t0`` (step ``step0``) to ``t_end`` (s) by steps of
    ``dt`` (s): a tqdm bar (``tqdm.auto``) on a terminal or in a notebook, else log lines on
    ``stream`` (default: standard error)."""

    def __init__(self, name: str, t_end: float, dt: float, t0=0.0, step0=0, stream=None):
        self.name, self.t_end, self.stream = name, t_end, stream or sys.stderr
        self.t, self.step, self.clock = t0, step0, time.perf_counter()
        self.bar = None
        notebook = in_notebook()
        if notebook or is_terminal(self.stream):
            tqdm = bar_class(notebook)
            total = max(1, math.ceil(t_end / dt - 1e-9))
            self.bar = tqdm(total=total, initial=step0, desc=name, unit="step", file=self.stream)
            return
        self.next_tenth = math.floor(10 * t0 / t_end + 1e-9) + 1
        start = "resumes at" if step0 else "starts at"
        self._line(f"{start} t = {t0:.6g} s (step {step0}), t_end = {t_end:.6g} s, dt = {dt:g} s")

    def advance(self, st) -> None:
        """The state ``st`` of the step just taken."""
        self.t, self.step = st.t, st.step
        if self.bar is not None:
            self.bar.update(st.step - self.bar.n)
            if st.step % 25 == 0:
                self.bar.set_postfix(t=f"{st.t:.4f}", it=st.newton_iterations, refresh=False)
            return
        tenth = math.floor(10 * st.t / self.t_end + 1e-9)
        if self.next_tenth <= tenth < 10:
            self.next_tenth = tenth + 1
            self._line(f"{10 * tenth}% t = {st.t:.6g} s, step {st.step}, {self._wall()}")

    def close(self, status: str = "completed", stop=None) -> None:
        """The run's last line: where it ends, or, for a failure, the (t in s, step) its
        error names (``stop``): a step is numbered by the row it ends on, so a step that
        failed is one past the last state reached, and t is where it started."""
        if self.bar is not None:
            self.bar.close()
            return
        if stop is not None and stop[1] >= 0:
            t, step = stop
            self._line(f"stops ({status}) in step {step} at t = {t:.6g} s, {self._wall()}")
            return
        end = "ends" if status == "completed" else f"stops ({status})"
        self._line(f"{end} at t = {self.t:.6g} s, step {self.step}, {self._wall()}")

    def _wall(self) -> str:
        return f"{time.perf_counter() - self.clock:.1f} s wall"

    def _line(self, text: str) -> None:
        print(f"{self.name}: {text}", file=self.stream, flush=True)


def bar_class(notebook: bool):
    """The tqdm bar for a notebook (``notebook``) or a terminal: tqdm's widget in a notebook
    with ipywidgets, else its text bar, which a notebook shows too. (``tqdm.auto`` in a
    notebook without ipywidgets warns "IProgress not found" into the cell, then gives the
    text bar.)"""
    if notebook and importlib.util.find_spec("ipywidgets") is not None:
        from tqdm.auto import tqdm
    else:
        from tqdm import tqdm
    return tqdm


def is_terminal(stream) -> bool:
    """Whether ``stream`` is a terminal (a bar shows), not a file or a pipe (a log)."""
    try:
        return stream.isatty()
    except (AttributeError, ValueError):  # no isatty, or a closed stream
        return False
