"""Uniform gravity and the centrifugal load of a rotating frame."""

from dataclasses import replace

import numpy as np

from ..core.contract import Term, combined
from .point import vector3


class Gravity:
    """Uniform gravity ``g`` (m/s^2) on every body and point mass.

    The generalized force is ``M u_g`` with ``u_g`` the coordinates of the uniform field
    ``r(x) = g`` (positions ``g``, slopes 0): ANCF shape functions, natural coordinates and
    point masses all reproduce a constant field exactly, so ``M u_g = int rho S^T g dV`` is
    the consistent gravity load of every body.  The mass a deploying cable gains or loses
    (``System.deploy``) adds a time-dependent weight (``Deployment.weight``), booked as
    external work.

    Parameters
    ----------
    g : array_like (3,)
        Gravitational acceleration (m/s^2).

    Examples
    --------
    The forces on the position coordinates add up to the weight (0.2 kg here):

    >>> import skfem_cable as sc
    >>> sec = sc.Section(E=1e9, A=1e-4, I=1e-10, rho=1000.0)
    >>> cable = sc.Cable.straight([0, 0, 0], [2, 0, 0], 4, sec)
    >>> dofs, f = sc.Gravity([0, -9.81, 0]).bind(sc.System([cable])).force
    >>> f[cable.position_mask].reshape(-1, 3).sum(axis=0)
    array([ 0.   , -1.962,  0.   ])
    """

    def __init__(self, g):
        self.g = vector3(g, "g")

    def space_fixed_force(self, t):
        """The acceleration ``g``, fixed in space (``solvers.steady.check_space_fixed``)."""
        return self.g

    def __repr__(self):
        return f"Gravity({self.g.tolist()})"

    def bind(self, system):
        u = system.rigid_motion_velocity(system.q0, (0, 0, 0), velocity=self.g)
        force = (np.arange(system.n_dofs), system.mass_matrix() @ u)
        weights = [d.bind_weight(system, self.g) for d in system.deployments.values()]
        if not weights:
            return Term(force=force, name="gravity")
        return replace(combined(weights, "gravity"), force=force)


class Centrifugal:
    """Centrifugal force ``-M (Omega x (Omega x (q - u_c)))`` on every 3-vector of
    coordinates in a frame rotating at the constant rate ``omega`` (rad/s) about the axis
    through ``center``.

    All coordinates (ANCF positions and slopes, natural coordinates of rigid bodies) are
    vectors that rotate with the frame, so the kinetic energy in the rotating frame gives
    this force exactly; ``u_c`` holds the coordinates of the uniform field ``r(x) = center``
    (positions ``center``, slopes and unit vectors 0, as in ``Gravity``), so that only
    positions are measured from the axis.  The force is affine in ``q`` with the constant
    tangent ``-M (I (x) [Omega]_x^2)``.  With it ``solve_static`` finds steady spinning
    states of supported systems (``solve_steady`` adds it itself and handles free ones),
    and ``modes(..., spin=omega)`` their vibrations.

    Parameters
    ----------
    omega : array_like (3,)
        Angular velocity of the frame (rad/s).
    center : array_like (3,)
        A point of the rotation axis (m); default the origin.

    Examples
    --------
    A tether clamped at the hub, spinning at 2 rad/s: the root tension of the steady state
    is ``rho A Omega^2 L^2 / 2 = 0.8 N``:

    >>> import skfem_cable as sc
    >>> sec = sc.Section(E=1e9, A=1e-4, I=1e-10, rho=1000.0)
    >>> cable = sc.Cable.straight([0, 0, 0], [2, 0, 0], 4, sec)
    >>> system = sc.System([cable]).clamp(cable.node(0)).add_centrifugal([0, 0, 2.0])
    >>> round(float(sc.solve_static(system).tension(cable, 0.0)), 4)
    0.8
    """

    def __init__(self, omega, center=(0.0, 0.0, 0.0)):
        self.omega = vector3(omega, "omega")
        self.center = vector3(center, "center")

    @property
    def frame_rate(self):
        """The angular velocity (rad/s) of the rotating frame whose inertia this load is:
        the property by which ``modes`` and ``solve_steady`` recognise a system already
        in a rotating frame."""
        return self.omega

    def bind(self, system):
        if system.deployments:
            raise ValueError("Centrifugal: the system has deploying cables, whose mass "
                             "changes with their length; build the cables at their free "
                             "length for a steady spinning state")
        C = spin_matrix(system, system.mass_matrix(), self.omega, 2).tocoo()
        matrix = C.tocsr()
        values = C.data
        u_c = system.rigid_motion_velocity(system.q0, (0, 0, 0), velocity=self.center)

        def add(ev, index):
            ev.f_ext -= matrix @ (ev.q - u_c)
            ev.add_tangent(index, -values, sign=-1.0)

        return Term(add=add, rows=C.row.astype(np.int64), cols=C.col.astype(np.int64),
                    name="centrifugal")


def spin_matrix(system, M, omega, power):
    """``M (I (x) W^power)`` with ``W = [omega]_x`` acting on every 3-vector of coordinates
    of ``system`` (``System.rotation_operator``; ``power = 1``: half the gyroscopic matrix;
    ``2``: minus the centrifugal stiffness)."""
    W = np.linalg.matrix_power(np.cross(omega, np.eye(3)).T, power)
    return (M @ system.rotation_operator(W)).tocsr()
