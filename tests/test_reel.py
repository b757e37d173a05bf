"""Reels with inertia whose coordinate is the free length (``sc.Reel``,
``System.deploy(..., reel=...)``): the reel's equation, its tangent, and its physics."""

import numpy as np
import pytest
from demo_modules import load_demo
from lagrange import cubic_path, inertial_force, lagrange_force
from scipy.integrate import solve_ivp

import skfem_cable as sc

SECTION = sc.Section.circular(1e-3, 2e11, 1000.0)     # 3.1 g/m, EA = 628 kN
MU = SECTION.mass_per_length
SOFT = sc.Section.circular(1e-3, 1e9, 1000.0)         # the same mass, EA = 3.1 kN


def hanging(drive, L0=5.0, top=2.0, tip_mass=0.5, inertia=0.02, capacity=30.0, n=6):
    """A tether hanging from a reel fixed at ``(0, 0, top)`` under gravity ``-z``, with an
    end mass; returns ``(system, tether, reel)``."""
    tether = sc.Cable.straight([0, 0, top], [0, 0, top - L0], n, SECTION)
    reel = sc.Reel(L0, radius=0.1, inertia=inertia, drive=drive)
    system = sc.System([tether, reel]).deploy(tether, reel=reel, capacity=capacity)
    system.add_point_mass(tether.node(-1), tip_mass).add_gravity([0, 0, -9.81])
    return system, tether, reel


def hub_system(drive=None, gravity=(0.0, -9.81, 1.0)):
    """A hub with a reel on its rim paying out a tether through an exit guide."""
    hub = sc.RigidBody.cylinder(radius=0.5, height=0.3, density=1000.0)
    tether = sc.Cable.straight([0, 0.5, 0], [0, 3.5, 0], 3, SOFT)
    reel = sc.Reel(3.0, radius=0.1, inertia=0.01, drive=drive)
    system = sc.System([hub, tether, reel]).deploy(tether, hub.point([0, 0.5, 0]), reel=reel,
                                                   capacity=50.0, direction=[0, 1, 0])
    system.add_point_mass(tether.node(-1), 0.3)
    if gravity is not None:
        system.add_gravity(gravity)
    return system, hub, tether, reel


@pytest.mark.parametrize("block", ["q", "v", "a"])
def test_reel_tangent_matches_differences(block):
    """The iteration matrix's blocks ``dr/dq``, ``dr/dv`` and ``dr/da`` of the whole
    residual (cable, reel and hub: inertia of the deployment, the elastic coupling with the
    length, the weight, the servo and the exit guide) against central differences (each
    row to 1e-6 of its largest entry; the residual is at most quadratic in the velocities
    and linear in the accelerations, whose central differences of unit step are exact)."""
    system, hub, tether, reel = hub_system(sc.Servo(lambda t: 3 + t, 4.0, 2.0))
    lay, n = system.layout, system.n_dofs
    rng = np.random.default_rng(3)
    z = [system.q0 + 0.01 * rng.normal(size=n), rng.normal(size=n), rng.normal(size=n)]
    z[0][system.dofs(reel)] = 3.4
    lam = rng.normal(size=lay.n_c)
    k = "qva".index(block)

    def residual(z):
        return system.evaluate(z[0], z[1], 0.4, lam, a=z[2], cM=1.0)[0][:n]

    data = np.zeros(lay.nnz)
    coefficients = np.eye(3)[k]
    system.evaluate(z[0], z[1], 0.4, lam, cK=coefficients[0], cC=coefficients[1], data=data,
                    a=z[2], cM=coefficients[2])
    tangent = lay.matrix(data).toarray()[:n, :n]
    differences = np.zeros((n, n))
    for j in range(n):
        up, down = [x.copy() for x in z], [x.copy() for x in z]
        step = (1e-6 if block == "q" else 1.0) * max(1.0, abs(z[k][j]))
        up[k][j] += step
        down[k][j] -= step
        differences[:, j] = (residual(up) - residual(down)) / (2 * step)
    scale = np.abs(differences).max(axis=1)
    rows = scale > 1e-3 * scale.max()
    error = np.abs(tangent - differences).max(axis=1)[rows] / scale[rows]
    assert error.max() < 1e-6


def _material_kinetic_energy(system, tether, reel, q, v):
    """``T`` of the tether's free part, ``1/2 int rho A |S v + c S_x q|^2 ds`` with
    ``c = (l'/l)(L0 - x)`` at its Gauss points, the material wound on the drum (``1/2 rho
    A (C - l) l'^2``) and riding with the anchor, and the constant masses of the rest
    (hub, drum, end mass)."""
    ell, rate = q[system.dofs(reel)[0]], v[system.dofs(reel)[0]]
    L0 = tether.length
    d = system.dofs(tether)
    e = tether.element_dofs
    p = tether.mesh.p[0]
    ones = np.ones(tether.n_elements)
    x = np.einsum("egA,eA->eg", tether.S, np.stack([p[:-1], ones, p[1:], ones], axis=1))
    qc, vc = q[d], v[d]
    vm = (np.einsum("egA,eAi->egi", tether.S, vc[e].reshape(-1, 4, 3))
          + ((rate / ell) * (L0 - x))[..., None]
          * np.einsum("egA,eAi->egi", tether.Sx, qc[e].reshape(-1, 4, 3)))
    free = 0.5 * MU * np.einsum("eg,egi,egi->", tether.weights * ell / L0, vm, vm)
    drum = 0.5 * MU * (50.0 - ell) * rate**2
    dofs, G = system.position_map(system.deployment(tether).anchor)
    riding = 0.5 * MU * (50.0 - ell) * np.sum((G @ v[dofs]) ** 2)
    constant = 0.5 * v @ (system.mass_matrix() @ v) - 0.5 * vc @ (tether.mass_matrix() @ vc)
    return free + drum + riding + constant


def test_reel_inertia_is_lagrange_of_the_kinetic_energy():
    """The deployment's inertial force on the tether, the hub and the reel's length is
    ``d/dt dT/dv - dT/dq`` of the kinetic energy computed independently from the material
    velocity (differences along a cubic path; 1e-6 of the largest force)."""
    system, hub, tether, reel = hub_system(gravity=None)
    term = system.deployment(tether).bind(system)
    n = system.n_dofs
    rng = np.random.default_rng(4)
    c = [rng.normal(size=n) * s for s in (1.0, 0.5, 0.3, 0.1)]
    c[0] = system.q0 + 0.01 * c[0]
    c[0][system.dofs(reel)] = 3.2
    path = cubic_path(c)

    def kinetic(q, v, t):
        return _material_kinetic_energy(system, tether, reel, q, v)

    t = 0.3
    lagrange = lagrange_force(kinetic, path, t, h=1e-5)   # T is not quadratic in l
    inertial = inertial_force(system, term, system.mass_matrix(), path, t)
    assert np.abs(inertial - lagrange).max() < 1e-6 * np.abs(lagrange).max()


def test_falling_tether_from_a_braked_reel():
    """A stiff tether with an end mass unwinds under gravity from a drum of inertia ``J``
    with a viscous brake: the free length follows the closed system's equation
    ``(J/R^2 + rho A C + m) l'' = (rho A l + m) g - c l' / R`` (the drum, its content and
    the hanging part share the rim speed) to 4e-5 of the distance fallen (measured 1.8e-5:
    the tether's stretch, 4e-5 m, and its axial ringing), and the energy books close with
    the brake's work (1e-6 of the energy exchanged)."""
    J, C, c, R, m, g = 0.02, 30.0, 0.3, 0.1, 0.5, 9.81
    system, tether, reel = hanging(sc.Brake(c), inertia=J, capacity=C)
    r = sc.simulate(system, t_end=1.0, dt=1e-3, rho_inf=0.9)
    ell = r.q[:, system.dofs(reel)[0]]

    def rhs(t, y):
        return [y[1], ((MU * y[0] + m) * g - c * y[1] / R) / (J / R**2 + MU * C + m)]

    exact = solve_ivp(rhs, (0.0, 1.0), [5.0, 0.0], rtol=1e-12, atol=1e-12,
                      dense_output=True).sol(r.t)[0]
    assert np.abs(ell - exact).max() < 4e-5 * (exact[-1] - 5.0)
    energy = r.energy
    exchanged = np.abs(energy["kinetic"]).max()
    assert np.abs(energy["balance"]).max() < 1e-6 * exchanged
    assert energy["external_work"][-1] < 0      # the brake takes energy out


def test_servo_holds_the_configurational_force():
    """In equilibrium the reel's force balances the configurational (Eshelby) force of
    the material leaving it, ``T lam - W`` (tension times stretch less the strain energy
    per unstretched length at the exit): not the tension alone, because unstretched
    material is stretched as it leaves.  ``solve_static`` with a servo-held reel: 1e-8
    (measured 1.5e-10); the pin carries the weight ``(rho A l + m) g`` exactly."""
    k, R, m, g = 30.0, 0.1, 0.5, 9.81
    system, tether, reel = hanging(sc.Servo(lambda t: 5.0, k, 1.0), tip_mass=m)
    state = sc.solve_static(system)
    ell = state.q[system.dofs(reel)[0]]
    held = k * (ell - 5.0) / R
    T = float(state.tension(tether, 0.0))
    stretch = np.linalg.norm(state.q[system.dofs(tether.node(0))[3:]]) / (ell / 5.0)
    W = 0.5 * SECTION.E * SECTION.A * ((stretch**2 - 1) / 2) ** 2
    assert held == pytest.approx(T * stretch - W, rel=1e-8)
    assert -state.lam[2] == pytest.approx((MU * ell + m) * g, rel=1e-9)
    assert held / T - 1 > 1e-6     # the configurational correction is resolved


def _spinning_hub(dt, t_end=4.0):
    """A free hub in zero gravity spinning at 2 rad/s pays out a tether through an exit
    guide from a servo-held reel on its rim; returns the run and the system."""
    system, hub, tether, reel = hub_system(
        sc.Servo(lambda t: 3.0 + 0.5 * t, 40.0, 4.0, rate=lambda t: 0.5), gravity=None)
    v = system.rigid_motion_velocity(system.q0, [2.0, 0.0, 0.0])
    r = sc.simulate(system, t_end=t_end, dt=dt, rho_inf=0.8, newton="full",
                    initial=sc.State(system, system.q0, v=v))
    return r, system


def test_reel_on_a_free_hub_conserves_momentum():
    """Nothing acts from outside a hub paying out a tether from its reel: the linear and
    angular momentum of hub, reel content and tether are conserved to the integrator's
    accuracy, second order in the step (drift ratios 4 +- 0.8 when the step halves;
    measured angular 6.5e-5 -> 1.6e-5 of ``|H|``)."""
    drifts = []
    for dt in (0.02, 0.01):
        r, system = _spinning_hub(dt)
        H = np.array([system.angular_momentum(q, v, t=t) for q, v, t in zip(r.q, r.v, r.t)])
        P = np.array([system.linear_momentum(q, v, t) for q, v, t in zip(r.q, r.v, r.t)])
        drifts.append([np.abs(H - H[0]).max() / np.linalg.norm(H[0]), np.abs(P - P[0]).max()])
    ratios = np.array(drifts[0]) / drifts[1]
    assert np.all((3.2 < ratios) & (ratios < 4.8))
    assert drifts[1][0] < 3e-5
    assert r.q[-1, system.dofs(system.bodies[2])[0]] > 4.9      # it did deploy


def test_rigid_motions_leave_the_reel_alone():
    """Rigid velocities, rotations and momenta act on the 3-vectors of coordinates only:
    the reel's length is a scalar (``vector_mask``)."""
    system, hub, tether, reel = hub_system(gravity=None)
    i = system.dofs(reel)[0]
    v = system.rigid_motion_velocity(system.q0, [0.3, -1.0, 2.0], velocity=[1, 2, 3])
    assert v[i] == 0.0
    assert system.rotate(system.q0, np.eye(3)[[1, 2, 0]])[i] == system.q0[i]
    assert len(system.vectors) * 3 == system.n_dofs - 1
    moving = np.zeros(system.n_dofs)
    moving[i] = 1.0
    assert np.allclose(system.angular_momentum(system.q0, moving), 0.0)


def test_bad_reels_are_refused():
    with pytest.raises(ValueError, match="radius must be finite and > 0"):
        sc.Reel(1.0, radius=0.0)
    with pytest.raises(ValueError, match="inertia must be >= 0"):
        sc.Reel(1.0, radius=0.1, inertia=-1.0)
    with pytest.raises(TypeError, match="drive must have torque"):
        sc.Reel(1.0, radius=0.1, drive=lambda t: 0.0)
    with pytest.raises(ValueError, match="damping must be >= 0"):
        sc.Brake(-1.0)
    with pytest.raises(ValueError, match="stiffness must be finite and > 0"):
        sc.Servo(lambda t: 1.0, 0.0, 1.0)
    system, hub, tether, reel = hub_system()
    with pytest.raises(ValueError, match="modes: the system has deploying cables"):
        sc.modes(system)
    with pytest.raises(ValueError, match="Centrifugal: the system has deploying cables"):
        _ = system.add_centrifugal([1.0, 0, 0]).layout


def test_settled_spin_rate_is_the_angular_momentum_prediction():
    """Reels on a free spinning hub pay out two tethers through exit guides (10 m -> 30 m;
    ``demos/reel_spin_rate.py`` goes to 1 km): once the reels hold, the system turns
    rigidly at the rate at which the deployed configuration, stretched by its own spin
    (``analytic.rotating_string``, not the elements), carries the run's angular momentum
    (1e-6 relative; measured 2.2e-8).  Against the initial angular momentum the rate is
    off by the integrator's drift only (asked 1e-4, measured 2.6e-5 at ``omega h =
    0.05``)."""
    demo = load_demo("reel_spin_rate")
    out = demo.main(duration=100.0, settle=40.0, average=20.0, dt=0.1, l1=30.0, n_elements=3)
    assert out["difference"] < 1e-6
    assert abs(out["measured"] / out["from_start"] - 1) < 1e-4
    assert out["measured"] < (1 - 1e-4) * demo.OMEGA0   # the spin dropped (by 2.9e-4)
    assert np.all(np.abs(out["lengths"] - 30.0) < 0.05)


def test_scene_file_with_a_braked_reel(tmp_path):
    """``skfem-cable run demos/reel_brake.toml``: the scene file's reel gives the run of
    ``test_falling_tether_from_a_braked_reel`` (free length 5.6875 m after 1 s, to 1e-5),
    and the summary reports it; a reel with a length too, or two drives, are refused with
    the key named."""
    import json
    from pathlib import Path

    from skfem_cable import scene_file
    from skfem_cable.cli.command import main

    scene = Path(__file__).resolve().parents[1] / "demos" / "reel_brake.toml"
    out = tmp_path / "run"
    assert main(["run", str(scene), "--out", str(out), "--no-plots"]) == 0
    cable = json.loads((out / "summary.json").read_text())["outputs"]["cables"]["tether"]
    assert cable["length"] == pytest.approx(5.687504, rel=1e-5)
    text = scene.read_text()
    twice = text.replace("brake = 0.3 }", "brake = 0.3, motor = 1.0 }")
    with pytest.raises(scene_file.SceneFileError, match="deploy.0..reel.motor and brake"):
        scene_file.loads_text(twice, "twice.toml")
    both = text.replace("capacity = 30.0", "capacity = 30.0\nlength = 5.0")
    with pytest.raises(scene_file.SceneFileError, match="length and reel both"):
        scene_file.loads_text(both, "both.toml")


def test_a_reel_wound_in_completely_stops_the_run_with_its_length():
    """A motor winds a tether in until nothing is left: a Newton iterate outside
    ``(0, capacity]`` makes the step retry smaller (``contract.OutOfDomain``) and, when
    even the smallest step cannot stay inside, the run stops with the length named and
    the steps computed so far kept."""
    tether = sc.Cable.straight([0, 0, 0], [2.0, 0, 0], 4, SOFT)
    reel = sc.Reel(2.0, radius=0.1, inertia=0.01, drive=sc.Motor(-0.5))
    system = sc.System([tether, reel]).deploy(tether, reel=reel, capacity=5.0)
    system.add_point_mass(tether.node(-1), 0.1)
    with pytest.raises(sc.SimulationError, match=r"step failed.*deployment of 'cable': "
                                                 r"length\(.*\) = .* must lie in \(0, 5\]"
                       ) as failure:
        sc.simulate(system, t_end=5.0, dt=0.01, max_halvings=4)
    kept = failure.value.result
    ell = kept.q[:, system.dofs(reel)[0]]
    assert len(kept) > 10 and 0 < ell[-1] < 0.5 and np.all(np.diff(ell) < 0)
