"""The evaluation of a system (``SystemEvaluation``, a base of ``System``): its residual and
tangents through the contract of ``contract`` on the fixed pattern of its layout, the
constraints' values and terms, and the bodies' internal forces alone (``assemble``)."""

import numpy as np

from ..core.contract import Evaluation


class SystemEvaluation:
    """What a ``System`` evaluates: ``evaluate`` (residual and KKT values), the constraint
    values and terms, and ``assemble``; the layout is the one a solver took
    (``layout=``) or the system's current one (``System._solved``)."""

    def constraint_values(self, q, t=0.0, layout=None):
        """``C(q, t)`` of every constraint (``layout``: as in ``evaluate``)."""
        lay = self._solved(layout)
        r = np.zeros(lay.n_c)
        lay.constraints(q, t, np.zeros(lay.n_c), np.zeros(self.n_dofs), r, 1.0)
        return r

    def constraint_velocity_term(self, q, t=0.0, layout=None):
        """``C_t`` of every constraint: consistent velocities satisfy ``C_q v = -C_t``
        (``layout``: as in ``evaluate``)."""
        return self._constraint_terms(lambda c, d: c.velocity_term(q[d], t), layout)

    def constraint_accel_term(self, q, v, t=0.0, layout=None):
        """``(C_q v)_q v + 2 C_qt v + C_tt`` of every constraint (Eq. 2): consistent
        accelerations satisfy ``C_q a = -`` this (``layout``: as in ``evaluate``)."""
        return self._constraint_terms(lambda c, d: c.accel_term(q[d], v[d], t), layout)

    def _constraint_terms(self, term, layout):
        lay = self._solved(layout)
        out = np.zeros(lay.n_c)
        for c, d, rows in zip(self.constraints, lay.cdofs, lay.crows):
            out[rows] = term(c, d)
        return out

    def evaluate(self, q, v, t, lam, load_factor=1.0, cK=1.0, cC=0.0, scale=1.0, data=None,
                 reference_force=False, a=None, cM=0.0, layout=None):
        """Residual of the equations of motion without inertia, and tangents.

        ``r = [f_int(q, v) - load_factor f_ext(q, v, t) + C_q^T lambda, scale C(q, t)]``
        with ``lambda = lam`` the true multipliers.  ``v = None`` means statics (no
        damping, zero velocity).  If ``data`` (CSR values of the KKT pattern, holding the
        caller's constant part ``Layout.mass_data``/``Layout.linear_data``) is given,
        ``cK`` times the stiffness and ``cC`` times the damping tangent are added.  ``a``
        and ``cM``: the accelerations and the coefficient of their derivatives, for terms
        with inertia beyond the constant mass (``contract``).  ``layout``: the one a solver
        took at its start (``current_layout``), which it evaluates without describing the
        system again at every call; by default the system as it is now
        (``current_layout``: an edit since the last solve is seen).

        Returns
        -------
        r : ndarray (n_dofs + n_constraints,)
        info : dict
            ``energy`` (axial, bending), ``power`` (dissipated, axial and bending),
            ``f`` (internal force: elastic and damping), ``f_damping`` (its damping part),
            ``f_nc`` (non-constant external force, whose
            work is booked as external work), ``f_con`` (``C_q^T lambda``: minus the
            constraint forces, which work only where constraints are driven) and, with
            ``reference_force``, ``force_ref`` (largest norm of the internal, external and
            constraint forces: a scale for convergence tests).
        """
        lay = self._solved(layout)
        n = self.n_dofs
        ev = Evaluation(self, t, q, v, lam, cK, cC, data, a, cM)
        for term, index in lay.body_terms:
            term.evaluate(ev, index)
        # loads see the load factor through their tangent coefficients
        ev.cK, ev.cC = cK * load_factor, cC * load_factor
        for term, index in lay.load_terms:
            term.evaluate(ev, index)
        f_ext = load_factor * (lay.f_const + ev.f_ext)
        f_con = np.zeros(n)
        r = np.empty(n + lay.n_c)
        lay.constraints(q, t, lam, f_con, r[n:], scale, data, cK)
        r[:n] = ev.f - f_ext + f_con
        info = {"energy": ev.energy, "power": ev.power, "f": ev.f, "f_damping": ev.f_damping,
                "f_nc": load_factor * ev.f_ext, "f_con": f_con}
        if reference_force:
            info["force_ref"] = max(np.linalg.norm(ev.f), np.linalg.norm(f_ext),
                                    np.linalg.norm(f_con))
        return r, info

    def assemble(self, q, v=None, cK=1.0, cC=0.0, layout=None):
        """The bodies' internal force ``f = dU/dq + dD/dv`` and its tangent ``cK df/dq + cC
        df/dv`` (sparse, ``n_dofs`` square) at ``q`` and ``v`` (None: statics, no
        dissipation), by the compiled kernels; loads and constraints left out
        (``layout``: as in ``evaluate``).

        Examples
        --------
        >>> import skfem_cable as sc
        >>> sec = sc.Section(E=1e9, A=1e-6, I=1e-12, rho=1e3)
        >>> cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sec)
        >>> f, K = sc.System([cable]).assemble(cable.q0 * 1.01)   # stretched by 1 %
        >>> round(float(f[12]), 6), K.shape                      # the tip's axial force
        (10.1505, (18, 18))
        """
        lay = self._solved(layout)
        data = np.zeros(lay.nnz)
        _, info = self.evaluate(q, v, 0.0, np.zeros(self.n_constraints), load_factor=0.0,
                                cK=cK, cC=cC, data=data, layout=lay)
        n = self.n_dofs
        return info["f"], lay.matrix(data)[:n, :n].tocsr()
