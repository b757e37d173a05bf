"""The electric solar-wind sail of the paper (Sects. 2.1, 3, 4.1): a rigid cylindrical hub
in natural coordinates, ``p`` ANCF tethers pinned to its rim, remote units at their tips,
the solar-wind Coulomb force, and the auxiliary outputs of Sect. 3.

Frames (Sect. 2.1): H heliocentric ecliptic; I parallel to H with origin at ``R0`` (the hub
centre at t = 0), in which the system is formulated; O the orbit frame (``Z_O`` radial from
the Sun); B the hub body frame (``X_B`` the spin axis); E the frame of the remote units'
mean plane.

Departures from the paper, each a slip of the text (see ``docs/esail.md``): tether ``i``
sits at ``zeta_i = 2 pi (i - 1)/p`` in the hub mid-plane (Eqs. 57, 79; Eq. 54 writes
``2 pi i / p`` and measures from base point A); the initial stretch is the exact steady
rotating-cable solution anchored at the hub rim (Eq. 79 ignores the hub radius in the
strain, which would open the joints by ``R eps``); angles are measured from ``Z_O`` for both
the thrust and the reaction (Eqs. 74, 77 write an elevation); the precession angle is the
azimuth of the projection of ``X_E`` (``atan2``, not ``acos``); ``reaction_force`` is the force
the tethers apply to the hub (the paper's multipliers carry the opposite sign).
"""

from dataclasses import dataclass, field, replace

import numpy as np
from scipy.spatial.transform import Rotation

from ..cable import Cable
from ..coulomb import AU, THRUST_EXPONENT, SolarWind, SolarWindForce, SunAtFocus
from ..frames import R1, dcm_321, euler_321, euler_323, orbit_frame
from ..inputs import InputTable, system_inputs
from ..orbit import MU_SUN, Orbit
from ..rigid import RigidBody
from ..runner.directory import register_files
from ..section import Section, check_positive
from ..solvers.settle import settle
from ..solvers.steady import solve_steady
from ..state import State
from ..system import System

# the files of the ``esail`` scene's run directory (``run``, ``figures``), for its summary
register_files({"esail_outputs.npz": "every E-sail output of esail.outputs, as numpy arrays"},
               after="animation.mp4")
register_files({
    "plots/esail_tether.png": "tether coning, lagging and stretch against time (Fig. 6)",
    "plots/esail_hub.png": "hub rates and attitudes, sail attitude (Figs. 7-8)",
    "plots/esail_forces.png": "thrust and root reactions in the orbit frame (Fig. 9)",
    "plots/esail_psd.png": "spectra of tether and hub motions, Table 2 modes marked",
    "plots/esail_coning.gif": "side view of the sail's coning, Sun direction drawn (--animate)",
}, patterns=("plots/esail_*.png", "plots/esail_*.gif"))


@dataclass
class BaselineConfig:
    """Table 1 of the paper and Sect. 4.1 (SI units); every field is editable.

    ``voltage`` is one value for all tethers, a sequence with one per tether, or callables
    ``V(t)`` (voltage modulation); one callable may return all the voltages (an
    ``Input`` of one value per tether that a controller sets, ``control``).
    """

    n_tethers: int = 12
    tether_length: float = 10e3
    tether_area: float = 4.28e-9
    tether_inertia: float = 1.47e-18
    tether_density: float = 7653.0
    tether_E: float = 70e9
    gamma_axial: float = 1.0
    gamma_bending: float = 1.0
    voltage: object = 20e3
    remote_mass: float = 1.5
    hub_height: float = 2.0
    hub_radius: float = 1.0
    hub_density: float = 884.0
    spin_rate: float = 4e-3
    R0: tuple = (np.sqrt(0.5) * AU, np.sqrt(0.5) * AU, 0.0)
    wind: SolarWind = field(default_factory=SolarWind)

    def validate(self):
        """Raise ``ValueError`` naming the first invalid field."""
        if int(self.n_tethers) != self.n_tethers or self.n_tethers < 1:
            raise ValueError(f"n_tethers must be a positive integer, got {self.n_tethers!r}")
        for name in ("tether_length", "tether_area", "tether_inertia", "tether_density",
                     "tether_E", "remote_mass", "hub_height", "hub_radius", "hub_density",
                     "spin_rate"):
            check_positive(name, getattr(self, name))
        for name in ("gamma_axial", "gamma_bending"):
            check_positive(name, getattr(self, name), allow_zero=True)
        R0 = np.asarray(self.R0, dtype=float)
        if R0.shape != (3,) or not np.all(np.isfinite(R0)) or np.hypot(R0[0], R0[1]) == 0:
            raise ValueError(f"R0 must be a finite 3-vector off the ecliptic pole, got {self.R0!r}")
        return self

    @property
    def spin_period(self):
        """Nominal spin period ``T_s = 2 pi / omega_0`` (s)."""
        return 2 * np.pi / self.spin_rate

    @property
    def centrifugal_ratio(self):
        """The centrifugal tension at a tether's root, ``omega_0^2 L (m_u + m_t / 2)``
        (remote unit ``m_u``, tether ``m_t``), over the Coulomb force on the tether
        perpendicular to the wind at the voltage (20 kV when it is modulated), ``f L``:
        Janhunen and Toivanen's criterion for the spin rate asks for at least 5 (the
        E-sail paper's Ref. 18)."""
        tether = self.tether_density * self.tether_area * self.tether_length
        nominal = self.voltage if np.isscalar(self.voltage) else BaselineConfig.voltage
        return self.spin_rate**2 * (self.remote_mass + tether / 2) \
            / self.wind.force_per_length(nominal)

    @property
    def section(self):
        return Section(E=self.tether_E, A=self.tether_area, I=self.tether_inertia,
                       rho=self.tether_density, gamma_axial=self.gamma_axial,
                       gamma_bending=self.gamma_bending)


#: A full-size sail: 100 tethers of 20 km (the paper's section and remote units; about
#: 0.9 N at 1 AU), spinning at 1.2e-3 rad/s (period 87 min) so that the centrifugal
#: ratio (``BaselineConfig.centrifugal_ratio``) is 5.85, above the 5 of Janhunen and
#: Toivanen, "An intrinsic way to control E-sail spin" (2014, arXiv:1406.6847).
FULL_SIZE = BaselineConfig(n_tethers=100, tether_length=20e3, spin_rate=1.2e-3)

#: The relative tolerance of adaptive steps (``simulate(rtol=...)``, with ``atol`` 1e-3 m)
#: that keeps the thrust, the mean coning and the sail's spin rate (``outputs``'
#: ``spin_rate``) of ``FULL_SIZE`` within 1e-3 of a fixed 0.5 s run over an hour (largest
#: differences measured over the hour from the windless spin: spin rate 2.8e-5, coning
#: 2.5e-4, thrust 8.6e-6; at 3e-4 the coning is 2.1e-3 off; ``docs/benchmarks.md``).  The
#: steps hold their local error to 1.1e-5 (``GeneralizedAlpha``'s proportionality
#: transform).  Over a day the coning's slow swing accumulates phase.  The hub's own
#: rate carries a libration against the tethers (a period of about 130 s, up to 20 %)
#: whose phase only steps of about 0.5 s follow.  From the sail's state under the wind
#: (``settled``) the hour takes 146 steps instead of 1037, its outputs within 2.0e-3 (the
#: hub's rate; the others within 2.4e-4).
MISSION_RTOL = 5e-5


@dataclass
class ESailScene:
    """A built E-sail: the system, its bodies, the initial state and what ``outputs``
    needs (``zeta`` tether angles, ``anchors`` in the body frame, ``R0`` the heliocentric
    position of the origin of I at t = 0, ``orbit`` the heliocentric orbit of the system's
    reference point or None: I fixed; ``options`` the tethers' ``n_elements``, ``kind``,
    ``formulation`` and the wind's ``exponent`` it was built with)."""

    config: BaselineConfig
    alpha: float
    system: System
    hub: RigidBody
    tethers: list
    anchors: np.ndarray
    zeta: np.ndarray
    wind_force: SolarWindForce
    initial: State
    R0: np.ndarray
    orbit: Orbit | None = None
    options: dict = field(default_factory=dict)

    def heliocentric(self, t, reference=None):
        """Heliocentric position (m) of the origin of the system's coordinates at times
        ``t`` (nt,): ``R0`` fixed, or the reference point ``R(t)`` of the run's
        ``reference`` (``Result.reference``: the orbit and its rebases; None: the orbit as
        given); (nt, 3)."""
        t = np.asarray(t, dtype=float)
        if self.orbit is None:
            return np.broadcast_to(self.R0, t.shape + (3,))
        return (self.orbit if reference is None else reference).position(t)


def rotating_cable_stretch(s, hub_radius, length, EA, mass_per_length, tip_mass, omega):
    """Steady radial state of a cable spinning at ``omega`` about an axis, anchored at
    ``hub_radius`` with a tip mass: ``T' = -mu omega^2 r``, ``r' = lambda(T)`` with the
    Green-strain law ``T = EA (lambda^2 - 1) lambda / 2``, ``r(0) = hub_radius``,
    ``T(L) = m omega^2 r(L)``.  Returns the radius ``r`` and the stretch ``lambda`` at the
    reference arc lengths ``s`` (fixed-point iteration on a fine grid, converged to
    round-off)."""
    grid = np.union1d(np.linspace(0.0, length, 20001), s)
    r = hub_radius + grid
    for _ in range(50):
        centrifugal = mass_per_length * omega**2 * r
        tail = np.concatenate([[0.0], np.cumsum(0.5 * (centrifugal[1:] + centrifugal[:-1])
                                                * np.diff(grid))])
        T = tip_mass * omega**2 * r[-1] + tail[-1] - tail
        lam = np.ones_like(T)
        for _ in range(30):  # Newton on lam^3 - lam = 2 T / EA
            lam -= (lam**3 - lam - 2 * T / EA) / (3 * lam**2 - 1)
        r_new = hub_radius + np.concatenate([[0.0], np.cumsum(0.5 * (lam[1:] + lam[:-1])
                                                             * np.diff(grid))])
        done = np.max(np.abs(r_new - r)) <= 1e-15 * r[-1]
        r = r_new
        if done:
            break
    return np.interp(s, grid, r), np.interp(s, grid, lam)


def build(config, alpha_deg, n_elements, kind="cable", formulation=None):
    """Build the baseline E-sail of Sect. 4.1 for sailing angle ``alpha_deg`` (deg) with
    ``n_elements`` elements per tether of ``kind`` ("cable" or "truss") in the
    ``formulation`` of ``Cable`` (None: the default; ``"paper"`` is the paper's own).

    The hub starts at the origin of I with body Euler angles ``(0, alpha - 90 deg, 0)``
    relative to O, all tethers radial in the hub mid-plane, stretched by the steady
    rotating-cable solution for the spin ``omega_0`` about ``X_B``, and the whole sail in
    rigid rotation (Eqs. 79-82).  The frame I is fixed, the Sun at ``-R0``.
    """
    return _build(config.validate(), alpha_deg, n_elements, kind, formulation)


def build_orbit(config, alpha_deg, n_elements, kind="cable", formulation=None, orbit=None,
                exponent=THRUST_EXPONENT):
    """The sail of ``build`` on a heliocentric orbit (``System.add_orbit``): the system's
    coordinates are offsets from the orbit's reference point ``R(t)``, the Sun's
    differential gravity acts on every mass, and the solar wind is evaluated at each Gauss
    point's heliocentric position ``R(t) + x`` (``SunAtFocus``), its force scaled by
    ``(AU / r)^exponent``.

    ``orbit`` defaults to the circular orbit of 1 AU in the ecliptic, ``Orbit(MU_SUN,
    AU)``; its central body must be the Sun.  The sail starts at the reference point at
    t = 0, at rest relative to it apart from its spin: ``config.R0`` is replaced by
    ``orbit.position(0)`` (the sailing angle is set against the Sun line there).
    """
    orbit = Orbit(MU_SUN, AU) if orbit is None else orbit
    cfg = replace(config, R0=tuple(orbit.position(0.0))).validate()
    return _build(cfg, alpha_deg, n_elements, kind, formulation, orbit, exponent)


def _build(cfg, alpha_deg, n_elements, kind, formulation, orbit=None,
           exponent=THRUST_EXPONENT):
    """``build`` of a validated config; with ``orbit``, the system is put on it and the Sun
    sits at its focus."""
    if int(n_elements) != n_elements or n_elements < 1:
        raise ValueError(f"n_elements must be a positive integer, got {n_elements!r}")
    if not np.isfinite(alpha_deg) or abs(alpha_deg) > 90:
        raise ValueError(f"alpha_deg must lie in [-90, 90], got {alpha_deg!r}")
    alpha = np.deg2rad(alpha_deg)
    R0 = np.asarray(cfg.R0, dtype=float)
    C_I_O = orbit_frame(R0)
    C_B_O = dcm_321(0.0, alpha - np.pi / 2, 0.0)
    C_I_B = C_I_O @ C_B_O.T
    hub = RigidBody.cylinder(cfg.hub_radius, cfg.hub_height, cfg.hub_density,
                             rotation=C_I_B, name="hub")
    sec = cfg.section
    p = int(cfg.n_tethers)
    zeta = 2 * np.pi * np.arange(p) / p
    radial_B = np.column_stack([np.zeros(p), np.cos(zeta), np.sin(zeta)])
    anchors = cfg.hub_radius * radial_B
    s = np.linspace(0.0, cfg.tether_length, int(n_elements) + 1)
    r, lam = rotating_cable_stretch(s, cfg.hub_radius, cfg.tether_length, sec.EA,
                                    sec.mass_per_length, cfg.remote_mass, cfg.spin_rate)
    tethers = []
    for i in range(p):
        e = C_I_B @ radial_B[i]
        cable = Cable(Cable.straight([0, 0, 0], [cfg.tether_length, 0, 0], int(n_elements),
                                     sec).mesh, sec, r[:, None] * e, lam[:, None] * e,
                      law=kind, name=f"tether{i + 1}", formulation=formulation)
        tethers.append(cable)
    system = System([hub, *tethers])
    for cable, x in zip(tethers, anchors):
        system.pin(cable.node(0), hub.point(x))
        system.add_point_mass(cable.node(-1), cfg.remote_mass)
    sun = -R0 if orbit is None else SunAtFocus(orbit)
    wind_force = SolarWindForce(tethers, cfg.voltage, cfg.wind, sun_position=sun,
                                exponent=exponent)
    system.add_load(wind_force)
    if orbit is not None:
        system.add_orbit(orbit)
    q0 = system.q0
    omega_I = C_I_B @ np.array([cfg.spin_rate, 0.0, 0.0])
    v0 = system.rigid_motion_velocity(q0, omega_I)
    return ESailScene(cfg, alpha, system, hub, tethers, anchors, zeta, wind_force,
                      State(system, q0, v=v0), R0, orbit,
                      {"n_elements": n_elements, "kind": kind, "formulation": formulation,
                       "exponent": exponent})


#: ``settled``'s relaxation: steps of this share of a spin period (4 deg of spin) ...
SETTLE_STEP = 1.0 / 90.0
#: ... over this many spin periods (4.4 h for ``FULL_SIZE``).  Measured on ``FULL_SIZE``
#: (the start in modified Newton, then a day of adaptive steps with the local error held
#: to 1e-5, two threads): 5.5 periods of 1/180 took 6.2 s, then 3933 steps; these 5.4 s,
#: then 3466 steps (3 of 1/180: 3.9 s, then 4001 steps; 5.5 of 1/45: 9.3 s, then 3262;
#: longer relaxation steps need more Newton iterations).  Now (full Newton, ``settle``'s
#: default; ``MISSION_RTOL``): 4.4 s, then 3284 steps.
SETTLE_SPINS = 3.0


def settled(scene, spins=SETTLE_SPINS):
    """``scene`` started from its state under the wind instead of the windless spin of
    ``build`` (which the wind's onset sets ringing and coning for the whole run):

    1. the relative equilibrium of the sail turned to face the wind (``solve_steady``
       about its spin axis turned onto the wind line, where the wind is constant in the
       spinning frame: the tethers coned, the sail accelerating along the axis), turned
       back to the sailing angle;
    2. ``spins`` spin periods of dynamic relaxation from there (``solvers.settle.settle``:
       steps of ``SETTLE_STEP`` of a spin period at rho_inf = 0, from t = -``spins``
       periods), which take a factor 1e3 off the modes of periods below about an eighth
       of the spin period (``omega h > 0.59``) that the tilt against the wind sets off.

    The slow coning oscillation is not reached by the relaxation (its ``omega h`` is
    0.07); the equilibrium keeps it small.  ``FULL_SIZE`` at 10 deg and ``MISSION_RTOL``:
    the mean coning stays within 4.65 to 4.80 deg over a day (from the windless spin, or
    relaxed from it without the equilibrium, it swings between 0 and 9 deg with a period
    of 1.4 h), and the adaptive steps take 3284 steps a day (``docs/benchmarks.md``,
    "Mission-length runs").  The sail has sailed during the
    relaxation: it starts off the origin (or the orbit's reference point), moving with
    the velocity the thrust gave it.
    """
    if not (np.isfinite(spins) and spins > 0):
        raise ValueError(f"spins must be a finite number > 0, got {spins!r}")
    system, initial = scene.system, scene.initial
    # on an orbit the Sun line turns and the Sun's tides act: the equilibrium is that of
    # the sail fixed at the orbit's start, the rest is left to the relaxation
    fixed = scene if scene.orbit is None else _build(
        replace(scene.config, R0=tuple(scene.R0)), np.degrees(scene.alpha), **scene.options)
    axis = scene.hub.rotation(initial.q[system.dofs(scene.hub)])[:, 0]
    R = _facing(axis, scene.R0 / np.linalg.norm(scene.R0))  # the wind blows from the Sun
    turned = State(fixed.system, system.rotate(initial.q, R), v=system.rotate(initial.v, R))
    steady = solve_steady(fixed.system, scene.config.spin_rate * (R @ axis), initial=turned)
    start = State(system, system.rotate(steady.q, R.T), v=system.rotate(steady.v, R.T))
    period = scene.config.spin_period
    duration = spins * period
    state = settle(system, duration, SETTLE_STEP * period, initial=start, t_start=-duration)
    return replace(scene, initial=State(system, state.q, state.lam, v=state.v, t=0.0))


def _facing(axis, wind):
    """The least rotation that turns the unit vector ``axis`` onto the line of ``wind``
    (onto ``wind`` or ``-wind``, whichever is nearer)."""
    target = wind if axis @ wind >= 0 else -wind
    return Rotation.align_vectors([target], [axis])[0].as_matrix()


def _angles(vec_Z):
    """Coning (out of the spin plane) and lagging angles of vectors in the tether frames Z
    (Eqs. 59, 61)."""
    gamma = np.arctan2(vec_Z[..., 0], np.hypot(vec_Z[..., 1], vec_Z[..., 2]))
    beta = np.arctan2(vec_Z[..., 2], vec_Z[..., 1])
    return gamma, beta


def outputs(scene, result):
    """Auxiliary variables of Sect. 3 as time series (leading axis: the saved steps).

    Returns a dict with ``t`` and: ``coning``, ``lagging``, ``root_coning``,
    ``root_lagging``, ``length_ratio`` (nt, p); ``omega_B`` (nt, 3, rad/s, the hub's);
    ``spin_rate`` (nt, rad/s: the remote units' mean rate about the normal of their plane,
    the sail's spin without the hub's libration); ``euler_B``
    (psi, theta, phi) and ``euler_E`` (Psi, Theta, Phi) (nt, 3, rad); ``sailing_angle``,
    ``precession_angle`` (nt, rad); ``thrust`` (I) and ``thrust_O`` (nt, 3, N),
    ``thrust_angle`` (from ``Z_O``, rad), ``thrust_moment`` (about the anchors, I, N m);
    ``coulomb_force_B``, ``coulomb_moment_B`` per tether (nt, p, 3, body frame);
    ``reaction_force`` (force of the tethers on the hub, I) and ``reaction_force_O``,
    ``reaction_moment`` (about the hub centre, I), ``reaction_angle`` (from ``Z_O``); and
    the energies of ``result.energy``.
    """
    system, hub = scene.system, scene.hub
    d = result.q[:, system.dofs(hub)]
    C_I_B = hub.rotation(d)
    origin = hub.positions(d, np.zeros(3))
    C_I_O = orbit_frame(scene.heliocentric(result.t, result.reference) + origin)
    out = {"t": result.t}
    rho_Z, tau_Z, ratio = [], [], []
    for zeta, cable in zip(scene.zeta, scene.tethers):
        qc = result.q[:, system.dofs(cable)]
        nodes = qc.reshape(len(result.t), -1, cable.element.nodal_dofs, 3)
        C_Z_I = R1(zeta) @ np.swapaxes(C_I_B, -1, -2)
        rho_Z.append(np.einsum("tij,tj->ti", C_Z_I, nodes[:, -1, 0] - nodes[:, 0, 0]))
        tau_Z.append(np.einsum("tij,tj->ti", C_Z_I, nodes[:, 0, 1]))
        a = np.einsum("egA,teAi->tegi", cable.Sx, cable.element_vectors(qc))
        ratio.append(np.einsum("eg,teg->t", cable.weights, np.linalg.norm(a, axis=-1))
                     / cable.length)
    out["coning"], out["lagging"] = _angles(np.stack(rho_Z, axis=1))
    out["root_coning"], out["root_lagging"] = _angles(np.stack(tau_Z, axis=1))
    out["length_ratio"] = np.stack(ratio, axis=1)
    out["omega_B"] = hub.angular_velocity(d, result.v[:, system.dofs(hub)])
    C_B_O = np.swapaxes(C_I_B, -1, -2) @ C_I_O
    out["euler_B"] = euler_321(C_B_O)
    # E frame: normal of the least-squares plane of the remote units (Eqs. 67-70)
    tips = np.stack([result.q[:, system.dofs(c)[-6:-3]] for c in scene.tethers], axis=1)
    centre = tips.mean(axis=1, keepdims=True)
    normal = np.linalg.svd(tips - centre)[2][:, -1]
    normal *= np.sign(np.einsum("ti,ti->t", normal, C_I_B[:, :, 0]))[:, None]
    k_E = np.cross(normal, tips[:, 0] - centre[:, 0])
    k_E /= np.linalg.norm(k_E, axis=1, keepdims=True)
    C_I_E = np.stack([normal, np.cross(k_E, normal), k_E], axis=-1)
    out["spin_rate"] = _spin_rate(tips - centre, np.stack(
        [result.v[:, system.dofs(c)[-6:-3]] for c in scene.tethers], axis=1), normal)
    out["euler_E"] = euler_323(np.swapaxes(C_I_E, -1, -2) @ C_I_O)
    out["sailing_angle"] = np.arccos(np.clip(np.einsum("ti,ti->t", C_I_B[:, :, 0],
                                                       C_I_O[:, :, 2]), -1, 1))
    i_E_O = np.einsum("tji,tj->ti", C_I_O, normal)
    out["precession_angle"] = np.arctan2(i_E_O[:, 1], i_E_O[:, 0])
    # Coulomb resultants (Eqs. 72-76) by the same quadrature as the force
    force_B, moment_B = _coulomb_resultants(scene, result, C_I_B)
    thrust = np.einsum("tij,tpj->ti", C_I_B, force_B)
    out["coulomb_force_B"], out["coulomb_moment_B"] = force_B, moment_B
    out["thrust"] = thrust
    out["thrust_O"] = np.einsum("tji,tj->ti", C_I_O, thrust)
    out["thrust_angle"] = _angle_from_z(out["thrust_O"])
    out["thrust_moment"] = np.einsum("tij,tpj->ti", C_I_B, moment_B)
    # reactions on the hub from the joint multipliers (Eqs. 77-78)
    pins = [result.multipliers[c.name] for c in system.constraints if c.name.startswith("pin")]
    lam = np.stack(pins, axis=1)
    out["reaction_force"] = lam.sum(axis=1)
    out["reaction_force_O"] = np.einsum("tji,tj->ti", C_I_O, out["reaction_force"])
    anchors_I = hub.positions(d, scene.anchors)
    out["reaction_moment"] = np.cross(anchors_I - origin[:, None], lam).sum(axis=1)
    out["reaction_angle"] = _angle_from_z(out["reaction_force_O"])
    out.update(result.energy)
    return out


def _spin_rate(arms, velocities, normal):
    """The remote units' mean angular rate (rad/s) about ``normal`` (nt, 3), from their
    positions relative to their centre ``arms`` and velocities (nt, p, 3): the sail's spin
    rate, without the hub's libration against the tethers, which ``omega_B`` shows."""
    relative = velocities - velocities.mean(axis=1, keepdims=True)
    radial = arms - np.einsum("tpi,ti->tp", arms, normal)[..., None] * normal[:, None]
    rate = np.einsum("tpi,ti->tp", np.cross(radial, relative), normal)
    return (rate / np.einsum("tpi,tpi->tp", radial, radial)).mean(axis=1)


def _angle_from_z(F_O):
    return np.arctan2(np.hypot(F_O[..., 0], F_O[..., 1]), F_O[..., 2])


def _coulomb_resultants(scene, result, C_I_B):
    """Per-tether Coulomb force ``int f dx`` and moment ``int (r - r_anchor) x f dx`` about
    the anchor, in the body frame, (nt, p, 3) each."""
    inputs = system_inputs(scene.system)
    missing = sorted(set(inputs) - set(result.inputs))
    if missing:
        raise ValueError(f"outputs: the result holds no history of the inputs "
                         f"{', '.join(map(repr, missing))} (set by controllers): the "
                         "Coulomb force of past saved steps cannot be recomputed")
    return _resultants(scene, result, C_I_B, InputTable(inputs))


def _resultants(scene, result, C_I_B, table):
    """``_coulomb_resultants`` with the inputs of ``table`` (an ``inputs.InputTable``)
    set, at each saved step, to the values the result recorded."""
    wf, system = scene.wind_force, scene.system
    sources = wf.sources(table)
    nt, p = len(result.t), len(scene.tethers)
    force = np.zeros((nt, p, 3))
    moment = np.zeros((nt, p, 3))
    for k, t in enumerate(result.t):
        for name in table.values:
            table.set(name, result.inputs[name][k])
        coef = wf.coefficients(t, sources)
        for i, cable in enumerate(scene.tethers):
            qc = result.q[k, system.dofs(cable)]
            qe = cable.element_vectors(qc)
            r = np.einsum("egA,eAi->egi", cable.S, qe)
            a = np.einsum("egA,eAi->egi", cable.Sx, qe)
            f = wf.line_force(r, a, coef[i, None, None], t, result.reference)
            fw = f * cable.weights[..., None]
            force[k, i] = fw.sum(axis=(0, 1))
            moment[k, i] = np.cross(r - qc[:3], fw).sum(axis=(0, 1))
    RT = np.swapaxes(C_I_B, -1, -2)
    return np.einsum("tij,tpj->tpi", RT, force), np.einsum("tij,tpj->tpi", RT, moment)


def rigid_coning(config, out, tether=0):
    """Coning angle of a rigid tether from the pendulum equation Eq. 83,
    ``gamma'' + gamma omega_1^2 (1 + eps) = -M_c3^B / ((m_u + m_t/3) L0^2)`` with
    ``eps = 3 R (2 m_u + m_t) / (2 L0 (3 m_u + m_t))`` (Eq. 84), driven by the simulated
    spin rate ``omega_1`` and Coulomb moment of the tether; starts in the spin plane at
    rest relative to the hub.  Returns ``gamma(t)`` at ``out["t"]``."""
    from scipy.integrate import solve_ivp

    t = out["t"]
    L0, R, mu = config.tether_length, config.hub_radius, config.remote_mass
    mt = config.section.mass_per_length * L0
    eps = 3 * R * (2 * mu + mt) / (2 * L0 * (3 * mu + mt))
    inertia = (mu + mt / 3) * L0**2
    w1 = out["omega_B"][:, 0]
    Mz = out["coulomb_moment_B"][:, tether, 2]

    def rhs(s, y):
        w = np.interp(s, t, w1)
        return [y[1], -y[0] * w * w * (1 + eps) - np.interp(s, t, Mz) / inertia]

    sol = solve_ivp(rhs, (t[0], t[-1]), [0.0, 0.0], t_eval=t, rtol=1e-10, atol=1e-14,
                    max_step=(t[1] - t[0]) * 5)
    return sol.y[0]


def spinning_tether(config, n_elements=5, formulation=None):
    """One tether of the sail in the frame rotating with the nominal spin about x: pinned
    at the hub rim (to ground), its remote unit at the tip, centrifugal loads, starting
    from the analytic steady stretch (the system of Table 2's frequencies);
    ``formulation``: see ``Cable``."""
    from skfem import MeshLine

    sec, L = config.section, config.tether_length
    s = np.linspace(0.0, L, int(n_elements) + 1)
    r, lam = rotating_cable_stretch(s, config.hub_radius, L, sec.EA, sec.mass_per_length,
                                    config.remote_mass, config.spin_rate)
    e = np.array([0.0, 1.0, 0.0])
    cable = Cable(MeshLine(s), sec, r[:, None] * e, lam[:, None] * e, name="tether1",
                  formulation=formulation)
    system = System([cable]).pin(cable.node(0)).add_point_mass(cable.node(-1),
                                                               config.remote_mass)
    system.add_centrifugal([config.spin_rate, 0.0, 0.0])
    return system


def spinning_modes(config, alpha_deg=0.0, n_elements=5, kind="cable", k=200):
    """Natural frequencies (Hz) of the whole sail about its steady spin, in the frame
    rotating with the nominal spin (``modes(..., spin=...)``): the initial state of
    ``build`` is the steady state (the centrifugal, elastic and joint forces balance to
    round-off; the joint and hub multipliers follow by least squares).  The Coulomb force
    is left out (sail off)."""
    from ..solvers.modal import modes

    cfg = BaselineConfig(**{**config.__dict__, "voltage": 0.0})
    scene = build(cfg, alpha_deg, n_elements, kind)
    system = scene.system
    q = system.q0
    C_I_B = scene.hub.rotation(q[system.dofs(scene.hub)])
    omega = C_I_B @ np.array([cfg.spin_rate, 0.0, 0.0])
    system.add_centrifugal(omega)
    lay = system.layout
    n = system.n_dofs
    r, _ = system.evaluate(q, None, 0.0, np.zeros(lay.n_c))
    J = lay.matrix(lay.linear_data).toarray()[n:, :n]
    for j in lay.nonlinear:
        d = lay.cdofs[j]
        J[np.ix_(lay.crows[j], d)] = system.constraints[j].jacobian(q[d])
    lam = np.linalg.lstsq(J.T, -r[:n], rcond=None)[0]
    freqs, _ = modes(system, State(system, q, lam), k=k, spin=omega)
    return freqs


def psd(t, x, segments=4):
    """Welch power spectral density of samples ``x`` (leading axis time) at uniform times
    ``t``: returns frequencies (Hz) and densities.  The package's one spectrum
    (``spectra.spectrum``, also drawn by ``plot.psd``): Hann window, ``segments``
    half-overlapping segments (1: the whole run), mean removed."""
    from ..spectra import spectrum

    return spectrum(t, x, segments=segments)


#: Table 2 of the paper: first natural frequencies (Hz) of a pinned rotating tether with
#: its remote unit (the bending value is no mode of this sail: ``docs/esail.md``); its
#: spin frequency, 6.37e-4 Hz, is ``1 / T_s``, which ``psd_figure`` takes from the run.
TABLE2_HZ = {"1st bending": 7.34e-3, "1st axial": 2.17e-2}


def distinct_frequencies(freqs, rtol=0.02):
    """The frequencies (Hz) of ``freqs`` that differ by more than ``rtol`` from the next
    lower one kept: one mark per cluster of near-equal modes (the ``p`` tethers' copies
    of a mode), zeros dropped."""
    kept = []
    for f in np.sort(np.asarray(freqs, dtype=float)):
        if f > 0 and (not kept or f > kept[-1] * (1 + rtol)):
            kept.append(f)
    return np.array(kept)


def psd_figure(out, path, tether=0, modes=None):
    """PSDs of tether ``tether``'s tip coning and lagging angles (deg) and length ratio
    (``plot.psd``, segments fit to resolve the spin) with marks at the run's mean spin
    frequency, the bending and axial frequencies of Table 2 and, when given, the
    ``distinct_frequencies`` of ``modes`` (Hz, e.g. ``spinning_modes``)."""
    from .. import plot

    t, k, deg = out["t"], tether, np.rad2deg(1.0)
    f_spin = float(np.mean(out["omega_B"][:, 0])) / (2 * np.pi)
    markers = {"spin": f_spin}
    markers.update({f"{name}\n(Table 2)": f for name, f in TABLE2_HZ.items()})
    if modes is not None:
        markers["modes of the spinning sail"] = distinct_frequencies(modes)
    signals = {"tip coning": deg * out["coning"][:, k], "tip lagging": deg * out["lagging"][:, k],
               "L / L0": out["length_ratio"][:, k]}
    units = {"tip coning": "deg", "tip lagging": "deg", "L / L0": ""}
    return plot.psd(t, signals, path, title=f"tether {k + 1}: power spectral densities",
                    markers=markers, units=units, f_min=f_spin)


def coning_animation(result, path, up_scale=10.0, **options):
    """Side view of a run of the sail (``plot.animate``, view ``"side"``): the spin axis
    up, looking perpendicular to it and to the Sun, whose direction is drawn as an arrow
    (from the ``SolarWindForce`` of ``result.system``); offsets along the spin axis are
    drawn ``up_scale`` times larger so that a coning of a degree shows.  ``options`` go
    to ``plot.animate``.  Returns the number of frames."""
    from .. import plot

    wind = next(load for load in result.system.loads if isinstance(load, SolarWindForce))
    return plot.animate(result, path, view="side", sun=wind.sun_at(result.t[0]),
                        up_scale=up_scale,
                        title="E-sail, side view: spin axis up", **options)


def figures(out, plots_dir, tether=0, modes=None, animation=None):
    """The paper's kinds of figures (Figs. 6-9) from ``outputs``: tether angles and mean
    strain, hub rates and attitude, thrust and reactions in the orbit frame, PSDs
    (``psd_figure``, ``modes`` marked when given; the energies of Fig. 10 are the run's
    ``plots/energies.png``) and,
    when ``animation`` (the run's ``Result``) is given, ``esail_coning.gif``
    (``coning_animation``; needs off-screen OpenGL).  Returns the paths written."""
    from pathlib import Path

    from .. import plot

    d = Path(plots_dir)
    d.mkdir(parents=True, exist_ok=True)
    t, deg = out["t"], np.rad2deg(1.0)
    k = tether
    paths = [d / "esail_tether.png", d / "esail_hub.png", d / "esail_forces.png",
             d / "esail_psd.png"]
    plot.histories(t, {"coning [deg]": {"tip": deg * out["coning"][:, k],
                                        "root": deg * out["root_coning"][:, k]},
                       "lagging [deg]": {"tip": deg * out["lagging"][:, k],
                                         "root": deg * out["root_lagging"][:, k]},
                       "mean strain\nL / L0 - 1 [ppm]": 1e6 * (out["length_ratio"][:, k] - 1)},
                   paths[0], title=f"tether {k + 1}")
    plot.histories(t, {"omega_B [rad/s]": {f"w{i + 1}": out["omega_B"][:, i]
                                           for i in range(3)},
                       "hub Euler [deg]": {n: deg * out["euler_B"][:, i]
                                           for i, n in enumerate(("psi", "theta", "phi"))},
                       "sail Euler [deg]": {n: deg * out["euler_E"][:, i]
                                            for i, n in enumerate(("Psi", "Theta", "Phi"))}},
                   paths[1], title="hub rates and attitudes")
    plot.histories(t, {"thrust (O) [N]": {c: out["thrust_O"][:, i]
                                          for i, c in enumerate("xyz")},
                       "reaction on hub (O) [N]": {c: out["reaction_force_O"][:, i]
                                                   for i, c in enumerate("xyz")},
                       "angles from Z_O [deg]": {"thrust": deg * out["thrust_angle"],
                                                 "reaction": deg * out["reaction_angle"]}},
                   paths[2], title="thrust and reactions")
    psd_figure(out, paths[3], k, modes)
    if animation is not None:
        paths.append(d / "esail_coning.gif")
        coning_animation(animation, paths[-1])
    return paths


def run(options):
    """The ``esail`` scene of ``skfem-cable run``: the baseline sail (``--alpha``, default
    10 deg; ``--elements`` per tether, default 5) for three spin periods at dt = 0.1 s,
    rho_inf = 0.25; the run directory gets the paper's figures and ``esail_outputs.npz``
    (every output of ``outputs``) besides the standard series, results and summary."""
    from pathlib import Path

    from ..runner.drive import run_dynamic

    cfg = BaselineConfig()
    alpha = options.value("alpha", 10.0)
    scene = build(cfg, alpha, options.value("elements", 5),
                  formulation=options.formulation)

    def key_numbers(result):
        out = outputs(scene, result)
        if options.out is not None:
            np.savez_compressed(Path(options.out) / "esail_outputs.npz", **out)
            if options.plots:
                figures(out, Path(options.out) / "plots",
                        animation=result if options.animate else None)
        thrust = np.linalg.norm(out["thrust"], axis=1)
        return {"thrust_mean_N": thrust.mean(),
                "thrust_angle_mean_deg": np.rad2deg(out["thrust_angle"]).mean(),
                "coning_max_deg": np.rad2deg(np.abs(out["coning"])).max(),
                "lagging_max_deg": np.rad2deg(np.abs(out["lagging"])).max(),
                "omega1_final": out["omega_B"][-1, 0],
                "energy_balance_rel": np.abs(out["balance"]).max() / out["total"][0],
                "wind_work_J": out["external_work"][-1]}

    # one saved step per 5 s (4.6 samples per period of the fastest mode, the axial one
    # at 0.022 Hz) and one ParaView frame per minute: the run directory is 6x smaller
    # than saving every second, with every field and mode resolved
    defaults = {"t_end": 3 * cfg.spin_period, "dt": 0.1, "every": 50, "rho_inf": 0.25,
                "series_every": 12}
    parameters = {"alpha_deg": alpha, "elements_per_tether": scene.tethers[0].n_elements,
                  "tethers": cfg.n_tethers, "kind": "cable",
                  "formulation": scene.tethers[0].formulation}
    return run_dynamic("esail", scene.system, scene.initial, options, defaults, parameters,
                       key_numbers)[0]
