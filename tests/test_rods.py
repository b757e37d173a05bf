"""The rod (issue 48, docs/rods.md): torsion alone, anisotropy, exact tangents, rigid
tumbling, the loads reaching it as a cable, and the reference frames in checkpoints."""

import dataclasses

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.scenes.classics import ELASTICA_SECTION as ELASTICA

#: A bar stiff in bending and soft in torsion: its lowest modes are torsional.
SHAFT = sc.Section(E=2e11, A=1e-4, I=1e-6, rho=7850.0, G=1e9, J=1e-9, I_edge=1e-6)
TAPE = sc.Section.tape(0.02, 50e-6, E=7e10, rho=2700.0)


def twist_share(system, rod, shape):
    """The part of a mode shape's mass-weighted norm in the rod's twist coordinates."""
    M = system.mass_matrix()
    twist = np.zeros(system.n_dofs, bool)
    twist[system.dofs(rod)[~rod.vector_mask]] = True
    part = np.where(twist, shape, 0.0)
    return (part @ M @ part) / (shape @ M @ shape)


def component_share(system, rod, shape, axis):
    """The part of a mode shape's position coordinates along ``axis``."""
    positions = system.dofs(rod)[rod.position_mask].reshape(-1, 3)
    u = shape[positions]
    return np.sum(u[:, axis] ** 2) / max(np.sum(u**2), 1e-300)


def test_section_tape_and_circular():
    """Saint-Venant J of a thin tape and of a round wire, the principal stiffnesses, the
    polar mass moment and the default G = E / (2 (1 + nu))."""
    w, t, E, rho = 0.02, 50e-6, 7e10, 2700.0
    assert TAPE.GJ == pytest.approx(E / 2.6 * w * t**3 / 3 * (1 - 0.63 * t / w), rel=1e-15)
    assert TAPE.EI_edge / TAPE.EI_flat == pytest.approx((w / t) ** 2, rel=1e-14)
    assert TAPE.polar_mass_moment == pytest.approx(rho * (w * t**3 + t * w**3) / 12, rel=1e-15)
    wire = sc.Section.circular(1e-3, 2e11, 7850.0, G=8e10)
    assert wire.GJ == pytest.approx(8e10 * np.pi * 1e-12 / 2, rel=1e-15)
    assert wire.EI_edge == wire.EI_flat == wire.EI
    soft = sc.Section.circular(1e-3, 2e11, 7850.0, nu=0.25)
    assert soft.GJ == pytest.approx(8e10 * np.pi * 1e-12 / 2, rel=1e-15)
    # the default G follows E when a section is replaced (no stale shear modulus)
    assert dataclasses.replace(soft, E=1e11).GJ == pytest.approx(4e10 * np.pi * 1e-12 / 2,
                                                                  rel=1e-15)
    assert sc.Section.principal_axes == ("normal", "width")
    with pytest.raises(ValueError, match="thickness must be <= width"):
        sc.Section.tape(1e-3, 2e-3, 7e10, 2700.0)
    with pytest.raises(ValueError, match=r"nu must be in \(-1, 0.5\]"):
        sc.Section.circular(1e-3, 2e11, 7850.0, nu=0.7)


def test_torsional_modes_of_a_clamped_free_rod():
    """omega_k = (2k - 1) pi / (2 L) sqrt(GJ / (rho I_p)), k = 1..3, at 16 elements within
    1e-4 (measured 1.4e-11, 9.8e-9, 2.0e-7: the cubic Hermite twist converges as h^6)."""
    L = 1.0
    rod = sc.Rod.straight([0, 0, 0], [L, 0, 0], 16, SHAFT, normal=[0, 0, 1])
    system = sc.System([rod]).clamp(rod.node(0))
    freqs, shapes = sc.modes(system, k=3)
    c = np.sqrt(SHAFT.GJ / SHAFT.polar_mass_moment)
    exact = (2 * np.arange(1, 4) - 1) * np.pi / (2 * L) * c
    assert np.abs(2 * np.pi * freqs / exact - 1).max() < 1e-4
    assert min(twist_share(system, rod, s) for s in shapes) > 1 - 1e-12


def test_tip_torque_twists_the_tip_by_TL_over_GJ():
    """A tip moment T along the rod twists its tip by T L / GJ, the torque is T all along
    and the material frame is turned by that angle: to round-off (1e-12)."""
    L, T = 1.5, 0.3
    rod = sc.Rod.straight([0, 0, 0], [L, 0, 0], 8, SHAFT, normal=[0, 0, 1])
    system = sc.System([rod]).clamp(rod.node(0)).add_point_moment(rod.node(-1), [T, 0, 0])
    q = sc.solve_static(system).q[system.dofs(rod)]
    angle = T * L / SHAFT.GJ
    assert rod.twist(q, L) == pytest.approx(angle, rel=1e-12)
    assert np.abs(rod.torque(q, np.linspace(0, L, 7)) / T - 1).max() < 1e-12
    d1, d2, t = rod.frame(q, L)
    assert np.allclose(d1, [0, -np.sin(angle), np.cos(angle)], atol=1e-12)
    assert np.allclose(np.cross(t, d1), d2, atol=1e-15)


def test_clamp_twist_free_and_driven():
    """``clamp(node, twist=False)`` leaves the twist free (a rigid twist mode at zero
    frequency), a driven twist follows ``twist(t)`` and turns the whole shaft."""
    rod = sc.Rod.straight([0, 0, 0], [1, 0, 0], 4, SHAFT, normal=[0, 0, 1])
    free = sc.System([rod]).clamp(rod.node(0), twist=False)
    assert [c.name for c in free.constraints] == ["clamp Node(rod, 0)"]
    assert abs(sc.modes(free, k=1)[0][0]) < 1e-3
    driven = sc.System([rod]).clamp(rod.node(0), twist=lambda t: 0.1 * t)
    result = sc.simulate(driven, t_end=0.05, dt=0.01)
    q = result.q[-1][driven.dofs(rod)]
    assert rod.twist(q, 0.0) == pytest.approx(0.005, rel=1e-12)
    with pytest.raises(ValueError, match="twist must be True, False or a callable"):
        sc.System([rod]).clamp(rod.node(0), twist="yes")


def test_tape_bending_frequencies_stand_in_the_stiffness_ratio():
    """A clamped tape: its first bending frequency in the plane of its normal (flatwise)
    and in the plane of its width (edgewise) stand in the ratio sqrt(EI_edge / EI_flat)
    to 1e-6 (measured 1.1e-7)."""
    rod = sc.Rod.straight([0, 0, 0], [1, 0, 0], 16, TAPE, normal=[0, 0, 1])
    system = sc.System([rod]).clamp(rod.node(0))
    freqs, shapes = sc.modes(system, k=2)
    flat = [f for f, s in zip(freqs, shapes) if component_share(system, rod, s, 2) > 0.999]
    ratio = np.sqrt(TAPE.EI_edge / TAPE.EI_flat)
    sigma = (2 * np.pi * flat[0] * ratio) ** 2
    freqs, shapes = sc.modes(system, k=4, sigma=sigma)
    edge = [f for f, s in zip(freqs, shapes) if component_share(system, rod, s, 1) > 0.999]
    assert edge[0] / flat[0] == pytest.approx(ratio, rel=1e-6)


def test_string_modes_of_a_tape_under_tension_are_the_cables():
    """A tape 0.1 % shorter than its span, clamped at one end and pinned at the other: its
    flatwise modes are those of the cable of the same section (EI = EI_flat) to 1e-6."""
    start, end, length = [0, 0, 0], [1, 0, 0], 1 / 1.001
    rod = sc.Rod.between(start, end, length, 16, TAPE, normal=[0, 0, 1])
    cable = sc.Cable.between(start, end, length, 16, TAPE)

    def flatwise(body, k, sigma=None):
        system = sc.System([body]).clamp(body.node(0)).pin(body.node(-1))
        freqs, shapes = sc.modes(system, sc.solve_static(system), k=k, sigma=sigma)
        return [f for f, s in zip(freqs, shapes) if component_share(system, body, s, 2) > 0.999]

    cable_modes = flatwise(cable, 8)[:3]
    assert len(cable_modes) == 3
    for f in cable_modes:  # the rod also has torsional modes between them: look near each
        near = flatwise(rod, 4, (2 * np.pi * f) ** 2)
        assert min(abs(g / f - 1) for g in near) < 1e-6


def element_forces(rod, system, q):
    """The rod kernel alone (not the cable's): its forces, dense tangent and energy."""
    function, pack = rod.bind(system).kernels[-1]
    n = system.n_dofs
    edofs = pack[0]
    index = edofs[:, :, None] * n + edofs[:, None, :]
    f, data, energy = np.zeros(n), np.zeros(n * n), np.zeros(2)
    z = np.zeros(n)
    ev = (q, z, np.array([0.0, 1.0, 0.0, 0.0]), f, z.copy(), z.copy(), data, energy,
          np.zeros(2))
    function(pack, index, ev)
    return f, data.reshape(n, n), energy[1]


def test_rod_tangent_against_central_differences():
    """The rod's own forces are the gradient of its energy and its tangent their
    derivative, against central differences (step 1e-6) at a bent, stretched and twisted
    state with both reference frames away from the tangents: 1e-6 relative (measured
    5e-11, 6e-11); the whole system (cable part, moment with twist) by ``sc.check_tangent``."""
    section = sc.Section(E=1e3, A=1e-4, I=1e-6, rho=1e3, G=2e3, J=3e-6, I_edge=4e-6)
    rod = sc.Rod.straight([0, 0, 0], [1, 0, 0], 3, section, normal=[0, 0.3, 1])
    system = sc.System([rod]).clamp(rod.node(0))
    system.add_point_moment(rod.node(-1), [0.2, 0.1, -0.3])
    rng = np.random.default_rng(4)
    q = system.q0 + 0.1 * rng.standard_normal(system.n_dofs)
    f, K, W = element_forces(rod, system, q)
    step = 1e-6
    fd_f, fd_K = np.zeros_like(f), np.zeros_like(K)
    for j in range(system.n_dofs):
        dq = np.zeros_like(q)
        dq[j] = step
        plus, minus = element_forces(rod, system, q + dq), element_forces(rod, system, q - dq)
        fd_f[j] = (plus[2] - minus[2]) / (2 * step)
        fd_K[:, j] = (plus[0] - minus[0]) / (2 * step)
    assert W > 0
    assert np.abs(f - fd_f).max() < 1e-6 * np.abs(f).max()
    assert np.abs(K - fd_K).max() < 1e-6 * np.abs(K).max()
    assert sc.check_tangent(system, q).error < 1e-6


def tumbling(rod, omega):
    """Coordinates and velocities of ``rod`` turning rigidly at ``omega`` about its centre."""
    q = rod.q0.copy()
    v = np.zeros_like(q)
    centre = rod.q0[:3] + 0.5 * (rod.q0[rod.n_centreline - 6:rod.n_centreline - 3]
                                 - rod.q0[:3])
    vectors = q[:rod.n_centreline].reshape(-1, 2, 3)
    moved = vectors - np.stack([centre, np.zeros(3)])
    v[:rod.n_centreline] = np.cross(omega, moved).ravel()
    tangents = vectors[:, 1] / np.linalg.norm(vectors[:, 1], axis=1)[:, None]
    v[rod.n_centreline::2] = tangents @ omega
    return q, v


def test_tumbling_straight_rod_stores_no_bending_or_twist():
    """A free straight tape turning at 10 rad/s about an oblique axis (the component along
    the rod spins its section), a quarter turn in 200 steps: its bending and twist energy
    stay below 1e-10 of its kinetic energy, it spins at omega . t to 1e-6 (measured 1.5e-7:
    the Newton tolerance, on twist coordinates whose forces are 1e-7 of the centreline's)
    and its stretching is the cable's to 1e-9 (the centrifugal stretch is physical)."""
    omega = 10 * np.array([0.6, 0.0, 0.8])
    rod = sc.Rod.straight([-0.5, 0, 0], [0.5, 0, 0], 8, TAPE, normal=[0, 1, 0])
    cable = sc.Cable.straight([-0.5, 0, 0], [0.5, 0, 0], 8, TAPE)
    system, plain = sc.System([rod]), sc.System([cable])
    q, v = tumbling(rod, omega)
    t_end = 0.25 * 2 * np.pi / np.linalg.norm(omega[[0, 2]] * [0, 1]).max()
    result = sc.simulate(system, t_end=t_end, dt=t_end / 200, initial=(q, v))
    reference = sc.simulate(plain, t_end=t_end, dt=t_end / 200,
                            initial=(q[:rod.n_centreline], v[:rod.n_centreline]))
    (parts,) = system.energy_parts(result.q[-1], result.v[-1]).values()
    (cable_parts,) = plain.energy_parts(reference.q[-1], reference.v[-1]).values()
    assert parts["bending and twist"] < 1e-10 * parts["kinetic"]
    assert parts["axial"] == pytest.approx(cable_parts["axial"], rel=1e-9)
    assert np.allclose(result.v[-1][rod.n_centreline::2], omega[0], rtol=1e-6)


def swinging(G=None, stop_at=None):
    """A wire pinned at one end, swinging out of its plane under gravity (3-D: the
    reference frames turn and matter), and ``[rod, cable, observers]``."""
    section = sc.Section.circular(2e-3, 2e9, 1500.0, G=G)
    rod = sc.Rod.straight([0, 0, 0], [1, 0, 0], 6, section, normal=[0, 0, 1])
    system = sc.System([rod]).pin(rod.node(0)).add_gravity([0, 0, -9.81])
    q, v = rod.q0.copy(), np.zeros(rod.n_dofs)
    # positions and slopes turning about the vertical through the pin
    v[:rod.n_centreline] = np.cross([0.0, 0.0, 2.0],
                                    q[:rod.n_centreline].reshape(-1, 3)).ravel()
    return system, rod, (q, v)


def water(body):
    """Morison drag of a current with added mass, and a ``LineLoad`` (Python force)."""
    return [sc.MorisonDrag(body, 1025.0, 4e-3, 1.2, 0.1, current=[0.0, 0.5, 0.0],
                           added_mass=1.0),
            sc.LineLoad(body, lambda x, v, t: -0.02 * v)]


@pytest.mark.parametrize("loads", [lambda body: [], water], ids=["gravity", "water"])
def test_rod_without_torsional_stiffness_follows_the_cable(loads):
    """A wire swinging in 3-D under gravity (and in a current: Morison drag with added
    mass, a ``LineLoad``): as a rod with G = 1e-12 E (no torsional coupling) its
    centreline follows the cable's to 1e-8 of the length (measured 8.3e-15 under
    gravity, 5.0e-15 in water); the loads reach it through the line-body hook as the cable's."""
    system, rod, (q, v) = swinging(G=2e-3)
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 6, rod.section)
    plain = sc.System([cable]).pin(cable.node(0)).add_gravity([0, 0, -9.81])
    for body, s in ((rod, system), (cable, plain)):
        for load in loads(body):
            s.add_load(load)
    n = rod.n_centreline
    result = sc.simulate(system, t_end=0.3, dt=2e-3, initial=(q, v))
    reference = sc.simulate(plain, t_end=0.3, dt=2e-3, initial=(q[:n], v[:n]))
    assert np.abs(result.q[-1][:n] - result.q[0][:n]).max() > 0.1
    assert np.abs(result.q[:, :n] - reference.q).max() < 1e-8


def test_reference_frames_are_checkpointed_bit_for_bit(tmp_path):
    """The rod's reference frames are a run's state in its checkpoints: a run interrupted
    and continued from its store is the uninterrupted one bit for bit."""
    from skfem_cable import io

    class Interrupt(sc.Observer):
        def saved(self, run, step):
            if step.t >= 0.1:
                raise KeyboardInterrupt

    system, rod, initial = swinging()
    full = sc.simulate(system, 0.2, 2e-3, every=5, initial=initial)
    system, rod, initial = swinging()
    with pytest.raises(KeyboardInterrupt):
        sc.simulate(system, 0.2, 2e-3, every=5, initial=initial,
                    observers=[io.RunStore(tmp_path, chunk=3), Interrupt()])
    system, rod, initial = swinging()
    resumed = sc.simulate(system, 0.2, 2e-3, every=5, initial=initial,
                          resume=io.resume(tmp_path), observers=[io.RunStore(tmp_path)])
    twist = system.dofs(rod)[~rod.vector_mask]
    assert np.abs(full.q[-1][twist]).max() > 1e-6   # the twist moves: the frames matter
    np.testing.assert_array_equal(resumed.q, full.q)
    np.testing.assert_array_equal(resumed.v, full.v)


def test_cantilever_rolls_into_a_full_circle_under_a_tip_moment():
    """The elastica under a tip moment M = 2 pi EI / L closes into a full circle: the
    rod's tip (16 elements, 20 load steps: the reference frames carried along the load
    path, through tangents turned by pi) is the cable's to 1e-10 (measured 3e-16: the
    bending is planar, no twist) and returns to the root within 1e-4 L (measured 9.7e-5
    for both; 1.6e-6 at 32 elements)."""
    tips = []
    for body in (sc.Rod.straight([0, 0, 0], [1, 0, 0], 16, ELASTICA, normal=[0, 0, 1]),
                 sc.Cable.straight([0, 0, 0], [1, 0, 0], 16, ELASTICA)):
        system = sc.System([body]).clamp(body.node(0))
        system.add_point_moment(body.node(-1), [0, 0, 2 * np.pi * ELASTICA.EI])
        state = sc.solve_static(system, load_steps=20)
        tips.append(state.position(body, 1.0))
    assert np.linalg.norm(tips[0] - tips[1]) < 1e-10
    assert np.linalg.norm(tips[0]) < 1e-4


def test_tip_loaded_elastica_within_the_cables_bound():
    """The tip-loaded elastica ``P = 10 EI / L^2`` at 16 elements, as the cable's
    (``test_locking``): the tip within 2.6e-5 of the closed form."""
    from skfem_cable.analysis.analytic import elastica_tip_load

    rod = sc.Rod.straight([0, 0, 0], [1, 0, 0], 16, ELASTICA, normal=[0, 0, 1])
    system = sc.System([rod]).clamp(rod.node(0))
    system.add_point_load(rod.node(-1), [0, -10 * ELASTICA.EI, 0])
    tip = sc.solve_static(system, load_steps=20).position(rod, 1.0)
    u, w = elastica_tip_load(10.0)
    assert max(abs(1 - tip[0] - u), abs(-tip[1] - w)) <= 2.6e-5


def test_docstring_examples_run():
    """The examples of the rod's and the sections' docstrings."""
    import doctest

    from skfem_cable.bodies import rod, section

    for module in (rod, section):
        result = doctest.testmod(module, optionflags=doctest.ELLIPSIS)
        assert result.attempted > 0 and result.failed == 0


def test_energy_of_a_bent_twisted_rod_is_objective():
    """A bent, stretched and twisted tape, its reference frames away from its tangents:
    turning the coordinates and the frames rigidly leaves its bending and twist energy
    unchanged to 1e-12 (measured 2e-16) and turns its forces with it."""
    from scipy.spatial.transform import Rotation

    rod = sc.Rod.straight([0, 0, 0], [1, 0, 0], 4, TAPE, normal=[0, 0.2, 1])
    system = sc.System([rod])
    rng = np.random.default_rng(7)
    q = system.q0 + 0.1 * rng.standard_normal(system.n_dofs)
    R = Rotation.from_rotvec([0.3, -1.1, 2.0]).as_matrix()
    function, pack = rod.bind(system).kernels[-1]
    t0, d0 = pack[9], pack[10]
    t0[:] = rng.standard_normal(t0.shape) * 0.1 + [1, 0, 0]
    t0 /= np.linalg.norm(t0, axis=1)[:, None]
    d0[:] = np.cross(t0, rng.standard_normal(t0.shape))
    d0 /= np.linalg.norm(d0, axis=1)[:, None]

    def evaluate(q):
        f, energy, z = np.zeros_like(q), np.zeros(2), np.zeros_like(q)
        ev = (q, z, np.array([0.0, 1.0, 0.0, 0.0]), f, z.copy(), z.copy(), np.zeros(0),
              energy, np.zeros(2))
        function(pack, np.zeros((0, 0, 0), np.int64), ev)
        return f, energy[1]

    f, W = evaluate(q)
    turned = q.copy()
    turned[:rod.n_centreline] = (q[:rod.n_centreline].reshape(-1, 3) @ R.T).ravel()
    t0[:], d0[:] = t0 @ R.T, d0 @ R.T
    f_turned, W_turned = evaluate(turned)
    assert W > 0 and W_turned == pytest.approx(W, rel=1e-12)
    n = rod.n_centreline
    assert np.allclose(f_turned[:n].reshape(-1, 3), f[:n].reshape(-1, 3) @ R.T,
                       rtol=0, atol=1e-12 * np.abs(f).max())
    assert np.allclose(f_turned[n:], f[n:], rtol=0, atol=1e-12 * np.abs(f).max())


def test_rod_between_hangs_with_directors_normal_to_its_slopes():
    """``Rod.between`` builds the cable's catenary with directors made normal to its
    slopes; a clamp to a rigid body ties the twist to the body (``TwistTie``, one more
    equation) or leaves it free, and refuses to drive it."""
    rod = sc.Rod.between([0, 0, 0], [1, 0, 0], 1.2, 6, TAPE, normal=[0, 1, 0])
    slopes = rod.q0[:rod.n_centreline].reshape(-1, 2, 3)[:, 1]
    assert np.abs(np.einsum("ij,ij->i", slopes, rod.directors)).max() < 1e-15
    assert np.allclose(np.linalg.norm(rod.directors, axis=1), 1, atol=1e-15)
    assert rod.length == pytest.approx(1.2)
    hub = sc.RigidBody.cylinder(radius=0.1, height=0.1, density=100.0)
    with pytest.raises(ValueError, match="twist: a clamp"):
        sc.System([hub, rod]).clamp(rod.node(0), position=hub.point([0, 0, 0]),
                                    twist=lambda t: t)
    tied = sc.System([hub, rod]).clamp(rod.node(0), position=hub.point([0, 0, 0]))
    assert tied.n_constraints == 6 + 6
    system = sc.System([hub, rod]).clamp(rod.node(0), position=hub.point([0, 0, 0]),
                                         twist=False)
    assert system.n_constraints == 6 + 5
