"""
A bouncing ball against its exact impact times
==============================================

A rigid disk dropped from 1 m on a rigid plane with Newton's restitution e = 0.8. The exact
impact times are t₁ = √(2h₀/g) and t_{k+1} = t_k + 2eᵏt₁; each computed impact lies in the
step that contains it, so the error of the k-th impact stays below k steps.
"""

import tempfile

import matplotlib.pyplot as plt
import numpy as np

import fecontact
from fecontact.cli import load_case
from fecontact.testing import ball_impact_times

sim = load_case("bouncing_ball").build().replace(t_end=2.5)
out = tempfile.mkdtemp()
summary = fecontact.run(sim, out)
history = fecontact.load_run(out).history

computed = np.array([i["time"] for i in summary["impacts"]])
exact = ball_impact_times(len(computed))
print("impact time errors in steps:", np.round((computed - exact) / sim.dt, 2))

fig, ax = plt.subplots(figsize=(7, 3.5))
ax.plot(history["t"], history["gap"], label="gap (m)")
ax.plot(exact, np.zeros_like(exact), "k|", ms=14, label="exact impact times")
ax.set_xlabel("t (s)")
ax.legend()
fig.tight_layout()
