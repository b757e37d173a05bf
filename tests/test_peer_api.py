"""What the peers' cases needed, as API (issue 32): Exudyn's law, split Gauss rules, a
clamp of the whole slope, pins along some directions, cables of any length between two
points, law parameters that vary in time, and the zero and plain starts."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable import constraints, laws
from skfem_cable.analysis.analytic import elastic_catenary
from skfem_cable.scene_file import loads_text
from skfem_cable.scenes import peer_suites as ps
from skfem_cable.solvers.galpha import GeneralizedAlpha

SEC = sc.Section.circular(0.01, 2e9, 1000.0, gamma_axial=1e-3, gamma_bending=1e-2)


def bent(cable, seed=0, size=0.05):
    """The cable's coordinates, perturbed (a general state for tangent checks)."""
    rng = np.random.default_rng(seed)
    return cable.q0 + size * rng.standard_normal(cable.n_dofs)


def test_exudyn_law_tangent_and_damping_against_differences():
    """``law="exudyn"``: stiffness and damping tangents match central differences at a
    perturbed, moving state (the law's own damping with ``gamma_axial``,
    ``gamma_bending``), on the split rules."""
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 3, SEC, law="exudyn",
                              quadrature=ps.EXUDYN_RULES)
    system = sc.System([cable])
    q, v = bent(cable), bent(cable, 1) - cable.q0
    assert sc.check_tangent(system, q, v).error < 1e-6


def test_exudyn_law_energy_is_engineering_strain_and_reference_curvature():
    """A uniformly stretched arc of stretch ``lam`` and curvature ``k`` per current length
    stores ``EA (lam - 1)^2 / 2 + EI (lam k)^2 / 2`` per unit reference length with
    Exudyn's law, ``EA ((lam^2 - 1) / 2)^2 / 2 + EI k^2 / 2`` with ours."""
    lam, k = 1.01, 0.7
    a = np.array([lam, 0.0, 0.0])
    b = np.array([0.0, lam**2 * k, 0.0])  # r_xx of an arc: lam^2 k along the normal
    x = np.concatenate([a, b])[:, None]
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 1, SEC, law="exudyn")
    out = cable.densities(x, np.zeros_like(x), np.ones(1))
    assert out["ea"][0] == pytest.approx(SEC.EA * (lam - 1) ** 2 / 2, rel=1e-12)
    assert out["eb"][0] == pytest.approx(SEC.EI * (lam * k) ** 2 / 2, rel=1e-12)
    green = sc.Cable.straight([0, 0, 0], [1, 0, 0], 1, SEC).densities(
        x, np.zeros_like(x), np.ones(1))
    assert green["eb"][0] == pytest.approx(SEC.EI * k**2 / 2, rel=1e-12)


def test_split_quadrature_equals_the_single_rule_with_the_same_points():
    """``quadrature={"axial": 5, "bending": 5}`` is the ``"paper"`` formulation's own
    5-point rule in two passes: the same forces and tangent to round-off."""
    one = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, SEC, formulation="paper")
    two = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, SEC,
                            quadrature={"axial": 5, "bending": 5})
    assert two.formulation == "paper" and two.quadrature == {"axial": 5, "bending": 5}
    q = bent(one)
    (f1, K1), (f2, K2) = (sc.System([c]).assemble(q) for c in (one, two))
    assert np.allclose(f1, f2, rtol=0, atol=1e-10 * np.abs(f1).max())
    assert abs(K1 - K2).max() < 1e-10 * abs(K1).max()
    three = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, SEC, quadrature={"bending": 2})
    assert three.quadrature == {"axial": 5, "bending": 2}


@pytest.mark.parametrize("quadrature, formulation, match", [
    ({"axial": 0}, None, r"quadrature\['axial'\] must be a whole number"),
    ({"axial": 2.5}, None, r"quadrature\['axial'\]"),
    ({"shear": 3}, None, "keys 'axial' and/or 'bending'"),
    ([5, 3], None, "must be a dict"),
    ({"axial": 5}, "lobatto", "formulation='paper'"),
])
def test_quadrature_refused_with_the_reason(quadrature, formulation, match):
    with pytest.raises(ValueError, match=match):
        sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, SEC, quadrature=quadrature,
                          formulation=formulation)


def test_full_slope_clamp_holds_the_stretch_at_the_root():
    """Pulled along its axis, a cable clamped with ``slope="full"`` keeps its root slope
    ``(1, 0, 0)``, where the direction clamp lets it stretch with the rest; six equations,
    the last three the generalized force on the slope."""
    roots = {}
    for slope in ("direction", "full"):
        cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, SEC)
        system = sc.System([cable]).clamp(cable.node(0), slope=slope)
        system.add_point_load(cable.node(-1), [0.01 * SEC.EA, 0, 0])
        state = sc.solve_static(system)
        roots[slope] = state.slope(cable, 0.0)
        assert system.n_constraints == (5 if slope == "direction" else 6)
    assert roots["full"] == pytest.approx([1, 0, 0], abs=1e-12)
    assert roots["direction"][0] > 1.009
    (joint,) = constraints.clamp(cable.node(0), slope="full")
    assert joint.labels == ["Fx", "Fy", "Fz", "Mx", "My", "Mz"]


def test_full_slope_clamp_driven_and_refused():
    """A driven full clamp moves position and slope together; ``slope`` names its choices,
    and a body point is refused."""
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, SEC)
    turn = lambda t: np.array([np.cos(t), np.sin(t), 0.0])  # noqa: E731
    (joint,) = constraints.clamp(cable.node(0), direction=turn, slope="full")
    assert joint.driven
    assert joint.offset(0.0, 1) == pytest.approx([0, 0, 0, 0, 1, 0], abs=1e-8)
    with pytest.raises(ValueError, match="slope must be 'direction' or 'full'"):
        constraints.clamp(cable.node(0), slope="whole")
    hub = sc.RigidBody.cylinder(radius=1.0, height=0.5, density=100.0)
    with pytest.raises(ValueError, match="slope='full'"):
        constraints.clamp(cable.node(0), position=hub.point([0, 1, 0]), slope="full")


def test_pin_along_directions_slides_freely_across_them():
    """A soft beam pinned at its root and, at its tip, held only vertically (a roller on
    the x-axis) sags under gravity: the tip slides inwards along x and the two joints'
    vertical forces carry the weight."""
    sec = sc.Section.circular(0.01, 2e7, 1000.0)
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 8, sec)
    system = sc.System([cable]).pin(cable.node(0))
    system.pin(cable.node(-1), directions=[[0, 0, 1]])
    system.add_gravity([0, 0, -9.81])
    roller = system.constraints[-1]
    assert roller.labels == ["F1"] and roller.n_eq == 1 and roller.name.startswith("sliding")
    state = sc.solve_static(system, load_steps=4)
    tip = state.position(cable, 1.0)
    assert tip[2] == pytest.approx(0.0, abs=1e-12)
    assert tip[0] < 0.99
    weight = sec.mass_per_length * 9.81
    assert -(state.lam[2] + state.lam[3]) == pytest.approx(weight, rel=1e-9)


def test_pin_along_directions_follows_a_moving_target():
    """Along its directions the node follows a moving target (the offset is the target's
    component), with the target's derivatives projected too; bad directions are refused."""
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, SEC)
    path = lambda t: np.array([1.0 + t, 2 * t, 3 * t])  # noqa: E731
    joint = constraints.pin(cable.node(-1), path, directions=[[0, 1, 1], [1, 0, 0]])
    D = np.array([[0, 1, 1], [1, 0, 0]]) / np.array([[np.sqrt(2)], [1]])
    assert joint.offset(0.5) == pytest.approx(D @ path(0.5))
    assert joint.offset(0.5, 1) == pytest.approx(D @ [1, 2, 3], rel=1e-8)
    for bad, match in (([[1, 0, 0], [2, 0, 0]], "independent"),
                       (np.eye(3), "one or two"), ([[np.nan, 0, 0]], "one or two")):
        with pytest.raises(ValueError, match=match):
            constraints.pin(cable.node(-1), directions=bad)


def test_cable_between_hangs_to_the_elastic_catenary():
    """A 10 m steel cable between pins 8 m apart starts as the inextensible catenary of its
    length (``Cable.between``) and ``solve_static`` converges from it to the elastic
    catenary: the midpoint's sag within 1e-3 m of Irvine's (the discretisation error of 16
    elements: 4e-4 m)."""
    sec = sc.Section.circular(1e-3, 2e11, 7850.0)
    cable = sc.Cable.between([0, 0, 0], [8, 0, 0], 10.0, 16, sec)
    assert cable.length == 10.0
    lengths = np.linalg.norm(np.diff(cable.q0.reshape(-1, 6)[:, :3], axis=0), axis=1)
    assert lengths.sum() == pytest.approx(10.0, rel=1e-3)  # chords of the arcs
    assert np.linalg.norm(cable.q0.reshape(-1, 6)[:, 3:], axis=1) == pytest.approx(1.0)
    system = sc.System([cable]).pin(cable.node(0)).pin(cable.node(-1))
    system.add_gravity([0, 0, -9.81])
    state = sc.solve_static(system)
    xz = elastic_catenary(np.array([5.0]), 8.0, 0.0, 10.0, sec.mass_per_length * 9.81,
                          sec.EA)
    assert state.position(cable, 5.0)[2] == pytest.approx(xz[0][0, 1], abs=1e-3)


def test_cable_between_stretched_straight_and_its_errors():
    """Shorter than the distance: straight, uniformly stretched (slopes of length ``d /
    L``), also on the quintic element; a sag along the chord and bad lengths are refused
    naming the parameter."""
    taut = sc.Cable.between([0, 0, 0], [0, 0, -101], 100.0, 4, SEC, element="hermite5")
    assert taut.q0[3:6] == pytest.approx([0, 0, -1.01])
    slack = sc.Cable.between([0, 0, 0], [3, 0, 4], 6.0, 6, SEC, element="hermite5",
                             sag=[0, -1, 0])
    assert slack.q0[-9:-6] == pytest.approx([3, 0, 4])
    with pytest.raises(ValueError, match="sag .* is parallel"):
        sc.Cable.between([0, 0, 0], [0, 0, -1], 2.0, 2, SEC)
    with pytest.raises(ValueError, match="length must be a finite"):
        sc.Cable.between([0, 0, 0], [1, 0, 0], -1.0, 2, SEC)
    with pytest.raises(ValueError, match="start and end must differ"):
        sc.Cable.between([0, 0, 0], [0, 0, 0], 1.0, 2, SEC)


#: A scene file's wire and the head of its cable (the keys under test follow).
WIRE = """
[solver]
analysis = "static"

[sections.wire]
radius = 0.01
E = 2e9
rho = 1000.0

[[cables]]
name = "line"
section = "wire"
start = [0, 0, 0]
end = [8, 0, 0]
elements = 8
"""


def test_scene_file_takes_the_new_keys():
    """TOML: a cable of a given length with a sag, Exudyn's law and rules, a full clamp
    and a roller; a misspelt part of the rule is named."""
    scene = loads_text(WIRE + """
length = 10.0
sag = [0, 0, -1]
kind = "exudyn"
quadrature = { axial = 5, bending = 3 }

[[constraints]]
type = "clamp"
node = { cable = "line", index = 0 }
slope = "full"

[[constraints]]
type = "pin"
node = { cable = "line", index = -1 }
directions = [[0, 0, 1]]
""")
    (cable,) = scene.system.cables()
    assert cable.law is laws.exudyn and cable.quadrature == {"axial": 5, "bending": 3}
    assert cable.length == 10.0 and scene.system.n_constraints == 7
    with pytest.raises(Exception, match="quadrature.axal"):
        loads_text(WIRE + "quadrature = { axal = 5 }\n")


def test_time_dependent_parameter_books_its_work():
    """A soft cable released with a 1 kg mass at its end, whose axial stiffness doubles
    over the run (``EA(t)``, refreshed once per step): the stiffening does work on it
    (booked as external work) and the books close to 1e-4 of that work with rho_inf =
    1 (measured 2.4e-5; a jump of the energy at either end of the step would leave
    2.6e-3); the tension reported at a time uses the stiffness of that time; compiled and
    Python steps agree to round-off."""
    soft = sc.Section.circular(0.01, 2e5, 1000.0)
    law = laws.truss.with_parameters(EA=lambda t: soft.EA * (1 + t / 0.5))
    runs = {}
    for compiled in (True, False):
        cable = sc.Cable.straight([0, 0, 0], [0, 0, -1], 4, soft, law=law)
        system = sc.System([cable]).pin(cable.node(0))
        system.add_gravity([0, 0, -9.81])
        system.add_point_mass(cable.node(-1), 1.0)
        runs[compiled] = sc.simulate(system, 0.5, 1e-3, rho_inf=1.0, compiled=compiled)
    r = runs[True]
    assert r.stats["path"] == "compiled"
    assert np.abs(r.q - runs[False].q).max() < 1e-12
    E = r.energy
    work = E["external_work"][-1]
    assert work > 0.05 * E["elastic"].max()
    assert abs(E["balance"]).max() < 1e-4 * work
    cable = r.system.cables()[0]
    dofs = r.system.dofs(cable)
    now = r.tension(cable, 0.0)[-1]
    then = cable.tension(r.q[-1, dofs], 0.0, t=0.0)  # the same shape, the first stiffness
    assert now == pytest.approx(2 * then, rel=1e-3)


def test_time_dependent_parameter_refused_where_it_cannot_act():
    """A callable that gives no finite number is named with the time; a deploying cable
    refuses a law whose parameters vary."""
    bad = laws.green.with_parameters(EA=lambda t: np.nan)
    with pytest.raises(ValueError, match="parameter EA must be a finite number, got nan"):
        sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, SEC, law=bad)
    law = laws.green.with_parameters(EA=lambda t: SEC.EA)
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, SEC, law=law)
    system = sc.System([cable]).deploy(cable, length=lambda t: 0.5 + 0.1 * t)
    with pytest.raises(ValueError, match="vary in time"):
        system.layout  # noqa: B018


def test_zero_and_plain_starts():
    """``initial_acceleration="zero"`` starts with zero accelerations and multipliers;
    ``pseudo_acceleration="initial"`` keeps ``abar_0 = a_0``; both continue bit for bit
    from a checkpoint; other values are refused."""
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 3, SEC)
    system = sc.System([cable]).clamp(cable.node(0)).add_gravity([0, -9.81, 0])
    r = sc.simulate(system, 0.01, 1e-3, initial_acceleration="zero")
    assert not r.a[0].any() and not r.lam[0].any()
    for options in ({"initial_acceleration": "zero"}, {"pseudo_acceleration": "initial"}):
        whole = GeneralizedAlpha(system, **options)
        whole.initialize(system.q0, np.zeros(system.n_dofs), 0.0)
        for _ in range(2):
            whole.step(1e-3)
        snap = whole.snapshot()
        for _ in range(3):
            whole.step(1e-3)
        again = GeneralizedAlpha(system, **options)
        again.restore(snap)
        for _ in range(3):
            again.step(1e-3)
        assert np.array_equal(whole.q, again.q)
    with pytest.raises(ValueError, match="initial_acceleration must be"):
        sc.simulate(system, 0.01, 1e-3, initial_acceleration="rest")
    with pytest.raises(ValueError, match="pseudo_acceleration must be"):
        sc.simulate(system, 0.01, 1e-3, pseudo_acceleration="fit")
