"""E-sail thrust laws: the force per unit length on a tether perpendicular to the solar wind,
looked up by name (``thrust_law``) for ``SolarWindForce(..., law=...)``.

A thrust law is an object with this contract (``ThrustLaw``):

``force_per_length(voltage, wind, distance)``
    The force per unit length (N/m) on a tether at the voltage ``voltage`` (V) across
    the wind ``wind`` (a ``SolarWind``, whose data hold at 1 AU) at the heliocentric
    distance ``distance`` (m).  The law carries its own dependence on the distance: it
    evaluates its formula at the local plasma, density ``n (AU / r)^2``, speed ``u``,
    electron temperature ``T_e (AU / r)^(1/3)`` (``local_plasma``), or scales itself as
    the paper's law does.
``exponent(voltage, wind, distance)``
    ``p = -d ln f / d ln r`` at ``distance``: the compiled force
    (``kernels.coulomb.point``) evaluates the law at each Gauss point as
    ``f(d) (d / rho)^p`` with ``d`` the reference distance; a tether of 10 km spans
    ``1e-7`` of an AU, so the local power law is the law to ``1e-14`` and its Jacobian,
    the kernel's exact one, the law's.
``anchor``
    A fixed reference distance ``d`` (m) when the law is an exact power law of the
    distance (the paper's: the force at 1 AU times ``(AU / r)^p``, bit for bit as
    before); None: ``d`` is the Sun's distance from the system's origin, refreshed once
    per step with the wind (``SolarWindForce.bind``).

A law that is not a force across the solar wind instead carries the hook

``load(cables, voltage, *args, **options)``
    The load it needs, built from the arguments of ``SolarWindForce`` (``SolarWindForce``
    returns it in place of itself): ``"plasma-brake"`` (``plasma_brake.BrakeLoad``)
    builds a ``plasma_brake.PlasmaBrake``.

A law is registered under its name with a factory ``factory(exponent=None)`` taking the
``exponent`` of ``SolarWindForce`` (None: left at its default; only the paper's law,
which scales as ``(AU / r)^p``, accepts another: ``fixed``); ``register`` adds a law
(e.g. ``plasma_brake`` registers ``"plasma-brake"``) without touching this module.

Examples
--------
>>> from skfem_cable.loads.thrust_laws import thrust_law
>>> from skfem_cable import SolarWind, AU
>>> law = thrust_law("janhunen2009")
>>> f"{law.force_per_length(20e3, SolarWind(), AU) * 1e9:.1f} nN/m"
'477.9 nN/m'
>>> from skfem_cable.loads.thrust_laws import names
>>> names()
['janhunen2009', 'paper', 'plasma-brake', 'shielded']
"""

import math
from dataclasses import dataclass
from typing import Protocol

from scipy.constants import e as ELEMENTARY_CHARGE

from ..space.constants import AU
from .coulomb_drag import CoulombDrag

THRUST_EXPONENT = 7.0 / 6.0
"""Exponent ``p`` of the E-sail thrust's fall-off with solar distance, ``(AU / r)^p``
(Janhunen et al., "Electric solar wind sail: toward test missions", Rev. Sci. Instrum. 81,
111301, 2010, ref. [16] of the paper: thrust at constant voltage ``~ 1/r^(7/6)``).  The
ion-deflecting sheath of a tether is a few electron Debye lengths wide,
``lambda_D ~ sqrt(T_e / n)``, with the density ``n ~ r^-2`` and the electron temperature
``T_e ~ r^(-1/3)``, so ``lambda_D ~ r^(5/6)``; the force per unit length is the dynamic
pressure ``m_p n u^2 ~ r^-2`` times the sheath width: ``r^-2 r^(5/6) = r^(-7/6)``."""

#: Electron temperature of the solar wind at 1 AU (eV) of the shielded law's sheath
#: (``SheathLaw``; Janhunen & Sandroos 2007's average 1 AU wind).
ELECTRON_TEMPERATURE = 12.0

#: Relative step in ``ln r`` of the central difference of ``exponent`` (its error
#: ``~1e-8``, the truncation ``h^2``).
LOG_STEP = 1e-4


class ThrustLaw(Protocol):
    """The contract of a thrust law (module docstring)."""

    name: str
    anchor: float | None

    def force_per_length(self, voltage, wind, distance): ...

    def exponent(self, voltage, wind, distance): ...


_REGISTRY = {}


def register(name, factory):
    """Register the law ``factory(exponent=None) -> ThrustLaw`` under ``name`` (a new
    name, or ``ValueError``)."""
    if name in _REGISTRY:
        raise ValueError(f"law: {name!r} is already registered")
    _REGISTRY[name] = factory
    return factory


def names():
    """The registered law names, sorted."""
    return sorted(_REGISTRY)


def thrust_law(law, exponent=None):
    """The thrust law ``law``: a registered name (``names``), built with ``exponent``
    (None: its default), or a law object, returned as given (``exponent`` must then be
    None)."""
    if not isinstance(law, str):
        if exponent is not None:
            raise ValueError("exponent applies to a law given by name, not to a law object")
        return law
    factory = _REGISTRY.get(law)
    if factory is None:
        raise ValueError(f"law must be one of {names()}, got {law!r}")
    return factory(exponent=exponent)


def local_plasma(wind, distance):
    """``(n, u, T_e)`` at ``distance`` of a wind whose data hold at 1 AU: ``n ~ r^-2``
    (radial expansion at constant speed), ``u`` constant and ``T_e ~ r^(-1/3)`` (the
    electron temperature's fall-off that Janhunen et al. 2010, ref. [16] of the paper,
    use for the ``r^(-7/6)`` scaling of the thrust); ``T_e`` relative to its 1 AU value."""
    x = AU / distance
    return wind.density * x * x, wind.speed, x ** (1.0 / 3.0)


def log_slope(f, distance):
    """``-d ln f / d ln r`` at ``distance`` of a positive function ``f(r)`` (central
    difference of step ``LOG_STEP`` in ``ln r``); 0 where ``f`` vanishes."""
    up, down = f(distance * math.exp(LOG_STEP)), f(distance * math.exp(-LOG_STEP))
    if up <= 0.0 or down <= 0.0:
        return 0.0
    return -(math.log(up) - math.log(down)) / (2.0 * LOG_STEP)


@dataclass(frozen=True)
class PaperLaw:
    """The paper's law (Eq. 29, after Janhunen et al., Rev. Sci. Instrum. 81, 111301,
    2010, Eq. 1): ``0.18 max(0, V0 - V1) sqrt(eps0 m_p n) u`` at 1 AU
    (``SolarWind.force_per_length``), times ``(AU / r)^p`` (``p = 7/6``: the sheath
    width ``~ lambda_D ~ r^(5/6)`` times the dynamic pressure ``~ r^-2``; 0: the paper's
    uniform wind)."""

    exponent_p: float = THRUST_EXPONENT
    name: str = "paper"
    anchor: float = AU

    def force_per_length(self, voltage, wind, distance):
        return wind.force_per_length(voltage) * (AU / distance) ** self.exponent_p

    def exponent(self, voltage, wind, distance):
        return self.exponent_p


@dataclass(frozen=True)
class JanhunenLaw:
    """Janhunen's (Ann. Geophys. 27, 3089, 2009) thrust formula of a tether without
    trapped electrons (``coulomb_drag.CoulombDrag``, the one implementation the plasma
    brake shares) for the wind's protons at the local plasma (``local_plasma``: density
    ``n (AU / r)^2``, speed ``u``; the formula holds no temperature), with the wind's
    ``proton_mass`` and ``eps0``; 0 at ``V0 <= 0``.  At 20 kV in the average 1 AU wind
    (7.3 cm^-3, 400 km/s) and ``r_w*`` = 1 mm it gives 0.478 uN/m, the paper's
    "1 N ... for 2000 km total tether length" (0.5 uN/m) within 5 % (``docs/esail.md``).

    Parameters
    ----------
    drag : CoulombDrag
        ``r_w*`` (``electric_radius``, default 1 mm) and the fitting factor ``K``
        (``fit``, default 1: the formula as published).
    """

    drag: CoulombDrag = CoulombDrag()
    name: str = "janhunen2009"
    anchor: None = None

    def force_per_length(self, voltage, wind, distance):
        if voltage <= 0.0:
            return 0.0
        n, u, _ = local_plasma(wind, distance)
        return float(self.drag.force_per_length(voltage, n, u, wind.proton_mass, wind.eps0))

    def exponent(self, voltage, wind, distance):
        return log_slope(lambda r: self.force_per_length(voltage, wind, r), distance)


@dataclass(frozen=True)
class SheathLaw:
    """The semi-theoretical formula of Janhunen & Sandroos (Ann. Geophys. 25, 755, 2007)
    for a tether whose potential is shielded by the wind's electrons (the estimate with
    trapped electrons that Janhunen 2009 raises "about five times"): a proton of the wind
    is stopped where the tether's potential
    ``V(r) = V0 ln(1 + (r0/r)^2) / ln(1 + (r0/r_w)^2)`` equals its kinetic energy
    ``m_p u^2 / 2e``, at

    ``r_s = r0 / sqrt(exp[(m_p u^2 / (e V0)) ln(r0 / r_w)] - 1)``,

    and the force per unit length is ``K m_p n u^2 r_s`` (``K = 3.09`` from the
    deflection integral), with the sheath scale ``r0 = 2 lambda_De``,
    ``lambda_De = sqrt(eps0 T_e / (n e))`` the Debye length of the wind's electrons,
    ``T_e = 12 eV`` at 1 AU, ``T_e ~ r^(-1/3)``, and the wire radius ``r_w = 10 um``.
    ``K``, ``r0 = 2 lambda_De`` and ``r_w`` as recalled from the paper, whose text was not
    reachable here; nothing is fitted: the check is its abstract's "(5 +- 1) x 10^-8 N/m
    for 15 kV" in the average 1 AU wind, which the formula gives (57.5 nN/m;
    ``docs/esail.md``).

    Parameters
    ----------
    name : str
    temperature : float
        ``T_e`` at 1 AU (eV).
    wire_radius : float
        ``r_w`` (m).
    K : float
    """

    name: str = "shielded"
    temperature: float = ELECTRON_TEMPERATURE
    wire_radius: float = 1e-5
    K: float = 3.09
    anchor: None = None

    def sheath_scale(self, wind, distance):
        """``r0 = 2 lambda_De`` (m) at ``distance``."""
        n, _, cooling = local_plasma(wind, distance)
        T = self.temperature * cooling
        return 2.0 * math.sqrt(wind.eps0 * T / (n * ELEMENTARY_CHARGE))

    def force_per_length(self, voltage, wind, distance):
        if voltage <= 0.0:
            return 0.0
        n, u, _ = local_plasma(wind, distance)
        r0 = self.sheath_scale(wind, distance)
        a = wind.proton_mass * u * u / (ELEMENTARY_CHARGE * voltage)
        stop = r0 / math.sqrt(math.expm1(a * math.log(r0 / self.wire_radius)))
        return self.K * wind.proton_mass * n * u * u * stop

    def exponent(self, voltage, wind, distance):
        return log_slope(lambda r: self.force_per_length(voltage, wind, r), distance)


def _paper(exponent=None):
    return PaperLaw(THRUST_EXPONENT if exponent is None else float(exponent))


def fixed(name, build):
    """The factory of a law ``build()`` that carries its own dependence on the distance:
    it refuses an ``exponent`` (``ValueError`` naming the law)."""
    def factory(exponent=None):
        if exponent is not None:
            raise ValueError(f"exponent applies to law='paper' only: law={name!r} carries "
                             "its own dependence on the distance, got exponent="
                             f"{exponent!r}")
        return build()
    return factory


register("paper", _paper)
register("janhunen2009", fixed("janhunen2009", JanhunenLaw))
register("shielded", fixed("shielded", SheathLaw))
