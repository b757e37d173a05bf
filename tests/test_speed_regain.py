"""What the E-sail step skips to be fast (issue 47) gives what it gave: the assumed-strain
kernel's residual without tangent, the Newton step's entry point, the constant offsets of
fixed linear constraints."""

import numpy as np
import pytest

from skfem_cable import Cable, Section, System, simulate
from skfem_cable.solvers.compiled import entry_point

DAMPED = Section(E=7e10, A=3e-6, I=1e-12, rho=2700.0, gamma_axial=0.3, gamma_bending=0.7)


def _evaluate(system, q, v, tangent):
    data = np.zeros(system.layout.nnz) if tangent else None
    f, info = system.evaluate(q, v, 0.0, np.zeros(system.n_constraints), cK=0.7, cC=0.2,
                              data=data)
    return f, info


@pytest.mark.parametrize("section", [DAMPED, Section(E=7e10, A=3e-6, I=1e-12, rho=2700.0)])
def test_assumed_strain_residual_without_tangent_is_the_one_with_it(section):
    """The force (elastic and damping) and the energies of an evaluation without tangent
    are those of one with it, to round-off (the law's point functions with and without
    tangent are generated apart, their sums in other orders)."""
    cable = Cable.straight([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], 4, section,
                           formulation="assumed-strain")
    system = System([cable])
    rng = np.random.default_rng(5)
    q = cable.q0 + 0.05 * rng.standard_normal(cable.n_dofs)
    v = rng.standard_normal(cable.n_dofs)
    f_t, info_t = _evaluate(system, q, v, tangent=True)
    f_r, info_r = _evaluate(system, q, v, tangent=False)
    for key in ("energy", "power", "f_damping"):
        scale = max(np.abs(info_t[key]).max(), 1e-300)
        assert np.abs(info_t[key] - info_r[key]).max() <= 1e-14 * scale, key
    assert np.abs(f_t - f_r).max() <= 1e-14 * np.abs(f_t).max()
    if section.gamma_axial:
        # the damping force is the derivative of the Rayleigh function: f_d . v = P
        assert info_r["f_damping"] @ v == pytest.approx(info_r["power"].sum(), rel=1e-10)


def test_entry_point_is_the_compiled_function_for_the_types_of_its_arguments():
    from numba import njit

    @njit
    def add(a, pair):
        return a[0] + pair[0][0] + pair[1][0]

    args = (np.ones(2), (np.full(3, 2.0), np.arange(4)))
    assert add(*args) == 3.0
    assert entry_point(add, args)(*args) == 3.0
    assert entry_point(add.py_func, args) is add.py_func  # a Python function stays itself


def test_pinned_pendulum_runs_on_its_constant_offsets_as_on_fresh_ones():
    """A pin to a fixed point keeps its offset (set once per run); a pin moving in time
    refreshes it at every step: both hold their constraint."""
    cable = Cable.straight([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 4, DAMPED)
    fixed = System([cable]).pin(cable.node(0)).add_gravity([0.0, -9.81, 0.0])
    r = simulate(fixed, t_end=0.02, dt=1e-3)
    assert np.abs(r.q[:, :3]).max() <= 1e-12
    cable = Cable.straight([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 4, DAMPED)
    moving = System([cable]).pin(cable.node(0), lambda t: [0.0, 0.1 * t, 0.0],
                                  velocity=lambda t: [0.0, 0.1, 0.0])
    moving.add_gravity([0.0, -9.81, 0.0])
    r = simulate(moving, t_end=0.02, dt=1e-3)
    assert np.allclose(r.q[:, 1], 0.1 * r.t, rtol=0, atol=1e-12)
