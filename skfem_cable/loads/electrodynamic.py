"""Electrodynamic tethers: the Lorentz force on a cable carrying a current through a
magnetic field, such as the geomagnetic field in low Earth orbit.

A current ``I`` along a cable (positive towards increasing arc length) in a field ``B``
feels, per unit reference length,

    f = I r_x x B(r)

(``r_x dx`` is the element of length as a vector), at the points of the cable's line-body
hook (``lines``: any line body carries a current).  The load is compiled
(``kernels.electrodynamic``, with the array passes of ``kernels.line``) for a uniform
field and for a ``MagneticDipole``, with its exact tangent; a general field ``B(x, t)``
takes the Python path with a central-difference gradient.  In an orbiting system
(``System.add_orbit``) the coordinates are offsets from the orbit's reference point
``R(t)``: the field is evaluated at the absolute position
``R(t) + x`` and the motional EMF uses the absolute velocity ``V(t) + v``; both are
refreshed once per time step (``Term.prepare``).

The current is prescribed (a number or a function of time) or ``"short-circuit"``: the
uniform current ``I = E / R_c`` that the motional EMF ``E = int ((v - Omega x r) x B) .
r_x dx`` drives through the circuit's resistance ``R_c`` (``Omega``: the rotation of the
plasma, by default in orbit the central body's: the Earth's co-rotating ionosphere).
Such a tether is a brake: its power ``F . u = -E^2 / R_c`` is never positive.

References
----------
1. M. L. Cosmo and E. C. Lorenzini (eds.), "Tethers in Space Handbook", 3rd ed., NASA
   Marshall Space Flight Center, 1997 (electrodynamic tethers: the motional EMF ``(v x
   B) . L`` and the force ``I L x B``, deorbiting by the drag of the current).
2. J. D. Jackson, "Classical Electrodynamics", 3rd ed., Wiley 1999, Sect. 5.6 (the field of
   a magnetic dipole, Eq. 5.56).
3. N. Olsen et al., "The Swarm Initial Field Model for the 2014 Geomagnetic Field",
   Geophys. Res. Lett. 42 (2015) 1092-1098 (the dipole moment, about 7.7e22 A m^2, and its
   tilt of about 9.7 deg: the IGRF's first-degree coefficients).
"""

import numpy as np

from ..bodies.section import check_positive
from ..core import lines
from ..core.contract import Evaluation, Term
from ..core.inputs import declared, reader
from ..environment.epoch import bound_model
from ..environment.oml import Cathode
from ..kernels import electrodynamic as kernel
from ..space.constants import OMEGA_EARTH as OMEGA_EARTH  # re-exported: the plasma's co-rotation
from ..space.orbit import co_rotation
from .line import AlongCable
from .oml_circuit import bind_oml, circuit, names, profile, summary
from .point import vector3

MU0_OVER_4PI = 1.0e-7
"""``mu_0 / (4 pi)`` (T m / A; 1.00000000055e-7 in CODATA 2018, the difference is far
below the dipole model's own)."""
EARTH_DIPOLE_MOMENT = 8.0e22
"""Magnitude of the Earth's dipole moment (A m^2), the round value of the issue (the
2015 value is 7.7e22, Olsen et al.)."""
IDEAL = Cathode()
"""An ideal contactor (no voltage drop): ``ElectrodynamicForce``'s default cathode."""
FD_STEP = 6.06e-6
"""Relative step of the central-difference field gradient, about ``eps^(1/3)``."""


def _finite(name, value):
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number, got {value!r}") from None
    if not np.isfinite(value):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return value


class MagneticDipole:
    """The field of a magnetic dipole at the origin (the central body's centre):

        B(x) = mu_0 / (4 pi) (3 (m . x_hat) x_hat - m) / |x|^3

    (Jackson Eq. 5.56; ``kernels.electrodynamic`` Eq. 4).  With ``tilt = 0`` the moment
    points to ``-z`` (the Earth's points to geographic south), so the field on the
    equator points north (``+z``), ``mu_0 M / (4 pi r^3)``, and twice that over the poles.

    Parameters
    ----------
    moment : float
        Magnitude ``M`` of the moment (A m^2), > 0; default the Earth's, 8.0e22.
    tilt : float
        Angle (rad, in [0, pi]) between the dipole's north axis (``-m``) and ``+z``.
    azimuth : float
        Longitude (rad) of the north axis in the ``x, y`` plane at ``t = 0``.
    rotation_rate : float
        Rate (rad/s) at which a tilted axis turns about ``z`` (the central body's spin,
        e.g. ``OMEGA_EARTH``); the north axis is at longitude ``azimuth + rotation_rate t``.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> earth = sc.MagneticDipole()
    >>> B, dB = earth.field([sc.R_EARTH + 400e3, 0.0, 0.0])
    >>> f"{B[2]:.4e} T"                         # north, mu_0 M / (4 pi r^3)
    '2.5690e-05 T'
    """

    def __init__(self, moment=EARTH_DIPOLE_MOMENT, tilt=0.0, azimuth=0.0, rotation_rate=0.0):
        self.moment = check_positive("moment", moment)
        self.tilt = _finite("tilt", tilt)
        if not 0.0 <= self.tilt <= np.pi:
            raise ValueError(f"tilt must lie in [0, pi] (rad), got {tilt!r}")
        self.azimuth = _finite("azimuth", azimuth)
        self.rotation_rate = _finite("rotation_rate", rotation_rate)

    def axis(self, t=0.0):
        """Unit vector of the moment ``m`` at time ``t`` (``-z`` without tilt)."""
        phi = self.azimuth + self.rotation_rate * t
        st = np.sin(self.tilt)
        return -np.array([st * np.cos(phi), st * np.sin(phi), np.cos(self.tilt)])

    def sources(self, t):
        """``[B_0, mu_0 / (4 pi) m]`` (2, 3) at time ``t``: the compiled field's uniform
        part (zero) and moment."""
        return np.stack([np.zeros(3), MU0_OVER_4PI * self.moment * self.axis(t)])

    def field(self, x, t=0.0):
        """The field ``B`` (T) and its gradient ``dB/dx`` (T/m) at absolute positions
        ``x`` (..., 3): shapes (..., 3) and (..., 3, 3)."""
        return _compiled_field(self.sources(t), x)

    def __repr__(self):
        return (f"MagneticDipole(moment={self.moment:.6g}, tilt={self.tilt:.6g}, "
                f"azimuth={self.azimuth:.6g}, rotation_rate={self.rotation_rate:.6g})")


class UniformField:
    """A uniform, constant field ``B`` (T): what ``ElectrodynamicForce`` makes of a
    3-vector ``field``."""

    def __init__(self, B):
        self.B = vector3(B, "field")

    def sources(self, t):
        """``[B, 0]`` (2, 3): the compiled field's uniform part and (no) moment."""
        return np.stack([self.B, np.zeros(3)])

    def field(self, x, t=0.0):
        """``B`` and a zero gradient at the positions ``x`` (..., 3)."""
        return _compiled_field(self.sources(t), x)


def _compiled_field(sources, x):
    X = np.ascontiguousarray(np.asarray(x, dtype=float))
    if X.shape[-1:] != (3,):
        raise ValueError(f"positions must have shape (..., 3), got {X.shape}")
    points = X.reshape(-1, 1, 3)  # as the kernels' (ne, nq, 3): one compiled signature
    B, dB = np.empty(points.shape), np.empty(points.shape + (3,))
    kernel.dipole_points(np.ascontiguousarray(sources), points, B, dB)
    return B.reshape(X.shape), dB.reshape(X.shape + (3,))


def _drive(current, resistance):
    """``drive(t) -> [I_0, G]`` of the kernel (``I = I_0 + G E``) for the ``current`` and
    ``resistance`` arguments of ``ElectrodynamicForce``."""
    if isinstance(current, str):
        if current == "oml":
            return lambda t: np.zeros(2)  # the current is the circuit's (``oml_circuit``)
        if current != "short-circuit":
            raise ValueError(f"current must be a number (A), a callable current(t), "
                             f"'oml' or 'short-circuit', got {current!r}")
        if resistance is None:
            raise ValueError("current='short-circuit' needs the circuit's resistance "
                             "(ohm, > 0)")
        conductance = 1.0 / check_positive("resistance", resistance)
        return lambda t: np.array([0.0, conductance])
    if resistance is not None:
        raise ValueError(f"resistance is used only with current='short-circuit', got "
                         f"resistance={resistance!r} with current={current!r}")
    if callable(current):
        return lambda t: np.array([_finite(f"current({t!r})", current(t)), 0.0])
    value = _finite("current", current)
    return lambda t: np.array([value, 0.0])


class ElectrodynamicForce(AlongCable):
    """The Lorentz force ``f = I r_x x B`` per unit reference length on a cable carrying
    the current ``I`` through the magnetic field ``B``, with its tangent.

    Parameters
    ----------
    cable : Cable or line body
        The conductor: a ``Cable`` or any body with the line-body hook ``line_points``
        (``lines``).
    current : float, callable, ``"short-circuit"`` or ``"oml"``
        The current (A), positive towards increasing arc length; ``current(t)``;
        ``"short-circuit"``: ``I = E / resistance`` with ``E`` the cable's motional EMF
        (uniform along the cable, as in a tether whose ends are in contact with the
        plasma); or ``"oml"``: the current and bias a bare tether collects from the
        ``plasma`` (``environment.oml``, ``loads.oml_circuit``), solved at every
        evaluation, with the hollow cathode at the cable's start ``s = 0``.
    field : MagneticDipole, array_like (3,) or callable
        A dipole at the origin; a uniform field (T); or ``field(x, t) -> (n, 3)``, the field
        (T) at ``n`` absolute positions ``x`` (n, 3) (Python path, gradient by central
        differences with the step ``fd_step (1 + |x|)``, accurate to about ``fd_step^2``
        relative: Newton converges as with the exact gradient; a callable with its own
        ``field(x, t) -> (B, dB/dx)``, such as ``environment.IGRF``, gives the gradient).
        With ``current="oml"`` a Python field is evaluated once per step and linearised
        within it (``loads.oml_circuit``).
    resistance : float, optional
        Resistance (ohm, > 0) of the circuit, with ``current="short-circuit"`` only.
    plasma_rotation : array_like (3,) or None
        Angular velocity ``Omega`` (rad/s) of the plasma about the origin, e.g.
        ``[0, 0, OMEGA_EARTH]`` for a co-rotating ionosphere: the EMF uses the velocity
        relative to it, ``v - Omega x r``.  None (default): in a system in orbit the
        central body's rotation (``Orbit.body_rotation``: the Earth's for ``MU_EARTH``,
        as ``FreeMolecularDrag``'s atmosphere), else a plasma at rest.
    fd_step : float
        Relative step of the gradient of a callable field, in (0, 1).
    plasma : plasma, optional
        With ``current="oml"``: ``density(x, t)``, ``velocity(x, t)`` and ``ion_mass``
        (``environment.UniformPlasma``, ``environment.IRI``).
    cathode : Cathode
        The contactor at ``s = 0``: its voltage drop (V; 0, an ideal contactor).
    load : float
        Load resistance ``R_L`` (ohm, >= 0) between the tether and the cathode.
    conductivity : float
        The conductor's conductivity (S/m, > 0), over the section's area ``A``.
    perimeter : float, optional
        The collecting perimeter (m, > 0): ``2 (w + h)`` for a tape; default that of a
        round wire of the section's area, ``2 sqrt(pi A)``.
    insulated : tuple
        ``(s0, s1)``: the interval of arc length (m) that does not collect.
    supply_voltage : float
        A power supply's voltage (V) in series with the load, positive in the drag sense.
    sample_every : float or None
        With ``current="oml"``: None (default), the plasma's density and a Python field
        are evaluated once per time step at the tether's points; a time ``h`` (s, > 0):
        they are evaluated at knots every ``h`` seconds along the reference point,
        with their gradients, and interpolated in time (``loads.knots``: cubic; on a 5 km
        tether in a 400 km orbit within 2.6e-5 of IGRF and 5.5e-3 of IRI at ``h = 60``
        s, ``docs/environment.md``), for long runs with expensive models.
        Models made without an epoch take the system's (``System.add_orbit(...,
        epoch=...)``).
    coupling : bool or None
        With ``current="oml"``: whether the tangent carries the current's coupling (a
        block dense over the cable's coordinates: the exact tangent); None (default):
        when the cable has at most ``oml_circuit.COUPLED`` (64) coordinates, 9 elements.

    Notes
    -----
    The short-circuit current is evaluated from each Newton iterate and held fixed in
    the tangent (``kernels.electrodynamic``: the rank-one coupling left out, Newton
    slower by the ratio of the magnetic damping ``(L B)^2 / R_c`` to the inertia).  The
    OML current (``kernels.oml``, about 30 us on 50 stations, warm-started) enters the
    tangent with its coupling ``dI/dq``, ``dI/dv`` (``kernels.oml_coupling``, dense over
    the cable: ``coupling``).  In statics the offsets' velocity is zero, but the EMF
    still counts the reference point's velocity.

    Examples
    --------
    A 5 km tether along the local vertical in a 400 km equatorial orbit, carrying 1 A
    upwards: the force ``I L x B`` points against the motion (along-track is ``+y``).

    >>> import skfem_cable as sc
    >>> orbit = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3)
    >>> tether = sc.Cable.straight([-2.5e3, 0, 0], [2.5e3, 0, 0], 4,
    ...                            sc.Section.circular(1e-3, 7e10, 2700.0))
    >>> system = sc.System([tether]).add_orbit(orbit)
    >>> force = sc.ElectrodynamicForce(tether, 1.0, sc.MagneticDipole())
    >>> system.add_load(force) is system
    True
    >>> f"{force.evaluate(system, tether.q0)['force'][1]:.4f} N"
    '-0.1284 N'

    The current a bare aluminium tape (2 cm x 50 um) collects in a plasma of 1e11 m^-3
    (at rest: the tape moves through it at the orbital speed), with a 10 V hollow
    cathode at its lower end and a 100 ohm load:

    >>> tape = sc.Cable.straight([-2.5e3, 0, 0], [2.5e3, 0, 0], 10,
    ...                          sc.Section(E=7e10, A=0.02 * 5e-5, I=1e-12, rho=2700.0))
    >>> system = sc.System([tape]).add_orbit(orbit)
    >>> oml = sc.ElectrodynamicForce(tape, "oml", sc.MagneticDipole(),
    ...                              plasma=sc.environment.UniformPlasma(1e11),
    ...                              cathode=sc.Cathode(10.0), load=100.0,
    ...                              conductivity=3.5e7, perimeter=2 * (0.02 + 5e-5))
    >>> out = oml.evaluate(system, tape.q0)
    >>> f"I(0) = {out['current']:.3f} A, EMF = {out['emf']:.0f} V"
    'I(0) = 2.993 A, EMF = 985 V'
    >>> oml.bias(sc.State(system, tape.q0), [0.0, 2.5e3, 5e3]).round(1)  # V
    array([-309.3,  -31.2,  320.3])
    """

    def __init__(self, cable, current, field, resistance=None,
                 plasma_rotation=None, fd_step=FD_STEP, *, plasma=None, cathode=IDEAL,
                 load=0.0, conductivity=None, perimeter=None, insulated=(0.0, 0.0),
                 supply_voltage=0.0, sample_every=None, coupling=None):
        self.cable = cable
        self.oml = circuit(cable, current, plasma, cathode, load, conductivity,
                            perimeter, insulated, supply_voltage, sample_every, coupling)
        if self.oml is not None and plasma_rotation is not None:
            raise ValueError("plasma_rotation is not used with current='oml': the plasma's "
                             "velocity(x, t) gives the motion of the plasma")
        self.drive = _drive(current, resistance)
        self.drive(0.0)  # a bad current(t) fails now, not in the middle of a run
        self.circuit = (current, resistance)  # for the run's drive (``_bind``)
        self.plasma_rotation = (None if plasma_rotation is None
                                else vector3(plasma_rotation, "plasma_rotation"))
        if callable(getattr(field, "sources", None)):
            self.compiled, self.callable = field, None
        elif callable(field):
            self.compiled, self.callable = None, field
        else:
            self.compiled, self.callable = UniformField(field), None
        if not 0.0 < fd_step < 1.0:
            raise ValueError(f"fd_step must lie in (0, 1), got {fd_step!r}")
        self.fd_step = float(fd_step)

    def field_and_gradient(self, x, t, field=None):
        """The field (T) and its gradient (T/m) at absolute positions ``x`` (n, 3): the
        field's own ``field(x, t)`` when it has one (``IGRF``), else central differences;
        ``field``: the callable field to use (default the one given, without the
        system's epoch: ``environment.bound_model``)."""
        if self.compiled is not None:
            return self.compiled.field(x, t)
        field = self.callable if field is None else field
        if callable(getattr(field, "field", None)):
            return field.field(x, t)
        B = self._call(field, x, t)
        dB = np.empty(x.shape + (3,))
        step = self.fd_step * (1.0 + np.linalg.norm(x, axis=-1))
        for j in range(3):
            dx = np.zeros_like(x)
            dx[:, j] = step
            dB[:, :, j] = (self._call(field, x + dx, t)
                           - self._call(field, x - dx, t)) / (2 * step[:, None])
        return B, dB

    @staticmethod
    def _call(field, x, t):
        B = np.asarray(field(x, t), dtype=float)
        if B.shape != x.shape or not np.all(np.isfinite(B)):
            raise ValueError(f"field(x, t) must return a finite array of shape {x.shape} "
                             f"(one field vector per point, T), got shape {B.shape}")
        return B

    def bound_field(self, system):
        """The callable field at the system's epoch (``environment.bound_model``: a
        model made without an epoch takes the system's), None for a compiled one."""
        return None if self.callable is None else bound_model(self.callable, system.epoch,
                                                               "field")

    #: Bound with the run's reference in orbit (``bind(system, reference)``).
    reads_reference = True

    step_outputs = property(lambda self: names(self.cable.name, self.oml),
                            doc="Recorded per saved step (protocols.Load): oml_circuit.names.")

    def inputs(self):
        """The inputs the current reads (``inputs.declared``)."""
        return declared(self.circuit[0])

    def bind(self, system, reference=None, inputs=None):
        """The load's term: compiled (``kernels.electrodynamic.kernel``) for a uniform or
        dipole field, a Python ``add`` for a callable field; in orbit about the reference
        point of ``reference`` (the run's ``Reference``; None: the orbit as given); the
        current reads the run's values of its inputs (``inputs``: the run's
        ``InputTable``)."""
        return self._bind(system, reference, inputs)[0]

    def _bind(self, system, reference=None, inputs=None):
        """``(term, pack)``: the term and its pack (``kernels.electrodynamic.kernel``),
        whose scratch holds the forces at the points and whose last array ``[I, E]``
        the evaluations write; the points are the line-body hook's (``lines``)."""
        if self.oml is not None:
            return bind_oml(self, system, system.orbit if reference is None else reference)
        current, resistance = self.circuit
        run_drive = self.drive if inputs is None else _drive(reader(current, inputs),
                                                             resistance)
        orbit = system.orbit if reference is None else reference
        points = lines.line_points(self.cable, system)
        motion, source, drive = np.zeros((2, 3)), np.zeros((2, 3)), np.zeros(2)
        scratch = tuple(np.zeros(points.shape + shape) for shape in
                        [(3,)] * 4 + [(3, 3)] + [(3,)] + [(3, 3)] * 3 + [()])
        field = self.bound_field(system)
        pack = ((points.edofs, points.S, points.Sx, points.w), motion, source, drive,
                co_rotation(self.plasma_rotation, orbit), scratch, np.zeros(2))

        def prepare(t):
            if orbit is not None:
                motion[0], motion[1] = orbit.position(t), orbit.velocity(t)
            drive[:] = run_drive(t)
            if self.compiled is not None:
                source[:] = self.compiled.sources(t)

        prepare(0.0 if orbit is None else orbit.t0)
        name = f"electrodynamic force {self.cable.name}"
        rows, cols = points.tangent_pattern()
        if self.compiled is not None:
            return Term(kernels=((kernel.kernel, pack),), rows=rows, cols=cols,
                        prepare=prepare, name=name), pack

        def add(ev, index):
            prepare(ev.t)
            packed = ev.packed()
            kernel.gather(pack, packed)
            X, B, dB = scratch[0], scratch[3], scratch[4]
            B[:], dB[:] = (y.reshape(X.shape[:2] + y.shape[1:]) for y in
                           self.field_and_gradient(X.reshape(-1, 3), ev.t, field))
            kernel.finish(pack, index, packed)

        return Term(add=add, rows=rows, cols=cols, name=name), pack

    def _evaluated(self, system, q, v=None, t=0.0, reference=None):
        """The pack of the load's term (``_bind``) after one evaluation at ``(q, v, t)``
        (the OML environment taken at the positions of ``q``)."""
        q = np.asarray(q, dtype=float)
        if self.oml is not None:
            term, pack = bind_oml(self, system, system.orbit if reference is None
                                  else reference, q)
        else:
            term, pack = self._bind(system, reference)
        ev = Evaluation(system, t, q, None if v is None else np.asarray(v, dtype=float),
                        np.zeros(system.n_constraints))
        term.evaluate(ev, np.zeros(np.broadcast_shapes(term.rows.shape, term.cols.shape),
                                   dtype=np.int64))
        return pack

    def evaluate(self, system, q, v=None, t=0.0, reference=None):
        """The current (A), the motional (open-circuit) EMF ``E`` (V, whatever the
        current), the electrical power ``I E`` (W) and the total force (N, (3,)) on the
        cable at the coordinates ``q`` and velocities ``v`` (None: at rest relative to the
        reference point) of ``system`` at time ``t``: a dict with keys ``current``,
        ``emf``, ``power``, ``force``.  In orbit the offsets are taken from the reference
        point of ``reference`` (a run's, ``Result.reference``, with its rebases; None:
        the orbit as given).

        ``power = I E`` is what the motional EMF gives the circuit: positive when the
        tether generates (a short circuit: ``E^2 / R_c``, a brake), negative when a supply
        drives the current against the EMF (a thruster); the force's power on the motion
        relative to the plasma is ``-I E``.  With ``current="oml"`` (``oml_circuit.
        summary``): ``current`` is the cathode's ``I(0)``, ``power`` the motional power
        ``int I E ds``, with ``mean_current``, ``load_power`` ``R_L I(0)^2``, ``ohmic``
        (W) and the solver's ``iterations``.

        The total force is ``int f dx``, the sum of the forces at the points times their
        weights.
        """
        pack = self._evaluated(system, q, v, t, reference)
        if self.oml is not None:
            return summary(pack, self.oml)
        points, out, F = pack[0], pack[-1], pack[5][5]
        return {"current": float(out[0]), "emf": float(out[1]),
                "power": float(out[0] * out[1]),
                "force": np.einsum("eg,egi->i", points[3], F)}

    def summaries(self, result):
        """The summaries of ``evaluate`` (but the force) at every saved step of the run
        ``result`` (a ``Result`` of a system carrying this load), arrays (nt,), and the
        electrical ``energy`` (J): the trapezoidal time integral of ``power`` from the
        first saved step (with ``current="oml"`` what the load, the cathode, the ohmic
        heat and the sheath received; the books' external work of the force is minus
        it, ``docs/environment.md``)."""
        rows = [self.evaluate(result.system, q, v, t, result.reference)
                for q, v, t in zip(result.q, result.v, result.t)]
        out = {key: np.array([row[key] for row in rows]) for key in rows[0]
               if key != "force"}
        out["energy"] = np.concatenate([[0.0], np.cumsum(
            0.5 * np.diff(result.t) * (out["power"][1:] + out["power"][:-1]))])
        return out

    def point_data(self, system, q, v=None, t=0.0, reference=None):
        """``(cable, {"current": I(s), "bias": dV(s)})``: the profiles (A, V) as functions
        of the arc lengths ``s`` (m) at the state ``(q, v, t)`` (the ParaView output's
        point data, ``io.export.loads_point_data``); the current is uniform and there is
        no bias unless ``current="oml"`` (``oml_circuit.profile``: linear between the
        solver's nodes)."""
        pack = self._evaluated(system, q, v, t, reference)
        if self.oml is None:
            return self.cable, {"current": lambda s: np.full(np.shape(s), pack[-1][0])}
        return self.cable, {"current": lambda s: profile(pack, s, 0),
                            "bias": lambda s: profile(pack, s, 1)}

    def outputs(self, result):
        """Key numbers of a run (``runner.summary.run_outputs``): the ``evaluate``
        summaries (but the force) at its last saved step."""
        out = self.evaluate(result.system, result.q[-1], result.v[-1], result.t[-1],
                            result.reference)
        return {key: value for key, value in out.items() if key != "force"}

    def current(self, state, s):
        """The current (A, positive towards ``+s``) at the reference arc lengths ``s``
        (m) of the cable in the ``State`` ``state`` (``State.v``: its velocities, None
        at rest; ``State.t``), as ``Cable.tension(q, s)``: uniform for a prescribed or
        short-circuit current, the OML profile for ``"oml"`` (``point_data``)."""
        fields = self.point_data(state.system, state.q, state.v, state.t)[1]
        return fields["current"](s)

    def bias(self, state, s):
        """The OML bias ``V_tether - V_plasma`` (V) at the arc lengths ``s`` (m) of the
        cable in ``state`` (``current``); only with ``current="oml"``."""
        if self.oml is None:
            raise ValueError("bias: the tether's bias is computed with current='oml' only")
        return self.point_data(state.system, state.q, state.v, state.t)[1]["bias"](s)
