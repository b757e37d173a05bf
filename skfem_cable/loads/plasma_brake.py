"""The plasma brake: the Coulomb drag of the ionosphere's ram flow on a negatively biased
tether in low Earth orbit (Janhunen 2014), a load for ``System.add_load``.

A tether at the voltage ``V0 < 0`` relative to the plasma repels the electrons and
deflects the ions of the flow that meets it at the relative speed ``u`` (the orbital
speed, some 7.5 km/s, against an ionosphere co-rotating with the Earth).  Across the flow,
the force per unit length is the Coulomb drag of Janhunen's E-sail formula
(``coulomb_drag.CoulombDrag``, Ann. Geophys. 27, 3089, 2009, the one implementation the
E-sail law ``"janhunen2009"`` shares), which, as the 2014 abstract states, "reproduces
most of the simulation results well", with the ionosphere's ions (O+ in the F region),
the negative bias and the ram flow:

    dF/dz = K 3.864 m_i n u^2 sqrt(eps0 V~ / (e n)) exp(-V_i / V~),

``V~ = |V0| / ln(lambda_eff / r_w*)``, ``V_i = m_i u^2 / (2 e)`` a few volts for O+ at
7.5 km/s (``exp(-V_i / V~)`` is about 0.97 at 1 kV) and ``K`` the simulations' fitting
factor (1; "reduced by a modest factor" when the magnetic field is along the tether, the
2014 abstract).  The force grows as ``sqrt(n)`` (the sheath shrinks as the density
grows), as ``m_i u^2`` and about as ``sqrt(|V0|)``.

A tether at an angle to the flow meets its normal component ``u_n`` (a long cylinder's
sheath sees only the flow across it, as in the normal drag of ``drag.MorisonDrag``), so
that at every point

    f = k |u_n| u_n,   k = K 3.864 m_i sqrt(eps0 V~ n / e) exp(-V_i / V~),

the form of ``kernels.drag`` with the coefficients ``(k, 0, 0)``: the loop of the line
loads with its exact tangent in the positions (through the co-rotating flow) and the
velocities.  The coefficient ``k`` is the element's ``scale``, evaluated once per time
step from the plasma's density at the points predicted from the last accepted state
(``sampling.DensitySampler``, as the atmospheric drag's density), or from the density
sampled at knots along the orbit and interpolated (``sample_every``, ``knots``), with
``V_i`` of the reference point's speed relative to the plasma: frozen over the step (the
tangent omits ``dk/dx``, the density's scale height of some 100 km against a step's motion
relative to the tether).

References
----------
1. P. Janhunen, "Simulation study of the plasma-brake effect", Ann. Geophys. 32 (2014)
   1207-1216 (the 5 km, 0.055 kg tether braking a 260 kg object with 0.43 mN, about
   100 km of altitude a year from LEO).
2. P. Janhunen, "Increased electric sail thrust through removal of trapped shielding
   electrons by orbit chaotisation due to spacecraft body", Ann. Geophys. 27 (2009)
   3089-3100 (the thrust formula).
"""

from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

from ..bodies.section import check_positive
from ..core import lines
from ..core.contract import Evaluation, Term
from ..core.inputs import declared, reader
from ..environment.epoch import bound_model
from ..kernels import drag as kernel
from .coulomb_drag import CoulombDrag
from .drag import Flow
from .knots import OrbitKnots
from .sampling import DensitySampler
from .thrust_laws import fixed, register

#: The plasma brake's force per length across the flow: Janhunen's formula
#: (``coulomb_drag.CoulombDrag``: ``electric_radius`` ``r_w*``, default 1 mm; ``fit`` ``K``).
BrakeLaw = CoulombDrag


def _voltage(value):
    """``value(t)`` of a voltage (a number or a callable), checked negative."""
    def checked(t):
        v = float(value(t)) if callable(value) else float(value)
        if not (np.isfinite(v) and v < 0):
            raise ValueError(f"voltage of the plasma brake at t = {t!r} is {v!r}: it must "
                             "be finite and < 0 V (a negatively biased tether)")
        return v
    checked(0.0)  # a bad voltage fails now, not mid-run
    return checked


class _Coefficients(DensitySampler):
    """The brake's per-element coefficient ``k`` (the kernel's ``scale``): the sampled
    density's weighted mean over each element (``DensitySampler``) turned into ``k`` by
    ``coefficient(n, t)``, once per time."""

    def __init__(self, model, positions, weights, orbit, q0, coefficient):
        self.coefficient = coefficient
        super().__init__(model, positions, weights, orbit, q0)

    def prepare(self, t):
        if float(t) == self.done:
            return
        super().prepare(t)
        self.out[:] = self.coefficient(self.out, float(t))


class PlasmaBrake:
    """The plasma brake on one or more tethers (module notes): ``f = k |u_n| u_n`` per
    unit reference length, ``u_n`` the plasma's velocity relative to the tether across
    it, ``k`` of ``BrakeLaw`` from the plasma's density and ion mass.

    Parameters
    ----------
    cables : line body or sequence of them
        The tethers (bodies with the hook ``line_points``, the same points and functions
        per element).
    voltage : float or callable
        The tether's voltage ``V0`` (V, < 0; a few hundred volts to about 1 kV), or
        ``voltage(t)`` (refreshed once per step), e.g. an ``Input`` a controller sets
        (the run reads its values: ``inputs``).
    plasma : plasma
        ``density(x, t)`` (m^-3) at absolute positions and ``ion_mass`` (kg):
        ``environment.IRI`` (made without an epoch it takes the system's),
        ``environment.UniformPlasma``.
    brake : BrakeLaw
        The force per length's parameters (default ``BrakeLaw()``).
    omega : array_like (3,) or None
        Rotation rate of the plasma (rad/s); None: the central body's in orbit (the
        Earth's: a co-rotating ionosphere, as ``AtmosphericDrag``), zero otherwise.
    velocity : array_like (3,)
        A uniform velocity of the plasma (m/s) added to the rotation.
    sample_every : float or None
        None: the density is evaluated at the tethers' points once per step; a time
        ``h`` (s, > 0): at knots every ``h`` seconds along the reference point,
        interpolated (``loads.knots``), for long runs with IRI.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> from skfem_cable.loads.plasma_brake import PlasmaBrake
    >>> orbit = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 800e3)
    >>> tether = sc.Cable.straight([0, 0, 0], [5e3, 0, 0], 2,
    ...                            sc.Section.circular(3.6e-5, 7e10, 2700.0))
    >>> system = sc.System([tether]).add_orbit(orbit)
    >>> brake = PlasmaBrake(tether, -1e3, sc.environment.UniformPlasma(1e11))
    >>> force = brake.evaluate(system, tether.q0)["force"]
    >>> f"{force[1] * 1e3:.3f} mN"                  # against the motion (+y)
    '-0.694 mN'
    """

    #: Bound with the run's reference in orbit (``bind(system, reference)``).
    reads_reference = True

    def __init__(self, cables, voltage, plasma, brake=None, omega=None,
                 velocity=(0.0, 0.0, 0.0), sample_every=None):
        self.cables = [cables] if callable(getattr(cables, "line_points", None)) \
            else [lines.check_line_body(c, "cables") for c in cables]
        self.source, self.voltage = voltage, _voltage(voltage)
        if not callable(getattr(plasma, "density", None)):
            raise ValueError(f"plasma must have density(x, t) (m^-3) and ion_mass (kg), "
                             f"got {plasma!r}")
        self.plasma = plasma
        self.ion_mass = check_positive("plasma.ion_mass", getattr(plasma, "ion_mass", None))
        self.brake = BrakeLaw() if brake is None else brake
        self.flow = Flow(velocity, omega)
        self.sample_every = None if sample_every is None else \
            check_positive("sample_every", sample_every)

    def inputs(self):
        """The inputs the voltage reads (``inputs.declared``)."""
        return declared(self.source)

    def bind(self, system, reference=None, inputs=None):
        """The compiled term: the loop of ``kernels.line`` with ``kernels.drag.point``
        (coefficients ``(1, 0, 0)``) over the tethers' points (``lines.joined``), the
        elements' ``scale`` the coefficient ``k`` refreshed once per step with the flow
        (``Term.prepare``, the step hook ``_Coefficients``; ``V_i`` of the speed of the
        refreshed flow at the reference point, ``Flow.refresh``: ``|c_0 + W R - V|``);
        about the reference point of ``reference`` (the run's ``Reference``; None: the
        orbit as given); the voltage reads the run's values of its inputs (``inputs``:
        the run's ``InputTable``)."""
        return self._bind(system, reference, inputs=inputs)[0]

    def _bind(self, system, reference=None, knots=True, inputs=None):
        """``(term, pack, sampler)``; ``knots``: False, the density evaluated at the
        points even with ``sample_every`` (a single evaluation, ``evaluate``)."""
        voltage = self.voltage if inputs is None else _voltage(reader(self.source, inputs))
        points = lines.joined([lines.line_points(c, system) for c in self.cables])
        orbit = system.orbit if reference is None else reference
        arrays = self.flow.arrays(orbit)
        sampler = _Coefficients(self._density(system, points, orbit, knots),
                                lambda q: points.at(q)[0], points.w, orbit, system.q0,
                                lambda n, t: self.brake.coefficient(
                                    voltage(t), n, np.linalg.norm(arrays[0]),
                                    self.ion_mass))
        pack = points.pack((np.array([1.0, 0.0, 0.0, 0.0]), *arrays), sampler.out)
        hook = points.hook(kernel.point)

        def prepare(t):
            self.flow.refresh(arrays, t, orbit)
            sampler.prepare(t)

        rows, cols = points.tangent_pattern()
        term = Term(kernels=((hook, pack),), rows=rows, cols=cols, prepare=prepare,
                    hooks=(sampler,), name="plasma brake")
        return term, pack, sampler

    def _density(self, system, points, orbit, knots=True):
        """The plasma's density model at the system's epoch, or at knots
        (``sample_every``, if ``knots``) along the reference point plus the tethers'
        mean offset."""
        plasma = bound_model(self.plasma, system.epoch, "plasma")
        if self.sample_every is None or not knots:
            return plasma
        mean = points.at(system.q0)[0].reshape(-1, 3).mean(axis=0)
        knots = OrbitKnots(self.sample_every, 0.0 if orbit is None else orbit.t0,
                           lambda t: mean + (0.0 if orbit is None else orbit.position(t)),
                           None, plasma)
        return SimpleNamespace(density=lambda x, t: knots.at(x, t)[2])

    def evaluate(self, system, q, v=None, t=0.0, reference=None):
        """The brake at the coordinates ``q`` and velocities ``v`` (None: at rest
        relative to the reference point) of ``system`` at time ``t`` (the density
        evaluated at the points, not at knots): a dict with ``force`` (N, (3,): ``int f
        dx``), ``offset_power`` (W: the generalized force times the offsets' velocities
        ``v``, the rate of the run's books' external work), ``power`` (W: plus the force
        times the reference point's velocity, the rate of work on the absolute motion)
        and ``coefficient`` (kg/m^2, the elements' mean ``k``).  In orbit about the
        reference point of ``reference`` (a run's, ``Result.reference``; None: the orbit
        as given)."""
        q = np.asarray(q, dtype=float)
        v = np.zeros_like(q) if v is None else np.asarray(v, dtype=float)
        term, pack, sampler = self._bind(system, reference, knots=False)
        sampler.accept(q, v, t)
        ev = Evaluation(system, t, q, v, np.zeros(system.n_constraints))
        nd = pack[0].shape[1]
        term.evaluate(ev, np.zeros((0, nd, nd), dtype=np.int64))  # no tangent
        orbit = system.orbit if reference is None else reference
        V = np.zeros(3) if orbit is None else orbit.velocity(t)
        force, offset_power = pack[-1].copy(), float(ev.f_ext @ v)
        return {"force": force, "offset_power": offset_power,
                "power": offset_power + float(force @ V),
                "coefficient": float(sampler.out.mean())}

    def outputs(self, result):
        """Key numbers of a run (``runner.summary.run_outputs``): the along-track force
        (N, the force along the reference point's velocity) and the power at its last
        saved step."""
        out = self.evaluate(result.system, result.q[-1], result.v[-1], result.t[-1],
                            result.reference)
        V = result.reference.velocity(result.t[-1]) if result.reference is not None \
            else np.zeros(3)
        speed = np.linalg.norm(V)
        along = float(out["force"] @ V / speed) if speed > 0 else 0.0
        return {"along_track_force": along, "power": out["power"]}


@dataclass(frozen=True)
class BrakeLoad:
    """The entry ``"plasma-brake"`` of the thrust-law registry (``thrust_laws``): not a
    force across the solar wind but the hook ``load``, so that
    ``SolarWindForce(cables, voltage, law="plasma-brake", plasma=...)`` is the plasma
    brake."""

    name: str = "plasma-brake"

    def load(self, cables, voltage, *args, **options):
        """``PlasmaBrake(cables, voltage, *args, **options)``."""
        return PlasmaBrake(cables, voltage, *args, **options)


register("plasma-brake", fixed("plasma-brake", BrakeLoad))
