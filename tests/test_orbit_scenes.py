"""Systems in orbit as scenes: the ``[orbit]`` table of scene files, the ``tss`` scene,
output in the orbiting (LVLH) frame and the orbit in run summaries."""

import json

import meshio
import numpy as np
import pytest
from demo_modules import load_demo

import skfem_cable as sc
from skfem_cable import scene_file
from skfem_cable.cli import command as cli
from skfem_cable.io import StoreMismatch, export, run_observers
from skfem_cable.runner import RunOptions
from skfem_cable.scenes import catalog, tss
from skfem_cable.space.constants import J2_EARTH

L = 20e3
ORBIT = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3, e=0.01, inclination=0.5, raan=0.2,
                 argp=0.3, anomaly=0.4, t0=10.0)

SCENE = """
[sections.tether]
radius = 1e-3
E = 1e11
rho = 1.0

[[cables]]
name = "tether"
section = "tether"
start = [-10e3, 0, 0]
end = [10e3, 0, 0]
elements = 4

[[point_masses]]
at = { cable = "tether", index = 0 }
mass = 100.0

[[point_masses]]
at = { cable = "tether", index = -1 }
mass = 100.0

[orbit]
central_body = "earth"
altitude = 400e3
e = 0.01
inclination = 0.5
raan = 0.2
argp = 0.3
anomaly = 0.4
t0 = 10.0

[solver]
t_end = 100.0
dt = 10.0
"""


def api_system(j2=None):
    cable = sc.Cable.straight([-L / 2, 0, 0], [L / 2, 0, 0], 4,
                              sc.Section.circular(1e-3, 1e11, 1.0), name="tether")
    system = sc.System([cable]).add_point_mass(cable.node(0), 100.0)
    system.add_point_mass(cable.node(-1), 100.0)
    return system.add_orbit(ORBIT, j2=j2, body_radius=None if j2 is None else sc.R_EARTH)


def residual(system, q, t):
    return system.evaluate(q, None, t, np.zeros(system.n_constraints))[0][:system.n_dofs]


@pytest.mark.parametrize("j2", [None, J2_EARTH])
def test_orbit_table_builds_the_api_system(j2):
    """The same orbit (elements to round-off) and the same forces, to 1e-12 of their
    size, at a perturbed state, with and without ``j2 = true``."""
    text = SCENE.replace("t0 = 10.0", "t0 = 10.0\nj2 = true") if j2 else SCENE
    spec = scene_file.loads_text(text, "orbit.toml")
    api = api_system(j2)
    orbit = spec.system.orbit
    for key in ("mu", "a", "e", "inclination", "raan", "argp", "anomaly", "t0"):
        assert getattr(orbit, key) == pytest.approx(getattr(ORBIT, key), rel=1e-15)
    q = api.q0 + np.random.default_rng(1).normal(scale=10.0, size=api.n_dofs)
    expected = residual(api, q, 321.0)
    np.testing.assert_allclose(residual(spec.system, q, 321.0), expected, rtol=0,
                               atol=1e-12 * np.abs(expected).max())


def test_steady_start_in_orbit_defaults_to_the_orbits_rate():
    """``[initial] steady = true`` without ``angular_velocity``: at rest in the orbiting
    frame of a circular orbit, the dumbbell's tension ``3 n^2 L m / 2`` within 5e-3."""
    text = _orbit_table(central_body="earth", altitude=4e5) + "[initial]\nsteady = true\n"
    spec = scene_file.loads_text(text, "orbit.toml")
    n = spec.system.orbit.mean_motion
    np.testing.assert_allclose(spec.initial.v, spec.system.rigid_motion_velocity(
        spec.initial.q, spec.system.orbit.angular_velocity(0.0)), atol=1e-12)
    tension = spec.system.cables()[0].tension(spec.initial.q, L / 2)
    assert tension == pytest.approx(3 * n**2 * L * 50.0, rel=5e-3)


def _orbit_table(**keys):
    lines = [f"{k} = {json.dumps(v)}" for k, v in keys.items()]
    before, after = SCENE.split("[orbit]")
    return before + "[orbit]\n" + "\n".join(lines) + "\n\n" + after.split("\n\n", 1)[1]


@pytest.mark.parametrize("keys, message", [
    ({"central_body": "earth", "altitude": 4e5, "inclinaton": 0.1},
     "orbit.inclinaton is not a known key: did you mean 'inclination'?"),
    ({"central_body": "moon", "a": 7e6}, "orbit.central_body must be one of 'earth', "
                                         "'sun', got 'moon'"),
    ({"central_body": "earth", "mu": 4e14, "a": 7e6},
     "orbit.mu excludes orbit.central_body (give one of them)"),
    ({"a": 7e6}, "orbit.central_body is required ('earth' or 'sun'), or mu"),
    ({"mu": -1.0, "a": 7e6}, "orbit.mu must be a number > 0, got -1.0"),
    ({"central_body": "earth"}, "orbit.a is required (the semi-major axis, m), or altitude"),
    ({"central_body": "earth", "a": 7e6, "altitude": 4e5}, "orbit.altitude excludes orbit.a"),
    ({"central_body": "earth", "altitude": -1.0}, "orbit.altitude must be a number >= 0"),
    ({"mu": 4e14, "altitude": 4e5}, "orbit.altitude needs the central body's radius"),
    ({"central_body": "earth", "a": 7e6, "e": 1.0},
     "orbit.e must be a number in [0, 1) (elliptic orbits), got 1.0"),
    ({"central_body": "earth", "a": 7e6, "raan": "north"},
     "orbit.raan must be a finite number, got 'north'"),
    ({"central_body": "sun", "a": 1.5e11, "j2": True},
     "orbit.j2 = true needs a central body whose J2 is known"),
    ({"mu": 4e14, "a": 7e6, "j2": 1e-3}, "orbit.j2 needs the central body's radius"),
    ({"central_body": "earth", "a": 7e6, "j2": "yes"},
     "orbit.j2 must be true (the central body's J2), false or a number, got 'yes'"),
])
def test_bad_orbit_keys_and_values_are_named(keys, message):
    with pytest.raises(scene_file.SceneFileError) as err:
        scene_file.loads_text(_orbit_table(**keys), "bad.toml")
    assert str(err.value).startswith("bad.toml: ")
    assert message in str(err.value)


def test_mu_with_body_radius_takes_altitude_and_j2():
    spec = scene_file.loads_text(_orbit_table(mu=sc.MU_EARTH, body_radius=sc.R_EARTH,
                                              altitude=4e5, j2=J2_EARTH), "ok.toml")
    assert spec.system.orbit.a == sc.R_EARTH + 4e5


def test_orbit_and_uniform_gravity_are_refused_naming_both_tables():
    text = SCENE + "\n[loads]\ngravity = [0, 0, -9.81]\n"
    with pytest.raises(scene_file.SceneFileError,
                       match=r"^bad.toml: orbit excludes loads.gravity"):
        scene_file.loads_text(text, "bad.toml")
    with pytest.raises(scene_file.SceneFileError, match="did you mean 'orbit'"):
        scene_file.loads_text(SCENE.replace("[orbit]", "[orbt]"), "bad.toml")


def test_tss_models():
    with pytest.raises(ValueError, match="model must be one of 'ancf', 'rodchain', got "
                                         "'beads'$"):
        tss.scene(model="beads")
    with pytest.raises(ValueError, match="rod-chain model has no formulation"):
        tss.scene(model="rodchain", formulation="paper")
    assert catalog.SCENES["tss"].builder() is tss.scene
    with pytest.raises(ValueError, match="scene 'pendulum' does not take --model"):
        catalog.run_scene("pendulum", RunOptions(model="rodchain"))


def test_tss_rodchain_agrees_with_the_ancf_model(tmp_path):
    """``skfem-cable run tss --model rodchain``: the paper's rod chain (3 rods, compiled
    RK4 at its stable step) librates as the ANCF dumbbell does over 3 pitch periods:
    pitch and roll frequencies within 1e-3 of each other (measured 4.5e-4 and 1.3e-4) and
    within 0.5 % of ``sqrt(3) n`` and ``2 n``; its central tension is ``3 n^2 L m / 2``
    (3.840 N) within 0.5 %; the run directory has the summary and the ParaView series."""
    out = tmp_path / "chain"
    chain = catalog.run_scene("tss", RunOptions(out=out, model="rodchain", progress=False,
                                                plots=False))
    ancf = catalog.run_scene("tss", RunOptions(progress=False, plots=False))
    for key, rigid in (("pitch_frequency_over_n", np.sqrt(3)), ("roll_frequency_over_n", 2)):
        assert chain["outputs"][key] == pytest.approx(ancf["outputs"][key], rel=1e-3)
        assert chain["outputs"][key] == pytest.approx(rigid, rel=5e-3)
    assert chain["outputs"]["chain"]["central_tension_mean"] == pytest.approx(3.840,
                                                                              rel=5e-3)
    assert chain["parameters"]["model"] == "rodchain"
    assert (out / "summary.json").is_file() and (out / "series.pvd").is_file()
    assert len(list((out / "vtu").glob("*.vtu"))) == 31  # every 5th of the 151 saved steps


def test_run_tss_writes_the_orbit_into_the_summary(tmp_path, capsys):
    """The reference orbit, and the osculating orbit of the centre of mass at the start
    and at the end: ``a`` within 2e-5 of the reference (the dumbbell's centre of mass is
    not a point mass: 9e-6 measured), the true longitude advanced by ``n t`` within
    1e-4 rad."""
    out = tmp_path / "tss"
    assert cli.main(["run", "tss", "--t-end", "300", "--elements", "2", "--no-plots",
                     "--no-progress", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "orbit (osculating elements of the centre of mass" in printed
    summary = json.loads((out / "summary.json").read_text())
    orbit = summary["orbit"]
    reference = orbit["reference"]
    assert summary["frame"] == "inertial"
    assert orbit["mu"] == sc.MU_EARTH and reference["a"] == sc.R_EARTH + 400e3
    n = np.sqrt(sc.MU_EARTH / reference["a"] ** 3)
    for when, t in (("start", 0.0), ("end", 300.0)):
        elements = orbit[when]
        assert elements["t"] == pytest.approx(t, abs=1e-9)
        assert elements["a"] == pytest.approx(reference["a"], rel=2e-5)
        assert elements["e"] < 2e-5
        assert abs(np.angle(np.exp(1j * (elements["longitude"] - n * t)))) < 1e-4
    assert summary["outputs"]["pitch_max"] == pytest.approx(0.05, rel=1e-2)


def _series_points(run_dir):
    """Times, point positions and velocities of the written VTU frames."""
    frames = export.read_pvd(run_dir / "series.pvd")
    meshes = [meshio.read(run_dir / file) for _, file in frames]
    return (np.array([t for t, _ in frames]), np.array([m.points for m in meshes]),
            np.array([m.point_data["velocity"] for m in meshes]))


def test_lvlh_series_of_a_tether_at_rest_in_the_orbiting_frame(tmp_path):
    """The steady dumbbell (no offsets) over 0.3 pitch periods (16 minutes), 400 steps
    per period: in the LVLH series its points stay put within 0.1 m (measured 0.039 m,
    the integrator's phase error of the orbital rotation, falling as ``dt^2``: 0.63 m at
    100 steps) and move at below 3e-4 m/s (measured 1.1e-4), while in the inertial series
    they turn by ``n t`` (within 1e-5 rad; 8.9 km at the ends), at ``n |r|`` (11 m/s)."""
    runs = {}
    for frame in ("lvlh", "inertial"):
        scene = tss.scene(elements=2, pitch=0.0, roll=0.0, periods=0.3, steps_per_period=400,
                          every=8)
        scene.run(RunOptions(out=tmp_path / frame, plots=False, progress=False, frame=frame))
        runs[frame] = _series_points(tmp_path / frame)
    t, x, v = runs["lvlh"]
    assert len(t) >= 4
    assert np.abs(x - x[0]).max() < 0.1
    assert np.abs(v).max() < 3e-4
    assert np.abs(x[0][:, 1:]).max() < 1e-6 * L  # along the local vertical
    t_in, x_in, v_in = runs["inertial"]
    np.testing.assert_array_equal(t_in, t)
    assert np.abs(x_in - x_in[0]).max() > 8e3
    n = np.sqrt(sc.MU_EARTH / (sc.R_EARTH + 400e3) ** 3)
    tip = np.argmax(x_in[0][:, 0])
    angle = np.unwrap(np.arctan2(x_in[:, tip, 1], x_in[:, tip, 0]))
    np.testing.assert_allclose(angle, n * t, rtol=0, atol=1e-5)
    assert np.linalg.norm(v_in[0, tip]) == pytest.approx(n * np.linalg.norm(x_in[0, tip]),
                                                         rel=1e-6)


def test_inertial_frame_writes_the_coordinates_as_computed():
    system = api_system()
    q, v = system.q0, np.ones(system.n_dofs)
    assert export.output_frame(system).configuration(1.0, q, v) == (q, v)


def test_lvlh_frame_turns_slopes_and_takes_relative_velocities():
    """Slopes turn with the positions; a rigid rotation at the frame's rate has no
    velocity in it."""
    system = api_system()
    frame = export.output_frame(system, "lvlh")
    t = 500.0
    C = ORBIT.lvlh(t)
    q = system.rotate(system.q0, C.T)  # the tether along the radial axis at t
    v = system.rigid_motion_velocity(q, ORBIT.angular_velocity(t))
    moved, relative = frame.configuration(t, q, v)
    np.testing.assert_allclose(moved, system.q0, atol=1e-9)
    np.testing.assert_allclose(relative, 0.0, atol=1e-12)


def test_lvlh_frame_without_an_orbit_is_refused(tmp_path, capsys):
    out = tmp_path / "pendulum"
    assert cli.main(["run", "pendulum", "--t-end", "0.01", "--frame", "lvlh",
                     "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "frame 'lvlh' (the orbiting frame) needs a system in orbit" in err
    assert not out.exists()
    with pytest.raises(SystemExit):
        cli.main(["run", "pendulum", "--frame", "rotating"])
    assert "invalid choice: 'rotating'" in capsys.readouterr().err
    pendulum = sc.System([sc.Cable.straight([0, 0, 0], [1, 0, 0], 2,
                                            sc.Section.circular(1e-3, 1e9, 1e3))])
    with pytest.raises(ValueError, match="needs a system in orbit"):
        sc.simulate(pendulum, t_end=0.01, dt=0.01,
                    observers=run_observers(tmp_path / "api", progress=False, frame="lvlh"))
    with pytest.raises(ValueError, match="frame must be one of 'inertial', 'lvlh', got 'x'"):
        run_observers(tmp_path / "api", frame="x")


def test_a_continued_run_keeps_its_frame(tmp_path):
    scene = tss.scene(elements=2, periods=0.05, steps_per_period=100, every=1)
    out = tmp_path / "run"
    scene.run(RunOptions(out=out, plots=False, progress=False, frame="lvlh"))
    with pytest.raises(StoreMismatch, match="written in the frame 'lvlh', not 'inertial'"):
        scene.run(RunOptions(out=out, plots=False, progress=False, resume=True,
                             t_end=200.0))


def test_tss_libration_demo():
    """Pitch at ``sqrt(3) n (1 - (2 theta_0)^2 / 16)`` within 2e-3, roll at ``2 n``
    within 1e-3 (4 elements, 100 steps per pitch period, three periods)."""
    out = load_demo("tss_libration").main(elements=4, steps_per_period=100)
    assert out["pitch_frequency"] == pytest.approx(out["pitch_expected"], rel=2e-3)
    assert out["roll_frequency"] == pytest.approx(2.0, rel=1e-3)
    assert out["pitch_max"] == pytest.approx(tss.PITCH, rel=1e-2)


def test_esail_orbit_scene_reports_its_orbit():
    """The registered ``esail-orbit`` scene is the sail of ``esail.build_orbit``; two steps
    of it report the heliocentric orbit (1 AU) and the E-sail's numbers."""
    scene = catalog.builder("esail-orbit")(elements=1, t_end=2.0, dt=1.0, every=1)
    summary = scene.run(RunOptions(progress=False))
    assert summary["orbit"]["reference"]["a"] == sc.AU
    assert summary["orbit"]["end"]["a"] == pytest.approx(sc.AU, rel=1e-8)
    assert summary["outputs"]["thrust_mean_N"] > 0


@pytest.mark.parametrize(("line", "expected"), [("", None), ("rectify = 1e-3", 1e-3),
                                                ("rectify = 0", None)])
def test_solver_table_takes_the_rectification(line, expected):
    """``[solver] rectify``: the tolerance of Encke's rectification (``simulate``'s
    default when left out), 0 to switch it off; more than 0.1 is refused."""
    spec = scene_file.loads_text(SCENE.replace("dt = 10.0", f"dt = 10.0\n{line}"),
                                 "orbit.toml")
    assert spec.solver.get("rectify", "default") == ("default" if not line else expected)
    result = sc.simulate(spec.system, initial=spec.initial, **spec.solver)
    assert result.stats["rectification"] == ("none" if line == "rectify = 0" else "on")
    with pytest.raises(scene_file.SceneFileError, match=r"solver.rectify.*\[0.0, 0.1\]"):
        scene_file.loads_text(SCENE.replace("dt = 10.0", "dt = 10.0\nrectify = 0.5"),
                              "orbit.toml")
