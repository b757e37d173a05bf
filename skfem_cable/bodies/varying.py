"""The term of a cable whose law has parameters that vary in time
(``CableLaw.with_parameters(EA=lambda t: ...)``): the values are refreshed once per time
step, and the work their change does on the cable is booked as external work."""

from dataclasses import replace

import numpy as np

from ..core.contract import NO_INDEX, static_evaluation


class Varying:
    """The hooks of the term of a cable whose law's parameters depend on time.

    ``prepare(t)`` writes the parameters' values at ``t`` into every kernel pass (once per
    time step, ``contract.Term.prepare``: the step's equations hold at its end time, where
    Exudyn evaluates its user functions too).  ``energy_change(q0, q1, t0, t1)`` is the
    work done on the cable over a step by whatever changes its parameters: the change of
    the elastic energy with the values, at fixed coordinates, averaged over the step's
    two ends, ``(U(q0; p1) - U(q0; p0) + U(q1; p1) - U(q1; p0)) / 2``.  The step's
    equations average the forces of its two ends, ``f(q0; p0)`` and ``f(q1; p1)``, so that
    is the work they see, to second order in the step (a jump at either end alone would
    be first order: 2.6e-3 of the work on a soft hanging cable at steps of 1 ms, where
    this closes the books to 2.4e-5 of it, and to a quarter of that at half the step).

    Parameters
    ----------
    law : CableLaw
    section : Section
    term : contract.Term
        The cable's term (``cable_term``), values at ``t = 0``; each pass's pack holds
        its values at index ``VALUES``.
    """

    #: Index of the parameter values in a pass's pack (``cable_term``): after the tables
    #: of the pass's rule, before whether it damps and its ``span``'s address.
    VALUES = -3

    def __init__(self, law, section, term):
        self.law, self.section = law, section
        self.kernels = term.kernels
        m = term.rows.shape[1]
        self.no_index = NO_INDEX.reshape(0, m, m)  # no tangent, as the kernels take it

    def term(self, term):
        """The cable's term with these hooks; not merged with other cables' terms (their
        values would be refreshed together)."""
        return replace(term, key=None, prepare=self.prepare, energy_change=self.energy_change)

    def prepare(self, t):
        """``Term.prepare``: the parameter values at ``t``, in place."""
        values = self.law.parameter_values(self.section, t)
        for _, pack in self.kernels:
            pack[self.VALUES][:] = values

    def energy(self, q, t):
        """The elastic energy at the coordinates ``q`` (all the system's) with the values of
        time ``t``."""
        values = np.array(self.law.parameter_values(self.section, t))
        return static_evaluation(
            [(function, (*pack[:self.VALUES], values, *pack[self.VALUES + 1:]))
             for function, pack in self.kernels], q, self.no_index)[0]

    def energy_change(self, q0, q1, t0, t1):
        """``Term.energy_change``: the mean over ``q0`` and ``q1`` of ``U(q; p(t1)) -
        U(q; p(t0))``."""
        return 0.5 * (self.energy(q0, t1) - self.energy(q0, t0)
                      + self.energy(q1, t1) - self.energy(q1, t0))
