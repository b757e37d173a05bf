"""Surfaces carried by a rigid body (issue 49: ``body.cylinder``, ``body.sphere``,
``body.plane``; ``loads.contact_body``, ``docs/contact.md``): the exact tangent over the
line's and the body's coordinates, the reaction on the body, a pulley with inertia driven
by friction (the Atwood machine), a rising plate lifting a rope, the forces per element
in the run store and ParaView, and scene files.

Each scene is built once (module fixtures): two compiled steps, the drum and the plate.
"""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.constraints.linear import LinearConstraint
from skfem_cable.constraints.prescribed import Motion
from skfem_cable.core.contract import Evaluation
from skfem_cable.core.lines import line_points
from skfem_cable.kernels import contact as kernel
from skfem_cable.loads.contact import ContactToleranceWarning
from skfem_cable.loads.surface_broad_phase import ContactDampingWarning
from skfem_cable.scenes.capstan import LEG, ROPE, R, wrapped

G, M1, M2 = 9.81, 1.1, 1.0
#: Body x along world z: a drum's axis, a plate's normal.
UP = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]).T
H = 0.1          # the drum's and the plate's height (m)
RC = 5e-3        # the rope's radius (m)


def held(body, coordinates, target, name):
    """The linear constraint holding the body's ``coordinates`` (indices into its 12) on
    ``target`` (a vector or a ``Motion``)."""
    return LinearConstraint(lambda s: s.dofs(body)[coordinates], np.eye(len(coordinates)),
                            target, name, [f"{name}{k}" for k in coordinates])


@pytest.fixture(scope="module")
def rigs():
    """A rope over a free drum, contact with its cylinder, a sphere and a plane that it
    carries, at perturbed states (the drum's coordinates too) in contact, with
    velocities: ``[(system, q, v)]``."""
    cable = wrapped(R + RC, LEG, 6, 2)
    drum = sc.RigidBody.cylinder(R, H, 500.0, rotation=UP, name="drum")
    rng = np.random.default_rng(1)
    inward = np.tile([0.003, 0.003, 0.0, 0.0, 0.0, 0.0], cable.n_dofs // 6)
    out = []
    for surface in (drum.cylinder([0, 0, 0], [1, 0, 0], R), drum.sphere([0, 0.1, 0], R),
                    drum.plane([0.0, 0.45, 0], [0.05, 1, 0.1])):
        with pytest.warns(ContactDampingWarning, match="critical"):  # a small damping
            system = sc.System([cable, drum]).contact(cable, surface, friction=0.3,
                                                      damping=50.0, stiffness=1e6,
                                                      slip_velocity=0.01)
        q = system.q0.copy()
        q[system.dofs(cable)] += 2e-3 * rng.standard_normal(cable.n_dofs) - inward
        q[system.dofs(drum)] += 1e-3 * rng.standard_normal(12)
        out.append((system, q, 0.02 * rng.standard_normal(system.n_dofs)))
    return out


def test_the_tangent_couples_the_line_and_the_body_exactly(rigs):
    """``sc.check_tangent`` over the line's and the body's coordinates (penalty, damping
    and friction; off the rigid manifold too): relative error below 1e-6 in q and v
    (measured: 3e-9 and 9e-10 on the cylinder, 8e-11 and 2e-9 on the plane), with 6
    to 9 of 10 elements touching."""
    for system, q, v in rigs:
        contact = system.loads[-1]
        with pytest.warns(ContactToleranceWarning):   # deep, for a general check
            touching = np.count_nonzero(contact.resolve(system, q, v)["normal"] > 0)
        assert 6 <= touching < 10
        parts = [p for p in sc.check_tangent(system, q, v).parts
                 if p.name.startswith("contact")]
        assert {p.wrt for p in parts} == {"q", "v"}
        assert max(p.error for p in parts) < 1e-6, contact.surface


def test_the_body_takes_the_opposite_force_and_moment(rigs):
    """The contact's generalized forces on the line and on the body, projected on the
    rigid motions of the system (``System.rigid_motion_velocity``: the resultant and the
    moment about the origin), are equal and opposite within 1e-9 of the line's, with
    friction and damping on; the line's resultant is the elements' forces of
    ``resolve`` (normal times the surface's normal plus tangential) within 1e-9."""
    for system, q, v in rigs:
        contact = system.loads[-1]
        term = contact.bind(system)
        ev = Evaluation(system, 0.0, q, v, np.zeros(system.n_constraints))
        for function, pack in term.kernels:
            function(pack, np.zeros((0, 0, 0), dtype=np.int64), ev.packed())
        force = -ev.f                                   # the contact's applied forces
        line, body = (system.dofs(b) for b in system.bodies)
        modes = [system.rigid_motion_velocity(q, np.zeros(3), velocity=e) for e in np.eye(3)]
        modes += [system.rigid_motion_velocity(q, e) for e in np.eye(3)]
        on_line = np.array([force[line] @ m[line] for m in modes])
        on_body = np.array([force[body] @ m[body] for m in modes])
        assert np.abs(on_line + on_body).max() < 1e-9 * np.abs(on_line).max()
        with pytest.warns(ContactToleranceWarning):
            out = contact.resolve(system, q, v)
        normals = contact.surface.surface_array(q[body])[4:7]
        if contact.surface.kind == kernel.PLANE:          # one normal
            resultant = out["normal"].sum() * normals + out["tangential"].sum(axis=0)
            np.testing.assert_allclose(on_line[:3], resultant, rtol=1e-9,
                                       atol=1e-9 * np.abs(resultant).max())


@pytest.fixture(scope="module")
def atwood(tmp_path_factory):
    """Masses m1 = 1.1 kg and m2 = 1 kg on legs of 1 m of the capstan's rope (radius 5
    mm, 0.1 kg/m, damped by ``gamma_axial = 5e-3`` s) over a drum of R = 0.5 m, 2 kg
    (``J = 0.25 kg m^2``) turning freely on its axis (z, through the origin: base point
    A held, B held across the axis), with friction ``mu = 0.5``; 1 s at dt = 2e-3 s, saved
    every 10 ms into a run store: ``(system, cable, drum, result, store)``."""
    rope = sc.Section.circular(RC, 1.27e9, 1273.0, gamma_axial=5e-3)
    cable = wrapped(R + RC + 1e-5, 1.0, 16, 8, section=rope)
    drum = sc.RigidBody.cylinder(R, H, 2.0 / (np.pi * R**2 * H), rotation=UP, name="drum")
    bearing = [0, 1, 2, 3, 4]
    system = (sc.System([cable, drum]).add_gravity([0, -G, 0])
              .add_point_mass(cable.node(0), M1).add_point_mass(cable.node(-1), M2)
              .add_constraint(held(drum, bearing, drum.q0[bearing], "bearing"))
              .contact(cable, drum.cylinder([0, 0, 0], [1, 0, 0], R), friction=0.5))
    store = tmp_path_factory.mktemp("atwood") / "run"
    result = sc.simulate(system, t_end=1.0, dt=2e-3, every=5,
                         observers=[sc.io.RunStore(store)])
    return system, cable, drum, result, store


def test_atwood_machine_with_a_pulley_of_inertia(atwood):
    """The drum turns with the rope by friction alone.  With the descent ``x`` of m1, the
    rope (length L, all of it at speed ``x'``) turning the drum at ``x' / R_e`` (``R_e =
    R + r_c``: the rope's axis, where the contact measures the slip), Lagrange's equation
    of ``T = (M + J / R_e^2) x'^2 / 2`` and ``V = -g (m1 - m2) x - rho A g x^2`` (the
    overhang moves to m1's side, ``l1 - l2 = 2 x``) is

        (M + J / R_e^2) x'' = g (m1 - m2) + 2 rho A g x,   M = m1 + m2 + rho A L,

    so ``x = a0 / w^2 (cosh w t - 1)``, ``a0 = g (m1 - m2) / M_J``, ``w^2 = 2 rho A g /
    M_J``, ``M_J = M + J / R_e^2``.  m1's descent over 0.2 .. 1 s (from 0.1 s, after the
    rope's first stretch) within 1 % (measured 4.9e-3); without the drum's inertia it
    would be 43 % off.  The regularised friction lets the rope creep over the drum at
    ``v_s = eps r / sqrt(1 - r^2)``, ``r = sum |f_t| / (mu sum N)``, for a uniform slip
    (2.3e-5 m/s at 1 s).  The slip at 1 s (the velocities of the rope's points on the
    arc relative to the drum's, along the drum) has a mean that matches it within 15 %
    (the slip varies along the arc, from -5e-5 m/s where the rope comes onto the drum to
    4e-5 m/s where it leaves), and it is below 1e-3 of ``x'`` (0.31 m/s) everywhere: the
    rope does not slip.  The
    books close within 1e-4 of m1's loss of potential energy (measured 2.2e-5; friction
    and the rope's damping booked as dissipation)."""
    system, cable, drum, result, _ = atwood
    assert result.stats["path"] == "compiled"
    rho_a, J, Re = ROPE.mass_per_length, drum.inertia[0, 0], R + RC
    M = M1 + M2 + rho_a * cable.length + J / Re**2
    a0, w = G * (M1 - M2) / M, np.sqrt(2 * rho_a * G / M)
    t = result.t
    y = result.q[:, system.dofs(cable.node(0))[1]]
    exact = a0 / w**2 * (np.cosh(w * t) - 1)
    start, late = np.searchsorted(t, 0.1 - 1e-9), t >= 0.2 - 1e-9
    assert y[start] - y[late] == pytest.approx(exact[late] - exact[start], rel=1e-2)
    state, contact = result.state(-1), system.loads[-1]
    speed = -state.v[system.dofs(cable.node(0))[1]]
    X, _, V = line_points(cable, system).at(state.q, state.v)
    _, relative = contact.seen(system, state.q, state.v, X.reshape(-1, 3), V.reshape(-1, 3))
    along = np.stack([-X[..., 1], X[..., 0], 0 * X[..., 0]], -1) / np.hypot(X[..., 0],
                                                                         X[..., 1])[..., None]
    slips = np.einsum("egi,egi->eg", relative.reshape(X.shape), along)[X[..., 1] > 0]
    out = contact.forces(state)
    r = np.linalg.norm(out["tangential"], axis=1).sum() / (0.5 * out["normal"].sum())
    assert slips.mean() == pytest.approx(1e-3 * r / np.sqrt(1 - r * r), rel=0.15)
    assert np.abs(slips).max() < 1e-3 * speed
    loss = M1 * G * (y[0] - y[-1])
    assert abs(result.energy["balance"][-1]) < 1e-4 * loss


def test_the_run_store_holds_the_forces_per_element(atwood):
    """The contact's normal (ne,) and tangential (ne, 3) forces per element at every saved
    step (``step_arrays``: ``<name>_element_normal``, ``<name>_element_tangential``):
    recorded equal to ``forces`` of the saved states within 1e-9, adding up to the
    recorded totals, read back from the Zarr store unchanged; ParaView's arrays
    ``contact_normal`` and ``contact_tangential`` of a saved state are the same."""
    system, cable, _, result, store = atwood
    contact = system.loads[-1]
    normal, tangential = (result.outputs[f"{contact.name}_{key}"]
                          for key in ("element_normal", "element_tangential"))
    ne = cable.n_elements
    assert normal.shape == (len(result.t), ne) and tangential.shape == (len(result.t), ne, 3)
    for i in (0, len(result.t) // 2, -1):
        out = contact.forces(result.state(i))
        np.testing.assert_allclose(normal[i], out["normal"], rtol=1e-9,
                                   atol=1e-9 * np.abs(out["normal"]).max())
        np.testing.assert_allclose(tangential[i], out["tangential"], rtol=1e-9,
                                   atol=1e-9 * np.abs(out["tangential"]).max())
    np.testing.assert_allclose(normal.sum(axis=1), result.outputs[f"{contact.name}_normal"],
                               rtol=1e-12)
    stored = sc.Result.load(store, system).outputs
    for name, values in result.outputs.items():
        np.testing.assert_array_equal(stored[name], values, err_msg=name)
    state = result.state(-1)
    mesh = sc.export.system_mesh(system, state.q, state.v)
    shown = np.isfinite(mesh.point_data["contact_normal"])
    np.testing.assert_allclose(mesh.point_data["contact_normal"][shown], normal[-1])
    np.testing.assert_allclose(mesh.point_data["contact_tangential"][shown], tangential[-1])


LIFT, RISE = 0.05, 0.4        # the plate rises 5 cm in 0.4 s


def lift(t, order=0):
    """The plate's height (``order`` 0), speed (1) or acceleration (2) at ``t``: ``LIFT
    (u - sin(2 pi u) / (2 pi))``, ``u = t / RISE`` up to 1 (at rest at both ends)."""
    u = min(t / RISE, 1.0)
    k = 2 * np.pi
    return (LIFT * (u - np.sin(k * u) / k), LIFT / RISE * (1 - np.cos(k * u)),
            LIFT / RISE**2 * k * np.sin(k * u))[order]


@pytest.fixture(scope="module")
def rising():
    """A rope (1 m, 4 elements, the axial law of the drum's rope: the two runs share one
    compiled step) lying on a plate (R = 1 m, the top of a body) that rises
    on a prescribed motion (base point A on ``lift``, B held across the plate's normal
    and C along x: no turn), with gravity and ``mu = 0.3``; 0.6 s at dt = 1e-3 s,
    ``rho_inf = 0`` (the rope lands at the start): ``(system, rope, plate, result)``."""
    plate = sc.RigidBody.cylinder(1.0, H, 100.0, rotation=UP, name="plate")
    rope = sc.Cable.straight([-0.5, 0, H / 2 + RC], [0.5, 0, H / 2 + RC], 4, ROPE,
                             law="truss", name="rope")
    moved = [0, 1, 2, 3, 4, 6]
    up = np.array([0, 0, 1, 0, 0, 0.0])
    start = plate.q0[moved]
    motion = Motion(lambda t: start + lift(t) * up, lambda t: lift(t, 1) * up,
                    lambda t: lift(t, 2) * up, size=6)
    system = (sc.System([rope, plate]).add_gravity([0, 0, -G])
              .add_constraint(held(plate, moved, motion, "lift"))
              .contact(rope, plate.plane([H / 2, 0, 0], [1, 0, 0]), friction=0.3))
    result = sc.simulate(system, t_end=0.6, dt=1e-3, every=20, rho_inf=0.0)
    return system, rope, plate, result


def test_a_rising_plate_lifts_the_rope_on_it(rising):
    """The plate carries its surface: the rope stays on it (its height above the top is
    its radius within the stated tolerance ``1e-2 d``), moves with it (vertical speed
    within 1e-4 m/s of the plate's, which peaks at 0.25 m/s; measured 1e-5 m/s, the
    rate of the penalty's deflection as the push changes), and the plate pushes it with
    ``m (g + z'')`` within 1e-3 at every saved step from 20 ms on (``z''`` the prescribed
    acceleration: the rope's weight and inertia; measured 5e-5).  The books close within 2e-6 of the
    constraint's work (measured 4e-7)."""
    system, rope, _, result = rising
    contact = system.loads[-1]
    mass = ROPE.mass_per_length * rope.length
    tolerance = contact.tolerance * 2 * RC
    for i in range(1, len(result.t)):
        t, state = result.t[i], result.state(i)
        q, v = state.q[system.dofs(rope)], state.v[system.dofs(rope)]
        assert np.abs(q[2::6] - H / 2 - lift(t) - RC).max() < tolerance
        assert np.abs(v[2::6] - lift(t, 1)).max() < 1e-4
        push = contact.forces(state)["normal"].sum()
        assert push == pytest.approx(mass * (G + lift(t, 2)), rel=1e-3)
    work = result.energy["external_work"][-1]
    assert work > 0 and abs(result.energy["balance"][-1]) < 2e-6 * work


SCENE = """
[solver]
t_end = 0.1
dt = 1e-3
[[rigid_bodies]]
name = "drum"
radius = 0.5
height = 0.1
density = 100.0
rotation = [[0, 0, -1], [0, 1, 0], [1, 0, 0]]
[sections.rope]
radius = 5e-3
E = 1.27e9
rho = 1273.0
[[cables]]
name = "rope"
section = "rope"
start = [-1, 0.6, 0]
end = [1, 0.6, 0]
elements = 4
[[contacts]]
cable = "rope"
body = "drum"
cylinder = { axis_point = [0, 0, 0], axis = [1, 0, 0], radius = 0.5 }
friction = 0.2
"""


def test_a_scene_file_puts_a_surface_on_a_named_body():
    """``[[contacts]]`` with ``body = "drum"``: the cylinder is the drum's, in its frame
    (its axis along world z), and couples the drum; an edge on a body is refused, naming
    the key (no compiled step: nothing runs)."""
    spec = sc.scene_file.loads_text(SCENE)
    contact = spec.system.loads[-1]
    drum = next(body for body in spec.system.bodies if body.name == "drum")
    assert contact.body is drum and contact.friction == 0.2
    np.testing.assert_allclose(contact.surface.surface_array(), [2, 0, 0, 0, 0, 0, 1, 0.5],
                               atol=1e-15)
    edge = SCENE.replace("cylinder = { axis_point = [0, 0, 0], axis = [1, 0, 0], radius = "
                         "0.5 }", "edge = { point = [0, 0, 0], normal = [0, 1, 0], outward "
                         "= [1, 0, 0], radius = 0.1 }")
    with pytest.raises(sc.scene_file.SceneFileError, match="body.*not a edge"):
        sc.scene_file.loads_text(edge)
