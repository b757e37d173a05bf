"""A run's reference: the orbit and the rebases of its rectification."""

import bisect

import numpy as np

from .orbit import Orbit, _FunctionsOfTime


class Reference(_FunctionsOfTime):
    """The reference of a run of a system in orbit: the system's ``orbit`` and the arcs
    of the rebases of Encke's rectification (``solvers.rectify``), each in force from its
    rebase time on.  A run's state, not the model's: ``simulate`` makes one per run from
    ``System.orbit`` (the terms reading ``R(t)``, ``V(t)`` hold it through the system's
    binding, ``Layout.reference``), checkpoints save its ``rebases`` and the run's
    ``Result`` carries it (``Result.reference``).

    Parameters
    ----------
    orbit : Orbit
        The orbit as given: the arc in force before the first rebase.
    rebases : array_like (k, 7), optional
        Rebases to make at once (``restore``).

    Examples
    --------
    >>> import skfem_cable as sc
    >>> orbit = sc.Orbit(sc.MU_EARTH, 7e6)
    >>> reference = sc.Reference(orbit)
    >>> reference.rebase(orbit.position(10.0) + 1.0, orbit.velocity(10.0), 10.0)
    >>> reference.rebases.shape, len(sc.Reference(orbit).rebases)
    ((1, 7), 0)
    """

    def __init__(self, orbit, rebases=None):
        self.orbit = orbit
        self.restore(rebases)

    @property
    def mu(self):
        """The orbit's gravitational parameter (m^3/s^2)."""
        return self.orbit.mu

    @property
    def t0(self):
        """The orbit's epoch (s)."""
        return self.orbit.t0

    @property
    def central_body(self):
        """The orbit's ``central_body``."""
        return self.orbit.central_body

    def body_rotation(self):
        """The orbit's ``body_rotation()``."""
        return self.orbit.body_rotation()

    def copy(self):
        """A reference with the same arcs, to the last bit, that later rebases of this one
        leave alone."""
        return Reference(self.orbit, self.rebases)

    # --- the arcs of the rebases ---------------------------------------------------------
    def rebase(self, r, v, t):
        """Encke's rectification: from time ``t`` on, the reference is the orbit through
        the absolute position ``r`` (m) and velocity ``v`` (m/s), ``from_state(mu, r, v,
        t)``; before ``t`` the arcs in force stay.  Times of rebases must increase."""
        t = float(t)
        if self._starts and not t > self._starts[-1]:
            raise ValueError(f"Reference.rebase: t = {t!r} s is not after the last "
                             f"rebase at {self._starts[-1]!r} s")
        row = np.concatenate([[t], np.asarray(r, dtype=float), np.asarray(v, dtype=float)])
        self._arcs.append((row, Orbit.from_state(self.mu, row[1:4], row[4:], t)))
        self._starts.append(t)

    @property
    def rebases(self):
        """The rebases so far, one row ``(t, r, v)`` (7,) each: shape (k, 7)."""
        return np.array([row for row, _ in self._arcs]).reshape(-1, 7)

    def restore(self, rebases=None):
        """Drop the rebases, then make those of ``rebases`` (rows of ``rebases``) again:
        the same arcs, to the last bit."""
        self._arcs, self._starts = [], []
        rows = np.asarray([] if rebases is None else rebases, dtype=float).reshape(-1, 7)
        for row in rows:
            self.rebase(row[1:4], row[4:7], row[0])

    def arc(self, t):
        """The Keplerian orbit in force at the time ``t`` (a float): the orbit as given
        before the first rebase, else that of the latest rebase at or before ``t``."""
        if not self._starts or t < self._starts[0]:
            return self.orbit
        return self._arcs[bisect.bisect_right(self._starts, t) - 1][1]

    def _each_arc(self, t, function):
        """``function(arc, times)`` over the times ``t`` (array_like) in force on each
        arc, gathered in the shape of ``t`` (leading axes)."""
        t = np.asarray(t, dtype=float)
        if not self._starts:
            return function(self.orbit, t)
        flat = t.reshape(-1)
        index = np.searchsorted(self._starts, flat, side="right")
        out = None
        for k in np.unique(index):
            where = index == k
            part = function(self.orbit if k == 0 else self._arcs[k - 1][1], flat[where])
            if out is None:
                out = np.empty((flat.size, *part.shape[1:]))
            out[where] = part
        return out.reshape(t.shape + out.shape[1:])
