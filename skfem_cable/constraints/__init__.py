"""Holonomic constraints ``C(q, t) = 0`` imposed with Lagrange multipliers (paper Sect. 2.4).

A constraint acts on a few global coordinates ``q[dofs]`` and provides (the contract of
``contract``):

* ``n_eq``, ``name``, ``labels`` (one per equation: names the multipliers);
* ``linear``: True when the Jacobian ``C_q`` is constant (it then lives in one constant
  sparse matrix; the value may still move in time through ``offset(t)``);
* ``dofs(system)``: the global coordinates involved;
* ``value(qc, t)``, ``jacobian(qc, t)``, ``hessian(qc, lam, t)`` (the term
  ``d(C_q^T lambda)/dq`` of Eq. 15, None when zero);
* ``velocity_term(qc, t)`` = ``C_t`` and ``accel_term(qc, vc, t)`` =
  ``(C_q v)_q v + 2 C_qt v + C_tt`` (Eq. 2), for consistent initial velocities and
  accelerations.

Driven joints take callables of time.  Their time derivatives are given by the user
(``velocity``, ``acceleration``) or computed by ``time_derivatives``.  A linear constraint
whose equations repeat those of another (a node pinned or clamped twice) is refused when
added (``check_independent``).

Examples
--------
``System.clamp`` and ``System.pin`` build them; ``System.add_constraint`` takes any object
with this contract:

>>> import skfem_cable as sc
>>> from skfem_cable import constraints
>>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0))
>>> (joint,) = constraints.clamp(cable.node(0))
>>> joint.n_eq, joint.labels, joint.linear
(5, ['Fx', 'Fy', 'Fz', 'M1', 'M2'], True)
>>> joint.value(cable.q0[:6])               # satisfied by the initial coordinates
array([0., 0., 0., 0., 0.])
"""

from .dependence import (
    DEPENDENCE_LIMIT,
    check_independent,
    dependence_message,
    dependent_constraints,
)
from .joints import BodySlope, clamp, hold_twist, pin
from .linear import LinearConstraint, SlopeDirection, orthonormal_complement
from .prescribed import TIME_STEP, Motion, time_derivatives
from .twist_tie import TwistTie

__all__ = [
    "BodySlope",
    "DEPENDENCE_LIMIT",
    "LinearConstraint",
    "Motion",
    "SlopeDirection",
    "TIME_STEP",
    "TwistTie",
    "check_independent",
    "clamp",
    "dependence_message",
    "dependent_constraints",
    "hold_twist",
    "orthonormal_complement",
    "pin",
    "time_derivatives",
]
