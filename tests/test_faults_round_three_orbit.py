"""Faults, round three, in orbit: never a silent wrong answer.

Each test reproduces one fault of issue 45 and asserts what the user gets now.

* velocity-dependent loads of a system in orbit (free-molecular and Morison drag, the
  electrodynamic tether) see the absolute velocity ``V(t) + v`` at ``R(t) + x``: the same
  force as the same body moving at the orbital velocity in a fixed frame, in statics, in
  the compiled step and after a rectification;
* an electrodynamic tether reports its open-circuit EMF and power whatever its current;
* an orbit inside the central body is refused, naming ``a`` and the radius;
* the rectification stays off for every constraint a translation of the reference moves.
"""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable import plot, scene_file
from skfem_cable.core.contract import Evaluation
from skfem_cable.loads.drag import Flow, QuadraticDrag
from skfem_cable.loads.electrodynamic import OMEGA_EARTH
from skfem_cable.runner.summary import run_outputs
from skfem_cable.scenes import tss

ORBIT = dict(mu=sc.MU_EARTH, a=sc.R_EARTH + 400e3, e=0.02, inclination=0.5, raan=0.2,
             anomaly=0.7)
TETHER = sc.Section.circular(5e-4, 1e11, 1500.0)
T0 = 40.0


def orbit():
    return sc.Orbit(**ORBIT)


def cable_at(origin, n=4):
    """A 1 km tether from ``origin``, across the along-track flow at ``T0`` (radial and
    a little out of plane), slightly bent."""
    frame = orbit().lvlh(T0)
    ends = np.array(origin) + np.array([-500.0, 500.0])[:, None] * (
        frame[0] + 0.3 * frame[2])
    return sc.Cable.straight(ends[0], ends[1], n, TETHER)


def motion(cable):
    """Offsets' coordinates and velocities: bent and moving (m, m/s)."""
    rng = np.random.default_rng(5)
    dq = rng.normal(scale=2.0, size=cable.n_dofs) * np.tile([1, 1, 1, 1e-3, 1e-3, 1e-3],
                                                          cable.n_dofs // 6)
    return cable.q0 + dq, rng.normal(scale=3.0, size=cable.n_dofs)


def shifted(q, cable, d):
    """``q`` with every position moved by ``d`` (3,)."""
    out = np.array(q, dtype=float)
    out[cable.position_mask] += np.tile(d, int(cable.position_mask.sum()) // 3)
    return out


def load_force(system, load, q, v, t, reference=None):
    """The generalized force of ``load`` alone on ``system`` at ``(q, v, t)`` (bound with
    a run's ``reference`` when given)."""
    term = load.bind(system) if reference is None else load.bind(system, reference)
    ev = Evaluation(system, t, q, v, np.zeros(system.n_constraints))
    nd = load.cable.element_dofs.shape[1]
    term.evaluate(ev, np.zeros(load.cable.element_dofs.shape + (nd,), dtype=np.int64))
    return ev.f_ext.copy()


def total(cable, f):
    return f[cable.position_mask].reshape(-1, 3).sum(axis=0)


PROFILE_R = np.linalg.norm(sc.Orbit(**ORBIT).position(T0))


LOADS = {
    "free molecular, co-rotating air": lambda c: sc.FreeMolecularDrag(
        c, density=3e-12, diameter=1e-3),
    "free molecular, wind": lambda c: sc.FreeMolecularDrag(
        c, density=3e-12, diameter=1e-3, velocity=[30.0, -20.0, 10.0], omega=[0, 0, 0]),
    "Morison, profile": lambda c: sc.MorisonDrag(
        c, 1.0, 0.01, 1.2, 0.1, current=sc.CurrentProfile(
            PROFILE_R + np.array([-800.0, 0.0, 900.0]),
            [[10.0, 0, 0], [0, 20.0, 5.0], [-5.0, 0, 8.0]],
            vertical=orbit().lvlh(T0)[0])),
    "electrodynamic, short circuit": lambda c: sc.ElectrodynamicForce(
        c, "short-circuit", sc.MagneticDipole(tilt=0.2), resistance=200.0,
        plasma_rotation=[0, 0, OMEGA_EARTH]),
}


@pytest.mark.parametrize("name", list(LOADS))
def test_loads_in_orbit_see_the_orbital_velocity(name):
    """Before: ``FreeMolecularDrag`` on a tether of an orbiting system took the velocity
    relative to the reference point (a 1 km tether across the flow at 400 km, 3e-12
    kg/m^3: no drag at all where 1.94e-4 N is right, 1.70e-4 N relative to the
    co-rotating air), as did ``MorisonDrag``.  Now each load's generalized force on a
    bent, moving tether in an inclined, eccentric orbit equals (1e-9 relative, measured
    to round-off) that on the same tether at ``R + x`` moving at ``V + v`` in a fixed
    frame."""
    o = orbit()
    cable = cable_at(np.zeros(3))
    system = sc.System([cable]).add_orbit(o)
    q, v = motion(cable)
    R, V = o.position(T0), o.velocity(T0)
    fixed = cable_at(R)
    inertial = sc.System([fixed])
    make = LOADS[name]
    if name.startswith("free molecular, co"):
        # the default rotation is the Earth's: the fixed frame says so explicitly
        reference = sc.FreeMolecularDrag(fixed, density=3e-12, diameter=1e-3,
                                         omega=[0, 0, OMEGA_EARTH])
    else:
        reference = make(fixed)
    f = load_force(system, make(cable), q, v, T0)
    g = load_force(inertial, reference, shifted(q, cable, R), shifted(v, cable, V), T0)
    assert np.abs(g).max() > 0
    np.testing.assert_allclose(f, g, rtol=0, atol=1e-9 * np.abs(g).max())


def test_free_molecular_drag_of_the_issue():
    """The issue's tether: 1 km radial in a 400 km equatorial circular orbit, at rest in
    the translated frame: ``C_D rho d L |V|^2 / 2`` = 1.94e-4 N against the motion in air
    at rest, 1.70e-4 N relative to the air co-rotating at ``OMEGA_EARTH`` (the default);
    before, 0."""
    o = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3)
    cable = sc.Cable.straight([-500, 0, 0], [500, 0, 0], 4, TETHER)
    system = sc.System([cable]).add_orbit(o)
    V = np.linalg.norm(o.velocity(0.0))
    for omega, speed in ((None, V - OMEGA_EARTH * o.a), ([0, 0, 0], V)):
        load = sc.FreeMolecularDrag(cable, density=3e-12, diameter=1e-3, omega=omega)
        F = total(cable, load_force(system, load, cable.q0, np.zeros(cable.n_dofs), 0.0))
        expected = 2.2 * 3e-12 * 1e-3 * 1e3 * speed**2 / 2
        assert F == pytest.approx([0.0, -expected, 0.0], rel=1e-9, abs=1e-12 * expected)
    assert expected == pytest.approx(1.94e-4, rel=1e-3)


def test_drag_tangent_in_orbit():
    """``R(t)`` and ``V(t)`` do not depend on the coordinates: the drag's exact tangent
    holds in orbit, evaluated at the relative velocity (``dF/dq`` 1e-8, ``dF/dv`` 1e-6)."""
    cable = cable_at(np.zeros(3), n=3)
    q, v = motion(cable)
    load = QuadraticDrag(cable, (0.7, 0.3, 0.5), Flow(lambda t: [np.sin(t), 1.0, 0.0],
                                                       omega=None))
    system = sc.System([cable]).add_orbit(orbit()).add_load(load)
    check = sc.check_tangent(system, q, v * 1e3, t=T0)
    drag = {p.wrt: p.error for p in check.parts if p.name.startswith("QuadraticDrag")}
    assert drag["q"] < 1e-8 and drag["v"] < 1e-6, str(check)


def test_compiled_step_and_rectification_keep_the_absolute_velocity():
    """On the compiled step the drag of the orbital velocity decelerates the tether's
    centre of mass (before: not at all); after a rectification (a rebase of the
    reference on the centre of mass's osculating orbit and the offsets shifted) the drag
    is the same to 1e-9."""
    o = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3)
    cable = sc.Cable.straight([-500, 0, 0], [500, 0, 0], 4, TETHER)
    load = sc.FreeMolecularDrag(cable, density=3e-9, diameter=1e-3, omega=[0, 0, 0])
    system = sc.System([cable]).add_orbit(o).add_load(load)
    result = sc.simulate(system, 20.0, 1.0, rectify=None)
    mass = TETHER.mass_per_length * 1e3
    F = 2.2 * 3e-9 * 1e-3 * 1e3 * np.linalg.norm(o.velocity(0.0)) ** 2 / 2
    u = system.centre_of_mass(result.v[-1])
    assert u[1] == pytest.approx(-F / mass * 20.0, rel=1e-2)
    # a rebase: the same absolute velocity gives the same force
    q, v = motion(cable)
    reference = sc.Reference(o)  # a run's: the user's orbit is never rebased
    before = load_force(system, load, q, v, T0, reference)
    x, w = np.array([300.0, -200.0, 50.0]), np.array([0.4, -0.3, 0.2])
    R, V = reference.position(T0), reference.velocity(T0)
    reference.rebase(R + x, V + w, T0)
    dR, dV = R - reference.position(T0), V - reference.velocity(T0)
    after = load_force(system, load, shifted(q, cable, dR), shifted(v, cable, dV), T0,
                       reference)
    np.testing.assert_allclose(after, before, rtol=0, atol=1e-9 * np.abs(before).max())


def test_electrodynamic_tether_reports_emf_and_power_whatever_the_current():
    """Before: ``evaluate()["emf"]`` was 0 unless ``current="short-circuit"``, and the
    plasma was at rest unless ``plasma_rotation`` was given.  Now a prescribed current
    reports the same open-circuit EMF as the short circuit (the closed-form EMF of a
    radial tether relative to the ionosphere co-rotating with the Earth, the default in
    orbit, 1e-12) and the power ``I E``."""
    o = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3)
    l, R = 2.5e3, o.a
    cable = sc.Cable.straight([-l, 0, 0], [l, 0, 0], 4, TETHER)
    system = sc.System([cable]).add_orbit(o)
    kM, V = 1e-7 * 8.0e22, np.linalg.norm(o.velocity(0.0))
    emf = kM * (V / 2 * (1 / (R - l) ** 2 - 1 / (R + l) ** 2)
                - OMEGA_EARTH * (1 / (R - l) - 1 / (R + l)))
    for current in (1.5, lambda t: 1.5, "short-circuit"):
        extra = {"resistance": 100.0} if current == "short-circuit" else {}
        out = sc.ElectrodynamicForce(cable, current, sc.MagneticDipole(), **extra).evaluate(
            system, cable.q0)
        assert out["emf"] == pytest.approx(emf, rel=1e-12)
        assert out["power"] == pytest.approx(out["current"] * emf, rel=1e-12)
    assert out["power"] == pytest.approx(emf**2 / 100.0, rel=1e-12) and emf > 900.0


@pytest.mark.parametrize("a, e, message", [
    (1000.0, 0.0, r"a = 1000 m lies inside the central body of radius 6378137 m"),
    (sc.R_EARTH + 400e3, 0.1, r"periapsis a \(1 - e\) = .* = 6\d{6}\.?\d* m lies inside "
                              r"the central body of radius 6378137 m"),
])
def test_an_orbit_inside_the_central_body_is_refused(a, e, message):
    """Before: ``Orbit(MU_EARTH, 1000.0)`` (the altitude given as ``a``) was accepted and
    left to fail Newton.  Now ``add_orbit`` refuses it naming ``a`` and the Earth's
    radius, as it refuses an elliptic orbit whose periapsis is below the surface."""
    cable = sc.Cable.straight([-500, 0, 0], [500, 0, 0], 4, TETHER)
    with pytest.raises(ValueError, match=message):
        sc.System([cable]).add_orbit(sc.Orbit(sc.MU_EARTH, a, e=e))
    sc.System([cable]).add_orbit(sc.Orbit(sc.MU_EARTH, 1000.0 + sc.R_EARTH))  # grazing


def test_rectification_stays_off_for_a_sliding_pin():
    """A 1 km tether with two 100 kg end masses, each pushed by (0, 1, 0.3) N, in a 400 km
    orbit, its first node sliding on the plane normal to ``[1, -1, 0]`` through its
    start.  Before: ``stats["rectification"]`` said "on" (the check translated along
    ``[1, 1, 1]`` only, which the pin allows) and the first rebase moved the pinned node
    along the held direction (13 m; Newton then failed at t = 93 s).  Now the check
    translates along each axis: the rectification is off naming the pin, and the node
    keeps its held coordinate (1e-9 m) for 300 s."""
    o = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3)
    cable = sc.Cable.straight([-500, 0, 0], [500, 0, 0], 4,
                              sc.Section.circular(1e-3, 1e11, 1.0))
    system = sc.System([cable])
    for end in (cable.node(0), cable.node(-1)):
        system.add_point_mass(end, 100.0).add_load(sc.PointLoad(end, [0.0, 1.0, 0.3]))
    held = np.array([1.0, -1.0, 0.0]) / np.sqrt(2)
    system.pin(cable.node(0), directions=[held]).add_orbit(o)
    result = sc.simulate(system, 300.0, 1.0, every=10)
    assert result.stats["rectification"].startswith("off: constraint sliding pin Node(cable, 0)")
    assert result.stats["rectifications"] == 0
    node = system.dofs(cable.node(0))[:3]
    assert np.abs((result.q[:, node] - cable.q0[:3]) @ held).max() < 1e-9


@pytest.fixture(scope="module")
def librating():
    """A 2 km dumbbell (4 elements, 100 kg ends) in a 400 km orbit, released at rest in
    the orbiting frame pitched by 0.05 rad and rolled by 0.03 rad, for 600 s."""
    o = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3)
    system, cable = tss.dumbbell(o, n_elements=4, length=2e3)
    initial = tss.librated(system, o, 0.05, 0.03)
    return sc.simulate(system, initial=initial, t_end=600.0, dt=5.0, every=2), cable


def test_orbiting_run_tip_displacement_is_drawn_in_the_lvlh_frame(librating, tmp_path):
    """Before: ``plots/cables.png`` of an orbiting run measured the tips "in the spinning
    frame" (the rigid motion fitted to the whole system, which takes out the libration as
    well as the orbit's turn): 6.2e-5 m where the tips move 38.7 m in the orbiting frame.
    Now the tips are drawn about the centre of mass in the LVLH frame (``Orbit.to_lvlh``)."""
    result, cable = librating
    system = result.system
    tips = result.position(cable, cable.length)
    y = result.reference.to_lvlh(result.t, tips - system.centre_of_mass(result.q))
    moved = np.linalg.norm(y - y[0], axis=-1)
    fig = plot.cable_histories(result, tmp_path / "cables.png")
    tip = fig.axes[0]
    assert "LVLH frame" in tip.get_ylabel()
    np.testing.assert_allclose(tip.get_lines()[0].get_ydata(), moved, rtol=1e-12, atol=1e-9)
    assert moved.max() > 30.0


def test_orbiting_run_summary_gives_librations_and_centre_tension(librating):
    """Before: the summary of an orbiting run gave tip positions and root tensions only.
    Now each cable has its in-plane and out-of-plane libration angles (the end-to-end
    line in the LVLH frame: at the end and their largest over the run, from 0.05 and 0.03
    rad at the release) and its centre tension (mid-length: at the end and its largest)."""
    result, cable = librating
    numbers = run_outputs(result)["cables"][cable.name]
    pitch, roll = tss.attitude(result.system.orbit, cable, result.t,
                               result.q[:, result.system.dofs(cable)])
    assert numbers["libration_in_plane"] == pytest.approx(pitch[-1], rel=1e-12)
    assert numbers["libration_out_of_plane"] == pytest.approx(roll[-1], rel=1e-12)
    assert numbers["max_libration_in_plane_run"] == pytest.approx(0.05, rel=1e-3)
    assert numbers["max_libration_out_of_plane_run"] == pytest.approx(0.03, rel=5e-3)
    centre = result.tension(cable, cable.length / 2)
    assert numbers["centre_tension"] == centre[-1]
    assert numbers["max_centre_tension_run"] == centre.max() > 0.3


ORBIT_SCENE = """
[sections.tether]
radius = 1e-3
E = 1e11
rho = 1.0

[[cables]]
name = "tether"
section = "tether"
start = [-500, 0, 0]
end = [500, 0, 0]
elements = 2

[orbit]
central_body = "earth"
a = 1000.0

[solver]
t_end = 10.0
dt = 1.0
"""


def test_a_scene_file_orbit_inside_the_central_body_is_refused():
    """Before: ``[orbit] a = 1000.0`` (an altitude written as ``a``) was accepted.  Now
    the scene file is refused naming the table, ``a`` and the Earth's radius."""
    with pytest.raises(scene_file.SceneFileError, match=r"bad.toml: .*orbit is refused: "
                       r"Orbit: a = 1000 m lies inside the central body of radius 6378137 m"):
        scene_file.loads_text(ORBIT_SCENE, "bad.toml")
