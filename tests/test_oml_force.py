"""The Lorentz force of the OML current (``ElectrodynamicForce(current="oml")``): the
compiled fixed-mesh solver against the independent ``OMLProblem`` (scipy ``solve_bvp``),
its warm start, the tangent at fixed current against central differences, the Newton
iterations of a run in orbit against a prescribed current, and the energy books closed
with the electrical power."""

from collections import Counter

import numpy as np
import pytest
from test_electrodynamic import ORBIT, TILTED, force_and_tangent, librated

import skfem_cable as sc
from skfem_cable.core.contract import Evaluation
from skfem_cable.environment import BareTether, OMLProblem, UniformPlasma
from skfem_cable.kernels import line
from skfem_cable.loads.oml_circuit import stations

E_M, DENSITY = 0.15, 1e11            # V/m, m^-3 (tests/test_oml.py's case)
WIDTH, THICKNESS, SIGMA = 0.02, 5e-5, 3.5e7
TAPE = sc.Section(E=7e10, A=WIDTH * THICKNESS, I=1e-12, rho=2700.0)
PLASMA = UniformPlasma(DENSITY)
FIELD = [0.0, 0.0, 2e-5]             # T: a tether along +x moving along +y at 7.5 km/s


def L_star():
    return BareTether.tape(WIDTH, THICKNESS, 1.0, SIGMA).characteristic_length(E_M, DENSITY)


def oml_force(cable, field=FIELD, voltage_drop=20.0, load=50.0, insulated=(0.0, 0.0)):
    return sc.ElectrodynamicForce(cable, "oml", field, plasma=PLASMA,
                                  cathode=sc.Cathode(voltage_drop), load=load,
                                  conductivity=SIGMA, perimeter=2 * (WIDTH + THICKNESS),
                                  insulated=insulated)


def moving_tape(length, n_elements, **circuit):
    """A straight tape along +x moving at ``E_M / B`` along +y in ``FIELD``: a uniform
    motional field ``E_M`` along the tether; ``(force, state)``."""
    cable = sc.Cable.straight([0, 0, 0], [length, 0, 0], n_elements, TAPE)
    force = oml_force(cable, **circuit)
    system = sc.System([cable]).add_load(force)
    v = np.zeros(system.n_dofs)
    v[system.dofs(cable)[1::6]] = E_M / FIELD[2]
    return force, sc.State(system, system.q0, v=v)


@pytest.mark.parametrize("ratio, n_elements, voltage_drop, load, insulated", [
    (0.3, 20, 20.0, 50.0, 0.0), (4.0, 40, 20.0, 50.0, 0.0), (4.0, 40, 0.0, 0.0, 0.0),
    (15.0, 120, 20.0, 0.0, 0.0), (2.0, 30, 15.0, 0.0, 0.2)])
def test_fixed_mesh_solver_matches_solve_bvp(ratio, n_elements, voltage_drop, load,
                                             insulated):
    """Short (0.3 L*) and long (4 and 15 L*; L* = 3040 m) tethers, with and without a
    cathode drop and a load, and one with its first fifth insulated: the current and
    bias at the stations (5 Gauss points per element) within 1e-4 of the largest current
    and bias of ``OMLProblem`` (measured: 4.5e-5, 1.4e-5, 1.4e-8, 1.3e-7 and below)."""
    length = ratio * L_star()
    cut = (0.0, insulated * length)
    force, state = moving_tape(length, n_elements, voltage_drop=voltage_drop, load=load,
                               insulated=cut)
    tether = BareTether.tape(WIDTH, THICKNESS, length, SIGMA, insulated=cut)
    reference = OMLProblem(tether, E_M, DENSITY, sc.Cathode(voltage_drop),
                           load_resistance=load).solve()
    s = stations(state.system.loads[0].cable.line_points(state.system))[0]
    I, dV = force.current(state, s), force.bias(state, s)
    I_ref, dV_ref = reference.current(s), reference.bias(s)
    I_err = np.abs(I - I_ref).max() / np.abs(I_ref).max()
    dV_err = np.abs(dV - dV_ref).max() / np.abs(dV_ref).max()
    print(f"L/L* = {ratio}: current error {I_err:.2e}, bias error {dV_err:.2e}")
    assert I_err < 1e-4 and dV_err < 1e-4
    summary = force.evaluate(state.system, state.q, state.v)
    assert summary["current"] == pytest.approx(reference.cathode_current, rel=1e-4)
    assert summary["emf"] == pytest.approx(E_M * length, rel=1e-12)


def test_summaries_and_warm_start():
    """The motional power ``int I E ds`` goes to the load, the cathode, the ohmic heat and
    the sheath (``tests/test_oml.py``'s identity, the sheath's share positive); a second
    evaluation at a state 0.1 % away takes half the iterations of a cold start (measured
    5 against 10)."""
    force, state = moving_tape(2.0 * L_star(), 30, voltage_drop=30.0, load=40.0)
    out = force.evaluate(state.system, state.q, state.v)
    I0 = out["current"]
    sheath = out["power"] - out["load_power"] - 30.0 * I0 - out["ohmic"]
    assert 0.0 < sheath < 0.5 * out["power"]
    assert out["mean_current"] == pytest.approx(np.mean(force.current(
        state, np.linspace(0.0, 2.0 * L_star(), 20001))), rel=1e-3)
    assert out["force"][1] == pytest.approx(-out["mean_current"] * 2.0 * L_star()
                                            * FIELD[2], rel=1e-12)
    system = state.system
    term = force.bind(system)
    iterations = []
    index = np.zeros(np.broadcast_shapes(term.rows.shape, term.cols.shape), dtype=np.int64)
    for scale in (1.0, 1.001):
        ev = Evaluation(system, 0.0, state.q, scale * state.v, np.zeros(0))
        term.evaluate(ev, index)
        iterations.append(int(term.kernels[0][1][-1][4]))
    print(f"Newton iterations: cold {iterations[0]}, warm {iterations[1]}")
    assert iterations[1] <= 5 < iterations[0]


def inclined_tether():
    """A 2 km tether of 4 elements in an inclined, eccentric orbit, offsets perturbed."""
    orbit = sc.Orbit(sc.MU_EARTH, 7.2e6, e=0.1, inclination=0.8, raan=0.3, anomaly=1.0)
    cable = sc.Cable.straight([-1e3, 0, 0], [1e3, 0, 0], 4, TAPE)
    system = sc.System([cable]).add_orbit(orbit)
    q = system.q0 + np.random.default_rng(3).normal(scale=1.0, size=system.n_dofs)
    return cable, system, q


def central_differences(fn, q, mask, step=0.05):
    """Central differences of ``fn`` in every coordinate: ``step`` (m) for positions,
    ``1e-3 step`` for slopes (``test_electrodynamic``'s with a twentieth of its steps: the
    OML current is not linear in the slopes)."""
    out = np.empty((fn(q).size, q.size))
    for j in range(q.size):
        e = np.zeros(q.size)
        e[j] = step if mask[j] else 1e-3 * step
        out[:, j] = (fn(q + e) - fn(q - e)) / (2 * e[j])
    return out


def generalized(points, F):
    """``sum w S_A f`` of the forces ``F`` (ne, nq, 3) at the points."""
    f_ext = np.zeros(int(points.edofs.max()) + 1)
    none = np.zeros(F.shape + (3,))
    line.assemble(points.edofs, points.S, points.Sx, points.w, np.ascontiguousarray(F),
                  none, none, none, 0.0, 0.0, f_ext, np.zeros(0),
                  np.zeros((0, 0, 0), dtype=np.int64))
    return f_ext


@pytest.mark.parametrize("field", [TILTED, lambda x, t: TILTED.field(x, t)[0]],
                         ids=["dipole", "callable"])
def test_tangent_holds_the_current_fixed(field):
    """``dF/dq`` against central differences: the difference is the current's coupling
    ``sum w S_A (a x B) dI/dq`` (``I`` at the points, differenced too) within 1e-7 of the
    largest entry; the tangent with ``coupling=False`` is the one at fixed current, the
    coupling it leaves out (a dense block of the cable, ``tests/test_oml_coupling.py``
    checks it) is measured, not vacuous."""
    cable, system, q = inclined_tether()
    force = sc.ElectrodynamicForce(cable, "oml", field, plasma=PLASMA,
                                   cathode=sc.Cathode(10.0), load=100.0,
                                   conductivity=SIGMA, perimeter=2 * (WIDTH + THICKNESS),
                                   coupling=False)
    v = np.random.default_rng(4).normal(scale=3.0, size=system.n_dofs)
    t = 321.0
    F, K = force_and_tangent(force, system, q, v, t)
    mask = cable.position_mask
    fd = central_differences(lambda x: force_and_tangent(force, system, x, v, t)[0], q,
                             mask)
    points = cable.line_points(system)

    def currents(x):
        return force._evaluated(system, x, v, t)[7][9].copy()

    pack = force._evaluated(system, q, v, t)
    unit = pack[7][5] / pack[7][9][..., None]                  # a x B at the points
    dI = central_differences(lambda x: currents(x).ravel(), q, mask)
    coupling = np.stack([generalized(points, unit * dI[:, j].reshape(unit.shape[:2])[
        ..., None]) for j in range(q.size)], axis=1)
    error = np.abs(fd - K - coupling).max() / np.abs(fd).max()
    share = np.abs(coupling).max() / np.abs(fd).max()
    print(f"tangent: error {error:.2e}, omitted coupling {share:.2e} of the largest entry")
    assert error < 1e-7
    assert share > 1e-6


def dumbbell(load=None, m=500.0, n_elements=4, length=5e3):
    """``test_electrodynamic.dumbbell``'s 5 km tether between two 500 kg end masses."""
    cable = sc.Cable.straight([-length / 2, 0, 0], [length / 2, 0, 0], n_elements, TAPE)
    system = (sc.System([cable]).add_point_mass(cable.node(0), m)
              .add_point_mass(cable.node(-1), m).add_orbit(ORBIT))
    if load is not None:
        system.add_load(load(cable))
    return cable, system


def test_newton_iterations_in_orbit_match_a_prescribed_current():
    """The 5 km tape librating in orbit (dipole field, uniform plasma at rest) for 600 s
    at 5 s steps: the current held fixed in the tangent costs at most 5 % more Newton
    iterations than the same run with a prescribed current of the OML run's mean
    (measured 695 against 702, no step refused in either; at 20 s steps 428 against 394,
    the OML run refusing one step more, 8 against 7).  The coupling left out is 40 % of
    the force's own derivative (``test_tangent_holds_the_current_fixed``), but small
    against the inertia and the tether's stiffness in the iteration matrix."""
    _, system = dumbbell(load=lambda c: oml_force(c, field=sc.MagneticDipole(),
                                                  load=100.0))
    start = librated(system, 0.1)
    result = sc.simulate(system, t_end=600.0, dt=5.0, initial=start)
    assert result.stats["path"] == "compiled"
    mean = system.loads[-1].summaries(result)["mean_current"].mean()
    _, prescribed = dumbbell(load=lambda c: sc.ElectrodynamicForce(c, mean,
                                                                   sc.MagneticDipole()))
    other = sc.simulate(prescribed, t_end=600.0, dt=5.0, initial=start)
    steps = len(result.t) - 1
    print(f"Newton iterations per step: OML {result.stats['newton'] / steps:.2f}, "
          f"prescribed {other.stats['newton'] / steps:.2f}")
    assert result.stats["newton"] <= 1.05 * other.stats["newton"]


def spinning_tape(dt):
    """A free 1 km tape translating at 7.5 km/s through ``FIELD`` and spinning at 0.02
    rad/s about ``z``, for 100 s: the run and its force."""
    cable = sc.Cable.straight([-500.0, 0, 0], [500.0, 0, 0], 8, TAPE)
    force = oml_force(cable, voltage_drop=10.0, load=20.0)
    system = sc.System([cable]).add_load(force)
    omega = np.cross([0.0, 0.0, 0.02], np.eye(3)).T
    v = system.rotation_operator(omega) @ system.q0
    v[system.dofs(cable)[1::6]] += E_M / FIELD[2]
    start = sc.State(system, system.q0, v=v)
    return sc.simulate(system, t_end=100.0, dt=dt, initial=start), force


def test_energy_books_close_with_the_electrical_power():
    """The work of the Lorentz force (the books' external work) is minus the electrical
    energy ``int int I E ds dt`` (``summaries``: load, cathode, ohmic heat and sheath)
    within 1e-6 (measured 2.9e-8 and 1.1e-8: both trapezoidal sums of the same power);
    the books' balance (kinetic + elastic - external work) closes to the integrator's
    second order: 1.2e-5 of the electrical energy at ``dt = 1 s``, four times less at
    0.5 s."""
    gaps, balances = [], []
    for dt in (1.0, 0.5):
        result, force = spinning_tape(dt)
        electrical = force.summaries(result)["energy"]
        work = result.energy["external_work"] - result.energy["external_work"][0]
        gaps.append(abs(work[-1] + electrical[-1]) / electrical[-1])
        balances.append(np.abs(result.energy["balance"]).max() / electrical[-1])
        print(f"dt = {dt}: electrical energy {electrical[-1]:.4e} J, gap {gaps[-1]:.2e}, "
              f"balance {balances[-1]:.2e}")
    assert max(gaps) < 1e-6 and balances[0] < 1e-4
    assert balances[1] < 0.3 * balances[0]


def test_arguments_are_checked_by_name():
    cable = sc.Cable.straight([0, 0, 0], [100.0, 0, 0], 2, TAPE)
    with pytest.raises(ValueError, match="plasma"):
        sc.ElectrodynamicForce(cable, "oml", FIELD, conductivity=SIGMA)
    with pytest.raises(ValueError, match="current='oml'"):
        sc.ElectrodynamicForce(cable, 1.0, FIELD, plasma=PLASMA)
    with pytest.raises(ValueError, match="plasma_rotation"):
        sc.ElectrodynamicForce(cable, "oml", FIELD, plasma_rotation=[0, 0, 1e-4],
                               plasma=PLASMA, conductivity=SIGMA)
    with pytest.raises(ValueError, match="load"):
        sc.ElectrodynamicForce(cable, "oml", FIELD, plasma=PLASMA, conductivity=SIGMA,
                               load=-1.0)
    with pytest.raises(ValueError, match="insulated"):
        oml_force(cable, insulated=(50.0, 200.0)).bind(sc.System([cable]))
    state = sc.State(sc.System([cable]), cable.q0)
    with pytest.raises(ValueError, match="bias"):
        sc.ElectrodynamicForce(cable, 1.0, FIELD).bias(state, 0.0)
    force, state = moving_tape(100.0, 2)
    with pytest.raises(RuntimeError, match="did not converge"):  # the run: a NaN force
        force.evaluate(state.system, state.q, np.full_like(state.q, np.nan))


CALLS, POINTS = Counter(), Counter()
"""Calls of the counted models and the most points of a call (outside the models: a
run refuses a system whose loads change)."""


class Counting:
    """A model whose calls (and points per call) are counted in ``CALLS``, ``POINTS``:
    the plasma's ``density`` and ``velocity``, a field's ``field``."""

    def __init__(self, model):
        self.model = model
        self.ion_mass = getattr(model, "ion_mass", None)

    def _counted(self, name, x, t):
        CALLS[name] += 1
        POINTS[name] = max(POINTS[name], len(x))
        return getattr(self.model, name)(x, t)

    def density(self, x, t=0.0):
        return self._counted("density", x, t)

    def velocity(self, x, t=0.0):
        return self._counted("velocity", x, t)

    def field(self, x, t=0.0):
        return self._counted("field", x, t)

    def __call__(self, x, t=0.0):
        return self.field(x, t)[0]


def test_environment_is_evaluated_once_per_step():
    """In orbit with IGRF (a field evaluated in Python, linearised within the step) and a
    uniform plasma: the density, the plasma's velocity and the field are each called once
    per attempted step (and once at binding), every call with all the cable's points."""
    plasma, field = Counting(PLASMA), Counting(sc.environment.IGRF("2026-01-01"))
    cable, system = dumbbell(load=lambda c: sc.ElectrodynamicForce(
        c, "oml", field, plasma=plasma, cathode=sc.Cathode(10.0), load=100.0,
        conductivity=SIGMA, perimeter=2 * (WIDTH + THICKNESS)))
    start = librated(system, 0.1)
    CALLS.clear()
    result = sc.simulate(system, t_end=200.0, dt=20.0, initial=start)
    attempts = result.stats["steps"] + result.stats["rejected"]
    points = cable.line_points(system).w.size
    print(f"calls {dict(CALLS)} for {attempts} attempted steps")
    assert set(CALLS) == {"density", "velocity", "field"}
    for name, calls in CALLS.items():
        assert calls <= attempts + 1 and POINTS[name] == points
    assert result.stats["newton"] > 2 * attempts        # far more evaluations than calls


def test_paraview_and_run_summary_carry_the_current(tmp_path):
    """The ParaView output's point data carry the current and bias at the cable's sampled
    arc lengths (``io.export``), equal to ``force.current`` and ``force.bias`` there; a
    run's summary (``runner.run_outputs``) holds the force's numbers at its end."""
    import meshio

    from skfem_cable.io.export import write_series, write_vtu
    from skfem_cable.runner import run_outputs

    force, state = moving_tape(L_star(), 6, voltage_drop=10.0, load=20.0)
    mesh = meshio.read(write_vtu(tmp_path / "state.vtu", state.system, state))
    s = mesh.point_data["arc_length"]
    np.testing.assert_allclose(mesh.point_data["current"], force.current(state, s),
                               rtol=0, atol=1e-12)
    np.testing.assert_allclose(mesh.point_data["bias"], force.bias(state, s), rtol=0,
                               atol=1e-9)
    result, force = spinning_tape(10.0)
    series = write_series(result, tmp_path / "run", every=5)
    assert series.exists()
    last = meshio.read(sorted((tmp_path / "run" / "vtu").glob("*.vtu"))[-1])
    assert np.isfinite(last.point_data["bias"]).all()
    loads = run_outputs(result)["loads"]
    (numbers,) = loads.values()
    assert numbers["current"] == pytest.approx(force.summaries(result)["current"][-1])


def test_a_run_in_igrf_and_iri():
    """The 5 km tape in orbit through IGRF and IRI sharing one epoch for 60 s: the run
    keeps its system unchanged (the epoch's cached rotations are ``caches``, left out of
    the system's description) and collects a current from the ionosphere."""
    epoch = sc.Epoch("2026-01-01T12:00:00")
    _, system = dumbbell(load=lambda c: sc.ElectrodynamicForce(
        c, "oml", sc.environment.IGRF(epoch),
        plasma=sc.environment.IRI(epoch, f107=150.0), cathode=sc.Cathode(10.0),
        load=100.0, conductivity=SIGMA, perimeter=2 * (WIDTH + THICKNESS)))
    result = sc.simulate(system, t_end=60.0, dt=20.0, initial=librated(system, 0.1))
    out = system.loads[-1].outputs(result)
    print(f"IGRF and IRI: I(0) = {out['current']:.3f} A, EMF = {out['emf']:.1f} V")
    assert 0.0 < out["current"] and 0.0 < out["emf"]
