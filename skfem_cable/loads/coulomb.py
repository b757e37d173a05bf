"""The solar-wind Coulomb force on charged tethers (paper Sect. 2.2.3, Eqs. 27-35).

The wind's data (``SolarWind``) hold at 1 AU; at the heliocentric distance ``r`` of a point
of a tether the force per unit length is scaled by ``(AU / r)^p``, ``p = 7/6`` by default
(``THRUST_EXPONENT``).  The Sun's position in the system's coordinates is fixed
(``sun_position`` an array: a system without an orbit, the paper's translated frame I),
or moves with time (a callable ``t -> (3,)``): ``SunAtFocus(orbit)`` for a system in a
heliocentric orbit (``System.add_orbit``), whose coordinates are offsets from the orbit's
reference point ``R(t)``, so that the Sun sits at ``-R(t)``.

Examples
--------
>>> from skfem_cable import SolarWind
>>> f"{SolarWind().force_per_length(20e3):.3e} N/m"     # 20 kV at 1 AU
'4.494e-07 N/m'
"""

from dataclasses import dataclass

import numpy as np

from ..bodies.section import check_positive
from ..core import lines
from ..core.contract import Term
from ..core.inputs import declared, reader
from ..core.linalg import thread_count
from ..kernels import coulomb as kernel
from ..kernels import line
from ..space.constants import AU
from .plasma_brake import PlasmaBrake

THRUST_EXPONENT = 7.0 / 6.0
"""Exponent ``p`` of the E-sail thrust's fall-off with solar distance, ``(AU / r)^p``
(Janhunen et al., "Electric solar wind sail: toward test missions", Rev. Sci. Instrum. 81,
111301, 2010, ref. [16] of the paper: thrust at constant voltage ``~ 1/r^(7/6)``).  The
ion-deflecting sheath of a tether is a few electron Debye lengths wide,
``lambda_D ~ sqrt(T_e / n)``, with the density ``n ~ r^-2`` and the electron temperature
``T_e ~ r^(-1/3)``, so ``lambda_D ~ r^(5/6)``; the force per unit length is the dynamic
pressure ``m_p n u^2 ~ r^-2`` times the sheath width: ``r^-2 r^(5/6) = r^(-7/6)``."""


@dataclass
class SolarWind:
    """Solar-wind plasma at the sail (defaults: 1 AU averages of Sect. 2.2.3).

    Parameters
    ----------
    speed : float
        Bulk speed ``u`` (m/s).
    density : float
        Proton density ``n0`` (1/m^3).
    V1 : float
        Voltage of the bulk kinetic energy of a proton (V).
    proton_mass, eps0 : float
        ``m_i`` (kg) and the vacuum permittivity (F/m).

    Examples
    --------
    >>> from skfem_cable import SolarWind
    >>> slow = SolarWind(speed=3e5)
    >>> round(float(slow.force_per_length(20e3) / SolarWind().force_per_length(20e3)), 6)
    0.75
    >>> float(SolarWind().force_per_length(500.0))        # below V1: no force
    0.0
    """

    speed: float = 4.0e5
    density: float = 7.3e6
    V1: float = 1.0e3
    proton_mass: float = 1.67e-27
    eps0: float = 8.854e-12

    def __post_init__(self):
        for name in ("speed", "density", "proton_mass", "eps0"):
            setattr(self, name, check_positive(name, getattr(self, name)))
        self.V1 = check_positive("V1", self.V1, allow_zero=True)

    def force_per_length(self, voltage):
        """``0.18 max(0, V0 - V1) sqrt(eps0 m_i n0) u`` (N/m): the force per unit length on
        a tether perpendicular to the wind (Eq. 29)."""
        return (0.18 * max(0.0, voltage - self.V1)
                * np.sqrt(self.eps0 * self.proton_mass * self.density) * self.speed)


@dataclass(frozen=True)
class SunAtFocus:
    """The Sun at the focus of a heliocentric ``orbit`` (``Orbit`` with ``mu = MU_SUN``), as
    seen in the coordinates of a system on it (``System.add_orbit(orbit)``): offsets from
    the reference point ``R(t)``, so the Sun sits at ``-R(t)``.  A callable ``t -> (3,)``
    for ``SolarWindForce(sun_position=...)``; a Gauss point at offset ``x`` is then at the
    heliocentric position ``R(t) + x``.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> from skfem_cable.loads.coulomb import SunAtFocus
    >>> SunAtFocus(sc.Orbit(sc.MU_SUN, sc.AU))(0.0) / sc.AU
    array([-1., -0., -0.])
    """

    orbit: object

    def __call__(self, t):
        return -self.orbit.position(t)

    def seen_from(self, reference):
        """The Sun as seen in the coordinates of a run whose ``reference`` (an
        ``orbit.Reference``: the orbit and the rectification's rebases) is this orbit's;
        this one otherwise."""
        return SunAtFocus(reference) if getattr(reference, "orbit", None) is self.orbit \
            else self


class _Component:
    """Voltage ``k`` of a callable returning the voltages of all the cables."""

    def __init__(self, source, k):
        self.source, self.k = source, k

    def __call__(self, t):
        return float(np.asarray(self.source(t))[self.k])

    def inputs(self):
        """The inputs the source reads (``inputs.declared``)."""
        return declared(self.source)

    def reading(self, table):
        """Voltage ``k`` of the source as the run of ``table`` reads it."""
        return _Component(reader(self.source, table), self.k)


class SolarWindForce:
    """Coulomb drag of the solar wind on a set of cables, a load for ``System.add_load``.

    Parameters
    ----------
    cables : sequence of line bodies
        ``Cable``s, or any bodies with the line-body hook ``line_points`` (``lines``),
        with the same points and functions per element.
    voltage : float, callable, or sequence of them (one per cable)
        Tether voltage ``V0`` (V); a callable ``V0(t)`` modulates it in time, and one
        callable may return the voltages of all the cables at once (an array, e.g. an
        ``Input`` of one value per tether that a controller sets).
    wind : SolarWind
    sun_position : array_like (3,) or callable
        Position of the Sun in the system's coordinates: fixed (the frame I of the paper,
        ``-R0``, Eq. 32), or ``sun_position(t) -> (3,)`` refreshed once per time step
        (``SunAtFocus(orbit)`` for a system in a heliocentric orbit; for an orbit about
        the Earth, the Sun's position relative to the orbit's reference point).
    exponent : float
        ``p`` of the scaling ``(AU / r)^p`` of the force with the heliocentric distance
        ``r`` of each Gauss point (default ``THRUST_EXPONENT`` = 7/6; 0: the uniform wind
        of the paper's Eq. 29, bit for bit).
    law : None or "plasma-brake"
        None: the solar wind's force of Eq. 29; ``"plasma-brake"``: a
        ``plasma_brake.PlasmaBrake`` on the cables at the (negative) ``voltage``, made
        with the keywords ``plasma``, ``brake`` (a ``BrakeLaw``) and the others of
        ``PlasmaBrake`` (``docs/esail.md``, the plasma brake).

    Notes
    -----
    The force reads the cables only through their line-body hook; its kernel is the one
    loop of the line loads with the point function ``kernels.coulomb.point``.  Each tether
    element is pushed along the wind's component perpendicular to it, with
    ``SolarWind.force_per_length`` for a tether across the wind at 1 AU (Eqs. 27-35)
    times ``(AU / r)^p``; the wind blows radially from the Sun with the velocity
    ``u i_R`` of Eq. 32, not relative to the tether (as in the paper's force law).

    Examples
    --------
    A voltage switched off after 100 s on one of two tethers:

    >>> import skfem_cable as sc
    >>> sec = sc.Section.circular(1e-5, 7e10, 2700.0)
    >>> a = sc.Cable.straight([0, 0, 0], [0, 100, 0], 2, sec, name="a")
    >>> b = sc.Cable.straight([0, 0, 0], [0, -100, 0], 2, sec, name="b")
    >>> wind = sc.SolarWindForce([a, b], [20e3, lambda t: 20e3 if t < 100 else 0.0])
    >>> wind.voltages(50.0).tolist(), wind.voltages(150.0).tolist()
    ([20000.0, 20000.0], [20000.0, 0.0])
    >>> system = sc.System([a, b]).add_load(wind)
    """

    def __new__(cls, cables, voltage, *args, law=None, **options):
        """``law="plasma-brake"``: the plasma brake of a negatively biased tether in the
        ionosphere instead (``plasma_brake.PlasmaBrake(cables, voltage, **options)``,
        with ``plasma=...``)."""
        if law == "plasma-brake":
            return PlasmaBrake(cables, voltage, *args, **options)
        return super().__new__(cls)

    def __init__(self, cables, voltage, wind=None, sun_position=(-AU, 0.0, 0.0),
                 exponent=THRUST_EXPONENT, law=None):
        if law is not None:
            raise ValueError(f"law must be None or 'plasma-brake', got {law!r}")
        self.cables = list(cables)
        if callable(voltage) and np.ndim(voltage(0.0)) == 1:
            voltage = [_Component(voltage, k) for k in range(len(self.cables))]
        elif callable(voltage) or np.ndim(voltage) == 0:
            voltage = [voltage] * len(self.cables)
        if len(voltage) != len(self.cables):
            raise ValueError(f"voltage needs one value per cable ({len(self.cables)}), "
                             f"got {len(voltage)}")
        for k, v in enumerate(voltage):
            if not callable(v) and not (np.isfinite(v) and v >= 0):
                raise ValueError(f"voltage[{k}] must be >= 0 V or a callable, got {v!r}")
        self.voltage = list(voltage)
        self.wind = wind or SolarWind()
        self.sun = sun_position if callable(sun_position) else np.asarray(sun_position,
                                                                            dtype=float)
        if not np.isfinite(exponent):
            raise ValueError(f"exponent must be finite, got {exponent!r}")
        self.scaling = np.array([AU, float(exponent)])
        self.voltages(0.0)  # a bad voltage callable fails now, not mid-run

    def inputs(self):
        """The inputs the voltages read (``inputs.declared``)."""
        return declared(*self.voltage)

    def sources(self, table=None):
        """The voltages (numbers and functions of time) as the run of ``table`` (an
        ``inputs.InputTable``) reads them; None: as given (inputs at their initial
        values)."""
        return [reader(v, table) for v in self.voltage]

    def voltages(self, t, sources=None):
        """Tether voltages (V) at time ``t`` (of ``sources``, default the voltages as
        given); a voltage callable returning a negative or non-finite value is an error
        naming the tether (this model has one polarity: a positive tether repels the
        solar-wind protons)."""
        voltage = self.voltage if sources is None else sources
        if isinstance(voltage[0], _Component):
            out = np.asarray(voltage[0].source(t), dtype=float)
            if out.shape != (len(self.cables),):
                raise ValueError(f"voltage(t) must return {len(self.cables)} voltages, one "
                                 f"per cable, got shape {out.shape}")
        else:
            out = np.array([v(t) if callable(v) else v for v in self.voltage], dtype=float)
        bad = ~(np.isfinite(out) & (out >= 0))
        if bad.any():
            k = int(np.argmax(bad))
            raise ValueError(f"voltage of tether {self.cables[k].name!r} at t = {t!r} is "
                             f"{float(out[k])}: it must be finite and >= 0 V")
        return out

    def sun_source(self, reference=None):
        """The Sun's position, fixed or a function of time, in the coordinates of a run
        of ``reference`` (``orbit.Reference``, e.g. ``Result.reference``: a position with
        ``seen_from``, as ``SunAtFocus``, follows its rebases; None: as given)."""
        seen_from = getattr(self.sun, "seen_from", None)
        return self.sun if seen_from is None else seen_from(reference)

    def sun_at(self, t, reference=None):
        """The Sun's position (3,) in the system's coordinates at time ``t`` (of the run
        of ``reference``: ``sun_source``)."""
        sun = self.sun_source(reference)
        return np.asarray(sun(t) if callable(sun) else sun, dtype=float)

    def line_force(self, r, a, coef, t, reference=None):
        """Force per unit length (N/m) at points ``r`` (..., 3) of slopes ``a`` (..., 3)
        with the coefficients ``coef`` (...) of ``coefficients`` at time ``t`` (in the
        coordinates of the run of ``reference``, ``sun_at``):
        ``coef (AU / rho)^p (i_R - (t . i_R) t)`` (Eqs. 29-32, as the kernel)."""
        rel = r - self.sun_at(t, reference)
        rho = np.linalg.norm(rel, axis=-1, keepdims=True)
        i_R = rel / rho
        tangent = a / np.linalg.norm(a, axis=-1, keepdims=True)
        u_perp = i_R - np.sum(tangent * i_R, axis=-1, keepdims=True) * tangent
        return (coef[..., None] * (self.scaling[0] / rho) ** self.scaling[1]) * u_perp

    def coefficients(self, t, sources=None):
        """Force per unit length on a perpendicular tether at 1 AU, per cable (N/m), of
        the voltages of ``sources`` (``voltages``)."""
        return np.array([self.wind.force_per_length(V) for V in self.voltages(t, sources)])

    #: Deploying tethers are supported (``System.deploy`` with a prescribed length): the
    #: force per unit material length acts on the stretched mesh.
    stretches = True

    #: Bound with the run's reference in orbit (``bind(system, reference)``): a Sun
    #: position with ``seen_from`` (``SunAtFocus``) follows the run's rebases.
    reads_reference = True

    def bind(self, system, reference=None, inputs=None):
        """The compiled term: the loop of ``kernels.line`` with the point function
        ``kernels.coulomb.point`` (``point_uniform`` for a wind that does not scale with
        the distance: no power at every point) over the points of the cables' line-body hook
        (``lines.line_points``), the per-element coefficient its ``scale`` (its
        ``kernel_parallel`` on more than one thread, ``linalg.thread_count``).  A
        time-modulated voltage, a deploying tether (the mesh stretch ``lam(t)`` multiplies
        the force per unit mesh length) or a moving Sun refreshes, once per time step
        (``Term.prepare``), only what moves: the per-element coefficients or the Sun's
        position (seen from the run's ``reference`` when the position has ``seen_from``,
        as ``SunAtFocus``); the voltages read the run's values of their inputs
        (``inputs``: the run's ``InputTable``)."""
        parts = [lines.line_points(c, system) for c in self.cables]
        points = lines.joined(parts)
        cable_of_element = np.repeat(np.arange(len(parts)), [p.shape[0] for p in parts])
        sun = self.sun_at(0.0).copy()
        pack = points.pack((sun, self.scaling), self.coefficients(0.0)[cable_of_element])
        refresh = self._refreshers(system, (pack[4], cable_of_element), sun,
                                   self.sun_source(reference), self.sources(inputs))

        def prepare(t):
            for part in refresh:
                part(t)

        prepare(0.0)
        point = kernel.point if self.scaling[1] != 0.0 else kernel.point_uniform
        hooks = line.module(point, velocity=False)
        hook = hooks.kernel_parallel if thread_count() > 1 else hooks.kernel
        rows, cols = points.tangent_pattern()
        return Term(kernels=((hook, pack),), rows=rows, cols=cols, name="solar wind",
                    prepare=prepare if refresh else None)

    def _refreshers(self, system, elements, sun, source, voltages):
        """The functions of ``t`` refreshing, in place, the per-element coefficients
        ``coef`` of ``elements = (coef, cable_of_element)`` (with a voltage callable or a
        deploying tether; of the ``voltages`` sources) and the Sun's position ``sun`` (a
        callable ``sun_position``, evaluated as ``source``)."""
        coef, cable_of_element = elements
        deploying = [system.deployment(c) is not None for c in self.cables]
        for cable, deploys in zip(self.cables, deploying):
            if deploys and system.deployment(cable).reel is not None:
                raise ValueError(f"SolarWindForce on {cable.name!r}, deployed from a reel: "
                                 "the solar wind supports prescribed lengths only")

        def coefficients(t):
            per_cable = self.coefficients(t, voltages)
            if any(deploying):
                per_cable *= np.array([system.stretch(c, t) for c in self.cables])
            coef[:] = per_cable[cable_of_element]

        def sun_position(t):
            sun[:] = source(t)

        moving = any(callable(v) for v in self.voltage) or any(deploying)
        return [part for part, needed in ((coefficients, moving),
                                          (sun_position, callable(self.sun))) if needed]

    def add_force(self, system, q, t, f, data=None, index=None, cK=1.0):
        """Add the generalized force on the cables of ``system`` at the coordinates ``q``
        and time ``t`` to ``f`` and, with ``data``, ``cK`` times its derivative at
        ``index`` (ne, 3 nf, 3 nf); returns the force resultant (N).  The term's own
        kernel (``bind``) evaluates it."""
        term = self.bind(system)
        (hook, pack), = term.kernels
        if term.prepare is not None:
            term.prepare(t)
        q = np.ascontiguousarray(q, dtype=float)
        if data is None:
            data, index = np.zeros(0), np.zeros((0,) + pack[0].shape[1:] * 2, dtype=np.int64)
        hook(pack, index, (q, np.zeros_like(q), np.array([t, -cK, 0.0, 0.0]),
                           np.zeros_like(f), f, np.zeros_like(f), data, np.zeros(1),
                           np.zeros(1)))
        return pack[-1]
