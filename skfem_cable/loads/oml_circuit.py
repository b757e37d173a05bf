"""The OML circuit of a bare tether as ``ElectrodynamicForce(current="oml")`` binds it:
the fixed mesh of the solver on the line body's own points, the per-step environment
and the compiled term (``kernels.oml_force``).

The stations are the line body's quadrature points (Gauss-Legendre in every element, in
the elements' order from the cathodic end ``s = 0``); the solver's nodes are the stations,
the tether's ends and the insulated interval's edges (``kernels.oml``: fourth-order
Lobatto IIIA collocation, fields linear between stations as ``OMLProblem``'s).  The
motional field is per unit *reference* length (``E = ((u - u_p) x B) . r_x``, the EMF's
integrand); the collection and the ohmic drop are per unit reference length too (the
tether's strain, about 1e-4, is left out of its perimeter and resistance).

Once per time step (``Term.prepare(t)``; again at the same time, by an evaluation from
Python, it does nothing) the plasma's density and velocity and a Python field's value and
gradient (``IGRF``) are evaluated, one call each for all the points, at the positions
predicted for ``t`` from the last accepted state of the run, ``q_n + (t - t_n) v_n``
(``StepEnvironment``, a step hook), never at a Newton iterate's: the iterate of a step
that diverged and is refused (offsets of 5e8 m were seen) would otherwise put every
retry's density model out of range (``docs/environment.md``); within the
step the density and plasma velocity are held and such a field is linearised about those
positions (``kernels.oml_force.linearised_field``: its error is of the order of ``(dx /
r)^2`` for a displacement ``dx`` within the step, the field varying on the scale of the
distance ``r`` from the Earth's centre).  A dipole or uniform field is evaluated at every
iterate, compiled.  With ``sample_every`` the density and a Python field are instead
sampled at knots along the reference point and interpolated (``loads.knots``); the
plasma's velocity (the co-rotation, cheap) is still evaluated per step.  Models made
without an epoch take the system's (``environment.bound_model``).
"""

from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

from ..bodies.section import check_positive
from ..core import lines
from ..core.contract import Term
from ..environment.epoch import bound_model
from ..environment.oml import ELECTRON_MASS, Cathode, collection_coefficient
from ..kernels import oml_force as kernel
from ..kernels.oml import MAX_ITER
from .accepted import AcceptedState
from .knots import OrbitKnots

#: The numbers the OML force records at every saved step (``ElectrodynamicForce.
#: step_outputs``, ``Term.outputs``): ``summary``'s, the force by component.
#: The most coordinates of a line body whose OML force carries the current's coupling in
#: its tangent by default (``OMLCircuit.coupled``): 9 cable elements (60).  The block
#: then stays out of the linear solver's dense border (``model.layout.Layout.DENSE_ROW``,
#: 64); the 10-element wire of ``benchmarks/oml_cost.py`` (66) with it cost 2.3 times
#: the step without (``docs/environment.md``).
COUPLED = 64

OUTPUTS = ("current", "emf", "power", "mean_current", "anode_bias", "load_power", "ohmic",
           "force_x", "force_y", "force_z")


@dataclass(frozen=True)
class OMLCircuit:
    """What the OML current reads besides the geometry and the field (the parameters of
    ``ElectrodynamicForce`` with ``current="oml"``): the ``plasma`` (``density(x, t)``,
    ``velocity(x, t)``, ``ion_mass``: ``environment.plasma``), the ``cathode``, the
    ``load`` resistance (ohm, >= 0), the ``supply_voltage`` (V, in series, positive in
    the drag sense), the ``conductivity`` (S/m), the conducting ``area`` (m^2), the
    collecting ``perimeter`` (m) and the ``insulated`` interval ``(s0, s1)`` of arc
    length; ``sample_every``: None, the models once per step, or the spacing (s) of
    the knots they are sampled at (``loads.knots``); ``coupling``: whether the tangent
    carries the current's coupling (``coupled``)."""

    plasma: object
    cathode: Cathode
    load: float
    supply_voltage: float
    conductivity: float
    area: float
    perimeter: float
    insulated: tuple
    sample_every: object = None
    coupling: object = None

    def __post_init__(self):
        for name in ("density", "velocity"):
            if not callable(getattr(self.plasma, name, None)):
                raise TypeError(f"plasma must have density(x, t) and velocity(x, t) "
                                f"(environment.plasma), got {self.plasma!r}")
        check_positive("load", self.load, allow_zero=True)
        for name in ("conductivity", "area", "perimeter"):
            check_positive(name, getattr(self, name))
        if not np.isfinite(self.supply_voltage):
            raise ValueError(f"supply_voltage must be finite (V), got {self.supply_voltage!r}")
        if self.sample_every is not None:
            check_positive("sample_every", self.sample_every)
        if self.coupling not in (None, True, False):
            raise ValueError(f"coupling must be None (exact up to {COUPLED} coordinates), "
                             f"True or False, got {self.coupling!r}")

    def coupled(self, n_coordinates):
        """Whether the tangent of a line body of ``n_coordinates`` coordinates carries
        the current's coupling (``kernels.oml_coupling``, a block dense over them):
        ``coupling`` when given, else up to ``COUPLED`` coordinates."""
        return n_coordinates <= COUPLED if self.coupling is None else self.coupling

    def coefficients(self):
        """``(c, bc)``: ``c = (c_e, c_i, 1 / (sigma A))`` per unit density and ``bc =
        (V_C, R_L, V_s)`` (``kernels.oml``)."""
        c = np.array([collection_coefficient(1.0, self.perimeter, ELECTRON_MASS),
                      collection_coefficient(1.0, self.perimeter, self.plasma.ion_mass),
                      1.0 / (self.conductivity * self.area)])
        return c, np.array([self.cathode.voltage_drop, self.load, self.supply_voltage])


def circuit(cable, current, plasma, cathode, load, conductivity, perimeter, insulated,
             supply_voltage, sample_every=None, coupling=None):
    """The ``OMLCircuit`` of ``ElectrodynamicForce``'s arguments when ``current`` is
    ``"oml"`` (None otherwise, refusing its parameters)."""
    if not (isinstance(current, str) and current == "oml"):
        if plasma is not None or conductivity is not None or sample_every is not None \
                or coupling is not None:
            raise ValueError(f"plasma, conductivity, sample_every and coupling are used "
                             f"only with current='oml', got current={current!r}")
        return None
    if plasma is None or conductivity is None:
        raise ValueError("current='oml' needs plasma (density(x, t), velocity(x, t)) and "
                         "conductivity (S/m, > 0)")
    area = getattr(getattr(cable, "section", None), "A", None)
    if area is None:
        raise ValueError(f"cable: current='oml' reads the conductor's area from the line "
                         f"body's section.A, got {cable!r} without one")
    perimeter = 2.0 * np.sqrt(np.pi * area) if perimeter is None else perimeter
    return OMLCircuit(plasma, cathode, float(load), float(supply_voltage),
                      float(conductivity), float(area), float(perimeter), tuple(insulated),
                      sample_every, coupling)


def stations(points):
    """The arc lengths (ne nq,) of the points of ``points`` (``lines.LinePoints``) and
    the tether's length: the elements in order, each with a Gauss-Legendre rule (its
    weights checked)."""
    ne, nq = points.shape
    xi, weights = np.polynomial.legendre.leggauss(nq)
    lengths = points.w.sum(axis=1)
    if not np.allclose(points.w, 0.5 * weights[None, :] * lengths[:, None], rtol=1e-10):
        raise ValueError("cable: the OML current needs the line body's points on a "
                         "Gauss-Legendre rule in every element (lines.LinePoints.w)")
    starts = np.concatenate([[0.0], np.cumsum(lengths)[:-1]])
    return (starts[:, None] + 0.5 * (xi[None, :] + 1.0) * lengths[:, None]).ravel(), \
        float(lengths.sum())


def mesh_nodes(s, length, insulated):
    """``(z, i0, i1, wt, on, at)`` of ``kernels.oml`` for the stations ``s`` (increasing,
    inside ``(0, length)``) and the ``insulated`` interval: the nodes, the stations
    and weights of the fields' linear interpolation at them (constant beyond the end
    stations), the intervals' collecting flags and the node of each station."""
    s0, s1 = (float(v) for v in insulated)
    if not 0.0 <= s0 <= s1 <= length:
        raise ValueError(f"insulated must be an interval (s0, s1) with 0 <= s0 <= s1 <= "
                         f"the tether's length {length}, got {insulated!r}")
    edges = [s0, s1] if s1 > s0 else []
    z = np.unique(np.concatenate([[0.0, length], s, edges]))
    i1 = np.clip(np.searchsorted(s, z), 1, s.size - 1)
    i0 = i1 - 1
    wt = np.clip((z - s[i0]) / (s[i1] - s[i0]), 0.0, 1.0)
    middle = 0.5 * (z[1:] + z[:-1])
    on = np.where((middle >= s0) & (middle <= s1) & (s1 > s0), 0.0, 1.0)
    at = np.searchsorted(z, s)
    return (z, i0.astype(np.int64), i1.astype(np.int64), wt, on, at.astype(np.int64))


class StepEnvironment(AcceptedState):
    """The per-step environment of the OML term: a step hook of the run
    (``AcceptedState``: it keeps the last accepted state) and the term's ``prepare(t)``,
    which writes the offsets (ne, nq, 3) of the points predicted for ``t`` from that
    state, ``q_n + (t - t_n) v_n``, into ``offsets`` and calls ``refresh(t)`` (the models
    at those points), once per time; ``motion(t)`` (the reference point's position and
    velocity) at every call.  A diverged iterate of a refused step never reaches the
    models."""

    def __init__(self, positions, offsets, motion, refresh, q0, t0):
        self.positions, self.offsets = positions, offsets
        self.motion, self.refresh = motion, refresh
        self.accept(q0, np.zeros_like(q0), t0)

    def prepare(self, t):
        """The reference point at ``t`` and, once per time, the models at the predicted
        points (class docstring)."""
        t = float(t)
        self.motion(t)
        if t == self.done:
            return
        self.offsets[:] = self.positions(self.q + (t - self.t) * self.v)
        self.refresh(t)
        self.done = t


def bind_oml(force, system, orbit, q=None):
    """``(term, pack)`` of the OML force ``force`` (``ElectrodynamicForce``) on
    ``system`` about the reference point of ``orbit`` (None: no orbit): the pack of
    ``kernels.oml_force`` and the term's ``prepare`` (module docstring), whose first
    positions are those of ``q`` (default ``system.q0``; given, a single evaluation:
    the models are evaluated at the points, not at knots)."""
    circuit = force.oml
    points = lines.line_points(force.cable, system)
    s, length = stations(points)
    nodes = mesh_nodes(s, length, circuit.insulated)
    shape = points.shape
    motion, source = np.zeros((2, 3)), np.zeros((2, 3))
    cache = (np.zeros(shape + (3,)), np.zeros(shape + (3,)), np.zeros(shape + (3, 3)),
             np.zeros(shape + (3,)), np.zeros(s.size), np.zeros(shape + (3,)))
    mesh = (nodes, np.zeros(s.size), np.zeros(nodes[0].size), np.zeros(nodes[0].size))
    scratch = tuple(np.zeros(shape + extra) for extra in
                    [(3,)] * 4 + [(3, 3)] + [(3,)] + [(3, 3)] * 3 + [()] * 2)
    coordinates = np.unique(points.edofs)
    coupled = circuit.coupled(coordinates.size)
    pack = ((points.edofs, points.S, points.Sx, points.w), motion, source, cache, mesh,
            circuit.coefficients(), kernel.empty_work(nodes[0].size - 1), scratch,
            coupling_work(points, coordinates if coupled else coordinates[:0], nodes),
            np.zeros(6))

    plasma = bound_model(circuit.plasma, system.epoch, "plasma")
    field = force.bound_field(system)
    knots = None if circuit.sample_every is None or q is not None else OrbitKnots(
        circuit.sample_every, 0.0 if orbit is None else orbit.t0,
        lambda t: cache[5].reshape(-1, 3).mean(axis=0) + (
            0.0 if orbit is None else orbit.position(t)),
        field if field is None or callable(getattr(field, "field", None)) else
        SimpleNamespace(field=lambda x, t: force.field_and_gradient(x, t, field)), plasma)

    def move(t):
        if orbit is not None:
            motion[0], motion[1] = orbit.position(t), orbit.velocity(t)

    def refresh(t):
        X = (cache[5] + motion[0]).reshape(-1, 3)
        cache[0][:] = X.reshape(cache[0].shape)
        cache[3][:] = np.asarray(plasma.velocity(X, t)).reshape(cache[3].shape)
        if force.compiled is not None:
            source[:] = force.compiled.sources(t)
        if knots is not None:
            B, dB, cache[4][:] = knots.at(X, t)
        else:
            cache[4][:] = plasma.density(X, t)
            if field is not None:
                B, dB = force.field_and_gradient(X, t, field)
        if field is not None:
            cache[1][:], cache[2][:] = (np.reshape(B, cache[1].shape),
                                        np.reshape(dB, cache[2].shape))

    step = StepEnvironment(lambda y: points.at(y)[0], cache[5], move, refresh,
                           np.asarray(system.q0 if q is None else q, dtype=float),
                           0.0 if orbit is None else orbit.t0)
    step.prepare(step.t)
    rows, cols = tangent_pattern(points, coordinates if coupled else coordinates[:0])
    hook = kernel.kernel_dipole if force.compiled is not None else kernel.kernel_cached
    return Term(kernels=((hook, pack),), rows=rows, cols=cols, prepare=step.prepare,
                hooks=(step,), outputs=lambda: outputs(pack, circuit, force.step_outputs),
                name=f"OML electrodynamic force {force.cable.name}"), pack


def coupling_work(points, coordinates, nodes):
    """The coupling's arrays of ``kernels.oml_force``'s pack over the line body's
    ``coordinates`` (sorted; none: the coupling left out) for the solver's ``nodes``:
    ``(local, dy, G, D, H)`` (``kernels.oml_coupling``)."""
    ns, nd = points.w.size, points.edofs.shape[1]
    k, n = (nodes[0].size, ns) if coordinates.size else (0, 0)
    local = np.searchsorted(coordinates, points.edofs) if coordinates.size else \
        np.zeros((0, nd), dtype=np.int64)
    return (local.astype(np.int64), np.zeros((k, 2 * k)), np.zeros((n, n)),
            np.zeros((n, nd)), np.zeros((n, coordinates.size)))


def tangent_pattern(points, coordinates):
    """``(rows, cols)``, flat, of the OML force's tangent: the element blocks of the
    line body's points, then the block dense over ``coordinates`` (the coupling)."""
    rows, cols = np.broadcast_arrays(*points.tangent_pattern())
    return (np.concatenate([rows.ravel(), np.repeat(coordinates, coordinates.size)]),
            np.concatenate([cols.ravel(), np.tile(coordinates, coordinates.size)]))


def solved(pack):
    """``pack`` (``bind_oml``), or ``RuntimeError`` when its last evaluation's profile did
    not converge (``kernels.oml_force.finish``)."""
    if pack[-1][4] < 0:
        raise RuntimeError(f"OML current: Newton's iteration of the profile did not "
                           f"converge within {MAX_ITER} iterations (kernels.oml)")
    return pack


def profile(pack, s, row):
    """The current (``row`` 0, A) or bias (1, V) of the last evaluation of the pack
    ``pack`` (``bind_oml``) at arc lengths ``s`` (m): linear between the solver's
    nodes."""
    z, x = solved(pack)[4][0][0], pack[6][0]
    return np.interp(np.asarray(s, dtype=float), z, x[row::2])


def summary(pack, circuit):
    """The summaries of the last evaluation of ``pack`` (``ElectrodynamicForce.
    evaluate``): ``current`` ``I(0)`` (A), ``emf`` ``int E ds`` (V), ``power`` ``int I
    E ds`` (W), ``mean_current`` (A), ``anode_bias`` ``dV(L)`` (V), ``load_power``
    ``R_L I(0)^2`` (W), ``ohmic``
    ``int I^2 / (sigma A) ds`` (W), ``iterations`` and ``force`` (N, (3,))."""
    points, out, scratch = solved(pack)[0], pack[-1], pack[7]
    w, I = points[3], scratch[9]
    return {"current": float(out[0]), "emf": float(out[1]), "power": float(out[2]),
            "mean_current": float(out[3]), "anode_bias": float(out[5]),
            "load_power": circuit.load * float(out[0])**2,
            "ohmic": float(np.sum(w * I**2)) / (circuit.conductivity * circuit.area),
            "iterations": int(out[4]), "force": np.einsum("eg,egi->i", w, scratch[5])}


def names(prefix, circuit):
    """The per-step outputs' names of an OML force (``ElectrodynamicForce.step_outputs``:
    ``<prefix>_<key>`` for the keys of ``OUTPUTS``), none when ``circuit`` is None (a
    prescribed current)."""
    return () if circuit is None else tuple(f"{prefix}_{key}" for key in OUTPUTS)


def outputs(pack, circuit, names):
    """The per-step outputs (``OUTPUTS``) of the last evaluation of ``pack`` under
    ``names`` (the load's ``step_outputs``, in that order): NaN when its profile did not
    converge."""
    if pack[-1][4] < 0:
        return dict.fromkeys(names, np.nan)
    out = summary(pack, circuit)
    out.update(zip(("force_x", "force_y", "force_z"), out.pop("force")))
    return {name: float(out[key]) for name, key in zip(names, OUTPUTS)}
