"""The solar-wind Coulomb force on charged tethers (paper Sect. 2.2.3, Eqs. 27-35).

Examples
--------
>>> from skfem_cable import SolarWind
>>> f"{SolarWind().force_per_length(20e3):.3e} N/m"     # 20 kV at 1 AU
'4.494e-07 N/m'
"""

from dataclasses import dataclass

import numpy as np

from .contract import Term
from .kernels import coulomb as kernel
from .orbit import AU
from .section import check_positive

_EMPTY = np.zeros(0)
_NO_SCATTER = np.zeros((0, 12, 12), dtype=np.int64)


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


class SolarWindForce:
    """Coulomb drag of the solar wind on a set of cables, a load for ``System.add_load``.

    Parameters
    ----------
    cables : sequence of Cable
    voltage : float, callable, or sequence of them (one per cable)
        Tether voltage ``V0`` (V); a callable ``V0(t)`` modulates it in time.
    wind : SolarWind
    sun_position : array_like (3,)
        Position of the Sun in the simulation frame I (``-R0``, Eq. 32).

    Notes
    -----
    Each tether element is pushed along the wind's component perpendicular to it, with
    ``SolarWind.force_per_length`` for a tether across the wind (Eqs. 27-35); the wind
    blows radially from the Sun.

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

    def __init__(self, cables, voltage, wind=None, sun_position=(-AU, 0.0, 0.0)):
        self.cables = list(cables)
        if callable(voltage) or np.ndim(voltage) == 0:
            voltage = [voltage] * len(self.cables)
        if len(voltage) != len(self.cables):
            raise ValueError(f"voltage needs one value per cable ({len(self.cables)}), "
                             f"got {len(voltage)}")
        for k, v in enumerate(voltage):
            if not callable(v) and not (np.isfinite(v) and v >= 0):
                raise ValueError(f"voltage[{k}] must be >= 0 V or a callable, got {v!r}")
        self.voltage = list(voltage)
        self.wind = wind or SolarWind()
        self.sun = np.asarray(sun_position, dtype=float)
        per = [np.full(c.n_elements, k) for k, c in enumerate(self.cables)]
        self.cable_of_element = np.concatenate(per)
        self.S = np.ascontiguousarray(np.concatenate([c.S for c in self.cables]))
        self.Sx = np.ascontiguousarray(np.concatenate([c.Sx for c in self.cables]))
        self.w = np.ascontiguousarray(np.concatenate([c.weights for c in self.cables]))
        self.voltages(0.0)  # a bad voltage callable fails now, not mid-run

    def voltages(self, t):
        """Tether voltages (V) at time ``t``; a voltage callable returning a negative or
        non-finite value is an error naming the tether (this model has one polarity:
        a positive tether repels the solar-wind protons)."""
        out = np.array([v(t) if callable(v) else v for v in self.voltage], dtype=float)
        bad = ~(np.isfinite(out) & (out >= 0))
        if bad.any():
            k = int(np.argmax(bad))
            raise ValueError(f"voltage of tether {self.cables[k].name!r} at t = {t!r} is "
                             f"{float(out[k])}: it must be finite and >= 0 V")
        return out

    def coefficients(self, t):
        """Force per unit length on a perpendicular tether, per element (N/m)."""
        per_cable = np.array([self.wind.force_per_length(V) for V in self.voltages(t)])
        return per_cable[self.cable_of_element]

    #: Deploying tethers are supported (``System.deploy`` with a prescribed length): the
    #: force per unit material length acts on the stretched mesh.
    stretches = True

    def bind(self, system):
        """The compiled term (``kernels.coulomb.kernel``); a time-modulated voltage or a
        deploying tether (the mesh stretch ``lam(t)`` multiplies the force per unit mesh
        length) refreshes the per-element coefficients once per time step
        (``Term.prepare``)."""
        edofs = np.ascontiguousarray(np.concatenate(
            [c.global_element_dofs(system) for c in self.cables]))
        coef = np.array(self.coefficients(0.0), dtype=float)
        deploying = [system.deployment(c) is not None for c in self.cables]
        for cable, deploys in zip(self.cables, deploying):
            if deploys and system.deployment(cable).reel is not None:
                raise ValueError(f"SolarWindForce on {cable.name!r}, deployed from a reel: "
                                 "the solar wind supports prescribed lengths only")

        def prepare(t):
            coef[:] = self.coefficients(t)
            if any(deploying):
                stretch = np.array([system.stretch(c, t) for c in self.cables])
                coef[:] *= stretch[self.cable_of_element]

        prepare(0.0)
        pack = (edofs, self.S, self.Sx, self.w, coef, self.sun, np.zeros(3))
        constant = not any(callable(v) for v in self.voltage) and not any(deploying)
        return Term(kernels=((kernel.kernel, pack),), rows=edofs[:, :, None],
                    cols=edofs[:, None, :], name="solar wind",
                    prepare=None if constant else prepare)

    def add_force(self, edofs, q, t, f, data=None, index=None, cK=1.0):
        """Add the generalized force on the cables with global element coordinates
        ``edofs`` to ``f`` and, with ``data``, ``cK`` times its derivative at ``index``;
        returns the force resultant (N)."""
        resultant = np.zeros(3)
        want = data is not None
        kernel.force_tangent(q, (edofs, self.S, self.Sx, self.w),
                             (self.coefficients(t), self.sun),
                             (f, data if want else _EMPTY, index if want else _NO_SCATTER,
                              resultant), cK)
        return resultant
