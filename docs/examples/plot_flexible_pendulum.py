"""
The flexible pendulum against its stop
======================================

The founding case: an aluminium strip pinned at the origin with a mass at its tip falls
from the horizontal; the tip hits a rigid stop at x = 0. Run here to 0.6 s (the full case
runs to 1.5 s): the tip's x position has a kink at the impact, its velocity jumps and then
rings at the strip's first bending frequency.
"""

import tempfile

import matplotlib.pyplot as plt

import fecontact
from fecontact.cli import load_case

sim = load_case("flexible_pendulum").build().replace(t_end=0.6)
out = tempfile.mkdtemp()
summary = fecontact.run(sim, out)
history = fecontact.load_run(out).history

fig, (ax_x, ax_v) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
ax_x.plot(history["t"], history["tip_x"])
ax_x.set_ylabel("tip x (m)")
ax_v.plot(history["t"], history["tip_vx"])
ax_v.set_ylabel("tip vx (m/s)")
ax_v.set_xlabel("t (s)")
for impact in summary["impacts"]:
    for ax in (ax_x, ax_v):
        ax.axvline(impact["time"], color="0.7", lw=0.8)
fig.tight_layout()

print(f"{summary['steps']} steps, impacts at", [round(i["time"], 4) for i in summary["impacts"]])
print(f"max penetration {summary['max_penetration']:.1e} m")
