"""Deploying and retrieving tethers (``System.deploy``, ``skfem_cable.constraints.deploy``)."""

import numpy as np
import pytest
from demo_modules import load_demo
from lagrange import cubic_path, inertial_force, lagrange_force

import skfem_cable as sc

SECTION = sc.Section.circular(1e-3, 1e9, 1000.0)


def straight_deployment(rate, L0=10.0, n=8, tip_mass=5.0):
    """A tether leaving a reel fixed at the origin along x at a constant rate, with an end
    mass, in zero gravity, started with every material point moving at ``rate``."""
    tether = sc.Cable.straight([0, 0, 0], [L0, 0, 0], n, SECTION)
    system = sc.System([tether]).deploy(tether, length=lambda t: L0 + rate * t,
                                        rate=lambda t: rate, acceleration=lambda t: 0.0,
                                        direction=[1, 0, 0])
    system.add_point_mass(tether.node(-1), tip_mass)
    v = np.zeros((tether.n_nodes, 6))
    v[:, 0] = rate * tether.q0[0::6] / L0   # mesh points: a share x / L0 of the rate
    v[:, 3] = rate / L0                     # slopes r_x = (l / L0) e
    return tether, system, sc.State(system, system.q0, v=v.ravel())


@pytest.mark.parametrize("rate", [2.0, -1.5])
def test_straight_deployment_and_retrieval_are_exact(rate):
    """The tip stays at ``anchor + l(t) e`` (1e-8 relative; measured 8e-16: the motion
    lies in the finite-element space and is linear in time) and the tether carries no
    force (the reel's reaction vanishes)."""
    tether, system, initial = straight_deployment(rate)
    r = sc.simulate(system, t_end=4.0, dt=0.05, initial=initial, rho_inf=0.8)
    tip = r.position(tether, tether.length)[:, 0]
    ell = 10.0 + rate * r.t
    assert np.abs(tip / ell - 1).max() < 1e-8
    assert np.abs(r.tension(tether, np.linspace(0, 10, 9))).max() < 1e-6
    assert "deployment" in r.stats["path"]


def test_deployed_mass_follows_the_length():
    """The mass the integrator sees, ``dp/dv`` along a uniform translation, is
    ``rho A l(t)`` plus the end mass."""
    tether, system, initial = straight_deployment(2.0, tip_mass=5.0)
    unit = system.rigid_motion_velocity(system.q0, (0, 0, 0), velocity=(0, 1, 0))
    for t in (0.0, 1.0, 7.5):
        mass = (system.linear_momentum(system.q0, unit, t)
                - system.linear_momentum(system.q0, 0 * unit, t))[1]
        assert mass == pytest.approx(SECTION.mass_per_length * (10.0 + 2.0 * t) + 5.0,
                                     rel=1e-12)


def _kinetic_energy(tether, deployment, q, qd, t):
    """``T = 1/2 int rho A |v|^2 ds`` of the free part from the material velocity
    ``v = S qd + c S_x q``, ``c = (l'/l) (L0 - x)``, at the cable's Gauss points."""
    ell, rate, _ = deployment.state(t)
    L0 = tether.length
    e = tether.element_dofs
    x = np.einsum("egA,eA->eg", tether.S, tether.q0[e].reshape(-1, 4, 3)[..., 0])
    v = (np.einsum("egA,eAi->egi", tether.S, qd[e].reshape(-1, 4, 3))
         + ((rate / ell) * (L0 - x))[..., None]
         * np.einsum("egA,eAi->egi", tether.Sx, q[e].reshape(-1, 4, 3)))
    w = tether.weights * (ell / L0)
    return 0.5 * SECTION.mass_per_length * np.einsum("eg,egi,egi->", w, v, v)


def test_inertial_force_is_lagrange_of_the_kinetic_energy():
    """``F_in = d/dt dT/dv - dT/dq`` of the free part's kinetic energy, by differences
    along a curved path with an accelerating length (1e-7 relative)."""
    L0 = 3.0
    tether = sc.Cable.straight([0, 0, 0], [L0, 0, 0], 3, SECTION)

    def ell(t):
        return L0 + 0.5 * t + 0.3 * t**2 + 0.1 * np.sin(3 * t)

    system = sc.System([tether]).deploy(
        tether, length=ell, rate=lambda t: 0.5 + 0.6 * t + 0.3 * np.cos(3 * t),
        acceleration=lambda t: 0.6 - 0.9 * np.sin(3 * t))
    deployment = system.deployment(tether)
    rng = np.random.default_rng(1)
    path = cubic_path([rng.normal(size=tether.n_dofs) for _ in range(4)])

    def kinetic(q, qd, t):
        return _kinetic_energy(tether, deployment, q, qd, t)

    t = 0.7
    lagrange = lagrange_force(kinetic, path, t)    # unit steps: T is quadratic in q and v
    inertial = inertial_force(system, deployment.bind(system), tether.mass_matrix(), path, t)
    assert np.abs(inertial - lagrange).max() < 1e-7 * np.abs(lagrange).max()


@pytest.mark.parametrize("element", ["hermite3", "hermite5", "linear"])
def test_deployment_tangent_matches_differences(element):
    """The term's tangent blocks ``d/dq``, ``d/dv``, ``d/da`` of its force (with the
    reel's content at a body point) against central differences (1e-7,
    ``sc.check_tangent``), on every element type."""
    hub = sc.RigidBody.cylinder(radius=0.5, height=0.3, density=1000.0)
    tether = sc.Cable.straight([0, 0.5, 0], [0, 3.5, 0], 3, SECTION, element=element)
    system = sc.System([hub, tether]).deploy(
        tether, hub.point([0, 0.5, 0]), length=lambda t: 3 + t + t**2,
        rate=lambda t: 1 + 2 * t, acceleration=lambda t: 2.0, capacity=50.0)
    rng = np.random.default_rng(2)
    q, v, a = (system.q0 + 0.1 * rng.normal(size=system.n_dofs),
               rng.normal(size=system.n_dofs), rng.normal(size=system.n_dofs))
    check = sc.check_tangent(system, q, v, t=0.4, a=a)
    assert {p.wrt for p in check.parts} == {"q", "v", "a"}
    assert check.error < 1e-7, str(check)


def hub_deployment(dt, t_end=2.5, omega=1.0, rate=1.0, L0=5.0, R=0.5):
    """A free hub spinning at ``omega`` deploying a tether with an end mass from its rim,
    the reel's content moving with the hub; no external load."""
    hub = sc.RigidBody.cylinder(radius=R, height=0.3, density=1000.0)
    tether = sc.Cable.straight([0, R, 0], [0, R + L0, 0], 8, SECTION)
    system = sc.System([hub, tether]).deploy(
        tether, hub.point([0, R, 0]), length=lambda t: L0 + rate * t, rate=lambda t: rate,
        acceleration=lambda t: 0.0, capacity=100.0)
    system.add_point_mass(tether.node(-1), 1.0)
    v = system.rigid_motion_velocity(system.q0, [omega, 0, 0])
    outward = np.zeros((tether.n_nodes, 6))
    outward[:, 1] = rate * (tether.q0[1::6] - R) / L0
    outward[:, 4] = rate / L0
    v[system.dofs(tether)] += outward.ravel()
    r = sc.simulate(system, t_end=t_end, dt=dt, initial=sc.State(system, system.q0, v=v),
                    rho_inf=0.8)
    P = np.array([system.linear_momentum(q, u, t) for q, u, t in zip(r.q, r.v, r.t)])
    L = np.array([system.angular_momentum(q, u, t=t) for q, u, t in zip(r.q, r.v, r.t)])
    return P, L


def test_hub_deployment_conserves_momentum_to_second_order():
    """Linear and angular momentum of hub + reel + free tether: the drift is the
    integrator's (second order in the step: measured 2.5e-5 -> 6.3e-6 for the angular
    momentum, 9.2e-7 -> 2.7e-7 for the linear one, at h = 0.01, 0.005), not a flux
    missing from the model (that would not converge).  (With the start ``abar_0 = a_0``
    the linear momentum's drift was 7.6e-6 at h = 0.02 and fell faster than second order
    while that first-step error faded.)"""
    drifts = []
    for dt in (0.01, 0.005):
        P, L = hub_deployment(dt)
        scale = np.linalg.norm(L[0])
        drifts.append((np.abs(P - P[0]).max() / np.linalg.norm(P[0]),
                       np.abs(L - L[0]).max() / scale))
    (p1, l1), (p2, l2) = drifts
    assert l1 < 1e-4 and l2 < l1 / 3.0
    assert p1 < 3e-6 and p2 < p1 / 3.0


def test_bad_deployments_are_refused():
    tether = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, SECTION)
    with pytest.raises(ValueError, match=r"length\(0.0\) = -1.0 m must be > 0"):
        sc.System([tether]).deploy(tether, length=lambda t: -1.0 + t)
    with pytest.raises(ValueError, match=r"= 3.0 m must lie in \(0, 2\] \(the capacity\)"):
        sc.System([tether]).deploy(tether, length=3.0, capacity=2.0)
    with pytest.raises(ValueError, match="capacity must be a length > 0"):
        sc.System([tether]).deploy(tether, length=1.0, capacity=-2.0)
    system = sc.System([tether]).deploy(tether, length=1.0)
    with pytest.raises(ValueError, match="already deployed"):
        system.deploy(tether, length=1.0)
    with pytest.raises(ValueError, match="UniformLineLoad acts along 'cable', which deploys"):
        _ = system.add_line_load(tether, [0, 1, 0]).layout
    damped = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(
        1e-3, 1e9, 1000.0, gamma_axial=0.1), name="damped")
    with pytest.raises(ValueError, match="'damped' deploys and its law dissipates"):
        _ = sc.System([damped]).deploy(damped, length=1.0).layout
    reel = sc.Reel(1.0, radius=0.1)
    with pytest.raises(TypeError, match="needs length .* or reel .*, not both"):
        sc.System([tether, reel]).deploy(tether, length=1.0, reel=reel, capacity=5.0)
    with pytest.raises(ValueError, match="from a reel needs the capacity"):
        sc.System([tether, reel]).deploy(tether, reel=reel)
    with pytest.raises(ValueError, match="starts at the free length 2.0 m: it must be"):
        long = sc.Reel(2.0, 0.1)
        sc.System([tether, long]).deploy(tether, reel=long, capacity=5.0)


def test_lowering_a_hanging_tether_balances_momentum():
    """A tether with an end mass lowered from a fixed reel at 10 m/s under gravity:
    every material point moves at the reel's rate, so the tension below the reel is the
    weight hanging from it, ``(rho A l(t) + m) g``, and the support holds the weight less
    the momentum the reel gives the tether, ``rho A l'^2`` (control-volume balance; the
    flux is 6 % of the weight; measured deviations 1.2e-3 and 1.3e-3 of the weight).  The
    energy books close with the work of the reel's brake (-50.6 J; balance 2e-8 J)."""
    L0, rate, m, g = 10.0, 10.0, 0.5, 9.81
    tether = sc.Cable.straight([0, 0, 0], [0, -L0, 0], 10, SECTION)
    system = sc.System([tether]).deploy(tether, length=lambda t: L0 + rate * t,
                                        rate=lambda t: rate, acceleration=lambda t: 0.0,
                                        direction=[0, -1, 0])
    system.add_point_mass(tether.node(-1), m).add_gravity([0, -g, 0])
    hanging = sc.solve_static(system)
    nodes = hanging.q.reshape(-1, 6)
    v = np.zeros_like(nodes)          # the mesh velocities of a rigid descent at the rate
    v[:, 1] = rate * nodes[:, 1] / L0
    v[:, 4] = -rate * np.linalg.norm(nodes[:, 3:], axis=1) / L0
    r = sc.simulate(system, t_end=1.0, dt=0.005, rho_inf=0.8,
                    initial=sc.State(system, hanging.q, hanging.lam, v=v.ravel()))
    mu = SECTION.mass_per_length
    weight = (mu * (L0 + rate * r.t) + m) * g
    support = -r.multipliers[f"clamp {tether.node(0)!r}"][:, 1]
    assert np.abs(r.tension(tether, 0.0) - weight).max() < 2.5e-3 * weight.max()
    assert np.abs(support - (weight - mu * rate**2)).max() < 2.5e-3 * weight.max()
    brake = r.energy["external_work"][-1]
    assert brake < -45.0 and np.abs(r.energy["balance"]).max() < 1e-6 * abs(brake)


def test_retrieval_demo_follows_the_variable_length_pendulum():
    """Reeling in a swinging tether makes the swing grow, as the variable-length pendulum
    does (full demo, 10 m -> 2.5 m: growth 2.5932 against 2.5926; here 10 m -> 5 m)."""
    out = load_demo("tether_retrieval").main(l1=5.0, duration=30.0)
    assert out["growth"] > 1.5
    assert out["growth"] == pytest.approx(out["reference"], rel=2e-3)


def test_hub_deployment_demo_conserves_angular_momentum():
    """Four tethers deployed from a spinning hub (reduced: 10 m -> 20 m): the angular
    momentum about the spin axis drifts by less than 1e-3 (full demo: see its output),
    and the tension brakes the hub."""
    out = load_demo("hub_deployment").main(n_elements=4, l1=20.0, duration=20.0, hold=4.0, dt=0.05)
    assert out["momentum_drift"] < 1e-3
    assert out["hub_rate"][-1] < 0.9


def test_scene_file_lowers_a_tether():
    """``demos/tether_lowering.toml``: the end mass ends 30 m below the reel, stretched by
    the weight it carries (static stretch below 1e-3; measured within 2e-4 of 30 m)."""
    from pathlib import Path

    from skfem_cable import scene_file

    spec = scene_file.load(Path(__file__).resolve().parents[1] / "demos" /
                           "tether_lowering.toml")
    cable = spec.system.bodies[0]
    assert spec.system.deployment(cable).state(12.0)[0] == pytest.approx(30.0)
    r = sc.simulate(spec.system, initial=spec.initial, **spec.solver)
    tip = r.position(cable, cable.length)[-1]
    assert tip[1] == pytest.approx(-30.0, rel=1e-3)


def test_summary_of_a_deploying_scene_reports_the_free_length(tmp_path):
    """``skfem-cable run demos/tether_lowering.toml``: the summary's length is the free
    length at the end (30 m), and its root tension the one at that length (within 10 %
    of the weight hanging there; the run ends 2 s after the lowering stopped)."""
    import json
    from pathlib import Path

    from skfem_cable.cli.command import main

    scene = Path(__file__).resolve().parents[1] / "demos" / "tether_lowering.toml"
    out = tmp_path / "run"
    assert main(["run", str(scene), "--out", str(out), "--no-plots"]) == 0
    cable = json.loads((out / "summary.json").read_text())["outputs"]["cables"]["tether"]
    assert cable["length"] == pytest.approx(30.0, rel=1e-12)
    weight = (sc.Section.circular(1e-3, 1e11, 970.0).mass_per_length * 30.0 + 2.0) * 9.81
    assert cable["root_tension"] == pytest.approx(weight, rel=0.1)
