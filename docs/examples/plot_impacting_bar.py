"""
An elastic bar striking a wall
==============================

The classical wave-propagation impact: an elastic bar moving at v₀ hits a rigid wall; the
contact lasts exactly 2L/c, the time a compression wave takes to run to the free end and
back, and the bar leaves with its velocity reversed. Time is shown in units of L/c from
the first contact.
"""

import tempfile

import matplotlib.pyplot as plt

import fecontact
from fecontact.cli import load_case

sim = load_case("impacting_bar").build(n_elements=50)
out = tempfile.mkdtemp()
summary = fecontact.run(sim, out)
history = fecontact.load_run(out).history
p = sim.parameters
transit = p["length"] / (p["E"] / p["rho"]) ** 0.5  # L/c (s)

t = (history["t"] - p["gap"] / p["velocity"]) / transit
fig, (ax_f, ax_v) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
ax_f.plot(t, history["contact_force"])
ax_f.set_ylabel("wall force (N)")
ax_v.plot(t, history["v_mean"], label="mean")
ax_v.plot(t, history["v_free_end"], label="free end")
ax_v.set_ylabel("velocity (m/s)")
ax_v.set_xlabel("(t - t_contact) c / L")
ax_v.legend()
fig.tight_layout()

pressed = t[history["contact_force"] > 0]
print(f"contact from {pressed.min():.3f} to {pressed.max():.3f} L/c (exact: 0 to 2)")
