"""The energy books of the generalized-alpha integrator (``Books``, a base of
``GeneralizedAlpha``): the work of damping, of the non-constant external forces, of the
constraints and of time-dependent stored energies over a step, and the kinetic and
potential energy, so that the energy balance of a run can be checked (paper Sect. 5)."""

import numpy as np

from ..kernels.books import step_books


class Books:
    """``_step_books`` (the books at the end of a step), ``_open`` and ``_opened`` (at the
    current state), ``energies`` (of the current state) and ``_energies`` (of a dict of
    books); read the integrator's state and layout."""

    def _step_books(self, sums, q1, t1):
        """Energy books at the end ``(q1, t1)`` of a step, from the sums the compiled step
        computed (``sums``, (4,): the step's dissipated and external work, kinetic and
        potential energy, ``kernels.books.step_books``): the work of the damping and of
        the non-constant external forces over the step, ``dq . (f_n + f_{n+1}) / 2``
        (exact for the trapezoidal rule), the constraint forces ``-C_q^T lambda`` counted
        as external (they work where a constraint is driven, a moving pin; elsewhere
        ``C_q dq = 0`` to ``O(dq^3)``; those of the accepted multipliers also when Newton
        ends on a correction without evaluating it, ``kernels.step._constraints``: a
        change of the multipliers that the mean nodal mass of a heavy hub hid from the
        convergence test left the books of a damped rope on the hub open to first order
        in the step), the work of the explicit time dependence of stored energies
        (``System.energy_rate``: a deploying cable's reel), ``h (P_n + P_{n+1}) / 2``, and
        the work of the change of the terms' data over the step (``System.energy_change``:
        a law parameter that varies in time), added to the books so far.

        Returns
        -------
        dissipated, external_work, kinetic, potential, energy_rate : float
        """
        dissipated, external, kinetic, potential = sums.tolist()
        rate = self.system.energy_rate(q1, t1) if self.energy_depends_on_time else 0.0
        dissipated += self.dissipated
        external += self.external_work + 0.5 * (t1 - self.t) * (self.energy_rate + rate)
        if self.energy_changes:
            external += self.system.energy_change(self.q, q1, self.t, t1)
        return dissipated, external, kinetic, potential, rate

    def _open(self, forces, energy):
        """The books opened at the current state ``(q, v, t)``, where the forces are
        ``forces`` ``(f_damping, f_nc, f_con)`` and the elastic energy ``energy`` (2,):
        no work yet, the kinetic and potential energy there (``kernels.books``).  The
        forces are kept as given: accepted steps write theirs into them
        (``GeneralizedAlpha._accept``), so they must be arrays nothing else holds."""
        q, lay = self.q, self.lay
        dissipated, external, kinetic, potential = step_books(
            q, forces, forces, lay.mass.strided, lay.f_const, q, self.v,
            np.empty(q.size), (True, True))
        rate = self.system.energy_rate(q, self.t) if self.energy_depends_on_time else 0.0
        fd, fnc, fcon = forces
        return {"fd": fd, "fnc": fnc, "fcon": fcon, "dissipated": dissipated,
                "external_work": external, "elastic": energy.copy(),
                "kinetic": kinetic, "potential": potential, "energy_rate": rate}

    def _opened(self, info):
        """The books opened at the current state, with the evaluation ``info`` there (of
        ``System.evaluate``)."""
        return self._open((info["f_damping"], info["f_nc"], info["f_con"]), info["energy"])

    @staticmethod
    def _energies(books):
        return {"kinetic": books["kinetic"], "axial": books["elastic"][0],
                "bending": books["elastic"][1], "potential": books["potential"],
                "dissipated": books["dissipated"], "external_work": books["external_work"]}

    def energies(self):
        """Kinetic, axial, bending and potential energy, dissipated energy and external
        work (J) of the current state."""
        return self._energies(self.__dict__)
