"""The orbital-motion-limited (OML) current and bias along a bare electrodynamic tether:
a two-point boundary-value problem solved by collocation.

A bare tether collects electrons from the plasma where it is biased positively and ions
where negatively, as a thin cylinder of perimeter ``p`` in the OML regime (its
cross-section small compared with the Debye length; high bias ``e |dV| >> k T``), per
unit length (Sanmartín, Martínez-Sánchez & Ahedo 1993):

    j_e p = (e N_e p / pi) sqrt(2 e dV / m_e)      (dV > 0, electrons in)
    j_i p = (e N_e p / pi) sqrt(2 e |dV| / m_i)    (dV < 0, ions in)

Sign convention
---------------
The arc length ``s`` runs from the cathodic end (``s = 0``: the hollow cathode, through
the load) to the free end (``s = L``); ``E_m(s) = ((v - v_plasma) x B) . t`` is the
motional field projected on the tangent ``t = dr/ds``; ``I(s)`` is the conventional current
in the tether, positive towards ``+s`` (as ``ElectrodynamicForce``'s current: the force
per unit length is ``I t x B``); ``dV(s) = V_tether - V_plasma`` the bias.  In the
tether's frame the plasma's potential falls along the motional field, ``dV_p/ds =
-E_m``, and Ohm's law gives ``dV_t/ds = -I / (sigma A)``; charge conservation counts the
conventional current entering per unit length (ions in, electrons out):

    dI/ds  = -j_e(dV) p + j_i(dV) p     (zero on an insulated segment)
    ddV/ds = E_m - I / (sigma A)

with ``I(L) = 0`` at the free end (the anodic end when ``E_m > 0``) and at the cathodic
end ``dV(0) = -V_C - R_L I(0) + V_s``: the cathode sits ``V_C`` (its voltage drop; 0 for
an ideal contactor) below the local plasma, the load resistance ``R_L`` drops ``R_L
I(0)`` and a power supply in series adds ``V_s`` (positive: it drives more current in the
drag sense).  The issue's pair ``dI/dx = +(e N_e p / pi) sqrt(2 e dV / m_e)``, ``ddV/dx =
E_m - I / (sigma A)`` mixes two coordinates: with ``x = L - s`` measured from the anodic
end the current equation has the plus sign and the bias equation reads ``ddV/dx = I /
(sigma A) - E_m``; with ``s`` it is as above.  ``tests/test_oml.py`` solves the
problem independently in ``x``.

Solution
--------
The problem is solved as a whole by collocation: scipy's ``solve_bvp`` (fourth-order
Lobatto IIIA collocation with Newton's method and mesh refinement on the residual, to
the tolerance ``TOL``), the segments between the insulated interval's edges stacked on a
common variable and joined by continuity conditions (the right-hand side jumps there),
from the guess ``I = 0``, ``dV = dV(0) + int_0^s E_m`` on 101 nodes, or from a previous
profile (a warm start).  A single shooting on the free
end's bias is ill-conditioned once ``L > L*``: where the bias is small (behind an ideal
contactor) the linearised system ``ddV'' = (e N p / pi) sqrt(2 e / m_e) / (2 sigma A
sqrt(dV)) ddV`` grows and decays exponentially in both directions (measured: the
cathode's residual changes 1.6e5 times faster than the free end's bias for ``L = 4
L*``, and the current then carries errors of 1e-5 relative at a 1e-12 integration
tolerance); collocation is not affected.  One limit remains: with an ideal contactor
(``V_C = 0``) and no load, a tether longer than about 10 ``L*`` has a long segment at
nearly zero bias, where the collection's ``sqrt(dV)`` is not differentiable, and the
mesh refinement exceeds ``MAX_NODES`` (``RuntimeError``); any cathode drop (a hollow
cathode's 10 to 20 V) removes it (15 ``L*`` with 20 V: 960 nodes, 54 ms).  There the
high-bias OML law itself fails (``e dV`` below ``k T_e``).

The characteristic length of the theory (Sanmartín et al. 1993): with an ideal
tether (no ohmic drop) the current collected over ``L*`` equals the short-circuit current
``sigma E_m A``,

    (2/3) (e N_e p / pi) sqrt(2 e E_m / m_e) L*^(3/2) = sigma E_m A,

so that ``L* = (m_e E_m)^(1/3) (3 pi sigma h / (4 sqrt(2) e^(3/2) N_e))^(2/3)`` for a tape
of thickness ``h`` (``p = 2 w``) and the same with ``h -> R`` for a round wire of radius
``R``.  For ``L << L*`` and an ideal contactor without a load, ``I(0) = (2/3) (e N_e p /
pi) sqrt(2 e E_m / m_e) L^(3/2)``, the issue's formula: it is the leading term, and the
ohmic drop of that current, ``dV = E_m s - int_0^s I / (sigma A)``, lowers it by the
relative ``(2/5) (L / L*)^(3/2)`` (first order; ``tests/test_oml.py`` measures -0.40003).
For ``L >> L*`` the cathode's current tends to the short-circuit current ``sigma E_m A``.

References
----------
1. J. R. Sanmartín, M. Martínez-Sánchez and E. Ahedo, "Bare wire anodes for
   electrodynamic tethers", J. Propul. Power 9(3) (1993) 353-360.
2. G. Sánchez-Arriaga et al., "BETsMA v2.0: a software tool for the analysis and design
   of bare electrodynamic tethers", Acta Astronaut. 198 (2022) 471-481.
"""

from dataclasses import dataclass

import numpy as np

from ..bodies.section import check_positive
from .plasma import OXYGEN_ION_MASS

ELEMENTARY_CHARGE = 1.602176634e-19
"""``e`` (C, exact in the SI since 2019)."""
ELECTRON_MASS = 9.1093837015e-31
"""``m_e`` (kg, CODATA 2018)."""
TOL = 1e-8
"""Tolerance of the collocation's residual (``solve_bvp``'s ``tol``, relative to ``1 +
|dy/ds|``: the derivatives are small in SI units, so about 1e-8 A/m and V/m)."""
MAX_NODES = 200000
"""Largest mesh ``solve_bvp`` may refine to."""



@dataclass(frozen=True)
class Cathode:
    """The contactor at the tether's cathodic end: a hollow cathode emitting electrons at
    ``voltage_drop`` (V, >= 0) below the local plasma, or an ideal one (0)."""

    voltage_drop: float = 0.0

    def __post_init__(self):
        check_positive("voltage_drop", self.voltage_drop, allow_zero=True)


@dataclass(frozen=True)
class BareTether:
    """A bare (or partly insulated) conductive tether: its length ``L`` (m), the
    perimeter ``p`` (m) that collects, the conducting cross-section ``A`` (m^2), the
    conductivity ``sigma`` (S/m) and an ``insulated`` interval ``(s0, s1)`` of arc length
    (from the cathodic end) that does not collect; ``BareTether.round`` and
    ``BareTether.tape`` build the usual sections."""

    length: float
    perimeter: float
    area: float
    conductivity: float
    insulated: tuple = (0.0, 0.0)

    def __post_init__(self):
        for name in ("length", "perimeter", "area", "conductivity"):
            check_positive(name, getattr(self, name))
        s0, s1 = (float(v) for v in self.insulated)
        if not 0.0 <= s0 <= s1 <= self.length:
            raise ValueError(f"insulated must be an interval (s0, s1) with 0 <= s0 <= s1 "
                             f"<= length = {self.length}, got {self.insulated!r}")

    @classmethod
    def round(cls, radius, length, conductivity, insulated=(0.0, 0.0)):
        """A wire of ``radius`` (m): ``p = 2 pi R``, ``A = pi R^2``."""
        radius = check_positive("radius", radius)
        return cls(length, 2.0 * np.pi * radius, np.pi * radius**2, conductivity, insulated)

    @classmethod
    def tape(cls, width, thickness, length, conductivity, insulated=(0.0, 0.0)):
        """A tape ``width`` x ``thickness`` (m): ``p = 2 (w + h)``, ``A = w h``."""
        width, thickness = check_positive("width", width), check_positive("thickness",
                                                                          thickness)
        return cls(length, 2.0 * (width + thickness), width * thickness, conductivity,
                   insulated)

    def characteristic_length(self, motional_field, density):
        """Sanmartín's ``L*`` (m) for a uniform ``E_m`` (V/m, > 0) and ``N_e`` (m^-3):
        ``(2/3) (e N_e p / pi) sqrt(2 e E_m / m_e) L*^(3/2) = sigma E_m A``."""
        E = check_positive("motional_field", motional_field)
        c = collection_coefficient(check_positive("density", density), self.perimeter,
                                   ELECTRON_MASS)
        return (1.5 * self.conductivity * self.area * np.sqrt(E) / c) ** (2.0 / 3.0)


def motional_field(velocity, plasma_velocity, field, tangent):
    """The motional field ``E_m = ((v - v_plasma) x B) . t`` (V/m) at points along a
    tether: the velocities (m/s), the field ``B`` (T) and the unit tangent ``t = dr/ds``
    (towards the free end), each (..., 3); shape (...)."""
    relative = np.asarray(velocity, dtype=float) - np.asarray(plasma_velocity, dtype=float)
    return np.einsum("...i,...i->...", np.cross(relative, field), tangent)


def collection_coefficient(density, perimeter, mass):
    """``(e N p / pi) sqrt(2 e / m)``: the OML current per unit length per square root of
    volt of a species of ``mass`` (kg) (A m^-1 V^-1/2)."""
    return (ELEMENTARY_CHARGE * density * perimeter / np.pi
            * np.sqrt(2.0 * ELEMENTARY_CHARGE / mass))


def sampled(name, value, stations):
    """A function of arc length from a number or from values (n,) at ``stations`` (n,)
    (piecewise linear), vectorised over arc lengths."""
    values = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(values)):
        raise ValueError(f"{name} must be finite, got {value!r}")
    if values.ndim == 0:
        return lambda s: np.full(np.shape(s), float(values))
    if stations is None or np.shape(stations) != values.shape or values.ndim != 1:
        raise ValueError(f"{name} given at points needs stations of the same shape (arc "
                         f"lengths, m), got {values.shape} and {np.shape(stations)}")
    if not np.all(np.diff(stations) > 0.0):
        raise ValueError(f"stations must increase (arc lengths, m), got {stations!r}")
    return lambda s: np.interp(s, stations, values)


@dataclass
class OMLProfile:
    """The solved current (A) and bias (V) along the tether: ``current(s)``,
    ``bias(s)`` at arc lengths ``s`` (from the cathodic end; the collocation's cubic
    interpolant), the ``cathode_current`` ``I(0)``, the free end's bias ``anode_bias``
    ``dV(L)`` and the number of collocation ``nodes`` per segment."""

    solution: object
    segments: list
    cathode_current: float
    anode_bias: float
    nodes: int

    def _evaluate(self, s, row):
        s = np.asarray(s, dtype=float)
        flat, out = s.ravel(), np.full(s.size, np.nan)
        for k, (a, b, _) in enumerate(self.segments):
            inside = (flat >= a) & (flat <= b)
            tau = (flat[inside] - a) / (b - a) * self.segments[-1][1]
            out[inside] = self.solution(tau)[2 * k + row]
        return out.reshape(s.shape)

    def current(self, s):
        """The current ``I`` (A, positive towards ``+s``) at arc lengths ``s``."""
        return self._evaluate(s, 0)

    def bias(self, s):
        """The bias ``dV = V_tether - V_plasma`` (V) at arc lengths ``s``."""
        return self._evaluate(s, 1)


class OMLProblem:
    """The OML boundary-value problem of a tether in given fields (module docstring).

    Parameters
    ----------
    tether : BareTether
    motional_field : float or array_like
        ``E_m`` (V/m) along ``+s``: a number or values at ``stations``.
    density : float or array_like
        Electron density ``N_e`` (m^-3, > 0): a number or values at ``stations``.
    cathode : Cathode
    load_resistance : float
        ``R_L`` (ohm, >= 0).
    supply_voltage : float
        ``V_s`` (V) of a power supply in series, positive in the drag sense.
    stations : array_like, optional
        Arc lengths (m, increasing) of sampled ``motional_field`` and ``density``
        (interpolated linearly).
    ion_mass : float
        Ion mass (kg, > 0); default O+.

    Examples
    --------
    A 1 km aluminium tape in a 0.15 V/m motional field, with an ideal cathode:

    >>> from skfem_cable.environment import BareTether, OMLProblem
    >>> tape = BareTether.tape(0.02, 5e-5, 1000.0, 3.5e7)
    >>> profile = OMLProblem(tape, 0.15, 1e11).solve()
    >>> f"{profile.cathode_current:.4f} A"
    '0.9182 A'
    """

    def __init__(self, tether, motional_field, density, cathode=Cathode(),
                 load_resistance=0.0, supply_voltage=0.0, stations=None,
                 ion_mass=OXYGEN_ION_MASS):
        self.tether, self.cathode = tether, cathode
        self.E = sampled("motional_field", motional_field, stations)
        self.N = sampled("density", density, stations)
        if np.any(np.asarray(density, dtype=float) <= 0.0):
            raise ValueError(f"density must be > 0 (m^-3), got {density!r}")
        self.resistance = check_positive("load_resistance", load_resistance, allow_zero=True)
        self.supply = float(supply_voltage)
        self.c_e = collection_coefficient(1.0, tether.perimeter, ELECTRON_MASS)
        self.c_i = collection_coefficient(1.0, tether.perimeter,
                                          check_positive("ion_mass", ion_mass))
        edges = np.unique([0.0, *tether.insulated, tether.length])
        s0, s1 = tether.insulated
        self.segments = [(a, b, not s0 <= 0.5 * (a + b) <= s1)
                         for a, b in zip(edges[:-1], edges[1:])]
        """``(a, b, collecting)`` of the segments between the insulated interval's
        edges."""

    def rhs(self, s, y, collecting=True):
        """``(dI/ds, ddV/ds)`` (2, n) at arc lengths ``s`` (n,) for ``y = (I, dV)``
        (2, n); ``collecting`` False on the insulated segment."""
        I, dV = y
        rate = np.where(dV >= 0.0, -self.c_e, self.c_i) if collecting else 0.0
        return np.vstack([self.N(s) * rate * np.sqrt(np.abs(dV)),
                          self.E(s) - I / (self.tether.conductivity * self.tether.area)])

    def stacked_rhs(self, tau, Y):
        """The segments' systems on the common variable ``tau`` in [0, L]: ``Y`` (2 m,
        n) stacks ``(I, dV)`` of the ``m`` segments, ``s = a + tau (b - a) / L`` (a
        variable of the dimension of ``s``: ``solve_bvp``'s residuals, relative to ``1 +
        |dY/dtau|``, then weigh as in the arc length)."""
        L = self.tether.length
        return np.vstack([(b - a) / L * self.rhs(a + tau * (b - a) / L, Y[2 * k:2 * k + 2],
                                                  on)
                          for k, (a, b, on) in enumerate(self.segments)])

    def guess(self, nodes):
        """The common variable's ``nodes`` values and the guess ``I = 0``, ``dV = dV(0) +
        int_0^s E_m`` on each segment (2 m, nodes)."""
        L = self.tether.length
        tau, guess = np.linspace(0.0, L, nodes), []
        dV = self.supply - self.cathode.voltage_drop
        for a, b, _ in self.segments:
            s = a + tau * (b - a) / L
            emf = np.concatenate([[0.0], np.cumsum(np.diff(s) * 0.5
                                                   * (self.E(s[1:]) + self.E(s[:-1])))])
            guess += [np.zeros_like(s), dV + emf]
            dV += emf[-1]
        return tau, np.vstack(guess)

    def boundary(self, Y0, Y1):
        """``dV(0) = -V_C - R_L I(0) + V_s``, ``I(L) = 0`` and the continuity of ``(I,
        dV)`` between consecutive segments."""
        cathode = (Y0[1] + self.cathode.voltage_drop + self.resistance * Y0[0]
                   - self.supply)
        return np.concatenate([[cathode, Y1[-2]], Y1[:-2] - Y0[2:]])

    def solve(self, nodes=101, start=None):
        """The profile (``OMLProfile``) by ``solve_bvp``, from ``nodes`` equally spaced
        values of the common variable and the guess of the module docstring, or from the
        mesh and values of the profile ``start`` of the same tether (a warm start, e.g.
        the previous step's); raises ``RuntimeError`` when the collocation does not
        converge."""
        from scipy.integrate import solve_bvp  # here, not at import (0.2 s)

        if start is not None:
            tau = start.solution.x
            guess = start.solution(tau)
        else:
            tau, guess = self.guess(nodes)
        sol = solve_bvp(self.stacked_rhs, self.boundary, tau, guess, tol=TOL,
                        max_nodes=MAX_NODES)
        if not sol.success:
            raise RuntimeError(f"OML collocation did not converge: {sol.message}")
        return OMLProfile(sol.sol, self.segments, float(sol.y[0, 0]),
                          float(sol.y[-1, -1]), sol.x.size)
