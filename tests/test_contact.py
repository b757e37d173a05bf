"""Contact of cables with surfaces, with friction (issue 49; ``docs/contact.md``): the
compiled point function's tangents, the capstan, the Atwood machine with a massive rope,
and what is not built yet.

The capstan rig (issue 49, "Must show" 1) is the ``capstan`` scene's
(``skfem_cable.scenes.capstan``; its docstring: why the rope slides, and how the tensions
are read), which ``demos/capstan.py`` draws.
"""

import numpy as np
import pytest
from atwood import assert_follows_the_closed_form, atwood

import skfem_cable as sc
from skfem_cable.loads.contact import ContactToleranceWarning
from skfem_cable.loads.surface_broad_phase import ContactDampingWarning
from skfem_cable.scenes.capstan import (
    DRUM,
    LEG,
    ROPE,
    T1,
    R,
    V,
    capstan,
    leg_tensions,
    wrapped,
)


def test_tangents_against_central_differences():
    """The contact's tangent in q and v (penalty, damping, friction) on a cylinder, a
    sphere and a plane, at a perturbed state in contact (6 to 9 of 10 elements
    touching): relative error below 1e-6 (measured: 7e-11 in q, 2e-9 in v)."""
    cable = wrapped(R + 5e-3, LEG, 6, 2)
    rng = np.random.default_rng(1)
    inward = np.tile([0.003, 0.003, 0.0, 0.0, 0.0, 0.0], cable.n_dofs // 6)
    q = cable.q0 + 2e-3 * rng.standard_normal(cable.n_dofs) - inward
    v = 0.02 * rng.standard_normal(cable.n_dofs)
    for surface in (DRUM, sc.Sphere([0, 0.1, 0], R), sc.Plane([0, 0.45, 0], [0.1, 1, 0.05])):
        with pytest.warns(ContactDampingWarning, match="critical"):  # a small damping, named
            system = sc.System([cable]).contact(surface, cable, friction=0.3, damping=50.0,
                                                stiffness=1e6, slip_velocity=0.01)
        parts = [p for p in sc.check_tangent(system, q, v).parts if p.name.startswith("contact")]
        assert {p.wrt for p in parts} == {"q", "v"}
        assert max(p.error for p in parts) < 1e-6, surface


def test_capstan_slides_at_exp_mu_theta():
    """mu = 0.3, wrap pi: T2 / T1 = exp(mu pi) within 1 % in steady sliding, and the
    tension along the arc follows T1 exp(mu phi) within 1 % (phi from where the rope
    meets the drum on the T1 side, read from the points' positions); the run is on the
    compiled step, and the friction's work is booked as dissipation: over the steady
    0.1 s, the books' dissipation is the integral of the friction power (trapezoidal,
    every other step) within 1e-3, and its mean is (T2 - T1) V within 1 %."""
    mu = 0.3
    system, cable, contact = capstan(mu)
    result = sc.simulate(system, t_end=0.35, dt=1e-3, every=2)
    assert result.stats["path"] == "compiled"
    left, right = leg_tensions(result, cable, since=0.25)
    assert right / left == pytest.approx(np.exp(mu * np.pi), rel=1e-2)
    state = result.state(-1)
    s = np.linspace(LEG + 0.2, cable.length - LEG - 0.2, 9)
    x = cable.interpolate(state.q[system.dofs(cable)], s)[0]
    phi = np.arctan2(x[:, 1], -x[:, 0])
    assert state.tension(cable, s) == pytest.approx(left * np.exp(mu * phi), rel=1e-2)
    steady = result.t >= 0.25 - 1e-9
    power = [-contact.forces(result.state(i))["friction_power"] for i in np.flatnonzero(steady)]
    work = np.trapezoid(power, result.t[steady])
    booked = np.ptp(result.energy["dissipated"][steady])
    assert booked == pytest.approx(work, rel=1e-3)          # the books hold the friction
    assert work / 0.1 == pytest.approx((right - left) * V, rel=1e-2)


def test_capstan_without_friction_has_one_tension():
    """mu = 0: the tension is the same on both legs within 1e-4 at rest (the rope held
    by T1 and the pin, settled), and within 1e-3 while it slides; the drum's normal
    forces on the elements, as ParaView shows them, add up to ``pi T1`` within 1e-3."""
    system, cable, contact = capstan(0.0)
    sliding = sc.simulate(system, t_end=0.3, dt=1e-3, every=10)
    left, right = leg_tensions(sliding, cable, since=0.2)
    assert right == pytest.approx(left, rel=1e-3)
    held, _, contact = capstan(0.0, speed=0.0, cable=cable)
    settled = sc.solve_static(held, initial=sliding.state(-1))
    left, right = (settled.tension(cable, s) for s in (LEG / 2, cable.length - LEG / 2))
    assert right == pytest.approx(left, rel=1e-4)
    assert left == pytest.approx(T1, rel=1e-4)
    assert contact.forces(settled)["max_penetration"] < 1e-2 * 2 * 5e-3   # tolerance d
    mesh = sc.export.system_mesh(held, settled.q)       # what ParaView shows
    normal = mesh.point_data["contact_normal"]
    assert np.nansum(normal) == pytest.approx(np.pi * T1, rel=1e-3)   # int T / R ds
    assert np.isfinite(mesh.point_data["contact_force"][np.isfinite(normal)]).all()


def test_atwood_machine_with_a_massive_rope():
    """Masses m1 = 1.1 kg and m2 = 1 kg on a rope of 0.1 kg/m over a frictionless drum
    (legs of 1 m, g = 9.81): the descent ``x`` of m1 follows ``M x'' = g (m1 - m2) +
    rho A g (l1 - l2)``, ``l1 - l2 = 2 x`` (the overhang moves to m1's side; the
    rope on the half circle weighs on the drum, not on the motion), ``M = m1 + m2 +
    rho A L``: ``x = a0 / w^2 (cosh w t - 1)``, ``a0 = g (m1 - m2) / M``, ``w^2 = 2 rho A
    g / M``; within 1 % over 0.2 .. 1 s (and the speed at 1 s), counted from 0.1 s: the
    elastic rope (EA = 1e5 N) first stretches under the weights by about 2e-4 m, which
    the inextensible equation does not know (its bounce on the rope's stretch, at 50 Hz,
    damped by the rope's ``gamma_axial = 5e-3`` s)."""
    system, cable = atwood(E=1.27e9)   # EA = 1e5 N
    result = sc.simulate(system, t_end=1.0, dt=2e-3, every=10)
    assert_follows_the_closed_form(system, cable, result)


def test_what_is_not_built_yet_says_so():
    """Two surfaces and a thing that is neither a line nor a surface are refused, naming
    the parameter (line-to-line and self-contact: ``tests/test_contact_lines.py``)."""
    a, b = (sc.Cable.straight([0, 0, z], [1, 0, z], 2, ROPE) for z in (0.0, 0.1))
    system = sc.System([a, b])
    with pytest.raises(ValueError, match="two surfaces"):
        system.contact(DRUM, sc.Plane([0, 0, 0], [0, 1, 0]))
    with pytest.raises(TypeError, match="second must be a line body"):
        system.contact(a, "ground")
    with pytest.raises(ValueError, match="friction must be finite and >= 0"):
        system.contact(a, DRUM, friction=-0.1)


def test_a_cable_dropped_on_the_ground_comes_to_rest_without_tension():
    """A cable (with bending) dropped tilted (2 .. 10 cm) onto a plane with mu = 0.3, at
    rho_inf = 0 (an impact on the penalty: module docstring of ``loads.contact``): after
    1 s it is at rest, carries no tension (below 1e-6 of its weight), the ground carries
    its weight within 1 %, and it penetrates less than the stated tolerance d, also in
    the impact (``contact.watch()``, every 10 steps)."""
    w, length = 9.81 * ROPE.mass_per_length, 2.0
    cable = sc.Cable.straight([0, 0.025, 0], [length, 0.105, 0], 10, ROPE)
    ground = sc.Plane([0, 0, 0], [0, 1, 0])
    system = sc.System([cable]).add_gravity([0, -9.81, 0]).contact(cable, ground, 0.3)
    watch = system.loads[-1].watch()
    result = sc.simulate(system, t_end=1.0, dt=1e-3, every=10, rho_inf=0.0,
                         observers=[watch])
    assert max(row[1] for row in watch.history) < 1e-2 * 2 * 5e-3    # impact included
    state = result.state(-1)
    assert np.abs(state.v).max() < 1e-6
    s = np.linspace(0, length, 21)
    assert np.abs(state.tension(cable, s)).max() < 1e-6 * w * length
    forces = system.loads[-1].forces(state)
    assert forces["normal"].sum() == pytest.approx(w * length, rel=1e-2)
    assert forces["max_penetration"] < 1e-2 * 2 * 5e-3


def test_a_penetration_beyond_the_tolerance_is_reported():
    """A soft penalty (1e3 N/m^2) under a rope's weight (1 N/m) penetrates 1e-3 m, ten
    times the stated tolerance d: ``forces`` warns, naming the numbers."""
    cable = sc.Cable.straight([0, 4e-3, 0], [1, 4e-3, 0], 2, ROPE)
    system = sc.System([cable]).contact(cable, sc.Plane([0, 0, 0], [0, 1, 0]),
                                        stiffness=1e3)
    with pytest.warns(ContactToleranceWarning, match="penetration 0.001 m exceeds"):
        system.loads[-1].forces(sc.State(system, cable.q0))


SCENE = """
[solver]
t_end = 1.0
dt = 1e-3
rho_inf = 0.0
[sections.rope]
radius = 5e-3
E = 1.27e9
rho = 1273.0
[[cables]]
name = "rope"
section = "rope"
start = [0, 0.025, 0]
end = [2, 0.105, 0]
elements = 10
[loads]
gravity = [0, -9.81, 0]
[[contacts]]
cable = "rope"
plane = { point = [0, 0, 0], normal = [0, 1, 0] }
friction = 0.3
"""


def test_a_scene_file_reads_its_contacts():
    """``[[contacts]]``: the rope of a scene file lands on the plane it names (the ground
    carries its weight within 1 % after 1 s); a table with two surfaces, or none, is
    refused, naming the keys."""
    spec = sc.scene_file.loads_text(SCENE)
    contact = spec.system.loads[-1]
    assert (contact.friction, contact.surface.direction.tolist()) == (0.3, [0, 1, 0])
    result = sc.simulate(spec.system, **spec.solver)
    weight = 9.81 * spec.system.bodies[0].section.mass_per_length * 2.0
    assert contact.forces(result.state(-1))["normal"].sum() == pytest.approx(weight, rel=1e-2)
    two = SCENE + "sphere = { centre = [0, 0, 0], radius = 1.0 }\n"
    with pytest.raises(sc.scene_file.SceneFileError, match="exactly one surface"):
        sc.scene_file.loads_text(two)
