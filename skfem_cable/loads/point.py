"""Point loads, moments and masses at a node or a body point."""

import numpy as np

from ..bodies.section import vector3
from ..core.contract import Term
from ..core.inputs import declared, reader
from ..kernels import drives


class PointLoad:
    """Force (N, fixed in space) at a cable node or a rigid-body point: a 3-vector, or a
    callable ``force(t)`` returning one (a time-dependent load).

    Parameters
    ----------
    point : Node or body point
        ``cable.node(i)`` or ``RigidBody.point(x)``.
    force : array_like (3,) or callable
        The force (N), or ``force(t)``: a constant force is a generalized force with a
        potential (booked as potential energy), a time-dependent one does external work.

    Examples
    --------
    >>> import numpy as np, skfem_cable as sc
    >>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0))
    >>> pulse = sc.PointLoad(cable.node(-1), lambda t: [0.0, -np.sin(t), 0.0])
    >>> pulse.force(np.pi / 2)
    array([ 0., -1.,  0.])
    """

    def __init__(self, point, force):
        self.point = point
        self.fn = force if callable(force) else None
        self.value = None if callable(force) else vector3(force, "force")
        if self.fn is not None:
            self.force(0.0)  # fail now, not in the middle of a run

    def force(self, t):
        """The force (N) at time ``t`` (an ``Input`` at its initial value: a run reads
        its own, ``bind``)."""
        if self.fn is None:
            return self.value
        return vector3(self.fn(t), f"force({t!r})")

    def inputs(self):
        """The inputs the force reads (``inputs.declared``): an ``Input`` given as the
        force."""
        return declared(self.fn)

    #: The load's declared force fixed in space (``solvers.steady.check_space_fixed``).
    space_fixed_force = force

    def __repr__(self):
        force = "force(t)" if self.fn is not None else self.value.tolist()
        return f"PointLoad({self.point!r}, {force})"

    def bind(self, system, inputs=None):
        """The load's term: a constant force, or a function of time refreshed once per
        step (compiled, ``kernels.drives.point_force``) reading the run's values of its
        inputs (``inputs``: the run's ``InputTable``; None: their initial values)."""
        dofs, G = system.position_map(self.point)
        if self.fn is None:
            return Term(force=(dofs, G.T @ self.value), name=f"point load {self.point!r}")
        force = self.force(0.0)
        source = reader(self.fn, inputs)

        def prepare(t):
            force[:] = vector3(source(t), f"force({t!r})")

        pack = (np.ascontiguousarray(dofs, dtype=np.int64), np.ascontiguousarray(G), force)
        return Term(kernels=((drives.point_force, pack),), prepare=prepare,
                    name=f"point load {self.point!r}", writes=("f_ext",))


class PointMoment:
    """Moment ``M`` (N m, fixed in space) at a cable node.

    From the virtual work ``dW = M . (t x dt)`` with ``t = r_x / |r_x|``, the generalized
    force on the node's slope is ``f = M x r_x / |r_x|^2`` and its derivative is
    ``df/dr_x = ([M]_x |r_x|^2 - 2 (M x r_x) r_x^T) / |r_x|^4``.  On a node with a twist
    (a rod's, ``Node.has_twist``) the section also turns about the tangent by ``dphi -
    (a x t) . dt / (1 + a . t)`` (``a`` the node's reference tangent: the spin of the
    reference director ``R(a -> t) d``, ``docs/rods.md``), so the component along the
    tangent ``M . t`` acts on the twist angle and adds the slope force ``-(M . t) (a x t)
    / ((1 + a . t) |r_x|)`` (``reference_force``, zero where the frame is current, ``a =
    t``, its derivative not): the space-fixed (axial) moment with its exact tangent.  A
    torque about a rod's tangent that turns with it is ``TwistTorque`` (semi-tangential,
    conservative; ``docs/rods.md``, "End torques").

    Parameters
    ----------
    node : Node
        ``cable.node(i)``.
    moment : array_like (3,)
        The moment (N m).

    Examples
    --------
    A moment about ``z`` turns a slope along ``x`` towards ``y``:

    >>> import numpy as np, skfem_cable as sc
    >>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0))
    >>> sc.PointMoment(cable.node(-1), [0, 0, 1.0]).force(np.array([1.0, 0.0, 0.0]))
    array([0., 1., 0.])
    """

    def __init__(self, node, moment):
        self.node = node
        self.moment = vector3(moment, "moment")

    def force(self, a):
        """Generalized force ``M x a / |a|^2`` on the slope ``a = r_x``."""
        return np.cross(self.moment, a) / (a @ a)

    def stiffness(self, a):
        """``df/da`` (3 x 3)."""
        p = a @ a
        Mx = np.cross(self.moment, np.eye(3)).T  # Mx @ v = M x v
        return Mx / p - 2.0 * np.outer(np.cross(self.moment, a), a) / p**2

    def torque(self, a):
        """The moment about the tangent ``M . a / |a|`` and its derivative in ``a``."""
        n = np.sqrt(a @ a)
        return self.moment @ a / n, self.moment / n - (self.moment @ a) * a / n**3

    def reference_force(self, a, b):
        """The slope force ``g = -(M . a) (b x a) / (|a|^2 (|a| + b . a))`` of the moment
        about the tangent of a rod's node of slope ``a`` and reference tangent ``b`` (unit),
        ``-(M . t) (b x t) / ((1 + b . t) |a|)``, and its derivative ``dg/da`` (3, 3)."""
        m, v, s = self.moment @ a, np.cross(b, a), np.sqrt(a @ a)
        h = s**2 * (s + b @ a)
        grad_h = 3 * s * a + 2 * (b @ a) * a + s**2 * b
        bx = np.cross(b, np.eye(3)).T  # bx @ x = b x x
        return -m * v / h, -(np.outer(v, self.moment) + m * bx) / h + m * np.outer(v, grad_h) / h**2

    def bind(self, system):
        dofs = system.dofs(self.node)[3:6]
        twist = system.dofs(self.node.body)[self.node.twist_dofs] if self.node.has_twist \
            else dofs[:0]
        rows = np.concatenate([dofs, twist])
        frames = self.node.body.reference_frames(system) if twist.size else None

        def add(ev, index):
            a = ev.q[dofs]
            K = np.zeros((rows.size, 3))
            f, K[:3] = self.force(a), self.stiffness(a)
            if twist.size:
                T, K[3] = self.torque(a)
                g, K_g = self.reference_force(a, frames.t0[self.node.index])
                f, K[:3] = f + g, K[:3] + K_g
                ev.f_ext[twist] += T
            ev.f_ext[dofs] += f
            ev.add_tangent(index, K, sign=-1.0)

        return Term(add=add, rows=rows[:, None], cols=dofs[None, :],
                    name=f"moment {self.node!r}")


class PointMass:
    """Point mass (kg) at a cable node's position or at a body point (anything
    ``System.position_map`` accepts): a constant mass ``m G^T G``.

    Parameters
    ----------
    point : Node or body point
    mass : float
        Mass (kg), > 0.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section.circular(1e-3, 2e11, 7850.0))
    >>> system = sc.System([cable]).add_point_mass(cable.node(-1), 0.5)   # a tip mass
    >>> round(float(system.mass_matrix()[-6, -6] - cable.mass_matrix()[-6, -6]), 12)
    0.5
    """

    def __init__(self, point, mass):
        self.point = point
        if not (np.isfinite(mass) and mass > 0):
            raise ValueError(f"mass must be a finite number > 0, got {mass!r}")
        self.mass = float(mass)

    def entries(self, system):
        """``(rows, cols, values)`` of the mass ``m G^T G`` in ``system``'s coordinates
        (row by row)."""
        dofs, G = system.position_map(self.point)
        return (np.repeat(dofs, dofs.size), np.tile(dofs, dofs.size),
                self.mass * (G.T @ G).ravel())

    def bind(self, system):
        return Term(mass=self.entries(system), name=f"point mass {self.point!r}")
