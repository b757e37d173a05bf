"""Membrane locking and the formulations of the cable (docs/locking.md): the default
assumed-strain formulation on the elastica, the hanging cable, the taut string (in
``test_validation_statics``), the free cable's zero modes and the stress-free truss
catenary; the paper's and the Lobatto formulations by name; the tension guard of the
summaries."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.analysis.analytic import (
    elastica_catenary,
    elastica_tip_load,
    elastica_tip_load_angle,
)
from skfem_cable.scenes.classics import ELASTICA_SECTION as SEC


def cantilever(k, n=16, formulation=None):
    """The tip-loaded elastica (``P = k EI / L^2``, L = 1), solved statically."""
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], n, SEC, formulation=formulation)
    system = sc.System([cable]).clamp(cable.node(0))
    system.add_point_load(cable.node(-1), [0, -k * SEC.EI, 0])
    state = sc.solve_static(system, load_steps=max(10, int(2 * k)))
    return cable, state.q[:cable.n_dofs]


def tip_error(k, **options):
    cable, q = cantilever(k, **options)
    tip = cable.interpolate(q, 1.0)[0]
    u, w = elastica_tip_load(k)
    return max(abs(1 - tip[0] - u), abs(-tip[1] - w))


@pytest.mark.parametrize("k", [1.0, 2.0, 5.0, 10.0])
def test_elastica_tip_within_exudyn_reduced_integration(k):
    """16 elements, no option named: tip error <= 2.6e-5 (Exudyn's reduced integration
    reaches 2.6e-5 at k = 10; measured 5.8e-8, 2.2e-7, 1.3e-6, 4.3e-6), against 5.8e-5 ..
    5.6e-4 for the paper's formulation."""
    assert tip_error(k) <= 2.6e-5
    assert tip_error(k, formulation="paper") > 5 * tip_error(k)


@pytest.mark.parametrize("k", [15.0, 20.0])
def test_elastica_tip_large_loads(k):
    assert tip_error(k) <= 1e-3  # measured 7.8e-6, 1.3e-5


def test_exact_angle_is_the_elliptic_elastica():
    """The reference angle is consistent: zero moment (theta' = 0) at the tip and the tip
    position of the elliptic solution."""
    k = 5.0
    s = np.linspace(0, 1, 4001)
    theta = elastica_tip_load_angle(k, s)
    x, y = np.trapezoid(np.cos(theta), s), np.trapezoid(np.sin(theta), s)
    u, w = elastica_tip_load(k)
    assert 1 - x == pytest.approx(u, abs=1e-7) and y == pytest.approx(w, abs=1e-7)
    assert (theta[-1] - theta[-2]) / (s[1] - s[0]) == pytest.approx(0.0, abs=2e-3)


@pytest.mark.parametrize("k", [1.0, 2.0, 5.0, 10.0])
def test_recovered_tension_is_the_exact_axial_force(k):
    """N(s) = P sin(theta(s)) within 1 % of P everywhere, the clamp included, with 16
    elements and no option named (measured 5.8e-5, 3.3e-4, 1.9e-3, 5.5e-3 of P); the
    paper's formulation is off by tens of P (membrane locking)."""
    P = k * SEC.EI
    s = np.linspace(0, 1, 321)
    exact = P * np.sin(elastica_tip_load_angle(k, s))
    cable, q = cantilever(k)
    assert np.abs(cable.tension(q, s) - exact).max() < 0.01 * P
    paper, q = cantilever(k, formulation="paper")
    assert np.abs(paper.tension(q, s) - exact).max() > P


#: The hanging cable of the tension issue, as a scene file written from
#: docs/scene_files.md with no option: a steel wire of 2 mm radius, 12 m, pinned at two
#: points 10 m apart, 16 elements.
HANGING = """
[sections.steel]
E = 2.1e11
rho = 7850.0
radius = 0.002

[[cables]]
name = "wire"
section = "steel"
start = [0, 0, 0]
end = [12, 0, 0]
elements = 16

[[constraints]]
type = "pin"
node = { cable = "wire", index = 0 }

[[constraints]]
type = "pin"
node = { cable = "wire", index = -1 }
target = [10, 0, 0]

[loads]
gravity = [0, 0, -9.81]

[solver]
analysis = "static"
load_steps = 10
"""


def hanging_reference(s):
    """Tension of the hanging wire: the planar elastica-catenary of the Green law with
    bending (``analytic.elastica_catenary``, solved independently of the elements)."""
    sec = sc.Section.circular(2e-3, 2.1e11, 7850.0)
    return elastica_catenary(s, 10.0, 12.0, sec.mass_per_length * 9.81, sec.EA, sec.EI)[1]


def test_hanging_cable_tension_within_one_percent(tmp_path):
    """The scene file run as a new user would, ``skfem-cable run hanging.toml``: the
    summary reports the support tension 7.245 N (exact 7.2445 N; the paper's formulation
    reported -59.6 N), and the tension along the cable is within 1 % of its largest value
    everywhere (measured 1.9e-4), with no warning."""
    from skfem_cable import scene_file
    from skfem_cable.runner import RunOptions

    path = tmp_path / "hanging.toml"
    path.write_text(HANGING)
    summary = scene_file.run(path, RunOptions(plots=False, progress=False))
    wire = summary["outputs"]["cables"]["wire"]
    s = np.linspace(0.0, 12.0, 321)
    N = hanging_reference(s)
    assert wire["root_tension"] == pytest.approx(N[0], rel=1e-3)
    assert wire["max_tension"] == pytest.approx(N.max(), rel=1e-3)
    assert summary["warnings"] == []
    spec = scene_file.load(path)
    state = sc.solve_static(spec.system, **spec.solver)
    cable = spec.system.cables()[0]
    assert cable.formulation == "assumed-strain"
    assert np.abs(state.tension(cable, s) - N).max() < 0.01 * N.max()


def test_paper_formulation_on_the_hanging_cable_is_flagged(tmp_path):
    """The paper's formulation, named in the scene file: the summary carries the warnings
    of the tension guard naming the cable (a change of sign, stripes larger than the
    tension), also printed on stderr."""
    from skfem_cable import scene_file
    from skfem_cable.runner import RunOptions

    path = tmp_path / "hanging.toml"
    path.write_text(HANGING.replace('elements = 16', 'elements = 16\nformulation = "paper"'))
    summary = scene_file.run(path, RunOptions(plots=False, progress=False))
    assert summary["outputs"]["cables"]["wire"]["root_tension"] < -50  # -59.6 N
    sign, stripes = summary["warnings"]
    assert sign.startswith("cable 'wire': its tension changes sign")
    assert stripes.startswith("cable 'wire': its tension oscillates")
    assert "formulation 'paper'" in sign and "assumed-strain" in stripes


@pytest.mark.parametrize("n", [1, 2, 12, 40])
@pytest.mark.parametrize("law", ["cable", "truss"])
def test_free_straight_cable_has_exactly_the_rigid_zero_modes(n, law):
    """Stiffness spectrum of a free straight cable in the default formulation: five zero
    modes (three translations, two rotations; the spin about its own axis moves no
    coordinate) for the cable, and for the truss, stiff only along its axis, exactly its
    2 n + 1 axial strain values; nothing else (the paper's formulation has the same count).
    Zero: below 1e-13 of the largest eigenvalue (the rigid modes are at 1e-17, the softest
    bending mode of 40 elements at 1e-9)."""
    section = sc.Section(E=1e9, A=1e-4, I=1e-10, rho=7850.0)
    counts = []
    for formulation in ("assumed-strain", "paper"):
        cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], n, section, law=law,
                                  formulation=formulation)
        eig = np.abs(np.linalg.eigvalsh(sc.System([cable]).assemble(cable.q0)[1].toarray()))
        counts.append(int(np.sum(eig < 1e-13 * eig.max())))
    zero = counts[0]
    if law == "cable":
        assert zero == 5
    else:  # a truss only resists stretching: one stiff axial direction per sampled value
        assert cable.n_dofs - zero == 2 * n + 1
    assert counts[1] == zero


@pytest.mark.parametrize("n", [16, 32])
def test_stress_free_truss_catenaries_solve(n):
    """Trusses (no bending) from stress-free starts: the slack catenary of
    ``demos/slack_catenary.py`` from its straight state (pinned 2 m closer than its length;
    positions within 2e-5 of the span, 1.4e-5 and 1.7e-6 measured), and the steel catenary
    from the inextensible catenary, which the cubic field compresses slightly between the
    nodes (support force within 1e-6: 3.4e-7 and 2.1e-8)."""
    from demo_modules import load_demo
    from test_validation_statics import catenary_errors

    demo = load_demo("slack_catenary")
    cable, state = demo.hang(n)
    assert state.stats["converged"] and demo.errors(cable, state)[0] < 2e-5
    assert catenary_errors("steel", n, "truss")["H"] < 1e-6


def test_formulation_is_named_and_checked():
    """``formulation=`` takes the three names; ``locking_free`` keeps its meaning (False:
    the paper's, True: the Lobatto formulation); contradictions and other values are
    refused, naming the parameter and what it accepts."""
    make = sc.Cable.straight
    args = ([0, 0, 0], [1, 0, 0], 2, SEC)
    assert make(*args).formulation == "assumed-strain"
    assert make(*args, locking_free=False).formulation == "paper"
    assert make(*args, locking_free=True).formulation == "lobatto"
    assert tuple(sc.FORMULATIONS) == ("assumed-strain", "paper", "lobatto", "segment")
    with pytest.raises(ValueError, match="'segment' is not available on the element "
                                         "'hermite3'"):
        make(*args, formulation="segment")
    with pytest.raises(ValueError, match="formulation must be one of .*'assumed-strain'"):
        make(*args, formulation="mixed")
    with pytest.raises(ValueError, match="locking_free=True means formulation='lobatto'"):
        make(*args, formulation="paper", locking_free=True)
    with pytest.raises(TypeError, match="locking_free"):
        make(*args, locking_free="yes")


def test_a_law_whose_axial_part_is_not_a_function_of_the_stretch():
    """The assumed strain needs the axial part as a function of the stretch: a law that
    depends on the direction of r_x is refused by the default formulation, with the
    formulations that take it named, and runs with those."""
    @sc.cable_law
    def anisotropic(a, b, EA):
        return EA * (a[0] - 1) ** 2 / 2

    with pytest.raises(ValueError, match="anisotropic.*formulation='paper' or 'lobatto'"):
        sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, SEC, law=anisotropic)
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, SEC, law=anisotropic,
                              formulation="paper")
    assert np.allclose(sc.System([cable]).assemble(cable.q0 * 1.01)[0][[0, 12]], [-1e3, 1e3])


def test_cli_scene_and_scene_file_take_the_option(tmp_path):
    """`skfem-cable run cantilever` reports a root tension of ~0 at k = 10 (exact: 0;
    with --formulation paper: 6.4 N, 64 P), and a scene file selects the formulation per
    cable (then --formulation is refused for it)."""
    from skfem_cable import scene_file
    from skfem_cable.cli.command import main
    from skfem_cable.runner import RunOptions
    from skfem_cable.scenes.catalog import run_scene

    summary = run_scene("cantilever", RunOptions(plots=False, progress=False))
    assert summary["parameters"]["formulation"] == "assumed-strain"
    P = 10.0 * SEC.EI
    assert abs(summary["outputs"]["cables"]["cable"]["root_tension"]) < 0.01 * P
    paper = run_scene("cantilever", RunOptions(formulation="paper", plots=False,
                                               progress=False))
    assert paper["outputs"]["cables"]["cable"]["root_tension"] > 10 * P
    assert main(["run", "cantilever", "--formulation", "lobatto", "--elements", "4",
                 "--no-plots"]) == 0
    with pytest.raises(SystemExit):
        main(["run", "cantilever", "--formulation", "mixed"])
    path = tmp_path / "bar.toml"
    path.write_text('[sections.s]\nE = 1e9\nA = 1e-4\nI = 1e-10\nrho = 7850.0\n\n'
                    '[[cables]]\nname = "bar"\nsection = "s"\nstart = [0, 0, 0]\n'
                    'end = [1, 0, 0]\nelements = 4\nformulation = "lobatto"\n\n'
                    '[solver]\nt_end = 0.01\ndt = 0.001\n')
    spec = scene_file.load(path)
    assert spec.system.bodies[0].formulation == "lobatto"
    with pytest.raises(ValueError, match="--formulation"):
        scene_file.run(path, RunOptions(formulation="paper"))
    path.write_text(path.read_text().replace('"lobatto"', '"mixed"'))
    with pytest.raises(scene_file.SceneFileError, match="formulation"):
        scene_file.load(path)
