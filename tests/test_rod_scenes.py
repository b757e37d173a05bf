"""Rods in scene files, the catalog, the ParaView output and the tape-tether demo
(issue 48: ``docs/rods.md``)."""

import json

import meshio
import numpy as np
import pytest
from demo_modules import load_demo

import skfem_cable as sc
from skfem_cable import scene_file
from skfem_cable.cli import command as cli
from skfem_cable.io import export

SCENE = """
[sections.tape]
width = 0.02
thickness = 5e-5
E = 7e10
rho = 2700.0

[sections.wire]
radius = 5e-4
E = 7e10
rho = 2700.0
G = 2.5e10

[[rods]]
name = "tape"
section = "tape"
start = [0, 0, 0]
end = [1, 0, 0]
elements = 3
normal = [0, 1, 1]

[[cables]]
name = "wire"
section = "wire"
element = "rod"
start = [0, 1, 0]
end = [1, 1, 0]
length = 1.2
elements = 3

[[constraints]]
type = "clamp"
node = { rod = "tape", index = 0 }

[[constraints]]
type = "clamp"
node = { cable = "wire", index = 0 }
twist = false

[[constraints]]
type = "pin"
node = { rod = "wire", index = -1 }

[[loads.moment]]
at = { rod = "tape", index = -1 }
moment = [1e-6, 0, 0]

[loads]
gravity = [0, 0, -9.81]

[solver]
t_end = 0.01
dt = 0.002
"""


def python_scene():
    """The system of ``SCENE`` built in Python (a scene file reads its ``[[cables]]``
    before its ``[[rods]]``)."""
    tape = sc.Rod.straight([0, 0, 0], [1, 0, 0], 3,
                           sc.Section.tape(0.02, 5e-5, E=7e10, rho=2700.0),
                           normal=[0, 1, 1], name="tape")
    wire = sc.Rod.between([0, 1, 0], [1, 1, 0], 1.2, 3,
                          sc.Section.circular(5e-4, 7e10, 2700.0, G=2.5e10), name="wire")
    system = sc.System([wire, tape]).clamp(tape.node(0)).clamp(wire.node(0), twist=False)
    system.pin(wire.node(-1)).add_point_moment(tape.node(-1), [1e-6, 0, 0])
    return system.add_gravity([0, 0, -9.81])


def test_rods_of_a_scene_file_run_as_the_same_rods_built_in_python():
    """``[[rods]]``, ``element = "rod"`` (a hanging catenary), clamps with and without
    twist, ``{rod = ...}`` references: 5 steps equal to the Python scene's to 1e-12."""
    spec = scene_file.loads_text(SCENE, "rods.toml")
    assert [(type(b).__name__, b.name) for b in spec.system.bodies] == [("Rod", "wire"),
                                                                        ("Rod", "tape")]
    mine = sc.simulate(spec.system, **spec.solver)
    theirs = sc.simulate(python_scene(), **spec.solver)
    assert np.abs(mine.q - theirs.q).max() < 1e-12 * np.abs(theirs.q).max()
    twist = spec.system.dofs(spec.system.bodies[1])[-2]  # the tape's tip twist turned
    assert abs(mine.q[-1, twist]) > 1e-6


@pytest.mark.parametrize("change, message", [
    (("width = 0.02", "width = 1e-5"), "sections.tape.width is out of range"),
    (("twist = false", "twist = 0"), "constraints[1].twist must be true or false"),
    (('element = "rod"', 'element = "rods"'), "'rod'"),
    (("normal = [0, 1, 1]", "normal = [1, 0, 0]"), "rods[0].normal does not take"),
])
def test_rod_tables_name_the_key(change, message):
    with pytest.raises(scene_file.SceneFileError, match=message.replace("[", r"\[")):
        scene_file.loads_text(SCENE.replace(*change), "rods.toml")


def test_tape_tether_catalog_scene_runs(tmp_path, capsys):
    """``skfem-cable run tape-tether`` at reduced size: the summary and its ribbon."""
    out = tmp_path / "tape"
    assert cli.main(["run", "tape-tether", "--elements", "4", "--t-end", "40", "--no-plots",
                     "--out", str(out), "--no-progress"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["parameters"]["length"] == 5e3 and summary["steps"] == 4
    mesh = meshio.read(out / export.read_pvd(out / "series.pvd")[-1][1])
    assert "quad" in mesh.cells_dict and np.allclose(mesh.point_data["width"][0], 0.02)


def test_ribbon_of_a_twisted_tape_opens_with_the_width_along_its_frame(tmp_path):
    """A tape turned a quarter turn at its tip by a torque: the ribbon's edges at the tip
    lie ``w`` apart along the turned width axis ``d2 = -z`` (to 1e-12); pyvista reads
    the file with its point data."""
    tape = sc.Section.tape(0.02, 50e-6, E=7e10, rho=2700.0)
    rod = sc.Rod.straight([0, 0, 0], [1, 0, 0], 4, tape, normal=[0, 0, 1])
    system = sc.System([rod]).clamp(rod.node(0))
    system.add_point_moment(rod.node(-1), [0.5 * np.pi * tape.GJ, 0, 0])
    path = export.write_vtu(tmp_path / "tape.vtu", system, sc.solve_static(system),
                            points_per_element=4)
    mesh = meshio.read(path)
    tip = mesh.cells_dict["quad"][-1]
    edge = mesh.points[tip[2]] - mesh.points[tip[1]]
    assert np.abs(edge - [0, 0, -0.02]).max() < 1e-12
    assert np.abs(mesh.point_data["director"][16] - [0, -1, 0]).max() < 1e-12
    pv = pytest.importorskip("pyvista")
    grid = pv.read(path)
    assert grid.n_cells == 32 and "width_direction" in grid.point_data


def test_tape_tether_demo():
    """The 5 km tape's torsional period in orbit within 1e-2 of ``2 L / c`` (8 elements,
    1500 s), and its libration the round tether's to 1e-4 rad."""
    out = load_demo("tape_tether").main(elements=8, t_end=1500.0)
    assert out["torsion_period"] == pytest.approx(out["torsion_period_exact"], rel=1e-2)
    assert out["pitch_difference"] < 1e-4
