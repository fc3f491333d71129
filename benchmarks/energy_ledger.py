"""The energy ledger on the founding case and on the runs where energy was seen to rise, the
default cases that warn against the step size, and Newton's against Poisson's impact law
where they differ.

Each run goes through ``fecontact.run``; the tables give its ``energy_ledger`` (J), the
tangential part of its ``impact_work`` (J) and the warnings it raised (the phase named).

    python benchmarks/energy_ledger.py [--quick]
"""

from __future__ import annotations

import tempfile

from _common import markdown_table, parser, with_options, write_markdown

from fecontact import SolverError, run
from fecontact.testing import case

KEYS = ("impact_dissipation", "numerical_dissipation", "friction_dissipation", "created", "scale")


def ledger(label: str, sim) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        try:
            summary = run(sim, tmp, frames=False, checkpoint_every=0)
        except SolverError as err:
            return {"run": label, "status": f"failed: {err}"[:80]}
    led = summary["energy_ledger"]
    # the phase named: "..., in the <phase>[, where friction did positive work: ...]"
    phase = [
        w.split(", in the ")[-1].split(",")[0] + (" (friction's positive work)" * ("friction" in w))
        for w in summary["warnings"]
        if "created" in w
    ]
    row = {"run": label, "status": summary["status"]}
    row |= {k: led[k] for k in KEYS}
    row["created/scale"] = led["created"] / led["scale"]
    row["E_end-E_0"] = summary["energy_final"] - summary["energy_initial"]
    # the jumps' tangential impulses times the mean slip (J)
    row["P_T.mean_slip"] = summary["impact_work"]["tangential"]
    row["warns in"] = phase[0] if phase else "-"
    return row


def founding(quick: bool) -> list[dict]:
    build = case("flexible_pendulum").build
    if quick:  # through the first impact
        return [ledger("e_N = 0.5, rho_inf = 0.5", build(restitution=0.5).replace(t_end=0.35))]
    rows = []
    for e in (0.0, 0.5):
        for rho in (0.5, 0.8):
            sim = with_options(build(restitution=e), rho_inf=rho)
            rows.append(ledger(f"e_N = {e}, rho_inf = {rho}", sim))
    sim = build(restitution=1.0).replace(dt=2e-3)
    rows.append(ledger("e_N = 1, h = 2e-3", sim))
    return rows


def gains(quick: bool) -> list[dict]:
    bars = case("two_bars").build
    dt = bars(n_elements=20).dt
    disks = case("two_disks").build
    ball = case("ball_drop").build
    rows = [ledger("two_bars, h = 4x", bars(n_elements=20).replace(dt=4 * dt))]
    if not quick:
        rows += [
            ledger("two_disks, smooth off, dx/c", with_options(disks(), smooth_contact="off")),
            ledger("two_disks (default)", disks()),
            ledger("ball_drop (default)", ball()),
        ]
    return rows


def steps(quick: bool) -> list[dict]:
    """The default cases whose runs warn, at their step h, h/2 and h/4 (and with smooth
    contact on): how fast the energy they create falls with the step."""
    items = [("rocking_block", {}, "off"), ("rocking_block", {}, "on")]
    if not quick:
        items += [
            ("impacting_bar", {"n_elements": 20}, "off"),  # (the decoupled scheme)
            ("two_bars", {"n_elements": 20}, "off"),
            ("two_bars", {"n_elements": 20}, "on"),
            ("ball_drop", {}, "auto"),
        ]
    rows = []
    for name, kw, smooth in items:
        sim = with_options(case(name).build(**kw), smooth_contact=smooth)
        if quick:  # through the landing (t = 0.077 s), where the 1 s run creates its energy
            sim = sim.replace(t_end=0.1)
        for f in (1, 2, 4):
            label = f"{name} {kw or ''} smooth_contact={smooth}, h = {sim.dt / f:.3g}"
            rows.append(ledger(label, sim.replace(dt=sim.dt / f)))
    return rows


def laws(quick: bool) -> list[dict]:
    rows = []
    items = [
        ("kane_chain", {}, None),
        ("kane_chain", {"restitution": 0.5}, None),
        ("rigid_pendulum", {}, 1.0),
        ("rocking_block", {}, 1.0),
        ("bouncing_ball", {"restitution": 0.8}, 1.0),
    ]
    if quick:  # Kane's chain through its strike
        items = [("kane_chain", {}, 0.45)]
    for name, kw, t_end in items:
        sim = case(name).build(**kw)
        if t_end:
            sim = sim.replace(t_end=t_end)
        for law in ("newton", "poisson"):
            for integrator in ("nsga",) if quick else ("nsga", "moreau"):
                label = f"{name} {kw or ''} {law} {integrator}"
                rows.append(ledger(label, with_options(sim, impact_law=law, integrator=integrator)))
    return rows


def picture(path) -> None:
    """The founding case's ledger over time (e_N = 0.5, ρ∞ = 0.5): where the energy went,
    the layers of history.png's ledger panel."""
    import matplotlib.pyplot as plt

    from fecontact.io.history_plot import ledger_layers
    from fecontact.io.output import read_history

    sim = case("flexible_pendulum").build(restitution=0.5)
    with tempfile.TemporaryDirectory() as tmp:
        run(sim, tmp, frames=False, checkpoint_every=0)
        h = read_history(f"{tmp}/history.csv")
    layers, supply = ledger_layers(h)
    layers = [(k, y) for k, y in layers if k not in ("damping", "friction")]  # zero here
    fig, ax = plt.subplots(figsize=(8.5, 4))
    ax.stackplot(h["t"], *(y for _, y in layers), labels=[k for k, _ in layers])
    ax.plot(h["t"], supply, "k--", lw=1, label="supplied: E(0) − least gravity energy")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("J")
    ax.set_title("flexible pendulum, e_N = 0.5: where the gravity energy went")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main() -> None:
    args = parser(__doc__.splitlines()[0]).parse_args()
    sections = [
        ("The founding case (flexible pendulum against a stop)", founding(args.quick)),
        ("Runs where energy was seen to rise", gains(args.quick)),
        ("Default cases that warn, against the step", steps(args.quick)),
        ("Newton's and Poisson's impact laws", laws(args.quick)),
    ]
    text = ["# The energy ledger"]
    for title, rows in sections:
        columns = list(dict.fromkeys(k for r in rows for k in r))
        table = markdown_table(rows, columns)
        print(f"\n{title}\n\n{table}")
        text += ["", f"## {title}", "", table]
    if args.quick:
        write_markdown(f"{args.out}/energy_ledger_quick.md", "\n".join(text))
    else:
        write_markdown(f"{args.out}/energy_ledger.md", "\n".join(text))
        picture(f"{args.out}/energy_ledger.png")


if __name__ == "__main__":
    main()
