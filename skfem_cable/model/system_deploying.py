"""Deploying and retrieving cables through reels (``SystemDeploying``, a base of ``System``):
``deploy`` pins a cable's first node at its exit and makes its free length a function of
time or a reel's coordinate (``deploy.Deployment``); ``deployment`` and ``stretch`` read
it back."""

import numpy as np


class SystemDeploying:
    """The deployments of a ``System`` (``deployments``: cable id -> ``Deployment``)."""

    def deploy(self, cable, anchor=None, length=None, rate=None, acceleration=None,
               direction=None, capacity=None, reel=None):
        """Deploy (or retrieve) ``cable`` through a reel at ``anchor``: its node 0 is
        pinned there and its free length follows ``length(t)``, or is the coordinate of a
        ``reel`` with inertia and a torque law (see ``deploy``: the mesh stretches with
        the length, the nodes keep their identity). Returns the system.

        Parameters
        ----------
        cable : Cable
            Node 0 at the anchor, node -1 the tip; its length as built is the mesh length
            (build it with the free length at the start to start stress-free).
        anchor : None, array_like (3,) or body point
            The reel's exit point: fixed in space (None: node 0's initial position), or a
            point of a rigid body (``RigidBody.point``), e.g. a hub.
        length : callable or float
            Free (unstretched) length ``length(t)`` (m), > 0; None with ``reel``.
        rate, acceleration : callable, optional
            Its exact first and second derivatives (else central differences).
        direction : array_like (3,), optional
            Exit direction (an exit guide): the slope at node 0 is clamped to it, fixed
            in space for a fixed reel, in the body frame for a body ``anchor`` (it turns
            with a hub, ``constraints.BodySlope``).
        capacity : float, optional
            Total tether length (reel and free, m): the material still on the reel moves
            with a body ``anchor`` (its mass, ``rho A (capacity - length)``, changes) and,
            with a ``reel``, turns with its drum.
        reel : Reel, optional
            A body of the system (``sc.Reel``) whose coordinate is the free length: the
            length then follows from the reel's inertia and torque law, the tension at the
            exit and the tether's inertia (instead of ``length``).

        Returns
        -------
        System
            ``self``.

        Examples
        --------
        A tether deployed at 2 m/s from 1 m, with a 5 kg end mass:

        >>> import numpy as np, skfem_cable as sc
        >>> tether = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4,
        ...                            sc.Section.circular(1e-3, 1e9, 1000.0))
        >>> system = sc.System([tether]).deploy(tether, length=lambda t: 1 + 2 * t,
        ...                                     rate=lambda t: 2.0, acceleration=lambda t: 0.0)
        >>> system = system.add_point_mass(tether.node(-1), 5.0)
        >>> round(system.deployments[id(tether)].stretch(0.5), 12)
        2.0
        """
        from ..constraints.deploy import Deployment

        if id(cable) in self.deployments:
            raise ValueError(f"cable {cable.name!r} is already deployed")
        if (length is None) == (reel is None):
            raise TypeError("deploy needs length (a callable length(t) or a number, m) or "
                            "reel (a Reel body of the system), not both")
        if reel is not None and not np.isclose(reel.q0[0], cable.length, rtol=1e-12):
            raise ValueError(f"reel {reel.name!r} starts at the free length "
                             f"{float(reel.q0[0])!r} m: it must be the length of "
                             f"{cable.name!r} as built, {cable.length!r} m")
        if direction is not None:
            self.clamp(cable.node(0), direction=direction, position=anchor)
        else:
            self.pin(cable.node(0), anchor)
        exit_point = cable.q0[:3] if anchor is None else anchor
        deployment = Deployment(cable, length, rate, acceleration, exit_point, capacity,
                                None if reel is None else int(self.dofs(reel)[0]))
        self.deployments[id(cable)] = deployment
        return self.add_load(deployment)

    def deployment(self, body):
        """The ``Deployment`` of ``body`` (``deploy``), or None."""
        return self.deployments.get(id(body))

    def stretch(self, cable, t, q=None):
        """The mesh stretch of ``cable`` at times ``t`` (scalar or array) and coordinates
        ``q`` (``(n_dofs,)`` or one row per time; needed for a reel's length): the free
        length over the length as built for a deploying cable (``deploy``), else 1."""
        deployment = self.deployment(cable)
        if deployment is None:
            return np.ones(np.shape(t)) if np.ndim(t) else 1.0
        if np.ndim(t):
            rows = [None] * np.size(t) if q is None else np.reshape(q, (np.size(t), -1))
            return np.array([deployment.stretch(float(ti), qi)
                             for ti, qi in zip(np.ravel(t), rows)]).reshape(np.shape(t))
        return deployment.stretch(float(t), q)
