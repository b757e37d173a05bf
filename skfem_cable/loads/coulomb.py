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
from typing import ClassVar

import numpy as np

from ..bodies.section import check_positive
from ..core import lines
from ..core.contract import Term
from ..core.inputs import declared, reader
from ..kernels import coulomb as kernel
from ..space.constants import AU
from . import plasma_brake  # noqa: F401 (registers law="plasma-brake")
from .solar_wind_series import SolarWindSeries, WindStatistics, read_series, synthetic_series
from .thrust_laws import THRUST_EXPONENT, thrust_law  # noqa: F401 (the scenes import it here)


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

    #: A steady wind: ``SolarWindForce`` reads it once (``SolarWindSeries`` varies).
    varies: ClassVar[bool] = False

    def __post_init__(self):
        for name in ("speed", "density", "proton_mass", "eps0"):
            setattr(self, name, check_positive(name, getattr(self, name)))
        self.V1 = check_positive("V1", self.V1, allow_zero=True)

    def force_per_length(self, voltage):
        """``0.18 max(0, V0 - V1) sqrt(eps0 m_i n0) u`` (N/m): the force per unit length on
        a tether perpendicular to the wind (Eq. 29)."""
        return (0.18 * max(0.0, voltage - self.V1)
                * np.sqrt(self.eps0 * self.proton_mass * self.density) * self.speed)

    def at(self, t):
        """The wind at time ``t``: this one (a steady wind)."""
        return self

    @classmethod
    def series(cls, times, density, speed, direction=None, B=None, constants=None):
        """A wind varying in time (``SolarWindSeries``): ``density`` (1/m^3) and ``speed``
        (m/s) at 1 AU sampled at ``times`` (s), linear between them, optional field ``B``
        (nt, 3) (T), with the ``V1``, ``proton_mass`` and ``eps0`` of ``constants`` (a
        ``SolarWind``; None: the defaults).  ``direction`` must be None: the force's wind
        blows radially from the Sun (Eq. 32)."""
        if direction is not None:
            raise ValueError("direction: the solar wind of SolarWindForce blows radially "
                             f"from the Sun (Eq. 32); only None is accepted, got {direction!r}")
        return SolarWindSeries(times, density, speed, B, constants or cls())

    @classmethod
    def read_series(cls, source, constants=None):
        """``series`` of a CSV file or an xarray Dataset (``solar_wind_series.read_series``)."""
        return read_series(source, constants or cls())

    @classmethod
    def synthetic(cls, duration, step=600.0, seed=0, stats=None, constants=None):
        """A seeded synthetic ``series`` of ``duration`` s sampled every ``step`` s, of the
        statistics ``stats`` (``solar_wind_series.WindStatistics``: slow and fast streams,
        log-normal fluctuations, stream interfaces, with their sources; None: its
        defaults)."""
        return synthetic_series(duration, constants or cls(), step, seed,
                                stats or WindStatistics())


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
    wind : SolarWind or SolarWindSeries
        The wind's data at 1 AU, steady or varying in time (``SolarWind.series``:
        sampled once per time step).
    sun_position : array_like (3,) or callable
        Position of the Sun in the system's coordinates: fixed (the frame I of the paper,
        ``-R0``, Eq. 32), or ``sun_position(t) -> (3,)`` refreshed once per time step
        (``SunAtFocus(orbit)`` for a system in a heliocentric orbit; for an orbit about
        the Earth, the Sun's position relative to the orbit's reference point).
    exponent : float
        ``p`` of the scaling ``(AU / r)^p`` of the paper's law with the heliocentric
        distance ``r`` of each Gauss point (default None: ``THRUST_EXPONENT`` = 7/6; 0: the
        uniform wind of the paper's Eq. 29, bit for bit); the other laws carry their own
        dependence on the distance.
    law : str or thrust law
        The force per unit length on a tether across the wind (``loads.thrust_laws``):
        ``"paper"`` (Eq. 29, the default), ``"janhunen2009"``, ``"shielded"``,
        ``"plasma-brake"`` (a law with the hook ``load``: a ``plasma_brake.PlasmaBrake``
        on the cables at the negative ``voltage``, with the keywords ``plasma``,
        ``brake`` and the others of ``PlasmaBrake``: ``docs/esail.md``), any registered
        name (``thrust_laws.names()``), or a law object.

    Notes
    -----
    The force reads the cables only through their line-body hook; its kernel is the one
    loop of the line loads with the point function ``kernels.coulomb.point``.  Each tether
    element is pushed along the wind's component perpendicular to it, with
    the law's force per unit length for a tether across the wind (Eqs. 27-35; the
    paper's: ``SolarWind.force_per_length`` at 1 AU times ``(AU / r)^p``); the wind
    blows radially from the Sun with the velocity ``u i_R`` of Eq. 32, not relative to
    the tether (as in the paper's force law).

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

    def __new__(cls, cables, voltage, *args, law="paper", exponent=None, **options):
        """A law with the hook ``load`` (``thrust_laws``) builds the load it needs instead
        (``law="plasma-brake"``: ``plasma_brake.PlasmaBrake(cables, voltage, **options)``,
        with ``plasma=...``)."""
        hook = getattr(thrust_law(law, exponent), "load", None)
        if hook is not None:
            return hook(cables, voltage, *args, **options)
        return super().__new__(cls)

    def __init__(self, cables, voltage, wind=None, sun_position=(-AU, 0.0, 0.0),
                 exponent=None, law="paper"):
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
        if exponent is not None and not np.isfinite(exponent):
            raise ValueError(f"exponent must be finite, got {exponent!r}")
        self.law = thrust_law(law, exponent)
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
            out = np.array([v(t) if callable(v) else v for v in voltage], dtype=float)
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

    def line_force(self, r, a, coef, t, reference=None, sources=None):
        """Force per unit length (N/m) at points ``r`` (..., 3) of slopes ``a`` (..., 3)
        with the coefficients ``coef`` (...) of ``coefficients`` at time ``t`` (in the
        coordinates of the run of ``reference``, ``sun_at``): ``line_forces`` with the
        Sun's position and the ``scaling`` at ``t``."""
        return self.line_forces(r, a, coef, self.sun_at(t, reference),
                                self.scaling(t, sources, reference))

    @staticmethod
    def line_forces(r, a, coef, sun, scaling):
        """Force per unit length (N/m) at points ``r`` (..., 3) of slopes ``a`` (..., 3)
        with the coefficients ``coef`` (...), the Sun at ``sun`` (..., 3) and ``scaling``
        ``(d, p)`` (..., 2) (``scaling``), each broadcast against the points (the points
        of many saved steps at once, with each step's Sun and scaling):
        ``coef (d / rho)^p (i_R - (t . i_R) t)`` (Eqs. 29-32, as the kernel)."""
        rel = r - sun
        rho = np.linalg.norm(rel, axis=-1, keepdims=True)
        i_R = rel / rho
        tangent = a / np.linalg.norm(a, axis=-1, keepdims=True)
        u_perp = i_R - np.sum(tangent * i_R, axis=-1, keepdims=True) * tangent
        d, p = np.moveaxis(np.asarray(scaling, dtype=float), -1, 0)
        return (coef[..., None] * (d[..., None] / rho) ** p[..., None]) * u_perp

    def distance(self, t, reference=None):
        """The reference distance ``d`` (m) of the force at ``t``: the law's ``anchor``
        (1 AU for the paper's law), or the Sun's distance from the system's origin."""
        anchor = self.law.anchor
        return anchor if anchor is not None else float(np.linalg.norm(self.sun_at(t, reference)))

    def scaling(self, t, sources=None, reference=None):
        """``(d, p)`` (2,) at ``t``: the reference distance (``distance``) and the law's
        exponent ``p = -d ln f / d ln r`` there, at the cables' mean voltage (the
        exponents of other voltages differ by less than 0.1, over a sail that spans
        ``1e-7`` of ``d``: ``1e-8`` of the force)."""
        d = self.distance(t, reference)
        V = float(np.mean(self.voltages(t, sources)))
        return np.array([d, self.law.exponent(V, self.wind.at(t), d)])

    def coefficients(self, t, sources=None, reference=None):
        """Force per unit length on a tether across the wind at the reference distance
        (``distance``; 1 AU for the paper's law), per cable (N/m), of the voltages of
        ``sources`` (``voltages``) in the wind at ``t`` (the law evaluated once per
        distinct voltage)."""
        return self.coefficients_at(self.voltages(t, sources), t, reference)

    def coefficients_at(self, voltages, t, reference=None):
        """``coefficients`` of the tether voltages ``voltages`` (V, one per cable)."""
        wind, d = self.wind.at(t), self.distance(t, reference)
        levels, which = np.unique(voltages, return_inverse=True)
        return np.array([self.law.force_per_length(V, wind, d) for V in levels])[which]

    #: Deploying tethers are supported (``System.deploy`` with a prescribed length): the
    #: force per unit material length acts on the stretched mesh.
    stretches = True

    #: Bound with the run's reference in orbit (``bind(system, reference)``): a Sun
    #: position with ``seen_from`` (``SunAtFocus``) follows the run's rebases.
    reads_reference = True

    def bind(self, system, reference=None, inputs=None):
        """The compiled term: the loop of ``kernels.line`` with the point function
        ``kernels.coulomb.point`` (``point_uniform`` for a wind that does not scale with
        the distance: no power at every point; ``scaling``, the law's distance and
        exponent and their series about the origin's distance from the Sun,
        ``kernels.coulomb.expansion``: a power per step, not per point) over the points of
        the cables' line-body hook (``lines.line_points``), the per-element coefficient its
        ``scale`` (its ``kernel_parallel`` on more than one thread,
        ``linalg.thread_count``).  A
        time-modulated voltage, a deploying tether (the mesh stretch ``lam(t)`` multiplies
        the force per unit mesh length) or a moving Sun refreshes, once per time step
        (``Term.prepare``), only what moves: the per-element coefficients or the Sun's
        position (seen from the run's ``reference`` when the position has ``seen_from``,
        as ``SunAtFocus``); the voltages read the run's values of their inputs
        (``inputs``: the run's ``InputTable``)."""
        parts = [lines.line_points(c, system) for c in self.cables]
        points = lines.joined(parts)
        cable_of_element = np.repeat(np.arange(len(parts)), [p.shape[0] for p in parts])
        sun = self.sun_at(0.0, reference).copy()
        voltages = self.sources(inputs)
        scaling = np.array(kernel.expansion(*self.scaling(0.0, voltages, reference), sun))
        pack = points.pack((sun, scaling),
                           self.coefficients(0.0, voltages, reference)[cable_of_element])
        refresh = self._refreshers(system, (pack[4], cable_of_element), (sun, scaling),
                                   reference, voltages)

        def prepare(t):
            for part in refresh:
                part(t)

        prepare(0.0)
        uniform = self.law.anchor is not None and scaling[1] == 0.0
        point = kernel.point_uniform if uniform else kernel.point
        hook = points.hook(point, velocity=False)
        rows, cols = points.tangent_pattern()
        return Term(kernels=((hook, pack),), rows=rows, cols=cols, name="solar wind",
                    prepare=prepare if refresh else None)

    def _refreshers(self, system, elements, params, reference, voltages):
        """The functions of ``t`` refreshing, in place and in this order, the Sun's
        position ``sun`` of ``params = (sun, scaling)`` (a callable ``sun_position``, seen
        from ``reference``), the law's ``scaling`` (a law without an anchor, in a wind
        or at a distance or voltages that vary), the scaling's series about the origin's
        distance from the Sun (``kernels.coulomb.expansion``: when either of these
        moves) and the per-element coefficients ``coef``
        of ``elements = (coef, cable_of_element)`` (with a voltage callable, a deploying
        tether or a varying wind; of the ``voltages`` sources)."""
        coef, cable_of_element = elements
        sun, scale = params
        source = self.sun_source(reference)
        deploying = [system.deployment(c) is not None for c in self.cables]
        for cable, deploys in zip(self.cables, deploying):
            if deploys and system.deployment(cable).reel is not None:
                raise ValueError(f"SolarWindForce on {cable.name!r}, deployed from a reel: "
                                 "the solar wind supports prescribed lengths only")

        modulated = any(callable(v) for v in self.voltage)
        moves = self.law.anchor is None and callable(self.sun)
        varies = self.wind.varies or moves

        def sun_position(t):
            sun[:] = source(t)

        def scaling(t):
            scale[:2] = self.scaling(t, voltages, reference)

        # in a steady wind at a fixed distance with fixed lengths, the coefficients are
        # those of the voltages alone: unchanged voltages (a controller's between its
        # samples, an on-off modulation's between switchings) keep them
        holds = not (varies or any(deploying))
        held = None

        def coefficients(t):
            nonlocal held
            volts = self.voltages(t, voltages)
            if holds:
                if held is not None and np.array_equal(volts, held):
                    return
                held = volts.copy()
            per_cable = self.coefficients_at(volts, t, reference)
            if any(deploying):
                per_cable *= np.array([system.stretch(c, t) for c in self.cables])
            coef[:] = per_cable[cable_of_element]

        def expansion(t):
            scale[:] = kernel.expansion(scale[0], scale[1], sun)

        rescales = self.law.anchor is None and (varies or modulated)
        return [part for part, needed in (
            (sun_position, callable(self.sun)),
            (scaling, rescales),
            (expansion, callable(self.sun) or rescales),
            (coefficients, modulated or any(deploying) or varies))
            if needed]

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
