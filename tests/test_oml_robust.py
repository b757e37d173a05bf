"""The OML force where a day of ``demos/ed_tether_deorbit.py`` used to stop (t = 22 483 s,
0.26 days): the models are evaluated at the positions predicted from the last accepted
state, not at a diverged Newton iterate of a refused step, and the compiled profile
solver converges in that regime (a 5 km tape at about 11 ``L*``) as ``solve_bvp`` does."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.core.contract import Evaluation
from skfem_cable.environment import BareTether, OMLProblem
from skfem_cable.environment.plasma import OXYGEN_ION_MASS
from skfem_cable.loads.oml_circuit import bind_oml, stations

LENGTH, WIDTH, THICKNESS, SIGMA = 5e3, 0.02, 5e-5, 3.5e7
TAPE = sc.Section(E=7e10, A=WIDTH * THICKNESS, I=1e-12, rho=2700.0)
B_Z = 2e-5                                # T, along z; the tape along +x moves along +y
# the motional field and density along the tape at the failing time (V/m, m^-3: the
# first evaluation of the step from t = 22 483.3 s, from the cathodic end to the free end)
E_ENDS, N_ENDS = (0.0961, 0.0904), (1.421e12, 1.347e12)
CATHODE, LOAD = 10.0, 100.0               # V, ohm (the demo's)


class LinearPlasma:
    """A plasma at rest whose density is linear in ``x`` between ``N_ENDS`` at the tape's
    ends, or, past ``SCALE`` m from it, exponential (a model out of its range: a
    diverged iterate's positions give an infinite or zero density); it records the
    positions it was evaluated at."""

    ion_mass = OXYGEN_ION_MASS
    SCALE = 1e5

    def __init__(self):
        self.seen = []

    def density(self, x, t):
        x = np.asarray(x, dtype=float)
        self.seen.append(x.copy())
        u = x[..., 0] / LENGTH
        linear = N_ENDS[0] + (N_ENDS[1] - N_ENDS[0]) * u
        far = np.linalg.norm(x, axis=-1) / self.SCALE
        with np.errstate(over="ignore"):
            return np.where(far > 1.0, linear * np.exp(far), linear)

    def velocity(self, x, t):
        return np.zeros(np.shape(x))


def tape(n_elements):
    """The 5 km tape along +x in ``B_Z`` moving along +y with the velocity that gives
    the failing time's motional field, linear in ``x`` (exact in the cubic elements):
    ``(force, plasma, state)``."""
    cable = sc.Cable.straight([0, 0, 0], [LENGTH, 0, 0], n_elements, TAPE)
    plasma = LinearPlasma()
    force = sc.ElectrodynamicForce(cable, "oml", [0.0, 0.0, B_Z], plasma=plasma,
                                   cathode=sc.Cathode(CATHODE), load=LOAD,
                                   conductivity=SIGMA, perimeter=2 * (WIDTH + THICKNESS))
    system = sc.System([cable]).add_load(force)
    dofs = system.dofs(cable)
    x = system.q0[dofs[0::6]]
    v = np.zeros(system.n_dofs)
    v[dofs[1::6]] = (E_ENDS[0] + (E_ENDS[1] - E_ENDS[0]) * x / LENGTH) / B_Z
    v[dofs[4::6]] = (E_ENDS[1] - E_ENDS[0]) / LENGTH / B_Z
    return force, plasma, sc.State(system, system.q0, v=v)


@pytest.fixture(scope="module")
def demo_tape():
    return tape(4)


def reference(s):
    """``OMLProblem`` (``solve_bvp``) with the same linear fields, sampled at ``s``."""
    ends = np.array([0.0, LENGTH])
    problem = OMLProblem(BareTether.tape(WIDTH, THICKNESS, LENGTH, SIGMA),
                         np.interp(s, ends, E_ENDS), np.interp(s, ends, N_ENDS),
                         sc.Cathode(CATHODE), load_resistance=LOAD, stations=s)
    return problem.solve()


def test_the_failing_regime_is_eleven_characteristic_lengths():
    """At the failing time the tape is about 11 ``L*`` (L* = 442 m at E = 0.093 V/m, N =
    1.4e12 m^-3): the regime of a long tether, its bias zero inside it."""
    ratio = LENGTH / BareTether.tape(WIDTH, THICKNESS, LENGTH, SIGMA).characteristic_length(
        np.mean(E_ENDS), np.mean(N_ENDS))
    assert 10.0 < ratio < 12.5


@pytest.mark.parametrize("n_elements, tolerance", [(4, (3e-2, 1e-2, 3e-3)),
                                                   (20, (1e-4, 1e-4, 1e-4))])
def test_solver_converges_at_the_failing_time(n_elements, tolerance, demo_tape):
    """The compiled solver (``kernels.oml``) from a cold start converges on the demo's
    mesh (4 elements, 20 stations) and on a finer one (20 elements); against
    ``solve_bvp``'s profile, the current and bias at the stations (relative to the
    largest) and the cathode's current: within 1e-4 on 20 elements (measured 1.9e-5,
    5.4e-6, 2.2e-6); on the demo's 4 elements the bias zero falls between stations 250 m
    apart and the current is off by 2.0e-2, the bias by 4.6e-3, the cathode's current by
    2.0e-3 (``docs/environment.md``)."""
    force, _, state = demo_tape if n_elements == 4 else tape(n_elements)
    out = force.evaluate(state.system, state.q, state.v)
    assert out["iterations"] > 0
    s = stations(force.cable.line_points(state.system))[0]
    ref = reference(s)
    I, dV = force.current(state, s), force.bias(state, s)
    errors = (np.abs(I - ref.current(s)).max() / np.abs(ref.current(s)).max(),
              np.abs(dV - ref.bias(s)).max() / np.abs(ref.bias(s)).max(),
              abs(out["current"] / ref.cathode_current - 1.0))
    print(f"{n_elements} elements: I(0) {out['current']:.4f} A against "
          f"{ref.cathode_current:.4f}; errors: current {errors[0]:.1e}, bias "
          f"{errors[1]:.1e}, I(0) {errors[2]:.1e}; {out['iterations']} iterations")
    assert all(e < tol for e, tol in zip(errors, tolerance))
    assert np.any(ref.bias(s) < 0.0) and np.any(ref.bias(s) > 0.0)


def test_a_refused_iterate_does_not_move_the_models(demo_tape):
    """What stopped the demo: a step's Newton iteration diverged (offsets of 5e8 m) and
    its iterate's positions were kept for the next ``prepare``, so every retry, at any
    step size, evaluated the density there (out of range: infinite) and the force was
    NaN.  Now the models are evaluated at the positions predicted from the last accepted
    state ``q_n + (t - t_n) v_n`` (the term's step hook): the retry's force is finite, its
    profile converged, and the model saw the predicted points only."""
    force, plasma, state = demo_tape
    system = state.system
    term, pack = bind_oml(force, system, None)
    (hook,) = term.hooks
    hook.accept(state.q, state.v, 0.0)  # what simulate's start does
    index = np.zeros(np.broadcast_shapes(term.rows.shape, term.cols.shape), dtype=np.int64)

    def evaluate(q, t):
        ev = Evaluation(system, t, q, state.v, np.zeros(0))
        term.evaluate(ev, index)
        return ev.f_ext

    wild = state.q + 5e8 * np.random.default_rng(0).normal(size=state.q.size)
    evaluate(wild, 28.0)               # a diverged iterate of the step to t = 28 s
    plasma.seen.clear()
    f = evaluate(state.q + 14.0 * state.v, 14.0)   # the retry, half the step
    points = force.cable.line_points(system)
    predicted = points.at(state.q + 14.0 * state.v)[0].reshape(-1, 3)
    assert len(plasma.seen) == 1 and np.allclose(plasma.seen[0], predicted, atol=1e-6)
    assert np.all(np.isfinite(f)) and pack[-1][4] > 0
    hook.accept(state.q + 14.0 * state.v, state.v, 14.0)   # accepted: the next step
    evaluate(state.q + 20.0 * state.v, 20.0)
    assert np.allclose(plasma.seen[-1], points.at(state.q + 20.0 * state.v)[0].reshape(
        -1, 3), atol=1e-6)


def test_the_run_store_records_the_oml_current(tmp_path):
    """The OML force declares its per-step outputs (``step_outputs``, ``Term.outputs``):
    the run records them at every saved step (``Result.outputs``) and the run store
    holds them (``output_<name>``), equal to the summaries recomputed from the saved
    states within 1e-6 (the step's last Newton iterate against the converged state).
    The system is ``test_oml_force``'s librating 5 km tape (its compiled step reused)."""
    from test_electrodynamic import librated
    from test_oml_force import dumbbell, oml_force

    _, system = dumbbell(load=lambda c: oml_force(c, field=sc.MagneticDipole(), load=100.0))
    result = sc.simulate(system, t_end=15.0, dt=5.0, initial=librated(system, 0.1),
                         observers=[sc.io.RunStore(tmp_path)])
    force = system.loads[-1]
    recomputed = force.summaries(result)
    for key in ("current", "emf", "power", "mean_current"):
        recorded = result.outputs[f"{force.cable.name}_{key}"]
        assert recorded.shape == result.t.shape
        np.testing.assert_allclose(recorded, recomputed[key], rtol=1e-6)
    stored = sc.Result.load(tmp_path, system).outputs
    assert set(stored) == set(force.step_outputs) == set(result.outputs)
    np.testing.assert_array_equal(stored[f"{force.cable.name}_current"],
                                  result.outputs[f"{force.cable.name}_current"])
