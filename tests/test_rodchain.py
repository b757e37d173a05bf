"""Rod-chain tether (``skfem_cable.rodchain``): the mass matrix and its O(n) solve against
dense linear algebra, forces and energies against finite differences and brute-force
quadrature, the paper's energy experiment, the swinging steel chain against a rigid-link
reference, small oscillations against rigid-chain and Bessel frequencies, and the moving
anchor against independent solutions."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import eigh, lu_factor, lu_solve
from scipy.special import jn_zeros

from skfem_cable.rodchain import RodChain, RodChainDivergence, circular_anchor, rk4_step
from skfem_cable.scenes import hanging_chain as scene
from skfem_cable.scenes import rigid_chain as reference
from skfem_cable.scenes import rodchain_studies as studies

G = np.array([0.0, -9.81, 0.0])
ROOT = Path(__file__).resolve().parents[1]


def load_demo():
    spec = importlib.util.spec_from_file_location("hanging_chain",
                                                  ROOT / "demos" / "hanging_chain.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


paper_chain, paper_state = studies.paper_chain, studies.paper_state


def random_chain(n, seed, **kwargs):
    rng = np.random.default_rng(seed)
    return RodChain(rng.uniform(0.05, 2.0, n), rng.uniform(0.3, 1.5, n),
                    rng.uniform(50.0, 500.0, n), **kwargs)


def random_rods(chain, seed, stretch=(0.8, 1.2)):
    rng = np.random.default_rng(seed)
    d = rng.standard_normal((chain.n, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    return d * (chain.lengths * rng.uniform(*stretch, chain.n))[:, None]


def fd_gradient(f, q, h=1e-6):
    grad = np.zeros_like(q)
    for idx in np.ndindex(q.shape):
        e = np.zeros_like(q)
        e[idx] = h
        grad[idx] = (f(q + e) - f(q - e)) / (2 * h)
    return grad


# --- mass matrix and its O(n) solve (Eqs. 6-8, 22-30) ------------------------------------------
@pytest.mark.parametrize("n", [1, 2, 3, 7, 40])
def test_mass_matrix_definition_closed_form_and_factorisation(n):
    m = np.random.default_rng(n).uniform(0.1, 3.0, n)
    chain = RodChain(m, np.ones(n), np.ones(n))
    Phi = np.tril(np.ones((n, n)))
    I = np.eye(n)
    D = np.diag(m)
    M7 = (Phi - I / 2).T @ D @ (Phi - I / 2) + D / 12  # Eq. 7
    np.testing.assert_allclose(chain.mass_matrix(), M7, rtol=1e-14, atol=1e-14)
    eps = np.eye(n, k=-1)
    G25 = D / 3 + (eps.T @ D + D @ eps) / 6 + eps.T @ D @ eps / 3  # Eqs. 24-25
    B = chain.mass_factor().toarray()
    assert np.all(np.triu(B, 1) == 0) and np.all(np.tril(B, -2) == 0)  # lower bidiagonal
    np.testing.assert_allclose(B.T @ B, G25, rtol=1e-13, atol=1e-15)  # Eqs. 26-27
    np.testing.assert_allclose(Phi.T @ B.T @ B @ Phi, M7, rtol=1e-13, atol=1e-14)


def mass_matvec_longdouble(chain, x):
    """``M x`` in long double from the closed form of Eq. 8 in O(n):
    ``(M x)_i = c_i sum_{j<=i} x_j + sum_{j>i} c_j x_j - m_i x_i / 6``."""
    c = chain.first_moments.astype(np.longdouble)[:, None]
    m = chain.masses.astype(np.longdouble)[:, None]
    x = x.astype(np.longdouble).reshape(chain.n, -1)
    cx = c * x
    return c * np.cumsum(x, axis=0) + np.cumsum(cx[::-1], axis=0)[::-1] - cx - m * x / 6


def refined_dense_solve(chain, M, b):
    """Dense LU solve refined with long-double residuals: accurate to ~eps, unlike plain LU
    whose forward error grows like cond(M) eps ~ n^2 eps."""
    lu = lu_factor(M)
    x = lu_solve(lu, b).reshape(chain.n, -1)
    bl = b.astype(np.longdouble).reshape(chain.n, -1)
    for _ in range(3):
        x = x + lu_solve(lu, (bl - mass_matvec_longdouble(chain, x)).astype(float))
    return x.reshape(b.shape)


@pytest.mark.parametrize("n", [1, 2, 3, 10, 100, 1000])
def test_solve_mass_against_dense_solves(n):
    rng = np.random.default_rng(1000 + n)
    # exact reference: integer masses (multiples of 6) and solution give an exact M x
    m_int = 6 * rng.integers(1, 100, n)
    x_true = rng.integers(-1000, 1000, (n, 3)).astype(float)
    chain = RodChain(m_int.astype(float), np.ones(n), np.ones(n))
    M = chain.mass_matrix()
    assert np.all(M == np.round(M))  # integer entries, so b below is exact
    b = M @ x_true
    err = np.linalg.norm(chain.solve_mass(b) - x_true) / np.linalg.norm(x_true)
    assert err < 1e-12
    # random real masses and right-hand sides (n,) and (n, 3)
    chain = RodChain(rng.uniform(0.1, 1.0, n), np.ones(n), np.ones(n))
    M = chain.mass_matrix()
    for b in (rng.standard_normal(n), rng.standard_normal((n, 3))):
        x = chain.solve_mass(b)
        assert x.shape == b.shape
        inf = np.inf
        backward = np.linalg.norm((b - M @ x).ravel(), inf) / (
            np.linalg.norm(M, inf) * np.linalg.norm(x.ravel(), inf)
            + np.linalg.norm(b.ravel(), inf))  # normwise backward error (Rigal-Gaches)
        assert backward < 1e-15
        if np.finfo(np.longdouble).eps < 1e-18:  # extended precision available
            x_ref = refined_dense_solve(chain, M, b)
            assert np.linalg.norm(x - x_ref) / np.linalg.norm(x_ref) < 1e-12
        if n <= 100:  # plain LU is itself accurate to ~cond(M) eps ~ n^2 eps
            x_lu = np.linalg.solve(M, b)
            assert np.linalg.norm(x - x_lu) / np.linalg.norm(x_lu) < 1e-12


def test_solve_mass_rejects_bad_rhs():
    chain = RodChain.uniform(4, mass=1.0, length=1.0, E=1.0, A=1.0)
    with pytest.raises(ValueError, match="rhs must have shape"):
        chain.solve_mass(np.ones(5))
    with pytest.raises(ValueError, match="rhs must have shape"):
        chain.solve_mass(np.ones((4, 3, 1)))
    with pytest.raises(ValueError, match="rhs must be finite"):
        chain.solve_mass(np.array([1.0, np.nan, 0.0, 0.0]))


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"masses": [1.0, -1.0], "lengths": [1, 1], "EA": [1, 1]}, "masses must be finite and > 0"),
        ({"masses": [1.0, 1.0], "lengths": [1], "EA": [1, 1]}, "lengths must have one entry"),
        ({"masses": [1.0, 1.0], "lengths": [1, 1], "EA": [1, 0]}, "EA must be finite and > 0"),
        ({"masses": [], "lengths": [], "EA": []}, "masses must be a non-empty"),
        ({"masses": [1.0], "lengths": [np.inf], "EA": [1]}, "lengths must be finite"),
        ({"masses": [1.0], "lengths": [1], "EA": [1], "compression": "yes"}, "compression"),
    ],
)
def test_constructor_validation(kwargs, match):
    with pytest.raises(ValueError, match=match):
        RodChain(**kwargs)


def test_uniform_constructor_and_validation():
    chain = RodChain.uniform(3, mass=0.5, length=2.0, E=2e9, A=1e-6)
    np.testing.assert_array_equal(chain.EA, [2e3] * 3)
    assert chain.total_mass == 1.5 and chain.rest_length == 6.0
    for kwargs, match in [({"n": 0}, "n must be an integer >= 1"),
                          ({"n": 2.5}, "n must be an integer"),
                          ({"mass": 0.0}, "mass must be finite and > 0"),
                          ({"E": -1.0}, "E must be finite and > 0"),
                          ({"A": "x"}, "A must be a real number")]:
        args = {"n": 3, "mass": 0.5, "length": 2.0, "E": 2e9, "A": 1e-6} | kwargs
        with pytest.raises(ValueError, match=match):
            RodChain.uniform(**args)


# --- forces and energies (Eqs. 3-4, 10-16) ----------------------------------------------------
@pytest.mark.parametrize("compression", [True, False])
def test_elastic_force_is_gradient_of_elastic_energy(compression):
    chain = random_chain(6, 1, compression=compression)
    q = random_rods(chain, 2)
    grad = fd_gradient(chain.elastic_energy, q)
    np.testing.assert_allclose(chain.elastic_force(q), grad, rtol=1e-7, atol=1e-7)
    T = chain.tension(q)
    compressed = np.linalg.norm(q, axis=1) < chain.lengths
    assert compressed.any() and (~compressed).any()
    assert np.all(T[~compressed] > 0)
    assert np.all(T[compressed] < 0) if compression else np.all(T[compressed] == 0)


def test_gravity_and_tip_forces_are_gradients_of_potential():
    chain = random_chain(5, 3)
    q = random_rods(chain, 4)
    P = np.array([0.3, -1.2, 2.0])
    origin = np.array([1.0, 2.0, 3.0])
    Q = chain.generalized_forces(q, gravity=G, tip_force=P, anchor=origin)
    grad = fd_gradient(lambda x: chain.potential_energy(x, G, origin, P), q)
    np.testing.assert_allclose(Q, -grad, rtol=1e-8, atol=1e-8)
    np.testing.assert_allclose(Q, np.outer(chain.first_moments, G) + P, rtol=1e-14)


def virtual_work(chain, q, v, dq, f, t, samples=4001):
    """``sum_i int_0^{l_i} f(r) . dr dl`` by the trapezoidal rule on each rod."""
    s = np.linspace(0.0, 1.0, samples)
    start = np.cumsum(q, axis=0) - q
    ustart = np.cumsum(v, axis=0) - v
    dstart = np.cumsum(dq, axis=0) - dq
    r = start[:, None] + s[None, :, None] * q[:, None]
    u = ustart[:, None] + s[None, :, None] * v[:, None]
    dr = dstart[:, None] + s[None, :, None] * dq[:, None]
    integrand = np.sum(f(t, r, u) * dr, axis=-1)
    ds = np.diff(s)
    per_rod = np.sum(0.5 * (integrand[:, 1:] + integrand[:, :-1]) * ds, axis=1)
    return float(np.sum(np.linalg.norm(q, axis=1) * per_rod))


def test_line_loads_satisfy_virtual_work():
    """Eqs. 14-16: ``Q . dq`` equals the virtual work of the line load for any ``dq``."""
    chain = random_chain(5, 5)
    rng = np.random.default_rng(6)
    q, v = random_rods(chain, 7), rng.standard_normal((5, 3))

    def field(t, r, u):  # smooth, position-, velocity- and time-dependent (N/m)
        return np.stack([np.sin(r[..., 1]) + t, r[..., 0] * r[..., 2], -0.3 * u[..., 2]], -1)

    Q = chain.generalized_forces(q, v, 0.7, line_load=field, quadrature=8)
    w = np.array([0.5, -2.0, 1.0])
    Qw = chain.generalized_forces(q, line_load=w)
    Qc = chain.generalized_forces(q, line_load=lambda t, r, u: np.broadcast_to(w, r.shape))
    np.testing.assert_allclose(Qc, Qw, rtol=1e-13)
    for _ in range(3):
        dq = rng.standard_normal((5, 3))
        W = virtual_work(chain, q, v, dq, field, 0.7)
        assert abs(np.sum(Q * dq) - W) < 1e-6 * max(1.0, abs(W))
        Ww = virtual_work(chain, q, v, dq, lambda t, r, u: np.broadcast_to(w, r.shape), 0.0)
        assert abs(np.sum(Qw * dq) - Ww) < 1e-9 * max(1.0, abs(Ww))


def test_line_load_shape_is_checked():
    chain = random_chain(3, 8)
    q = random_rods(chain, 9)
    with pytest.raises(ValueError, match="line_load"):
        chain.generalized_forces(q, line_load=lambda t, r, u: np.zeros(3))


def test_kinetic_energy_three_ways():
    """Eq. 4 (O(n)) against ``1/2 v^T M v`` (Eq. 6) and a brute-force mass integral."""
    chain = random_chain(7, 10)
    rng = np.random.default_rng(11)
    v = rng.standard_normal((7, 3))
    u0 = np.array([0.4, -0.1, 0.2])
    T = chain.kinetic_energy(v)
    np.testing.assert_allclose(T, 0.5 * np.sum(v * (chain.mass_matrix() @ v)), rtol=1e-13)
    s = np.linspace(0.0, 1.0, 20001)
    U = u0 + np.cumsum(v, axis=0) - v
    vel = U[:, None] + s[None, :, None] * v[:, None]
    dens = np.sum(vel * vel, -1)
    brute = 0.5 * np.sum(chain.masses * np.trapezoid(dens, s, axis=1))
    np.testing.assert_allclose(chain.kinetic_energy(v, u0), brute, rtol=1e-8)
    vt = np.stack([v, 2 * v])  # leading time axis
    np.testing.assert_allclose(chain.kinetic_energy(vt), [T, 4 * T], rtol=1e-13)


def test_acceleration_solves_equations_of_motion():
    chain = random_chain(9, 12)
    q = random_rods(chain, 13)
    P = np.array([0.0, 0.0, 1.5])
    a = chain.acceleration(q, gravity=G, tip_force=P)
    rhs = np.outer(chain.first_moments, G) + P - chain.elastic_force(q)  # Eq. 18
    np.testing.assert_allclose(chain.mass_matrix() @ a, rhs, rtol=1e-10, atol=1e-10)


def test_acceleration_rejects_zero_length_rod():
    chain = random_chain(3, 15)
    q = random_rods(chain, 16)
    q[1] = 0.0
    with pytest.raises(ValueError, match="rod 1 has zero length"):
        chain.acceleration(q, gravity=G)
    assert np.all(np.isfinite(chain.generalized_forces(q, gravity=G)))


def test_static_equilibrium_is_at_rest():
    chain = random_chain(8, 14)
    P = np.array([2.0, -1.0, 0.5])
    q = chain.static_equilibrium(G, P)
    a = chain.acceleration(q, gravity=G, tip_force=P)
    assert np.abs(a).max() < 1e-10 * np.linalg.norm(G)
    res = chain.simulate(q, np.zeros_like(q), 1.0, 1e-3, gravity=G, tip_force=P)
    assert np.abs(res.rods - q).max() < 1e-12
    with pytest.raises(ValueError, match="tensions every rod"):
        chain.static_equilibrium([0.0, 0.0, 0.0])


# --- the paper's energy experiment (Sect. 3, Fig. 3) --------------------------------------------
def relative_energy_error(res, every=1):
    """Eq. 31 over every ``every``-th saved step of ``res``."""
    E = res.energy["total"][::every]
    return np.abs(E - E[0]).max() / abs(E[0])  # Eq. 31


@pytest.fixture(scope="module")
def paper_run():
    """The paper's energy experiment: RK4 over 5 s at 1e-4 s, every step saved.  One run
    serves the tests that read it (a run saving every 10th step has the same energies at
    those steps, bit for bit)."""
    return paper_chain().simulate(*paper_state(), t_end=5.0, dt=1e-4, gravity=G, method="rk4")


def test_paper_energy_experiment_rk4(paper_run):
    res = paper_run
    assert res.t.shape == (50001,) and res.joints.shape == (50001, 21, 3)
    E0 = res.energy["total"][0]
    np.testing.assert_allclose(res.energy["kinetic"][0], 0.05 * (2665 + 20 / 12), rtol=1e-14)
    np.testing.assert_allclose(res.energy["potential"][0], -0.981 * 200, rtol=1e-14)
    assert res.energy["elastic"][0] == 0 and E0 < 0
    err = relative_energy_error(res)
    assert err < 6e-6  # the paper's bound (Fig. 3)
    assert err < 1e-9  # measured 1.7e-10
    np.testing.assert_allclose(res.joints[:, 1:] - res.joints[:, :-1], res.rods, atol=1e-12)


def test_energy_dict_has_the_cable_keys_and_balance_stays_small(paper_run):
    """The energy experiment: the dict of the cable ``Result.energy`` (no bending, no
    dissipation, no work of the conservative loads) and a balance of 1.7e-10 E(0) (at
    every step)."""
    E = paper_run.energy
    assert set(E) == {"kinetic", "axial", "bending", "elastic", "potential", "dissipated",
                      "external_work", "total", "balance"}
    np.testing.assert_array_equal(E["axial"], E["elastic"])
    for key in ("bending", "dissipated", "external_work"):
        assert not E[key].any()
    np.testing.assert_allclose(E["total"], E["kinetic"] + E["elastic"] + E["potential"],
                               rtol=1e-15)
    assert E["balance"][0] == 0
    assert np.abs(E["balance"]).max() < 1e-9 * abs(E["total"][0])  # measured 1.7e-10


def test_line_load_work_closes_the_energy_balance():
    """A uniform line load and a velocity-dependent callable one (drag) do work: the
    trapezoidal ``external_work`` over the saved steps closes the balance to second order
    in the output spacing (measured 2.2e-9 and 2.2e-7 of the work for every step and every
    10th step)."""
    chain = paper_chain()
    q0, v0 = paper_state()
    w = np.array([0.3, 0.0, 0.1])
    for every, tol in ((1, 1e-8), (10, 1e-6)):
        res = chain.simulate(q0, v0, 2.0, 1e-4, gravity=G, line_load=w, output_every=every)
        work = res.energy["external_work"]
        assert abs(work[-1]) > 10.0
        assert np.abs(res.energy["balance"]).max() < tol * np.abs(work).max()

    def drag(t, r, u):
        return np.broadcast_to(w, r.shape) - 0.05 * u

    res = chain.simulate(q0, v0, 0.2, 1e-4, gravity=G, line_load=drag, output_every=1)
    work = res.energy["external_work"]
    assert abs(work[-1]) > 0.1
    assert np.abs(res.energy["balance"]).max() < 1e-8 * np.abs(work).max()


def test_energy_error_converges_at_fifth_order_in_dt(paper_run):
    """The energy error every 1e-3 s at 4e-4, 2e-4 and 1e-4 s steps (the last the paper's
    run, read every 10th step)."""
    chain = paper_chain()
    q0, v0 = paper_state()
    dts = [4e-4, 2e-4, 1e-4]
    errs = [relative_energy_error(chain.simulate(q0, v0, 5.0, dt, gravity=G,
                                                 output_every=int(round(1e-3 / dt))))
            for dt in dts[:-1]] + [relative_energy_error(paper_run, every=10)]
    order = np.polyfit(np.log(dts), np.log(errs), 1)[0]
    assert 4.6 < order < 5.6, (errs, order)


def test_adaptive_paths_agree_with_rk4():
    chain = paper_chain()
    q0, v0 = paper_state()
    ref = chain.simulate(q0, v0, 1.0, 1e-4, gravity=G, output_every=100)
    for method in ("RK45", "DOP853"):
        res = chain.simulate(q0, v0, 1.0, 1e-2, gravity=G, method=method, rtol=1e-10,
                             atol=1e-12)
        assert res.stats["nfev"] > 0
        assert np.abs(res.joints - ref.joints).max() < 1e-7 * chain.rest_length
        assert relative_energy_error(res) < 1e-8


def test_python_rk4_path_matches_compiled_path():
    """A callable line load runs the RK4 loop in Python; with the same loads it must
    reproduce the compiled loop to round-off."""
    chain = paper_chain()
    q0, v0 = paper_state()
    w = np.array([0.2, 0.0, -0.1])
    fast = chain.simulate(q0, v0, 0.2, 1e-3, gravity=G, line_load=w, output_every=10)
    slow = chain.simulate(q0, v0, 0.2, 1e-3, gravity=G, output_every=10,
                          line_load=lambda t, r, u: np.broadcast_to(w, r.shape))
    np.testing.assert_allclose(slow.rods, fast.rods, rtol=0, atol=1e-11)
    np.testing.assert_allclose(slow.rod_velocities, fast.rod_velocities, rtol=0, atol=1e-9)


def test_slack_chain_never_pushes_and_conserves_energy():
    q0, v0 = paper_state()
    bar = paper_chain().simulate(q0, v0, 2.0, 1e-4, gravity=G, output_every=10)
    slack = paper_chain(compression=False).simulate(q0, v0, 2.0, 1e-4, gravity=G,
                                                    output_every=10)
    assert bar.tension.min() < -1.0  # the paper's rods are compressed in this experiment
    assert slack.tension.min() == 0.0
    assert relative_energy_error(slack) < 1e-6  # measured 3.3e-7 (force kink at l = l0)


def test_simulate_validates_inputs():
    chain = paper_chain()
    q0, v0 = paper_state()
    cases = [({"dt": 0.3}, "multiple"),
             ({"t_end": -1.0}, "t_end must be finite and > 0"),
             ({"dt": 0.0}, "dt must be finite and > 0"),
             ({"method": "euler"}, "method must be one of"),
             ({"gravity": [0, 1]}, "gravity must be a finite 3-vector"),
             ({"output_every": 0}, "output_every"),
             ({"output_every": 3}, "multiple of output_every"),
             ({"anchor": lambda t: t}, "anchor must map"),
             ({"quadrature": 0}, "quadrature"),
             ({"tip_force": [np.nan, 0, 0]}, "tip_force"),
             ({"rtol": 0.0, "method": "RK45"}, "rtol"),
             ({"max_strain": -1.0}, "max_strain")]
    for kwargs, match in cases:
        with pytest.raises(ValueError, match=match):
            chain.simulate(q0, v0, **({"t_end": 1.0, "dt": 0.005} | kwargs))
    with pytest.raises(ValueError, match="q0 must have shape"):
        chain.simulate(q0[:5], v0, 1.0, 0.005)
    with pytest.raises(ValueError, match="v0 must be a finite array"):
        chain.simulate(q0, np.full_like(v0, np.nan), 1.0, 0.005)


@pytest.mark.parametrize("n", [1, 2, 5, 30])
def test_max_frequency_is_highest_axial_eigenfrequency(n):
    chain = random_chain(n, 40 + n)
    lam = eigh(np.diag(chain.EA / chain.lengths), chain.mass_matrix(), eigvals_only=True)
    np.testing.assert_allclose(chain.max_frequency(), np.sqrt(lam.max()), rtol=1e-12)
    bound = np.sqrt(np.max(12 * chain.EA / (chain.lengths * chain.masses)))
    assert chain.max_frequency() <= bound


def test_unstable_step_is_rejected_or_stops_with_diagnostic():
    chain = scene.steel_chain(11)
    q0, v0 = scene.release_state(chain)
    dt = chain.stable_dt()
    with pytest.raises(ValueError, match="exceeds the RK4 stability limit"):
        chain.simulate(q0, v0, 1e-2, 1e-4, gravity=G)  # the paper's step
    with pytest.raises(RodChainDivergence, match="diverged at t = ") as info:
        chain.simulate(q0, v0, 2000 * 1.3 * dt, 1.3 * dt, gravity=G, check_stability=False)
    err = info.value
    assert 0 < err.t < 2000 * 1.3 * dt and err.step is not None and 0 <= err.rod < chain.n
    assert "stable for dt below" in str(err)
    res = chain.simulate(q0, v0, 20000 * 0.99 * dt, 0.99 * dt, gravity=G, output_every=100)
    assert np.abs(res.energy["total"]).max() < 1e-8 * res.energy["kinetic"].max()


def test_adaptive_failure_is_reported():
    chain = paper_chain()
    q0, v0 = paper_state()
    with pytest.raises(RodChainDivergence, match="diverged at t = "):
        chain.simulate(q0, v0, 1.0, 0.01, gravity=G, method="RK45", max_strain=1e-3)


# --- the steel chain (paper Sect. 3, Figs. 4-5) -------------------------------------------------
def test_steel_chain_matches_rigid_link_reference():
    chain = scene.steel_chain(11)
    t, tip = scene.free_end_trajectory(11, t_end=1.0)
    assert t.shape == (10001,) and tip.shape == (10001, 3)
    _, rigid = reference.rigid_chain_trajectory(chain.masses, chain.lengths, 1.0, 1e-4)
    dev = np.linalg.norm(tip - rigid, axis=1).max() / chain.rest_length
    assert dev < 1e-5  # measured 4.1e-6; the paper's ADAMS check: < 8e-3 m (0.7 %)
    assert np.abs(tip[:, 2]).max() == 0  # planar motion


def test_stiff_chain_converges_to_rigid_chain_as_inverse_stiffness():
    devs = []
    for scale in (1.0, 10.0):
        n = 4
        A = np.pi * 1e-6
        l0 = 1.1 / n
        chain = RodChain.uniform(n, 7801 * A * l0, l0, 207e9 * scale, A)
        dt = rk4_step(chain, 1e-3)
        res = chain.simulate(*scene.release_state(chain), 0.4, dt, gravity=G,
                             output_every=int(round(1e-3 / dt)))
        _, rigid = reference.rigid_chain_trajectory(chain.masses, chain.lengths, 0.4, 1e-3)
        devs.append(np.linalg.norm(res.free_end - rigid, axis=1).max())
    assert 7 < devs[0] / devs[1] < 13, devs


@pytest.mark.slow
def test_steel_chain_adaptive_agrees_with_rk4():
    """DOP853 on the stiff steel chain (its axial wave crosses it every 0.2 ms) against
    RK4 over 0.05 s, 230 crossings, the free end fallen 12 mm: 2.5e-14 L apart (over 0.1
    s 8.8e-14 L)."""
    t, rk4 = scene.free_end_trajectory(11, t_end=0.05)
    _, dop = scene.free_end_trajectory(11, t_end=0.05, method="DOP853", rtol=1e-10, atol=1e-12)
    assert np.abs(dop - rk4).max() < 1e-8 * scene.STEEL["length"]


def test_demo_runs_reduced():
    out = load_demo().main(n_rods=4, t_end=0.3)
    assert out["max_dev_rigid_rel"] < 2e-5
    assert out["max_dev_half_step_rel"] < 1e-8


# --- small oscillations (validation 4) ------------------------------------------------------------
def transverse_frequencies(chain, q_eq):
    return studies.transverse_frequencies(chain, q_eq, G)


def test_single_rod_is_a_compound_pendulum():
    chain = RodChain.uniform(1, mass=0.7, length=0.8, E=1e9, A=1e-6)
    q = chain.static_equilibrium(G)
    l = np.linalg.norm(q)
    np.testing.assert_allclose(l, 0.8 * (1 + 0.35 * 9.81 / 1e3), rtol=1e-14)
    np.testing.assert_allclose(transverse_frequencies(chain, q), np.sqrt(1.5 * 9.81 / l),
                               rtol=1e-10)


def test_linearised_chain_matches_rigid_link_frequencies():
    chain = paper_chain()  # 2 % static stretch: rigid links of the stretched lengths
    q = chain.static_equilibrium(G)
    w = transverse_frequencies(chain, q)
    w_rigid = reference.rigid_chain_frequencies(chain.masses, np.linalg.norm(q, axis=1), 9.81)
    np.testing.assert_allclose(w, w_rigid, rtol=1e-9)  # measured 5e-14


def test_frequencies_converge_to_continuous_hanging_chain():
    """omega_k -> (j_{0,k} / 2) sqrt(g / L) (Bessel J0 zeros) at second order in 1/n."""
    L, g = 20.0, 9.81
    w_cont = jn_zeros(0, 3) / 2 * np.sqrt(g / L)
    errs = []
    for n in (20, 40, 80):
        chain = RodChain.uniform(n, mass=1.0 / n, length=L / n, E=1e9, A=1.0)  # strain 1e-8
        w = transverse_frequencies(chain, chain.static_equilibrium(G))[:3]
        errs.append(w / w_cont - 1)
    errs = np.array(errs)
    assert np.all(errs > 0)  # the discrete chain is stiffer
    order = np.log2(errs[:-1] / errs[1:])
    assert np.all((order > 1.9) & (order < 2.1)), order
    assert errs[-1, 0] < 5e-6  # rigid links: 4.8e-6 at n = 80


def test_simulated_small_oscillation_has_linear_frequency():
    chain = RodChain.uniform(10, mass=0.1, length=1.0, E=1e11, A=1e-6)
    q_eq = chain.static_equilibrium(G)
    lengths = np.linalg.norm(q_eq, axis=1)
    H, inertia, moment = reference.rigid_chain_matrices(chain.masses, lengths)
    w2, modes = eigh(9.81 * np.diag(moment), H + np.diag(inertia))
    for k in (0, 1):
        theta = 1e-3 * modes[:, k] / np.abs(modes[:, k]).max()
        q0 = lengths[:, None] * np.column_stack([np.sin(theta), -np.cos(theta), 0 * theta])
        period = 2 * np.pi / np.sqrt(w2[k])
        dt = 5e-4
        t_end = dt * np.ceil(3 * period / dt)
        res = chain.simulate(q0, np.zeros_like(q0), t_end, dt, gravity=G)
        x = res.free_end[:, 0]
        i = np.nonzero(np.sign(x[1:]) != np.sign(x[:-1]))[0]
        crossings = res.t[i] - x[i] * dt / (x[i + 1] - x[i])
        half_period = np.polyfit(np.arange(crossings.size), crossings, 1)[0]
        np.testing.assert_allclose(np.pi / half_period, np.sqrt(w2[k]), rtol=1e-6)


# --- moving anchor ------------------------------------------------------------------------------
def test_anchor_in_uniform_motion_changes_nothing_relative():
    chain = random_chain(5, 20)
    q0 = chain.static_equilibrium(G) + 0.05
    v0 = np.zeros_like(q0)
    u = np.array([3.0, -1.0, 2.0])

    def moving(t):
        z = np.zeros((t.size, 3))
        return np.outer(t, u), z + u, z

    fixed = chain.simulate(q0, v0, 1.0, 1e-3, gravity=G, output_every=10)
    moved = chain.simulate(q0, v0, 1.0, 1e-3, gravity=G, output_every=10, anchor=moving)
    np.testing.assert_allclose(moved.rods, fixed.rods, rtol=0, atol=1e-14)
    np.testing.assert_allclose(moved.joints - np.outer(moved.t, u)[:, None], fixed.joints,
                               rtol=0, atol=1e-12)


def test_circular_anchor_derivatives():
    motion = circular_anchor(2.0, 3.0, center=[1.0, 0.0, 0.0], normal=[1.0, 1.0, 1.0], phase=0.3)
    t = np.linspace(0.0, 2.0, 7)
    h = 1e-6
    r, v, a = motion(t)
    rp, vp, _ = motion(t + h)
    rm, vm, _ = motion(t - h)
    np.testing.assert_allclose((rp - rm) / (2 * h), v, atol=1e-7)
    np.testing.assert_allclose((vp - vm) / (2 * h), a, atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(r - [1.0, 0.0, 0.0], axis=1), 2.0, rtol=1e-14)
    np.testing.assert_allclose((r - [1.0, 0.0, 0.0]) @ np.ones(3), 0.0, atol=1e-14)
    with pytest.raises(ValueError, match="radius"):
        circular_anchor(0.0, 1.0)


def test_spinning_hub_keeps_radial_relative_equilibrium():
    """A chain on a hub of radius R0 spinning at Omega, no gravity: the radial line rotating
    rigidly is an exact solution.  Newton's law on each rod gives its force as the mean of
    the continuous tension along it, ``T_i = H_{i-1} - Omega^2 m_i (R_{i-1}/2 + L_i/6)``
    with ``H_{i-1} = Omega^2 sum_{k>=i} m_k r_ck`` the hinge force at ``O_{i-1}``."""
    chain = RodChain(np.array([0.1, 0.2, 0.15, 0.1, 0.05]), np.array([1.0, 0.8, 1.2, 1.0, 0.5]),
                     np.full(5, 500.0))
    R0, Om = 1.5, 2.0
    m = chain.masses
    L = chain.lengths.copy()
    for _ in range(100):  # fixed point L = l0 (1 + T / EA)
        R = R0 + np.concatenate([[0.0], np.cumsum(L)])
        hinge = Om**2 * np.cumsum((m * 0.5 * (R[:-1] + R[1:]))[::-1])[::-1]
        T = hinge - Om**2 * m * (R[:-1] / 2 + L / 6)
        L = chain.lengths * (1 + T / chain.EA)
    assert np.max(L / chain.lengths) > 1.01  # visibly stretched
    q0 = np.column_stack([L, 0 * L, 0 * L])
    v0 = np.column_stack([0 * L, Om * L, 0 * L])  # Omega z x q
    period = 2 * np.pi / Om
    res = chain.simulate(q0, v0, 2 * period, period / 4000, anchor=circular_anchor(R0, Om),
                         output_every=100)
    e = np.column_stack([np.cos(Om * res.t), np.sin(Om * res.t), 0 * res.t])
    expected = L[None, :, None] * e[:, None, :]
    assert np.abs(res.rods - expected).max() < 1e-9 * L.sum()
    F0 = res.anchor_force()  # pulls the tether towards the hub axis
    np.testing.assert_allclose(F0, -hinge[0] * e, rtol=0, atol=1e-7 * hinge[0])  # 8.7e-9


def test_rod_on_oscillating_pivot_matches_pendulum_equation():
    """One stiff rod, pivot ``x_0 = A sin(nu t)``: theta'' = -3 (g sin th + x_0'' cos th) / 2l."""
    l, A_, nu = 0.6, 0.05, 7.0
    chain = RodChain.uniform(1, mass=1.0, length=l, E=1e15, A=1e-6)  # strain ~1e-8

    def pivot(t):
        z = np.zeros((t.size, 3))
        x, v, a = z.copy(), z.copy(), z.copy()
        x[:, 0], v[:, 0], a[:, 0] = A_ * np.sin(nu * t), A_ * nu * np.cos(nu * t), \
            -A_ * nu**2 * np.sin(nu * t)
        return x, v, a

    th0 = 0.3
    q0 = l * np.array([[np.sin(th0), -np.cos(th0), 0.0]])
    v0 = np.zeros((1, 3))
    res = chain.simulate(q0, v0, 3.0, 1e-5, gravity=G, anchor=pivot, output_every=100)

    def rhs(t, y):
        a0 = -A_ * nu**2 * np.sin(nu * t)
        return [y[1], -1.5 / l * (9.81 * np.sin(y[0]) + a0 * np.cos(y[0]))]

    # the pivot's initial velocity A nu is shared by the rod: its relative velocity is zero
    sol = solve_ivp(rhs, (0, 3.0), [th0, 0.0], t_eval=res.t, rtol=1e-12, atol=1e-12,
                    method="DOP853")
    theta = np.arctan2(res.rods[:, 0, 0], -res.rods[:, 0, 1])
    assert np.abs(theta - sol.y[0]).max() < 1e-7
    assert np.abs(theta).max() > 0.3  # the drive does something


def test_moving_anchor_energy_balance():
    """The anchor's work ``int F_0 . u_0 dt`` equals the change of the total energy."""
    chain = random_chain(4, 30)
    q0 = chain.static_equilibrium(G)

    def shaker(t):
        w = np.array([3.0, 5.0, 0.0])
        amp = np.array([0.2, 0.1, 0.0])
        return (amp * np.sin(np.outer(t, w)), amp * w * np.cos(np.outer(t, w)),
                -amp * w**2 * np.sin(np.outer(t, w)))

    res = chain.simulate(q0, np.zeros_like(q0), 2.0, 2e-4, gravity=G, anchor=shaker)
    power = np.sum(res.anchor_force() * shaker(res.t)[1], axis=1)
    work = np.concatenate([[0.0], np.cumsum(0.5 * (power[1:] + power[:-1]) * np.diff(res.t))])
    dE = res.energy["total"] - res.energy["total"][0]
    assert np.abs(dE).max() > 0.1  # energy is pumped in and out
    assert np.abs(dE - work).max() < 1e-6 * np.abs(dE).max()
    # the result books the same work (with the momentum balance for F_0)
    np.testing.assert_allclose(res.energy["external_work"], work, rtol=0,
                               atol=1e-10 * np.abs(work).max())
    assert np.abs(res.energy["balance"]).max() < 1e-6 * np.abs(dE).max()
