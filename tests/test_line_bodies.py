"""The built-in line loads on a line body that is not a ``Cable`` (issue 46, must-show 3):
the quadratic string of ``tests/line_body.py`` receives ``Gravity``, ``LineLoad``,
``UniformLineLoad`` (``add_line_load``), ``Buoyancy``, ``MorisonDrag`` with added mass,
``FreeMolecularDrag`` and the differential gravity of an orbit through its line-body hook
``line_points`` (``skfem_cable.core.lines``) and ``mass_points`` only.  For each: the force
against a closed form or a numpy quadrature over ``LinePoints.at``, the tangent against
central differences (``sc.check_tangent``) and a short run on the compiled step.  On a
cable, the ported loads equal the values of the hand-written loops they replace (commit
35fde8e) on a curved moving state; a body without the hook is refused."""

import numpy as np
import pytest
from line_body import QuadraticString

import skfem_cable as sc
from skfem_cable.core.contract import Evaluation
from skfem_cable.loads.line import UniformLineLoad
from skfem_cable.space.tidal import differential_gravity

RHO_A, EA, LENGTH = 0.8, 5e3, 3.0
START, END = np.array([0.0, 0.0, -2.0]), np.array([3.0, 0.0, -2.0])


def string(n=4):
    return QuadraticString(START, END, n, EA, RHO_A)


def moved(system, seed=1):
    """A curved state with velocities: ``(q, v)``."""
    rng = np.random.default_rng(seed)
    return (system.q0 + 0.05 * rng.standard_normal(system.n_dofs),
            0.6 * rng.standard_normal(system.n_dofs))


def external_force(system, q, v, t=0.0):
    """The external force: constant (``Layout.f_const``) plus non-constant (``f_nc``)."""
    info = system.evaluate(q, v, t, np.zeros(system.n_constraints))[1]
    return system.layout.f_const + info["f_nc"]


def quadrature(system, body, force):
    """``sum w S_A f`` in numpy over the body's points, ``force(X, A, V) -> (ne, nq, 3)``
    with the points' positions, slopes and velocities (``LinePoints.at``)."""
    points = body.line_points(system)
    return lambda q, v: _scatter(system, points, force(*points.at(q, v)))


def _scatter(system, points, F):
    ne, nq, nf = points.S.shape
    fe = np.einsum("eg,egA,egi->eAi", points.w, points.S, F).reshape(ne, 3 * nf)
    out = np.zeros(system.n_dofs)
    np.add.at(out, points.edofs, fe)
    return out


def tangent_errors(system, q, v, prefix, t=0.0):
    check = sc.check_tangent(system, q, v, t=t)
    errors = {p.wrt: p.error for p in check.parts if p.name.startswith(prefix)}
    assert errors, str(check)
    return errors, check


def run(system, steps=10, dt=2e-3):
    """A short run with the string's ends pinned."""
    result = sc.simulate(system, t_end=steps * dt, dt=dt, rho_inf=0.8)
    assert result.stats["steps"] == steps
    return result


def pinned(*loads, orbit=None):
    body = string()
    system = sc.System([body]).pin(body.node(0)).pin(body.node(-1))
    if orbit is not None:
        system.add_orbit(orbit)
    for load in loads:
        system.add_load(load(body) if callable(load) else load)
    return body, system


# --- constant loads -------------------------------------------------------------------


def test_gravity_weighs_the_string():
    body, system = pinned(sc.Gravity([0, 0, -9.81]))
    dofs, f = sc.Gravity([0, 0, -9.81]).bind(system).force
    total = np.zeros(system.n_dofs)
    np.add.at(total, dofs, f)
    assert total.reshape(-1, 3).sum(axis=0) == pytest.approx([0, 0, -9.81 * RHO_A * LENGTH],
                                                           rel=1e-13, abs=1e-13)
    assert run(system).stats["path"] == "compiled"


@pytest.mark.parametrize("make, per_length", [
    (lambda b: UniformLineLoad(b, [0.3, -2.0, 1.1]), [0.3, -2.0, 1.1]),
    (lambda b: sc.Buoyancy(b, 1025.0, 0.05, [0, 0, -9.81]),
     [0, 0, 1025.0 * np.pi * 0.05**2 / 4 * 9.81])], ids=["uniform", "buoyancy"])
def test_uniform_loads_are_the_per_length_force_times_the_length(make, per_length):
    """The total is the force per length times the length (1e-13); the generalized force
    is the quadrature ``sum w S_A f`` (1e-14); the string runs on the compiled step."""
    body, system = pinned(make)
    load = system.loads[-1]
    dofs, f = load.bind(system).force
    total = np.zeros(system.n_dofs)
    np.add.at(total, dofs, f)
    assert total.reshape(-1, 3).sum(axis=0) == pytest.approx(np.multiply(per_length, LENGTH),
                                                           rel=1e-13, abs=1e-13)
    expected = quadrature(system, body, lambda X, A, V: np.broadcast_to(per_length, X.shape))
    assert np.allclose(total, expected(system.q0, None), rtol=0, atol=1e-14 * abs(f).max())
    assert run(system).stats["path"] == "compiled"


def test_add_line_load_takes_a_line_body():
    body = string()
    system = sc.System([body]).add_line_load(body, [0, 1.0, 0])
    assert system.layout.f_const.reshape(-1, 3).sum(axis=0) == pytest.approx([0, LENGTH, 0],
                                                                            rel=1e-13)


# --- drag ------------------------------------------------------------------------------

PROFILE = sc.CurrentProfile([-2.3, -1.9, -1.5], [[0.3, 1.0, -0.2], [1.2, -0.4, 0.5],
                                                 [0.1, 0.2, 0.9]], ramp=lambda t: 1.0 + t)


def morison(body):
    return sc.MorisonDrag(body, 1025.0, 0.05, 1.2, 0.1, current=PROFILE, added_mass=1.0)


def test_morison_drag_in_a_uniform_current_is_the_per_length_drag_times_the_length():
    """A straight string at rest across a uniform current ``U``: ``rho d C_dn U^2 L / 2``."""
    U = 0.7
    body, system = pinned(lambda b: sc.MorisonDrag(b, 1025.0, 0.05, 1.2, 0.1,
                                                   current=[0, U, 0]))
    total = external_force(system, system.q0, None).reshape(-1, 3).sum(axis=0)
    assert total == pytest.approx([0, 1025.0 * 0.05 * 1.2 * U * U * LENGTH / 2, 0],
                                  rel=1e-13, abs=1e-13)


def test_morison_drag_on_a_curved_moving_string():
    """In a ramped elevation profile: the force equals the quadrature of ``line_force``
    at the points (1e-13), the tangent in ``q`` and ``v`` central differences, the added
    mass is ``C_a rho pi d^2 / 4`` times the string's consistent mass per ``rho_A`` and
    its translational total ``m_a L``, and the string runs on the compiled step."""
    body, system = pinned(morison)
    drag = system.loads[-1]
    q, v = moved(system)
    t = 0.3

    def force(X, A, V):
        c = np.array([[PROFILE.velocity(x, t) for x in row] for row in X])
        return np.array([[drag.line_force(a, u) for a, u in zip(*row)]
                         for row in zip(A, c - V)])

    f = external_force(system, q, v, t)
    assert np.allclose(f, quadrature(system, body, force)(q, v), rtol=0,
                       atol=1e-13 * abs(f).max())
    errors, check = tangent_errors(system, q, v, "MorisonDrag", t)
    assert errors["q"] < 1e-7 and errors["v"] < 1e-7, str(check)
    rows, cols, values = drag.added_mass(system)
    M = np.zeros((system.n_dofs,) * 2)
    np.add.at(M, (rows, cols), values)
    m_a = 1025.0 * np.pi * 0.05**2 / 4
    assert np.allclose(M, body.mass_matrix().toarray() * m_a / RHO_A, rtol=0, atol=1e-15)
    u = np.tile([1.0, 0, 0], system.n_dofs // 3)
    assert u @ M @ u == pytest.approx(m_a * LENGTH, rel=1e-13)
    assert run(system).stats["path"] == "compiled"


def test_free_molecular_drag_on_a_string():
    """A straight string at ``theta`` to a uniform flow: ``C_D rho d L |U| sin(theta) U / 2``
    (1e-12); in a co-rotating atmosphere on a curved moving string, the quadrature of
    ``line_force`` (1e-13) and the tangent; a compiled run."""
    rho, d, cd, theta = 3e-11, 1e-3, 2.2, 0.4
    U = np.array([-7.6e3, 0, 0])
    tilted = QuadraticString([0, 0, 0], [LENGTH * np.cos(theta), LENGTH * np.sin(theta), 0],
                             3, EA, RHO_A)
    system = sc.System([tilted]).add_load(sc.FreeMolecularDrag(tilted, rho, d, cd, velocity=U))
    total = external_force(system, tilted.q0, None).reshape(-1, 3).sum(axis=0)
    assert total == pytest.approx(cd * rho * d * LENGTH * 7.6e3 * np.sin(theta) * U / 2,
                                  rel=1e-12, abs=1e-12 * np.abs(total).max())

    omega = np.array([0.2, -0.1, 0.4])
    body, system = pinned(lambda b: sc.FreeMolecularDrag(b, 1e-3, 0.02, cd, velocity=[1, 2, 0],
                                                         omega=omega))
    drag = system.loads[-1]
    q, v = moved(system, seed=2)

    def force(X, A, V):
        u = np.array([1.0, 2.0, 0.0]) + np.cross(omega, X) - V
        return np.array([[drag.line_force(a, w) for a, w in zip(*row)] for row in zip(A, u)])

    f = external_force(system, q, v)
    assert np.allclose(f, quadrature(system, body, force)(q, v), rtol=0,
                       atol=1e-13 * abs(f).max())
    errors, check = tangent_errors(system, q, v, "FreeMolecularDrag")
    assert errors["q"] < 1e-7 and errors["v"] < 1e-7, str(check)
    assert run(system).stats["path"] == "compiled"


# --- a Python line load ------------------------------------------------------------------


def viscous(body):
    """``f = -c |x| v`` with its exact Jacobians."""
    c = 0.5
    return sc.LineLoad(
        body, lambda x, v, t: -c * v * np.linalg.norm(x, axis=1)[:, None],
        dq=lambda x, v, t: -c * v[:, :, None] * (x / np.linalg.norm(x, axis=1)[:, None])[:, None],
        dv=lambda x, v, t: -c * np.linalg.norm(x, axis=1)[:, None, None] * np.eye(3))


def test_line_load_on_a_string_keeps_the_rest_of_the_step_compiled():
    """The force is the quadrature of ``force`` at the points (1e-14), its tangent the
    differences; the run's path is compiled with this term its only Python part."""
    body, system = pinned(viscous)
    q, v = moved(system, seed=3)
    expected = quadrature(system, body, lambda X, A, V: -0.5 * V * np.linalg.norm(
        X, axis=2)[..., None])
    f = external_force(system, q, v)
    assert np.allclose(f, expected(q, v), rtol=0, atol=1e-14 * abs(f).max())
    errors, check = tangent_errors(system, q, v, "line load")
    assert errors["q"] < 1e-7 and errors["v"] < 1e-7, str(check)
    path = run(system).stats["path"]
    assert path.startswith("compiled (Python: "), path
    python = path[len("compiled (Python: "):-1].split("; ")
    assert len(python) == 1 and "line load string" in python[0], path


# --- differential gravity in orbit ---------------------------------------------------------


def test_differential_gravity_on_a_string_in_orbit():
    """``mass_points`` of the string: the force is the quadrature of ``rho_A (g(R + x) -
    g(R))`` at the points (1e-12), the tangent the differences; a compiled run."""
    orbit = sc.Orbit(sc.MU_EARTH, 7e6)
    body = QuadraticString([0, 0, 0], [0, 500.0, 0], 3, EA, RHO_A)
    system = sc.System([body]).add_orbit(orbit)
    q, v = moved(system, seed=4)
    q = system.q0 + 50 * (q - system.q0)
    t = 100.0
    R = orbit.position(t)
    expected = quadrature(system, body, lambda X, A, V: RHO_A * differential_gravity(
        sc.MU_EARTH, R, X))
    f = external_force(system, q, v, t)
    assert np.allclose(f, expected(q, v), rtol=0, atol=1e-12 * abs(f).max())
    check = sc.check_tangent(system, q, v, t=t)
    assert check.error < 1e-6, str(check)
    result = sc.simulate(system, t_end=10.0, dt=1.0)
    assert result.stats["path"] == "compiled"


# --- the hook, and the ported loads on a cable ----------------------------------------------


@pytest.mark.parametrize("make", [
    lambda b: sc.MorisonDrag(b, 1025.0, 0.05, 1.2, 0.1),
    lambda b: sc.FreeMolecularDrag(b, 1e-11, 1e-3),
    lambda b: sc.LineLoad(b, lambda x, v, t: -v),
    lambda b: UniformLineLoad(b, [0, 0, 1.0]),
    lambda b: sc.Buoyancy(b, 1025.0, 0.05, [0, 0, -9.81])],
    ids=["morison", "molecular", "lineload", "uniform", "buoyancy"])
def test_a_body_without_the_hook_is_refused(make):
    hub = sc.RigidBody.cylinder(radius=1.0, height=0.5, density=100.0)
    with pytest.raises(TypeError, match=r"cable must be a line body, with the hook "
                                        r"line_points\(system\)"):
        make(hub)


SECTION_OF_CABLE = sc.Section(E=2e9, A=1e-4, I=1e-9, rho=1000.0)
CABLE = sc.Cable.straight([0, 0, -1.0], [3.0, 0.4, -0.2], 5, SECTION_OF_CABLE)
CABLE_PROFILE = sc.CurrentProfile([-0.9, -0.4, 0.3], [[0.3, 1.0, -0.2], [1.2, -0.4, 0.5],
                                                      [0.1, 0.2, 0.9]],
                                  vertical=[0, 0.6, 0.8], ramp=lambda t: 1.0 + t)

#: ``signature`` of ``f``, ``dF/dq``, ``dF/dv`` and the constant force or added mass of the
#: loads on ``CABLE`` (``dense_tangents``) by the hand-written loops of commit 35fde8e,
#: before the port to the line-body hook.
BEFORE = {
    "morison": [(52.35031134593785, -22.10000649608519),
                (221.12235403888755, -50.14433599598634),
                (73.85684780074494, -31.52710063031165),
                (3.560053439051692, 2.009608242124306)],
    "molecular": [(7.520887339560309e-07, -8.044347894342911e-08),
                  (3.606606164795167e-06, 3.843109836704866e-06),
                  (2.932197473568809e-10, -8.62803389016829e-11), None],
    "lineload": [(1.4959133237420588, 0.8298728137518278),
                 (1.4373439205936458, 0.13721888293790285),
                 (0.6898701737516572, -0.3894235881622008), None],
    "buoyancy": [None, None, None, (26.238234897296508, -31.901628048838237)],
}

CABLE_LOADS = {
    "morison": lambda: sc.MorisonDrag(CABLE, 1025.0, 0.05, 1.2, 0.1, current=CABLE_PROFILE,
                                      added_mass=1.0, deformed_length=True),
    "molecular": lambda: sc.FreeMolecularDrag(CABLE, 3e-11, 1e-3, velocity=[-7.5e3, 100, 0],
                                              omega=[0, 0, 7.29e-5]),
    "lineload": lambda: sc.LineLoad(CABLE, lambda x, v, t: np.sin(x) - 0.3 * v * (1 + t)),
    "buoyancy": lambda: sc.Buoyancy(CABLE, 1025.0, 0.05, [0, 0, -9.81]),
}


def signature(x):
    """``(|x|, r . x)`` with ``r`` a fixed random array: a witness of the whole array."""
    r = np.random.default_rng(0).standard_normal(x.size)
    return float(np.linalg.norm(x)), float(r @ x.ravel())


def dense_tangents(load, t=0.3):
    """The ``signature`` of ``f``, ``dF/dq`` and ``dF/dv`` of ``load`` on ``CABLE`` at a
    curved moving state (the term evaluated alone into dense arrays) and of its constant
    force or mass (None where the term has none)."""
    system = sc.System([CABLE]).add_load(load)
    term = load.bind(system)
    n = system.n_dofs
    constant = None
    if term.force is not None:
        constant = np.zeros(n)
        np.add.at(constant, term.force[0], term.force[1])
    if term.mass is not None:
        constant = np.zeros((n, n))
        np.add.at(constant, (term.mass[0], term.mass[1]), term.mass[2])
    out = [None, None, None]
    if term.evaluates:
        q, v = moved(system, seed=7)
        rows, cols = np.broadcast_arrays(term.rows, term.cols)
        index = np.arange(rows.size, dtype=np.int64).reshape(rows.shape)
        for k, (cK, cC) in enumerate(((1.0, 0.0), (0.0, 1.0))):
            ev = Evaluation(system, t, q, v, np.zeros(0), cK, cC, np.zeros(rows.size))
            term.evaluate(ev, index)
            D = np.zeros((n, n))
            np.add.at(D, (rows.ravel(), cols.ravel()), -ev.data)
            out[0], out[k + 1] = ev.f_ext, D
    return [None if x is None else signature(x) for x in out + [constant]]


@pytest.mark.parametrize("name", list(CABLE_LOADS))
def test_ported_loads_equal_the_hand_written_loops_on_a_cable(name):
    """Forces, tangents, constant forces and the added mass to 1e-13 of their norm (the
    witness ``r . x`` to 1e-13 ``|r| |x|``, ``|r|`` < 40 here)."""
    for now, before in zip(dense_tangents(CABLE_LOADS[name]()), BEFORE[name]):
        assert (now is None) == (before is None)
        if now is not None:
            assert now[0] == pytest.approx(before[0], rel=1e-13)
            assert now[1] == pytest.approx(before[1], abs=1e-13 * 40 * before[0])


@pytest.mark.parametrize("element", ["hermite3", "hermite5", "linear"])
def test_uniform_load_on_a_cable_is_the_scikit_fem_assembly(element):
    """``LinePoints.force`` on a cable of each element equals ``Cable.line_load`` (the
    scikit-fem assembly on the exact rule) to round-off."""
    cable = sc.Cable.straight([0, 0, 0], [2.0, 0.5, -1.0], 3, SECTION_OF_CABLE, element=element)
    value = np.array([0.3, -2.0, 1.1])
    dofs, f = UniformLineLoad(cable, value).bind(sc.System([cable])).force
    expected = cable.line_load(value)
    assert np.array_equal(dofs, np.arange(cable.n_dofs))
    assert np.allclose(f, expected, rtol=0, atol=1e-15 * abs(expected).max())
