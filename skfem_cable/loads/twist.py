"""A torque on a rod node's twist: the semi-tangential end torque (``docs/rods.md``)."""

import numpy as np

from ..core.contract import Term


class TwistTorque:
    """Torque ``T`` (N m) on the twist angle of a rod's node: the generalized force ``T``
    on ``phi`` (virtual work ``T dphi``), a constant force of potential ``-T phi``.

    Its moment vector is ``m = T (a + t) / (1 + a . t)`` with ``t`` the node's tangent and
    ``a`` its reference tangent (``m . dtheta = T dphi`` for the section's rotation
    ``dtheta``, the twist measured from the smallest rotation ``R(a -> t)``): at ``t = a +
    dt``, ``m = T (a + dt / 2)`` to first order, the *semi-tangential* torque of Ziegler
    (*Principles of Structural Stability*, 1968) and Argyris et al. (*CMAME* 20 (1979)
    105), which is conservative, unlike the moment fixed in space (``PointMoment``).  Its
    tangent is zero (exact); it acts on rods only (``Node.has_twist``).

    Parameters
    ----------
    node : Node
        A rod's node (``rod.node(i)``).
    torque : float
        The torque (N m) about the tangent, finite.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> tape = sc.Section.tape(0.02, 50e-6, E=7e10, rho=2700.0)
    >>> rod = sc.Rod.straight([0, 0, 0], [1, 0, 0], 2, tape, normal=[0, 0, 1])
    >>> term = sc.TwistTorque(rod.node(-1), 0.5).bind(sc.System([rod]))
    >>> term.force[0].tolist(), term.force[1].tolist()
    ([22], [0.5])
    """

    def __init__(self, node, torque):
        if not node.has_twist:
            raise ValueError(f"node must be a rod's node (with a twist), got {node!r}")
        if not np.isfinite(torque):
            raise ValueError(f"torque must be a finite number (N m), got {torque!r}")
        self.node, self.torque = node, float(torque)

    def __repr__(self):
        return f"TwistTorque({self.node!r}, {self.torque})"

    def bind(self, system):
        """A constant generalized force ``T`` on the node's twist coordinate."""
        dofs = system.dofs(self.node.body)[self.node.twist_dofs]
        return Term(force=(dofs, np.array([self.torque])), name=f"twist torque {self.node!r}")
