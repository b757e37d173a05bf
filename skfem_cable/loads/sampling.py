"""A density model sampled at a body's points once per time step (``DensitySampler``):
the step hook and ``prepare`` of the drag terms (``drag.FreeMolecularDrag``,
``atmosphere.AtmosphericDrag``), so that a model such as ``environment.MSIS`` is never
called in the Newton iterations.  With ``sample_every=h`` the model is evaluated at knots
every ``h`` seconds along the reference point instead (``knots.OrbitKnots``: blocks of
knots in one call, the logarithm interpolated in time and carried to the points by its
gradient), so a step refused and retried, or a step shorter than ``h``, costs no model
call."""

import numpy as np

from ..bodies.section import check_positive
from ..environment.epoch import bound_model
from .accepted import AcceptedState
from .knots import OrbitKnots

FLOOR = 1e-300
"""The smallest density (kg/m^3) whose logarithm the knots interpolate."""


def is_model(density):
    """True when ``density`` is a model (an object with ``density(x, t)``), not a
    number."""
    return callable(getattr(density, "density", None))


def density_model(density):
    """``density`` if it is a model (``is_model``), else the number checked positive
    (``ValueError`` naming ``density``)."""
    return density if is_model(density) else check_positive("density", density)


class DensitySampler(AcceptedState):
    """The density of a model at a body's points, evaluated once per time step: a step
    hook of the run (``AcceptedState``: it keeps the last accepted state) and the
    term's ``prepare(t)`` (the density at the positions predicted for ``t``).

    Parameters
    ----------
    model : object with ``density(x, t)``
        The density (kg/m^3) at absolute positions ``x`` (..., 3) (m), ``t`` s after the
        epoch (already bound to the system's epoch: ``environment.bound_model``).
    positions : callable
        ``positions(q)``: the offsets (ne, nq, 3) of the body's points for the
        coordinates ``q``.
    weights : ndarray (ne, nq)
        The points' weights: ``out[e]`` is the weighted mean over element ``e``'s points.
    orbit : Orbit, Reference or None
        The reference point ``R(t)`` of a system in orbit (None: the positions are
        absolute).
    q0 : ndarray
        The coordinates before a run's first step (the system's initial ones).
    sample_every : float or None
        None: the model at the points at every time step; a spacing ``h`` (s, > 0): the
        model at knots every ``h`` seconds at the points' mean (module notes).

    Attributes
    ----------
    out : ndarray (ne,)
        The per-element density (kg/m^3) that the term's kernel reads, refreshed in place.
    calls : int
        Evaluations of the model so far (one per time step; at knots, the knots
        evaluated, ``BLOCK`` per model call).
    """

    def __init__(self, model, positions, weights, orbit, q0, sample_every=None):
        self.model, self.positions, self.orbit = model, positions, orbit
        self.weights = np.asarray(weights, dtype=float)
        self.out = np.zeros(self.weights.shape[0])
        self.calls, self.mean = 0, np.zeros(3)
        t0 = 0.0 if orbit is None else orbit.t0
        self.knots = None if sample_every is None else OrbitKnots(
            sample_every, t0, lambda t: self.mean + self.reference(t), None, model,
            floor=FLOOR)
        self.accept(q0, np.zeros_like(q0), t0)
        self.prepare(self.t)

    def reference(self, t):
        """The reference point ``R(t)`` (3,) (m) of a system in orbit, zero without."""
        return np.zeros(3) if self.orbit is None else self.orbit.position(t)

    def prepare(self, t):
        """The density at time ``t`` at the positions predicted from the last accepted
        state ``(q_n, v_n, t_n)``, ``q_n + (t - t_n) v_n``: evaluated once per time
        (the Python path calls ``prepare`` at every evaluation)."""
        t = float(t)
        if t == self.done:
            return
        x = self.positions(self.q + (t - self.t) * self.v) + self.reference(t)
        if self.knots is None:
            rho = np.asarray(self.model.density(x, t), dtype=float)
            self.calls += 1
        else:
            self.mean = x.reshape(-1, 3).mean(axis=0) - self.reference(t)
            rho = self.knots.at(x, t)[2]
            self.calls = self.knots.calls
        self.out[:] = np.sum(self.weights * rho, axis=1) / np.sum(self.weights, axis=1)
        self.done = t



def line_sampler(model, points, system, orbit, sample_every=None):
    """The ``DensitySampler`` of ``model`` at the points ``points`` (``lines.LinePoints``)
    of a line body of ``system`` in orbit ``orbit`` (a ``Reference`` or None), the model
    at the system's epoch (``environment.bound_model``), at knots every ``sample_every``
    seconds if given."""
    return DensitySampler(bound_model(model, system.epoch, "density"),
                          lambda q: points.at(q)[0], points.w, orbit, system.q0,
                          sample_every)
