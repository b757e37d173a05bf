"""Fluid drag on cables (``skfem_cable.loads.drag``): exact tangents against finite differences,
the point forces against their closed forms, free-molecular drag on straight tethers
against the integrated closed form, the settled mooring line in a current against the
cable equilibrium equations (``solve_bvp``), the demo's transient, MoorDyn (skipped
without ``moordyn``), the scene file and errors."""

import doctest
from pathlib import Path

import numpy as np
import pytest
from demo_modules import load, load_demo

import skfem_cable as sc
from skfem_cable import scene_file
from skfem_cable.loads.drag import Flow, QuadraticDrag

ROOT = Path(__file__).resolve().parents[1]
SECTION = sc.Section(E=2e9, A=1e-4, I=1e-9, rho=1000.0)


@pytest.fixture(scope="module")
def demo():
    return load_demo("mooring_current")


def external_force(system, q, v, t=0.0):
    """The non-constant external force ``f_ext(q, v, t)`` (``v`` None: statics)."""
    return system.evaluate(q, v, t, np.zeros(system.n_constraints))[1]["f_nc"]


PROFILE = sc.CurrentProfile([-0.5, 0.05, 0.3], [[0.3, 1.0, -0.2], [1.2, -0.4, 0.5],
                                                [0.1, 0.2, 0.9]], vertical=[0, 0.6, 0.8],
                            ramp=lambda t: 1.0 + t)


@pytest.mark.parametrize("current, deformed", [
    (PROFILE, True), (lambda t: [np.sin(t), 1.0, 0.0], False)], ids=["profile", "uniform"])
def test_tangents_match_finite_differences(current, deformed):
    """All three drag terms (normal, tangential, free-molecular cross term), a rotating
    flow, an elevation profile with a ramp or a time-dependent uniform current, per
    reference or deformed length: ``dF/dq`` to 1e-8, ``dF/dv`` to 1e-6 of the largest
    entry."""
    cable = sc.Cable.straight([0, 0, 0], [1.0, 0.2, 0.1], 3, SECTION)
    rng = np.random.default_rng(3)
    q = cable.q0 + 0.05 * rng.standard_normal(cable.n_dofs)
    v = rng.standard_normal(cable.n_dofs)
    load = QuadraticDrag(cable, (0.7, 0.3, 0.5), Flow(current, omega=[0.3, -0.2, 0.5]),
                         deformed)
    system = sc.System([cable]).add_load(load)
    check = sc.check_tangent(system, q, v, t=0.3)
    drag = {p.wrt: p.error for p in check.parts if p.name.startswith("QuadraticDrag")}
    assert drag["q"] < 1e-8 and drag["v"] < 1e-6, str(check)


def test_point_forces_match_closed_forms():
    """Morison: ``rho d C_dn |u_n| u_n / 2 + rho pi d C_dt |u_t| u_t / 2``; free-molecular:
    ``-C_D rho d |v_r x t| v_r / 2``; per deformed length: times ``|r_x|`` (1e-14)."""
    cable = sc.Cable.straight([0, 0, 0], [1.0, 0, 0], 1, SECTION)
    rho, d, cdn, cdt = 1025.0, 0.05, 1.2, 0.1
    a = np.array([1.2, 0.5, -0.3])
    u = np.array([0.4, -1.1, 0.7])
    t = a / np.linalg.norm(a)
    ut = (u @ t) * t
    un = u - ut
    morison = rho * d * (cdn * np.linalg.norm(un) * un + np.pi * cdt * np.linalg.norm(ut) * ut) / 2
    drag = sc.MorisonDrag(cable, rho, d, cdn, cdt)
    assert np.allclose(drag.line_force(a, u), morison, rtol=1e-14, atol=0)
    stretched = sc.MorisonDrag(cable, rho, d, cdn, cdt, deformed_length=True)
    assert np.allclose(stretched.line_force(a, u), np.linalg.norm(a) * morison, rtol=1e-14)
    vr = -u  # the tether's velocity relative to the atmosphere
    fm = -2.2 * 3e-11 * 1e-3 * np.linalg.norm(np.cross(vr, t)) * vr / 2
    molecular = sc.FreeMolecularDrag(cable, 3e-11, 1e-3)
    assert np.allclose(molecular.line_force(a, u), fm, rtol=1e-14, atol=0)


def resultant_and_moment(system, cable, f):
    """Force resultant and moment about the origin of a generalized force on a cable:
    ``sum_i f_r,i`` and ``sum_i (r_i x f_r,i + r_x,i x f_rx,i)``, which equal ``int f dx``
    and ``int r x f dx`` (rigid translations and rotations are exact virtual motions)."""
    fc = f[system.dofs(cable)].reshape(-1, 2, 3)
    qc = cable.q0.reshape(-1, 2, 3)
    return fc[:, 0].sum(axis=0), np.cross(qc, fc).sum(axis=(0, 1))


def test_free_molecular_straight_tether_closed_form():
    """A straight radial tether from ``R1`` to ``R2`` turning rigidly at ``Omega`` in an
    atmosphere co-rotating at ``omega``: ``v_r = (Omega - omega) r`` across the tether, so
    ``F = -C_D rho d (Omega - omega)|Omega - omega| (R2^3 - R1^3) / 6`` along the motion and
    the moment ``-C_D rho d (Omega - omega)|Omega - omega| (R2^4 - R1^4) / 8`` (1e-12); a
    tether at ``theta`` to a uniform flow ``U``: ``F = C_D rho d L |U| sin(theta) U / 2``."""
    R1, R2, Om, om, rho, d, cd = 6.7e6, 6.72e6, 1.2e-3, 7.29e-5, 3e-11, 1e-3, 2.2
    tether = sc.Cable.straight([R1, 0, 0], [R2, 0, 0], 4, SECTION)
    system = sc.System([tether]).add_load(
        sc.FreeMolecularDrag(tether, rho, d, cd, omega=[0, 0, om]))
    spin = system.rigid_motion_velocity(tether.q0, [0, 0, Om])
    F, M = resultant_and_moment(system, tether, external_force(system, tether.q0, spin))
    k = -cd * rho * d * (Om - om) * abs(Om - om)
    assert F == pytest.approx([0, k * (R2**3 - R1**3) / 6, 0], rel=1e-12, abs=1e-12 * abs(F[1]))
    assert M == pytest.approx([0, 0, k * (R2**4 - R1**4) / 8], rel=1e-12, abs=1e-12 * abs(M[2]))
    theta, U, L = 0.4, np.array([-7.6e3, 0, 0]), 500.0
    tilted = sc.Cable.straight([0, 0, 0], [L * np.cos(theta), L * np.sin(theta), 0], 3, SECTION)
    system = sc.System([tilted]).add_load(sc.FreeMolecularDrag(tilted, rho, d, cd, velocity=U))
    F, _ = resultant_and_moment(system, tilted, external_force(system, tilted.q0, None))
    assert F == pytest.approx(cd * rho * d * L * 7.6e3 * np.sin(theta) * U / 2, rel=1e-12,
                              abs=1e-12 * np.abs(F).max())


def test_time_dependent_currents_are_refreshed():
    """``current(t)`` and a ramped ``CurrentProfile`` at ``t = 2`` give the force of the
    steady current they equal at that time (``Term.prepare``)."""
    cable = sc.Cable.straight([0, 0, -3], [4, 0, -1], 3, SECTION)

    def force(current, t):
        load = sc.MorisonDrag(cable, 1000.0, 0.02, 1.1, 0.2, current=current)
        return external_force(sc.System([cable]).add_load(load), cable.q0, None, t)

    steady = force([0.3, 0.8, 0.0], 0.0)
    assert np.array_equal(force(lambda t: [0.15 * t, 0.4 * t, 0.0], 2.0), steady)
    ramped = sc.CurrentProfile([-2.0], [[0.1, 0.4, 0.0]], ramp=lambda t: t)
    assert np.allclose(force(ramped, 2.0), force([0.2, 0.8, 0.0], 0.0), rtol=1e-14)
    sheared = sc.CurrentProfile([-3.0, -1.0], [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    assert sheared.velocity([0, 0, -2.5]).tolist() == [0.25, 0.0, 0.0]


def test_buoyancy_is_the_displaced_weight():
    cable = sc.Cable.straight([0, 0, 0], [3.0, 0, 0], 3, SECTION)
    dofs, f = sc.Buoyancy(cable, 1025.0, 0.05, [0, 0, -9.81]).bind(sc.System([cable])).force
    total = f[cable.position_mask].reshape(-1, 3).sum(axis=0)
    assert total == pytest.approx([0, 0, 1025.0 * np.pi * 0.05**2 / 4 * 9.81 * 3.0], rel=1e-13)


def test_added_mass_term_is_the_scaled_consistent_mass():
    """``C_a rho pi d^2 / 4`` per unit length: the term's mass is the cable's consistent
    mass scaled by it over ``rho A``; its translational total is ``m_a L`` per axis."""
    cable = sc.Cable.straight([0, 0, 0], [3.0, 0, 0], 3, SECTION)
    rows, cols, values = sc.MorisonDrag(cable, 1025.0, 0.05, 1.2, 0.0,
                                        added_mass=1.0).added_mass(sc.System([cable]))
    M = np.zeros((cable.n_dofs, cable.n_dofs))
    np.add.at(M, (rows, cols), values)
    u = np.tile([1.0, 0, 0, 0, 0, 0], cable.n_nodes)  # a unit translation along x
    assert u @ M @ u == pytest.approx(1025.0 * np.pi * 0.05**2 / 4 * 3.0, rel=1e-13)


def test_added_mass_enters_the_integrator_mass_not_the_weight():
    """The integrator's mass is the line's plus ``C_a rho pi d^2 / 4`` per metre; gravity
    weighs the line only."""
    cable = sc.Cable.straight([0, 0, 0], [3.0, 0, 0], 3, SECTION)
    system = sc.System([cable]).add_load(sc.MorisonDrag(cable, 1025.0, 0.05, 1.2, 0.0,
                                                        added_mass=1.0))
    system.add_gravity([0, 0, -10.0])
    u = np.tile([1.0, 0, 0, 0, 0, 0], cable.n_nodes)
    line = SECTION.mass_per_length * 3.0
    assert u @ (system.layout.mass.scipy @ u) == pytest.approx(
        line + 1025.0 * np.pi * 0.05**2 / 4 * 3.0, rel=1e-12)
    assert system.layout.f_const[2::6].sum() == pytest.approx(-10.0 * line, rel=1e-12)


def test_settled_line_matches_the_equilibrium_equations(demo):
    """20 elements against ``solve_bvp`` (1e-8) of the extensible cable's equilibrium in
    the current: end tensions, sag and midpoint to 2e-5 (measured: 1.5e-6, 1.2e-6,
    1.3e-5, 4.1e-7, 9.9e-6).  The reference at the residual 1e-8 (580 nodes) is that of
    the demo's 1e-10 (2430 nodes, 15 times the CPU) to 4e-12."""
    reference, _ = demo.equilibrium(tol=1e-8)
    state, cable = demo.settled(20)
    ours = demo.numbers(state, cable)
    for key, value in reference.items():
        assert ours[key] == pytest.approx(value, rel=2e-5), key
    assert ours["tension_a"] > ours["tension_b"]  # the upstream end carries the drag


def test_demo_transient_settles_on_the_static_shape(demo):
    """The current switched on at rest in still water: after 30 s the drag has damped
    the motion onto the static state (upstream tension to 1e-4), on the compiled path."""
    out = demo.main(n_elements=8, t_end=30.0, dt=0.2)
    assert out["transient_tension_a"] == pytest.approx(out["tension_a"], rel=1e-4)
    assert out["path"] == "compiled"


def test_scene_file_mooring_line(demo):
    """``demos/mooring_line.toml`` (static) gives the demo's settled line to 1e-6."""
    spec = scene_file.load(ROOT / "demos" / "mooring_line.toml")
    state = sc.solve_static(spec.system)
    cable = spec.system.bodies[0]
    ref_state, ref_cable = demo.settled(cable.n_elements)
    ours, ref = demo.numbers(state, cable), demo.numbers(ref_state, ref_cable)
    for key in ("tension_a", "tension_b", "sag"):
        assert ours[key] == pytest.approx(ref[key], rel=1e-6), key


def test_scene_file_free_molecular_and_profile(tmp_path):
    """``[[loads.free_molecular]]`` and a ``current_profile`` give the loads built in
    Python (same force, 1e-14); a profile that is not increasing is named."""
    head = """
[sections.s]
E = 1e11
rho = 1500.0
radius = 5e-4
[[cables]]
name = "t"
section = "s"
start = [0, 0, -2]
end = [3, 1, 0]
elements = 2
[solver]
analysis = "static"
[loads]
"""
    body = """
[[loads.free_molecular]]
cable = "t"
density = 2e-11
diameter = 1e-3
velocity = [-7.5e3, 100.0, 0]
omega = [0, 0, 7.29e-5]
[[loads.morison]]
cable = "t"
rho = 1025.0
diameter = 0.05
cd_normal = 1.2
cd_tangential = 0.1
current_profile = { elevations = [-2.0, 0.0], velocities = [[0.2, 0, 0], [1.0, 0.5, 0]] }
"""
    spec = scene_file.loads_text(head + body, "drag.toml")
    cable = spec.system.bodies[0]
    profile = sc.CurrentProfile([-2.0, 0.0], [[0.2, 0, 0], [1.0, 0.5, 0]])
    python = sc.System([cable]).add_load(sc.FreeMolecularDrag(
        cable, 2e-11, 1e-3, velocity=[-7.5e3, 100.0, 0], omega=[0, 0, 7.29e-5]))
    python.add_load(sc.MorisonDrag(cable, 1025.0, 0.05, 1.2, 0.1, current=profile))
    v = np.full(cable.n_dofs, 0.3)
    assert np.allclose(external_force(spec.system, cable.q0, v),
                       external_force(python, cable.q0, v), rtol=1e-14, atol=0)
    bad = body.replace("[-2.0, 0.0]", "[0.0, -2.0]")
    with pytest.raises(scene_file.SceneFileError, match="current_profile elevations must be "
                       "finite and strictly increasing"):
        scene_file.loads_text(head + bad, "drag.toml")


def test_switched_on_current_is_refreshed_on_the_compiled_step(demo):
    """A current ``current(t)`` ramped in time: the compiled step (which calls
    ``Term.prepare`` once per step) and the Python step give the same run (1e-12)."""
    system, cable = demo.build(4, current=lambda t: [min(t, 1.0), 0.0, 0.2 * t])
    runs = [sc.simulate(system, t_end=1.0, dt=0.1, compiled=c) for c in (True, False)]
    assert runs[0].stats["path"] == "compiled"
    assert np.allclose(runs[0].q, runs[1].q, rtol=0, atol=1e-12 * demo.LINE["length"])
    assert np.abs(runs[0].q[-1] - runs[0].q[0]).max() > 1e-2  # the current moved the line


def test_moordyn_agrees_within_one_percent(demo):
    """MoorDyn 2.7 (40 segments): settled end tensions and sag within 1 % of ours
    (measured 1e-4, 4e-5, 3.5e-4), and the transient midpoint within 3 % of its
    displacement (1.2e-2)."""
    md = pytest.importorskip("moordyn")
    bench = load(ROOT / "benchmarks" / "mooring_moordyn.py")
    _, history, final, _, _ = bench.moordyn_run(md, 40, 30.0)
    state, cable = demo.settled(20)
    ours = demo.numbers(state, cable)
    for key in ("tension_a", "tension_b", "sag"):
        assert final[key] == pytest.approx(ours[key], rel=1e-2), key
    _, our_history, _, _, _ = bench.ours_run(20, 30.0)
    assert bench.transient_difference(our_history, history)["midpoint"] < 3e-2


def test_docstring_examples_run():
    from skfem_cable.loads import drag

    result = doctest.testmod(drag, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0 and result.failed == 0


@pytest.mark.parametrize("make, match", [
    (lambda c: sc.MorisonDrag(c, -1.0, 0.05, 1.2, 0.1), "rho must be finite and > 0"),
    (lambda c: sc.MorisonDrag(c, 1025.0, 0.0, 1.2, 0.1), "diameter must be finite and > 0"),
    (lambda c: sc.MorisonDrag(c, 1025.0, 0.05, -1.2, 0.1), "cd_normal must be finite and >= 0"),
    (lambda c: sc.MorisonDrag(c, 1025.0, 0.05, 1.2, 0.1, added_mass=-1),
     "added_mass must be finite and >= 0"),
    (lambda c: sc.MorisonDrag(c, 1025.0, 0.05, 1.2, 0.1, current=[1.0, 0]),
     "current must be a finite 3-vector"),
    (lambda c: sc.MorisonDrag(c, 1025.0, 0.05, 1.2, 0.1, current=lambda t: [np.nan, 0, 0]),
     r"current\(0.0\) must be a finite 3-vector"),
    (lambda c: sc.MorisonDrag(c, 1025.0, 0.05, 1.2, 0.1, deformed_length=1),
     "deformed_length must be True or False"),
    (lambda c: sc.CurrentProfile([0.0, -1.0], [[1, 0, 0], [0, 0, 0]]),
     "elevations must be finite and strictly increasing"),
    (lambda c: sc.CurrentProfile([0.0], [[1, 0]]), r"velocities must be a finite \(1, 3\)"),
    (lambda c: sc.CurrentProfile([0.0], [[1, 0, 0]], vertical=[0, 0, 2]),
     "vertical must be a unit vector"),
    (lambda c: sc.FreeMolecularDrag(c, 0.0, 1e-3), "density must be finite and > 0"),
    (lambda c: sc.FreeMolecularDrag(c, 1e-11, 1e-3, omega=[0, 0]),
     "omega must be a finite 3-vector"),
])
def test_bad_input_names_the_parameter(make, match):
    cable = sc.Cable.straight([0, 0, 0], [1.0, 0, 0], 1, SECTION)
    with pytest.raises((ValueError, TypeError), match=match):
        make(cable)
