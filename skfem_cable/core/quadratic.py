"""Quadratic constraints ``C_j(q) = 1/2 q^T H_j q - c_j`` with constant Hessians ``H_j``
on a set of coordinates: the rigid body's six (``rigid.RigidConstraints``, Eqs. 45-49) and
the exit guide's two (``constraints.BodySlope``).  Their compiled hook is
``kernels.rigid.constraint_kernel``."""

import numpy as np

from ..kernels.rigid import constraint_kernel


class QuadraticConstraints:
    """The constraint protocol (``contract``) of ``C_j = 1/2 q^T H_j q - c_j``.

    A subclass sets ``H`` (n_eq, m, m), symmetric, and ``c`` (n_eq,) on the ``m``
    coordinates of its ``dofs(system)``, and ``name`` and ``labels``.  The Jacobian is
    ``H_j q``, the Hessian term ``sum_j lambda_j H_j``, ``C_t = 0`` and ``(C_q v)_q v =
    v^T H_j v``.
    """

    linear = False

    @property
    def n_eq(self):
        return len(self.c)

    @property
    def kernel(self):
        """The compiled hook (``kernels.rigid.constraint_kernel``, see ``contract``)."""
        return constraint_kernel, (self.H, self.c)

    def value(self, qc, t=0.0):
        return 0.5 * np.einsum("i,jik,k->j", qc, self.H, qc) - self.c

    def jacobian(self, qc, t=0.0):
        return self.H @ qc

    def hessian(self, qc, lam, t=0.0):
        return np.einsum("j,jik->ik", lam, self.H)

    def velocity_term(self, qc, t=0.0):
        return np.zeros(self.n_eq)

    def accel_term(self, qc, vc, t=0.0):
        return np.einsum("i,jik,k->j", vc, self.H, vc)
