"""The work a step does not need is not done, and what the step does stays bit for bit
(issue 47, "back and beyond").

One small scene (a pinned tether of three elements in the solar wind, the Sun at 1 AU, no
orbit, no controllers), built once: its wind kernel without the distance scaling against
the scaled one at a unit scale, the scaled kernel against the force computed by hand, its
step hooks, and a run interrupted and resumed against the same run in one go (the books,
the guard and the state's copies of an accepted step in both)."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.control.controller import ControlLoop
from skfem_cable.io import RunStore, resume
from skfem_cable.loads.coulomb import AU, SolarWindForce
from skfem_cable.solvers import compiled as compiled_step
from skfem_cable.solvers.rectify import Rectification

SECTION = sc.Section.circular(1e-5, 7e10, 2700.0)
RUN = {"dt": 0.05, "rho_inf": 0.25}


def wind(cable, exponent, sun=(-AU, 0.0, 0.0)):
    return SolarWindForce([cable], 20e3, sun_position=np.asarray(sun), exponent=exponent)


@pytest.fixture(scope="module")
def scene():
    """A tether of 3 elements pinned at its root, in the wind (default exponent 7/6)."""
    cable = sc.Cable.straight([0, 0, 0], [3.0, 30.0, -4.0], 3, SECTION, name="tether")
    system = sc.System([cable]).pin(cable.node(0)).add_load(wind(cable, None))
    q = system.q0 + 0.2 * np.random.default_rng(3).standard_normal(system.n_dofs)
    return cable, system, q


def force_and_tangent(load, system, q):
    """The generalized force and tangent (dense) of ``load`` at ``q`` (its own kernel)."""
    term = load.bind(system)
    (function, pack), = term.kernels
    rows, cols = np.broadcast_arrays(term.rows, term.cols)
    index = np.arange(rows.size).reshape(rows.shape)
    n = system.n_dofs
    f, data = np.zeros(n), np.zeros(rows.size)
    function(pack, index, (q, np.zeros(n), np.array([0.0, 1.0, 0.0, 0.0]), np.zeros(n), f,
                           np.zeros(n), data, np.zeros(2), np.zeros(2)))
    tangent = np.zeros((n, n))
    np.add.at(tangent, (rows.ravel(), cols.ravel()), data)
    return f, tangent, term


def test_the_wind_without_scaling_compiles_no_power_and_equals_a_unit_scale(scene):
    """``exponent=0`` (the paper's Eq. 29): the kernel is the loop of
    ``kernels.coulomb.point_uniform`` (the scaling decided at setup: no power in it), and
    its force and tangent equal the scaled kernel's at a unit scale (``exponent=1e-300``:
    ``(d / rho)^p = 1`` and ``1 + p = 1`` exactly) to 1e-15."""
    cable, system, q = scene
    uniform_f, uniform_K, term = force_and_tangent(wind(cable, 0.0), system, q)
    scaled_f, scaled_K, scaled_term = force_and_tangent(wind(cable, 1e-300), system, q)
    assert "point_uniform" in term.kernels[0][0].__module__
    assert "point_uniform" not in scaled_term.kernels[0][0].__module__
    np.testing.assert_allclose(uniform_f, scaled_f, rtol=0,
                               atol=1e-15 * np.abs(scaled_f).max())
    np.testing.assert_allclose(uniform_K, scaled_K, rtol=0,
                               atol=1e-15 * np.abs(scaled_K).max())


def test_the_scaled_wind_in_scalars_is_the_force_by_hand(scene):
    """The point function computes in scalars (``kernels.coulomb._wind``); with the Sun
    50 m away (a scaling of order one across the tether) its resultant is ``sum w c (d /
    rho)^p (i_R - (t . i_R) t)`` over the Gauss points, computed here, within 1e-14."""
    cable, system, q = scene
    load = wind(cable, None, sun=(-40.0, -25.0, 10.0))
    qe = q[cable.element_dofs].reshape(-1, 4, 3)
    r = np.einsum("egA,eAi->egi", cable.S, qe)
    a = np.einsum("egA,eAi->egi", cable.Sx, qe)
    f = load.line_force(r, a, np.full(r.shape[:2], load.coefficients(0.0)[0]), 0.0)
    hand = np.einsum("eg,egi->i", cable.weights, f)
    resultant = load.add_force(system, q, 0.0, np.zeros(system.n_dofs))
    np.testing.assert_allclose(resultant, hand, rtol=0, atol=1e-14 * np.abs(hand).max())


@pytest.fixture(scope="module")
def runs(scene, tmp_path_factory):
    """The scene over 12 steps in one go, and over 6 steps then resumed to 12 (a store),
    counting the calls of the rectification's and the control loop's ``after_step`` and
    of the terms' ``prepare`` in both."""
    _, system, q = scene
    initial = sc.State(system, system.q0)
    counts = {"rectify": 0, "control": 0, "prepare": 0}
    patches = pytest.MonkeyPatch()
    for name, cls in (("rectify", Rectification), ("control", ControlLoop)):
        def after_step(self, integ, _name=name, _original=cls.after_step):
            counts[_name] += 1
            return _original(self, integ)
        patches.setattr(cls, "after_step", after_step)
    original_iterate = compiled_step.CompiledNewton.iterate

    def iterate(newton, *args):
        counts["prepare"] += len(newton.prepare)
        return original_iterate(newton, *args)

    patches.setattr(compiled_step.CompiledNewton, "iterate", iterate)
    try:
        whole = sc.simulate(system, t_end=12 * RUN["dt"], initial=initial, **RUN)
        store = tmp_path_factory.mktemp("run")
        sc.simulate(system, t_end=6 * RUN["dt"], initial=initial,
                    observers=[RunStore(store)], **RUN)
        resumed = sc.simulate(system, t_end=12 * RUN["dt"], resume=resume(store),
                              observers=[RunStore(store)], **RUN)
    finally:
        patches.undo()
    return whole, resumed, counts


def test_a_scene_without_orbit_or_controllers_runs_no_step_hooks(runs):
    """No orbit, no controllers, a steady wind at a fixed voltage: no rectification, no
    control loop and no refresh of the wind's data is called at any step."""
    whole, _, counts = runs
    assert whole.stats["steps"] == 12
    assert counts == {"rectify": 0, "control": 0, "prepare": 0}


def test_a_resumed_run_is_bit_for_bit_the_run_in_one_go(runs):
    """The state, the multipliers and the energy books of the run resumed at step 6
    (its checkpoint's books reopened, ``Books._open``) equal the uninterrupted run's,
    bit for bit, at every saved step (the accelerations at the resumed run's steps)."""
    whole, resumed, _ = runs
    assert len(resumed) == len(whole) == 13
    for name in ("t", "q", "v", "lam", "kinetic", "axial", "bending", "potential",
                 "dissipated", "external_work"):
        np.testing.assert_array_equal(getattr(resumed, name), getattr(whole, name), name)
    # the store keeps no accelerations of the steps before the interruption
    np.testing.assert_array_equal(resumed.a[7:], whole.a[7:])
