"""``sc.check_tangent``: a system whose tangents are exact passes, a wrong tangent is named
with its term, row and column."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.core.contract import Term

SECTION = sc.Section.circular(1e-3, 2e11, 7850.0, gamma_axial=1e-3)


def hub_and_tether():
    hub = sc.RigidBody.cylinder(radius=0.5, height=0.3, density=1000.0)
    tether = sc.Cable.straight([0, 0.5, 0], [0, 3.5, 0], 3, SECTION)
    system = sc.System([hub, tether]).pin(tether.node(0), hub.point([0, 0.5, 0]))
    system.add_load(sc.MorisonDrag(tether, rho=1025.0, diameter=0.02, cd_normal=1.2,
                                   cd_tangential=0.01, current=[0.3, 0.0, 0.1]))
    return system.add_point_mass(tether.node(-1), 2.0)


class WrongSpring:
    """A spring pulling the coordinate 0 back to zero whose tangent has the wrong sign."""

    def bind(self, system):
        def add(ev, index):
            ev.f_ext[0] -= 50.0 * ev.q[0]   # dF_ext/dq = -50: add_tangent(-50, sign=-1)
            ev.add_tangent(index, np.array([[50.0]]), sign=-1.0)

        return Term(add=add, rows=np.array([[0]]), cols=np.array([[0]]), name="wrong spring")


def test_exact_tangents_pass_in_statics_and_dynamics():
    """Cable (damped law), rigid body, pin, drag and point mass: every part within 1e-6
    of its differences, with and without velocities."""
    system = hub_and_tether()
    rng = np.random.default_rng(2)
    q = system.q0 + 1e-2 * rng.standard_normal(system.n_dofs)
    v = rng.standard_normal(system.n_dofs)
    for check in (sc.check_tangent(system, q), sc.check_tangent(system, q, v, t=0.3)):
        assert check.error < 1e-6, str(check)
    names = {p.name for p in check.parts}
    assert {"constraints C_q", "constraints d(C_q^T lam)/dq"} <= names
    assert any(p.wrt == "v" for p in check.parts)


def test_a_wrong_tangent_is_named():
    system = hub_and_tether().add_load(WrongSpring())
    check = sc.check_tangent(system, system.q0 + 0.01)
    assert check.worst.name == "wrong spring"
    assert check.error == pytest.approx(2.0, rel=1e-6)   # -50 against +50: twice the scale
    assert check.worst.row == check.worst.col == system.describe_dof(0)
    assert "wrong spring" in str(check)
