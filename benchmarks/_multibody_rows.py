"""What every row of ``explore_multibody.py`` measures: the run's common columns (status,
steps, fallbacks, created energy), the comparison with an exact answer, the p and k
independence of contact rows, and the order of a row run at several steps."""

from __future__ import annotations

import dataclasses

import numpy as np
from stress_3d import centres, executed, fallbacks

from fecontact import Probe

NAN = float("nan")


def measured(group: str, label: str, sim) -> tuple[dict, dict]:
    """Run ``sim``: its row's common columns and its history."""
    summary, h, status, message, cpu = executed(sim)
    ledger = summary.get("energy_ledger") or {}
    t = h.get("t", np.zeros(1))
    row = {
        "group": group,
        "run": label,
        "h (s)": sim.dt,
        "status": status if status == "completed" else f"{status} at {t[-1]:.4g} s",
        "steps": int(summary.get("steps", len(t) - 1)),
        "fallbacks": fallbacks(summary),
        "created / scale": ledger.get("created", NAN) / (ledger.get("scale") or NAN),
        "CPU (s)": cpu,
    }
    if message:
        row["message"] = message.splitlines()[0][:160]
    return row, h


def compared(row: dict, quantity: str, exact: float, value: float, also: str = "") -> dict:
    row.update(compared=quantity, exact=exact, measured=value)
    row["error"] = abs(value - exact) / abs(exact) if exact else abs(value)
    row["also"] = also
    return row


def with_pk(row: dict, sim, h: dict, size: float) -> dict:
    """The largest change of the centre probes with p ×1000 and with k ÷100, over ``size``."""
    base = centres(h)
    for name, option in (
        ("p x1000", {"penalty_scale": 1e3}),
        ("k /100", {"multiplier_scale": 1e-2}),
    ):
        other = centres(executed(with_options(sim, **option))[1])
        n = min(len(base), len(other))
        row[f"{name}: d centre / size"] = float(np.max(np.abs(other[:n] - base[:n]))) / size
    return row


def with_options(sim, **options):
    return sim.replace(options=dataclasses.replace(sim.options, **options))


def order(errors, ratio: float = 2.0) -> float:
    e = np.asarray(errors, dtype=float)
    return float(np.log(e[0] / e[-1]) / np.log(ratio ** (len(e) - 1)))


def centre_probes(body, offset: int = 0, name: str = "c") -> dict:
    return {
        f"{axis}{name}": Probe(
            lambda m, st, i=i: float(body.center(st.q[offset : offset + 6])[i]), "m", "centre"
        )
        for i, axis in enumerate("xyz")
    }


def spatial_omega(body, st, offset: int = 0) -> np.ndarray:
    return body.rotation(st.q[offset : offset + 6]) @ st.v[offset + 3 : offset + 6]
