"""What :func:`fecontact.run` returns: the run's ``summary.json`` as a dict, shown in a
notebook as a few lines (status, steps, impacts, penetration, warnings, folder) rather than
its hundred keys."""

from __future__ import annotations

from pathlib import Path

__all__ = ["RunSummary"]


class RunSummary(dict):
    """The ``summary.json`` of the run written into ``out_dir``: a dict (``summary["status"]``,
    ``json.dump`` as it is) whose repr says what the run did;
    ``fecontact.load_run(summary.out_dir)`` reads its history and frames back."""

    def __init__(self, summary: dict, out_dir) -> None:
        super().__init__(summary)
        self.out_dir = Path(out_dir)

    def __reduce__(self):
        # pickled (a sweep's workers return it) with its folder, as the dict it is
        return (type(self), (dict(self), self.out_dir))

    def __repr__(self) -> str:
        get = self.get
        dt = f"{get('dt_min', float('nan')):g}"
        if get("dt_max") != get("dt_min"):
            dt += f" to {get('dt_max', float('nan')):g}"
        penetration = get("max_penetration")
        lines = [
            f"{get('case', 'run')} (t_end = {get('t_end', float('nan')):g} s): "
            f"{get('status')}, {get('steps')} steps of dt {dt} s, "
            f"{get('step_halvings', 0)} halvings",
            f"  {len(get('impacts') or [])} impacts, max penetration "
            + (f"{penetration:.3g} m" if isinstance(penetration, float) else "none"),
        ]
        if get("message"):
            lines.append(f"  message: {get('message')}")
        lines += [f"  warning: {text}" for text in get("warnings") or []]
        lines.append(f"  -> {str(self.out_dir)!r} (fecontact.load_run(...): history, frames)")
        return "\n".join(lines)

    def _repr_pretty_(self, printer, cycle: bool) -> None:
        # IPython prints a dict subclass as a dict; a notebook shows the lines above instead
        printer.text(repr(self))
