"""What a user meets from a notebook, a mesh file and the command line: each mistake is one
InputError naming it, raised before any work."""

import numpy as np
import pytest

from fecontact import Beam2D, InputError, Material, Model, Probe, Section, Simulation, run


def pendulum_sim():
    b = Beam2D.straight([0, 0], [1, 0], 2, Material(E=1e9, rho=1e3), Section.circle(0.01))
    return Simulation(Model([b.pin(0)]), dt=1e-3, t_end=0.003)


@pytest.mark.parametrize(
    "field, value, words",
    [
        ("probes", {"tip": lambda model, st: 0.0}, r"probes\['tip'\] must be a Probe"),
        ("t_end", -1.0, "t_end must be > 0"),
        ("dt", "1e-3", "dt must be"),
        ("name", "my run", "name must be letters"),
    ],
)
def test_fields_set_after_construction_are_checked_before_the_folder(tmp_path, field, value, words):
    """In a notebook a Simulation is changed in place and run again: a bare function given as
    a probe went unchecked and failed as an AttributeError after history.csv and the first
    frame were written, leaving no summary.json and no .pvd."""
    sim = pendulum_sim()
    setattr(sim, field, value)
    with pytest.raises(InputError, match=words):
        run(sim, tmp_path / "out")
    assert not (tmp_path / "out").exists()
    sim.probes, sim.t_end, sim.dt, sim.name = (
        {"tip": Probe(lambda m, st: 0.0, "m")},
        3e-3,
        1e-3,
        "a",
    )
    assert run(sim, tmp_path / "out")["status"] == "completed"


def test_the_summary_run_returns_is_a_dict_shown_in_a_few_lines(tmp_path):
    """A notebook cell ending in ``run(...)`` printed the summary's hundred keys."""
    import pickle

    from fecontact.io.output import read_json

    summary = run(pendulum_sim(), tmp_path / "out")
    assert isinstance(summary, dict) and summary["status"] == "completed"
    assert summary == read_json(tmp_path / "out" / "summary.json")
    text = repr(summary)
    assert text.startswith("simulation (t_end = 0.003 s): completed, 3 steps of dt 0.001 s")
    assert str(tmp_path / "out") in text and len(text.splitlines()) == 3
    again = pickle.loads(pickle.dumps(summary))  # (a sweep's workers return it)
    assert again == summary and again.out_dir == summary.out_dir


@pytest.mark.parametrize(
    "argv, words",
    [
        (["run", "bouncing_bal"], "case not found: bouncing_bal (did you mean 'bouncing_ball'?)"),
        (["info", "two_disk"], "(did you mean 'two_disks'?)"),
        (["run", "bouncing_ball.py"], "bouncing_ball.py (did you mean 'bouncing_ball'?)"),
        (["run", "bouncing_ball", "--set", "restitutoin=0.5"], "(did you mean 'restitution'?)"),
        (["run", "bouncing_ball", "--set", "rhoinf=0"], "(did you mean 'rho_inf'?)"),
        (["sweep", "bouncing_ball", "--set", "hieght=1,2"], "(did you mean 'height'?)"),
    ],
)
def test_a_misspelt_case_or_parameter_is_given_the_name_meant(tmp_path, capsys, argv, words):
    from fecontact.cli.commands import main

    assert main([*argv, "--out", str(tmp_path / "out")] if argv[0] != "info" else argv) == 2
    err = capsys.readouterr().err
    assert words in err and "\n" not in err.strip()
    assert not (tmp_path / "out").exists()


def test_a_name_far_from_every_known_one_gets_no_suggestion(tmp_path, capsys):
    from fecontact.cli.commands import main

    assert main(["run", "bouncing_ball", "--set", "xyzzy=1", "--out", str(tmp_path)]) == 2
    assert "did you mean" not in capsys.readouterr().err


def test_beams_carry_their_section_radius_for_paraviews_tube_filter(tmp_path):
    """A beam's frames are line cells; ParaView's Tube filter (*Vary Radius: By Absolute
    Scalar*) draws the section from ``section_radius``, which the frames lacked."""
    import math

    import fecontact

    pyvista = pytest.importorskip("pyvista")
    run(pendulum_sim(), tmp_path / "out")
    beam = fecontact.load_run(tmp_path / "out").frames()[0][1]["beam2d0"]
    np.testing.assert_allclose(beam.point_data["section_radius"], 0.01, rtol=1e-15)
    line = pyvista.wrap(beam).extract_surface(algorithm="dataset_surface")
    tube = line.tube(scalars="section_radius", absolute=True, n_sides=64)
    # the tube is a 64-gon about the x axis: its y extent lies between r cos(π/64) and r
    # (1e-12 m: the round-off of VTK's vertices, ~1e-18 m at r = 1 cm, far below it)
    y = max(abs(tube.bounds[2]), abs(tube.bounds[3]))
    assert 0.01 * math.cos(math.pi / 64) - 1e-12 <= y <= 0.01 + 1e-12


@pytest.mark.parametrize("name", ["localize", "energy_retakes"])
def test_the_words_true_and_false_the_switch_error_offers_are_taken(name):
    """``--set localize=true`` gives the string "true": the error said "must be true, false
    (1, 0, on, off) or auto" and refused it."""
    from fecontact import IntegratorOptions

    for word, value in [("true", True), ("False", False), ("ON", True), ("auto", "auto")]:
        assert getattr(IntegratorOptions(**{name: word}), name) == value
    with pytest.raises(InputError, match=f"{name} must be true, false"):
        IntegratorOptions(**{name: "yes"})


def test_a_simulation_shows_what_runs_not_its_functions():
    """A notebook showed ``Simulation(model=<fecontact.model.Model object at 0x...>,
    probes={'tip': Probe(fn=<function ...>, ...)}, ...)``."""
    sim = pendulum_sim()
    sim.probes = {"tip": Probe(lambda m, st: 0.0, "m")}
    assert repr(sim) == (
        "Simulation('simulation': dt = 0.001 s, t_end = 0.003 s, integrator nsga; 1 body "
        "(Beam2D), 0 contacts, 0 joints, 9 dofs; probes: tip)"
    )


def test_paraview_names_the_stress_components(tmp_path):
    """The planar stress has four components, which ParaView labelled 0, 1, 2, 3: they carry
    their names (xx, yy, zz, xy) in the VTU, as the docs list them."""
    from fecontact import LinearElastic, Solid

    vtk = pytest.importorskip("vtk")
    body = Solid.rectangle([0, 0], [0.2, 0.1], 2, LinearElastic(E=1e6, nu=0.3, rho=1e3))
    sim = Simulation(Model([body], gravity=(0.0, -9.81)), dt=1e-3, t_end=0.002, name="plate")
    run(sim, tmp_path / "out", frame_format="vtu")
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(tmp_path / "out" / "plate_solid0_00001.vtu"))
    reader.Update()
    stress = reader.GetOutput().GetCellData().GetArray("stress")
    names = [stress.GetComponentName(i) for i in range(stress.GetNumberOfComponents())]
    assert names == ["xx", "yy", "zz", "xy"]


def test_a_solid_read_from_a_file_shows_what_the_file_gave(tmp_path):
    """A notebook showed ``<fecontact.bodies.solid.Solid object at 0x...>``: now the cells,
    volume, mass and groups, to check a file (its unit, its groups) before a run."""
    import meshio
    import skfem

    from fecontact import LinearElastic, Solid

    m = skfem.MeshTri.init_tensor(np.linspace(0, 200.0, 3), np.linspace(0.0, 100.0, 2))  # mm
    tags = [np.full(m.t.shape[1], 1)]
    meshio.Mesh(
        np.column_stack([m.p.T, np.zeros(m.p.shape[1])]),
        [("triangle", m.t.T)],
        cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags},
        field_data={"plate": np.array([1, 2])},
    ).write(tmp_path / "plate.msh", file_format="gmsh22")
    body = Solid.from_file(tmp_path / "plate.msh", LinearElastic(E=1e6, nu=0.3, rho=1e3), 1e-3)
    assert repr(body) == (
        "Solid(2D, plane strain, thickness 1 m, 6 nodes, 4 cells (P1 tri), volume 0.02 m³, "
        "mass 20 kg; groups: plate)"
    )
