"""The OML current's coupling in the tangent (``kernels.oml_coupling``): the full tangent
of ``ElectrodynamicForce(current="oml")`` in ``q`` and ``v`` against central differences
of the force, the option that leaves it out, and Newton's iterations with and without
it."""

from dataclasses import replace

import numpy as np
import pytest
from test_electrodynamic import TILTED
from test_oml_force import ORBIT, central_differences, dumbbell, inclined_tether, oml_force

import skfem_cable as sc
from skfem_cable.core.contract import Evaluation
from skfem_cable.loads.oml_circuit import COUPLED


def force_and_tangent(load, system, q, v, t, cK=1.0, cC=0.0):
    """The load's generalized force and ``cK dF/dq + cC dF/dv`` (dense) from its term."""
    term = load.bind(system)
    rows, cols = np.broadcast_arrays(term.rows, term.cols)
    ev = Evaluation(system, t, q, v, np.zeros(system.n_constraints), cK=cK, cC=cC,
                    data=np.zeros(rows.size))
    term.evaluate(ev, np.arange(rows.size))
    K = np.zeros((system.n_dofs,) * 2)
    np.add.at(K, (rows.ravel(), cols.ravel()), -ev.data)
    return ev.f_ext, K


@pytest.fixture(scope="module")
def tether():
    """``test_oml_force.inclined_tether`` (2 km tape, 4 elements, inclined eccentric
    orbit, perturbed offsets) with velocities, a 10 V cathode and a 100 ohm load."""
    cable, system, q = inclined_tether()
    v = np.random.default_rng(4).normal(scale=3.0, size=system.n_dofs)
    return cable, system, q, v, 321.0


@pytest.mark.parametrize("field", [TILTED, lambda x, t: TILTED.field(x, t)[0]],
                         ids=["dipole", "callable"])
def test_full_tangent_against_central_differences(tether, field):
    """``dF/dq`` and ``dF/dv`` against central differences of the force within 1e-6 of
    the largest entry (measured 5e-8 in ``q``, the differences' own error, falling as
    the step squared: 1.3e-5, 3.2e-6, 8.0e-7, 2.0e-7 at 0.2, 0.1, 0.05, 0.025 m; 6.9e-8
    in ``v``); ``coupling=False`` leaves out 0.40 of the largest entry of ``dF/dq``."""
    cable, system, q, v, t = tether
    force = oml_force(cable, field=field, voltage_drop=10.0, load=100.0)
    mask = cable.position_mask
    K = force_and_tangent(force, system, q, v, t)[1]
    fd = central_differences(lambda x: force_and_tangent(force, system, x, v, t)[0], q,
                             mask, step=0.0125)
    Kv = force_and_tangent(force, system, q, v, t, cK=0.0, cC=1.0)[1]
    fdv = central_differences(lambda x: force_and_tangent(force, system, q, x, t)[0], v,
                              np.ones(v.size, bool), step=0.01)
    error_q = np.abs(fd - K).max() / np.abs(fd).max()
    error_v = np.abs(fdv - Kv).max() / np.abs(fdv).max()
    fixed = oml_force(cable, field=field, voltage_drop=10.0, load=100.0)
    fixed.oml = replace(fixed.oml, coupling=False)
    left_out = np.abs(fd - force_and_tangent(fixed, system, q, v, t)[1]).max()
    print(f"tangent error: q {error_q:.2e}, v {error_v:.2e}; current fixed: "
          f"{left_out / np.abs(fd).max():.2f} left out")
    assert error_q < 1e-6 and error_v < 1e-6
    assert left_out > 0.3 * np.abs(fd).max()
    assert np.abs(fdv).max() > 1e-3 * np.abs(fd).max()  # the magnetic damping is there


def test_coupling_rule_and_pattern():
    """By default the tangent carries the coupling up to ``COUPLED`` (64) coordinates
    of the cable (9 elements, 60), a block dense over them; 10 elements (66) keep the
    element blocks; ``coupling`` given decides; a bad value is refused by name."""
    def pattern(n_elements, coupling=None):
        cable = sc.Cable.straight([0, 0, 0], [1e3, 0, 0], n_elements,
                                  sc.Section(E=7e10, A=1e-6, I=1e-12, rho=2700.0))
        system = sc.System([cable])
        load = sc.ElectrodynamicForce(cable, "oml", [0, 0, 2e-5],
                                      plasma=sc.environment.UniformPlasma(1e11),
                                      conductivity=3.5e7, coupling=coupling)
        term = load.bind(system)
        return system.n_dofs, np.unique(term.rows * system.n_dofs + term.cols).size

    n, entries = pattern(9)
    assert n == 60 <= COUPLED and entries == n * n
    n, entries = pattern(10)
    assert n == 66 > COUPLED and entries < n * n / 2
    assert pattern(10, coupling=True)[1] == 66 ** 2
    assert pattern(9, coupling=False)[1] < 60 ** 2 / 2
    with pytest.raises(ValueError, match="coupling"):
        pattern(2, coupling="exact")
    with pytest.raises(ValueError, match="coupling"):
        sc.ElectrodynamicForce(sc.Cable.straight([0, 0, 0], [1, 0, 0], 1, sc.Section(
            E=7e10, A=1e-6, I=1e-12, rho=2700.0)), 1.0, [0, 0, 1e-5], coupling=True)


def test_newton_with_and_without_the_coupling():
    """The 5 km tape between two 500 kg masses (``test_oml_force.dumbbell``: dipole,
    uniform plasma at rest, 10 V cathode, 100 ohm) along the local vertical, at rest in
    the orbiting frame, 600 s at 5 s steps with the coupling and with the current held
    fixed: the same states (within 1e-9 of the tether's length) and no more Newton
    iterations with it (measured 697 and 697, none refused).  The coupling is 0.40 of the
    force's own derivative but negligible in the iteration matrix: it does not set
    Newton's rate (``docs/environment.md`` "Tangent": on the deorbit's 300 km rung 533
    of 733 attempted steps refused with it, 376 of 576 without, 127 of 327 with a
    prescribed current)."""
    runs = {}
    for coupling in (True, False):
        cable, system = dumbbell(load=lambda c: oml_force(c, field=sc.MagneticDipole(),
                                                          load=100.0))
        system.loads[-1].oml = replace(system.loads[-1].oml, coupling=coupling)
        spin = system.rotation_operator(np.cross([0, 0, ORBIT.mean_motion], np.eye(3)).T)
        runs[coupling] = sc.simulate(system, t_end=600.0, dt=5.0, initial=sc.State(
            system, system.q0, v=spin @ system.q0))
        print(f"coupling {coupling}: {runs[coupling].stats['newton']} Newton iterations, "
              f"{runs[coupling].stats['rejected']} refused")
    exact, fixed = runs[True], runs[False]
    assert exact.stats["path"] == "compiled"
    assert np.abs(exact.q[-1] - fixed.q[-1]).max() < 1e-9 * 5e3
    assert exact.stats["newton"] <= fixed.stats["newton"]
