"""Lagrange's equations by differences, for checking inertial forces against a kinetic
energy evaluated independently (``test_deploy``, ``test_reel``)."""

import numpy as np

from skfem_cable.core.contract import Evaluation


def cubic_path(c):
    """``path(t, order)``: the coordinates ``c0 + c1 t + c2 t^2 + c3 t^3`` and their first
    and second time derivatives (``order`` 0, 1, 2)."""
    c0, c1, c2, c3 = c

    def path(t, order=0):
        return [c0 + c1 * t + c2 * t**2 + c3 * t**3, c1 + 2 * c2 * t + 3 * c3 * t**2,
                2 * c2 + 6 * c3 * t][order]

    return path


def gradient(f, z, h):
    """Central differences of ``f`` at ``z`` with the step ``h`` (exact for quadratics)."""
    eye = np.eye(z.size)
    return np.array([(f(z + h * eye[i]) - f(z - h * eye[i])) / (2 * h) for i in range(z.size)])


def inertial_force(system, term, mass, path, t):
    """The inertial force of a body whose inertia beyond its constant ``mass`` is the
    ``term``'s (``contract``: ``-(F_in - M a)`` in ``f_ext``), along ``path`` at ``t``."""
    ev = Evaluation(system, t, path(t), path(t, 1), np.zeros(system.n_constraints),
                    a=path(t, 2))
    term.evaluate(ev, None)
    return mass @ path(t, 2) - ev.f_ext


def lagrange_force(kinetic, path, t, h=1.0, dt=1e-4):
    """``d/dt dT/dv - dT/dq`` of ``kinetic(q, v, t)`` along ``path`` at ``t``: gradients
    with the step ``h``, the time derivative by central differences of step ``dt``."""
    def momentum(s):
        return gradient(lambda v: kinetic(path(s), v, s), path(s, 1), h)

    return (momentum(t + dt) - momentum(t - dt)) / (2 * dt) \
        - gradient(lambda q: kinetic(q, path(t, 1), t), path(t), h)
