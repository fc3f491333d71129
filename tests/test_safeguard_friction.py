"""Coulomb friction on the mortar safeguard's pointwise rows (fecontact.contact.safeguard_slip):
slip rows along each row's own normal, and the normal force of a held node rubbing as any
contact's (docs/validation/stress_2d.md, *Corners, rings, rotated scenes and rolling*)."""

import dataclasses

import numpy as np
import skfem

from fecontact import Contact, Model, run
from fecontact.bodies import Solid
from fecontact.bodies.meshes import ball_mesh
from fecontact.io.output import read_history
from fecontact.scenes import centre_of_mass_probes, solid_material, wave_step
from fecontact.simulation import Simulation

RUBBER = solid_material("neo-hookean", 1e7, 0.3, 1e3)


def check_slip_rows(rows, q, n_dofs):
    """The deep rows' slip rows at q: orthogonal to the node's normal (its gradient block made
    unit), unit on the node, and blind to a translation of both solids (their weights sum to
    zero); the shallow rows have none. Returns the deep rows."""
    _, dofs, G, _ = rows.evaluate(q)
    d = rows.dim
    GT_dofs, GT, T = rows.tangents(q)
    deep = np.flatnonzero(G[:, :d].any(axis=1))
    assert deep.size >= 1 and not GT[np.setdiff1d(np.arange(rows.size), deep)].any()
    n = G[deep, :d] / np.linalg.norm(G[deep, :d], axis=1)[:, None]
    # (unit vectors built from unit vectors: round-off)
    assert np.abs(np.einsum("mtd,md->mt", T[deep], n)).max() < 1e-14
    assert np.allclose(np.einsum("mtd,mtd->mt", T[deep], T[deep]), 1.0, atol=1e-14)
    for axis in np.eye(d):
        shift = np.tile(axis, n_dofs // d)  # both solids translated together
        slip = np.einsum("mtk,mk->mt", GT[deep], shift[np.broadcast_to(GT_dofs, G.shape)[deep]])
        assert np.abs(slip).max() < 1e-14
    return deep


def test_the_2d_rows_slip_along_their_facets():
    mat = solid_material("linear", 1e7, 0.3, 1e3)
    a = Solid.disk([-0.1 + 0.0015, 0.0], 0.1, 2, mat)
    b = Solid.disk([0.1 - 0.0015, 0.003], 0.1, 2, mat)
    pair = Contact(a, b, method="mortar", friction=0.4)
    model = Model([a, b], [pair], gravity=(0.0, 0.0))
    pair.detect_within(0.02)
    # both passes take the interface's μ
    assert pair.master_rows.friction == pair.pointwise.friction == 0.4
    assert model.contacts.frictional
    check_slip_rows(pair.master_rows, np.zeros(model.n), model.n)


def test_a_pole_behind_the_apex_of_a_turned_ball_slips_across_the_axis():
    """The coarsest balls pole into pole by 1 mm, one turned 30° (the rows' 3D smooth maximum:
    tests/test_mortar_safeguard.py): the pole's row pushes along the axis with a gradient of
    length cos θ < 1 on the node, its slip rows span the plane across the axis."""
    mat = solid_material("linear", 1e7, 0.3, 1e3)
    d, angle = 1e-3, np.radians(30.0)
    mesh = ball_mesh([-0.05 + d / 2, 0.0, 0.0], 0.05, 1)
    c, s = np.cos(angle), np.sin(angle)
    turn = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]) @ np.diag([-1.0, -1.0, 1.0])
    a, b = Solid(mesh, mat), Solid(dataclasses.replace(mesh, doflocs=turn @ mesh.doflocs), mat)
    pair = Contact(a, b, method="mortar", friction=0.3)
    model = Model([a, b], [pair], gravity=(0.0, 0.0, 0.0))
    pair.detect_within(0.005)
    rows = pair.pointwise
    deep = check_slip_rows(rows, np.zeros(model.n), model.n)
    j = np.argmax(a.X[rows.nodes, 0])
    assert j in deep
    _, _, T = rows.tangents(np.zeros(model.n))
    # the pole's tangents lie across the x axis (round-off of the symmetric planes)
    assert np.abs(T[j, :, 0]).max() < 1e-9


def test_a_disk_landing_on_a_finer_block_slides_with_coulombs_ratio(tmp_path):
    """A rubber disk (5 cm, refinements 2) 0.1 mm above a rubber block clamped at its base
    (40 × 3 cells, the finer boundary: the disk's nodes are master nodes), thrown at
    0.5 m/s along it under gravity, μ = 0.5. Over its first landing (to 10 ms) every contact
    slides forward (the disk has no spin), so the block's tangential impulse on the disk is
    μ times the normal one: ΔP_x = −μ (ΔP_y + m g t). The safeguard holds the disk's nodes
    for most of the landing; with frictionless rows the ratio was −0.0008."""
    mu, v0 = 0.5, 0.5
    xs, ys = np.linspace(-0.1, 0.4, 41), np.linspace(-0.03, 0.0, 4)
    block = Solid(skfem.MeshTri.init_tensor(xs, ys), RUBBER)
    block.fix(np.flatnonzero(np.isclose(block.X[:, 1], -0.03)))
    disk = Solid.disk([0.0, 0.05 + 1e-4], 0.05, 2, RUBBER)
    model = Model([disk, block], [Contact(disk, block, friction=mu)], gravity=(0.0, -9.81))
    sim = Simulation(
        model,
        dt=min(wave_step(b, 1.0) for b in (disk, block)),
        t_end=0.01,
        v0=model.translation(disk, (v0, 0.0)),
        probes={**centre_of_mass_probes(model, disk, 0), **centre_of_mass_probes(model, disk, 1)},
        output_interval=1e-3,
    )
    summary = run(sim, tmp_path, progress=False, frames=False)
    assert summary["mortar_held_steps"] > 20  # (the mechanism under test takes part)
    h = read_history(tmp_path / "history.csv")
    vx, vy, t = (np.asarray(h[k]) for k in ("vx_center", "vy_center", "t"))
    normal = vy[-1] - vy[0] + 9.81 * (t[-1] - t[0])
    ratio = (vx[-1] - vx[0]) / normal
    # measured −0.50097: the contact normals tilt by the block's dent (about 1 mrad, moving
    # the world-axis ratio by θ(1 + μ²)); 2 % of μ is 10 times that on any machine
    assert abs(ratio + mu) < 0.02 * mu
    ledger = summary["energy_ledger"]
    assert ledger["friction_dissipation"] > 0.0
