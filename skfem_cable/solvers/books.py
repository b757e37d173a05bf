"""The energy books of the generalized-alpha integrator (``Books``, a base of
``GeneralizedAlpha``): the work of damping, of the non-constant external forces, of the
constraints and of time-dependent stored energies over a step, and the kinetic and
potential energy, so that the energy balance of a run can be checked (paper Sect. 5)."""

import numpy as np

from ..kernels.books import step_books


class Books:
    """``_booked`` (the books at the end of a step), ``energies`` (of the current state)
    and ``_energies`` (of a dict of books); read the integrator's state and layout."""

    def _booked(self, info, q1, v1, t1, start=False):
        """Energy books at the end ``(q1, v1, t1)`` of a step with the evaluation ``info``
        there: the work of the damping and of the non-constant external forces over the
        step, ``dq . (f_n + f_{n+1}) / 2`` (exact for the trapezoidal rule), the constraint
        forces ``-C_q^T lambda`` counted as external (they work where a constraint is
        driven, a moving pin; elsewhere ``C_q dq = 0`` to ``O(dq^3)``), the work of the
        explicit time dependence of stored energies (``System.energy_rate``: a deploying
        cable's reel), ``h (P_n + P_{n+1}) / 2``, the work of the change of the terms'
        data over the step (``System.energy_change``: a law parameter that varies in
        time), and the kinetic and potential energy (``kernels.books``);
        ``start`` opens the books at ``q1``."""
        fd, fnc, fcon = info["f_damping"], info["f_nc"], info["f_con"]
        if "sums" in info:  # computed by the compiled step
            dissipated, external, kinetic, potential = info["sums"]
        else:
            M = self.lay.mass
            before = (fd, fnc, fcon) if start else (self.fd, self.fnc, self.fcon)
            dq = np.zeros_like(q1) if start else q1 - self.q
            dissipated, external, kinetic, potential = step_books(
                dq, before, (fd, fnc, fcon), (M.indptr, M.indices, M.data),
                self.lay.f_const, q1, v1)
        rate = self.system.energy_rate(q1, t1) if self.energy_depends_on_time else 0.0
        if not start:
            dissipated += self.dissipated
            external += self.external_work + 0.5 * (t1 - self.t) * (self.energy_rate + rate)
            if self.energy_changes:
                external += self.system.energy_change(self.q, q1, self.t, t1)
        return {"fd": fd, "fnc": fnc, "fcon": fcon, "dissipated": dissipated,
                "external_work": external, "elastic": info["energy"].copy(),
                "kinetic": kinetic, "potential": potential, "energy_rate": rate}

    @staticmethod
    def _energies(books):
        return {"kinetic": books["kinetic"], "axial": books["elastic"][0],
                "bending": books["elastic"][1], "potential": books["potential"],
                "dissipated": books["dissipated"], "external_work": books["external_work"]}

    def energies(self):
        """Kinetic, axial, bending and potential energy, dissipated energy and external
        work (J) of the current state."""
        return self._energies(self.__dict__)
