"""Building the E-sail: hub, tethers, joints and the solar wind, settled to its spin."""

import functools
import numbers
from dataclasses import replace

import numpy as np
from skfem import MeshLine

from ...bodies.cable import Cable
from ...bodies.rigid import RigidBody
from ...loads.coulomb import AU, THRUST_EXPONENT, SolarWindForce, SunAtFocus
from ...model.state import State
from ...model.system import System
from ...runner.directory import register_files
from ...solvers.settle import settle
from ...solvers.steady import solve_steady
from ...space.constants import MU_SUN
from ...space.frames import dcm_321, orbit_frame
from ...space.orbit import Orbit
from .config import ESailScene
from .report import _facing
from .ring import auxiliary_tension as auxiliary_tension_of
from .ring import check_ring, ring_cables, ring_length, ring_tension, ring_tip_mass, tip_spacing

#: The ring's default design tension: this share of a remote unit's centrifugal force
#: ``m_u omega^2 L`` (``FULL_RIG``: 21.6 mN, a strain of 2.3e-4).  Chosen so that the
#: ring stays taut in the sailing sail: the tips' distance from the spin axis follows the
#: coning (``d eps = -tan(coning) d coning``) and the lagging, and at 10 deg it swings the
#: ring's strain by 1.4e-4 below the design's (measured, ``docs/esail.md``, the rig's
#: day); at 5 % (2.3e-5) the ring went slack at every swing, its units rattling between
#: snaps that held the day's steps at 2.7 s.  The ring then pulls each unit inwards by
#: ``2 T sin(pi / p)``, 3.1 % of its centrifugal force.
AUXILIARY_SHARE = 0.5
#: Passes of the ring's design (``_ring_design``), each aiming its equivalent sail at the
#: design tension scaled by the ratio the ringed sail missed it by: the first misses by
#: the axial inertia left out (2.4 % for ``FULL_RIG``), the second by its square.
RING_PASSES = 2

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


def rotating_cable_stretch(s, hub_radius, length, EA, mass_per_length, tip_mass, omega):
    """Steady radial state of a cable spinning at ``omega`` about an axis, anchored at
    ``hub_radius`` with a tip mass: ``T' = -mu omega^2 r``, ``r' = lambda(T)`` with the
    Green-strain law ``T = EA (lambda^2 - 1) lambda / 2``, ``r(0) = hub_radius``,
    ``T(L) = m omega^2 r(L)``.  Returns the radius ``r`` and the stretch ``lambda`` at the
    reference arc lengths ``s`` (fixed-point iteration on a fine grid, converged to
    round-off; with numbers for the parameters, the latest 32 answers are remembered by
    their values and types: a scene built again asks again, 25 ms each)."""
    s = np.asarray(s, dtype=float)
    parameters = (hub_radius, length, EA, mass_per_length, tip_mass, omega)
    solve = _steady_spin if all(isinstance(x, numbers.Number) for x in parameters) \
        else _steady_spin.__wrapped__
    r, lam = solve(s.shape, s.tobytes(), *parameters)
    return r.copy(), lam.copy()


@functools.lru_cache(maxsize=32, typed=True)
def _steady_spin(shape, s, hub_radius, length, EA, mass_per_length, tip_mass, omega):
    """``rotating_cable_stretch`` at the arc lengths of ``shape`` whose bytes are ``s``."""
    s = np.frombuffer(s).reshape(shape)
    grid = np.union1d(np.linspace(0.0, length, 20001), s)
    r = hub_radius + grid
    for _ in range(50):
        centrifugal = mass_per_length * omega**2 * r
        tail = np.concatenate([[0.0], np.cumsum(0.5 * (centrifugal[1:] + centrifugal[:-1])
                                                * np.diff(grid))])
        T = tip_mass * omega**2 * r[-1] + tail[-1] - tail
        lam = _stretch(2 * T / EA)
        r_new = hub_radius + np.concatenate([[0.0], np.cumsum(0.5 * (lam[1:] + lam[:-1])
                                                             * np.diff(grid))])
        done = np.max(np.abs(r_new - r)) <= 1e-15 * r[-1]
        r = r_new
        if done:
            break
    return np.interp(s, grid, r), np.interp(s, grid, lam)


def _stretch(rhs):
    """The stretch ``lambda`` of the Green-strain law ``lambda^3 - lambda = rhs = 2 T / EA``
    by 30 Newton steps from 1, each applied only to the entries that the previous one
    changed: an entry a step leaves unchanged stays so (a step is a function of the entry
    alone), so the result is that of 30 steps on the whole array, at the cost of the few
    entries still moving (49 of 20,006 after the fourth step of the E-sail's tethers, which
    end in a two-cycle of the last bit)."""
    lam = np.ones_like(rhs)
    moving = np.arange(lam.size)
    for _ in range(30):
        old = lam[moving]
        new = old - (old**3 - old - rhs[moving]) / (3 * old**2 - 1)
        lam[moving] = new
        moving = moving[new != old]
    return lam


def build(config, alpha_deg, n_elements, kind="cable", formulation=None, remote_units=None,
          auxiliary=None, auxiliary_tension=None):
    """Build the baseline E-sail of Sect. 4.1 for sailing angle ``alpha_deg`` (deg) with
    ``n_elements`` elements per tether of ``kind`` ("cable" or "truss") in the
    ``formulation`` of ``Cable`` (None: the default; ``"paper"`` is the paper's own).

    The hub starts at the origin of I with body Euler angles ``(0, alpha - 90 deg, 0)``
    relative to O, all tethers radial in the hub mid-plane, stretched by the steady
    rotating-cable solution for the spin ``omega_0`` about ``X_B``, and the whole sail in
    rigid rotation (Eqs. 79-82).  The frame I is fixed, the Sun at ``-R0``.

    The full rig (``ring``): ``remote_units`` (a ``RemoteUnit``: its mass replaces
    ``config.remote_mass``) at the tips, and with ``auxiliary`` (a ``Section``) a ring of
    auxiliary tethers (law ``"tension-only"``) pinned to neighbouring tips, their
    reference length set so that the sail's steady spin under the wind holds them at
    ``auxiliary_tension`` (N; default ``AUXILIARY_SHARE``, half of a unit's centrifugal
    force ``m_u omega^2 L``; ``_ring_design``, ``RING_PASSES``).  The tethers' stretch is
    then that of the windless steady spin with the ring's pull on the tips
    (``ring.ring_tip_mass``), the start of ``build``.
    """
    if remote_units is not None:
        config = replace(config, remote_mass=remote_units.mass)
    config = config.validate()
    if auxiliary_tension is None:
        auxiliary_tension = AUXILIARY_SHARE * config.remote_mass * config.spin_rate**2 \
            * config.tether_length
    check_ring(auxiliary, auxiliary_tension, config.n_tethers)
    if auxiliary is None:
        return _build(config, alpha_deg, n_elements, kind, formulation,
                      remote_units=remote_units)
    target = auxiliary_tension
    for passes in range(RING_PASSES, 0, -1):
        length, free, steady = _ring_design(config, alpha_deg, n_elements, kind,
                                            formulation, auxiliary, target)
        scene = _build(config, alpha_deg, n_elements, kind, formulation,
                       remote_units=remote_units, auxiliary=auxiliary,
                       auxiliary_tension=auxiliary_tension, auxiliary_length=length)
        scene = replace(scene, facing=_facing_start(scene, free, steady))
        if passes > 1:
            found = auxiliary_tension_of(scene, steady_facing(scene)[0].q).mean()
            target *= auxiliary_tension / found
    return scene


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
           exponent=THRUST_EXPONENT, remote_units=None, auxiliary=None, auxiliary_tension=None,
           auxiliary_length=None):
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
    r, lam = _spin_stretch(cfg, s, auxiliary, auxiliary_length)
    tethers = []
    for i in range(p):
        e = C_I_B @ radial_B[i]
        cable = Cable(MeshLine(s), sec, r[:, None] * e, lam[:, None] * e,
                      law=kind, name=f"tether{i + 1}", formulation=formulation)
        tethers.append(cable)
    ring = [] if auxiliary is None else ring_cables(
        [r[-1] * (C_I_B @ e) for e in radial_B], auxiliary_length, auxiliary)
    system = System([hub, *tethers, *ring])
    for cable, x in zip(tethers, anchors):
        system.pin(cable.node(0), hub.point(x))
        system.add_point_mass(cable.node(-1), cfg.remote_mass)
    for i, cable in enumerate(ring):
        system.pin(cable.node(0), tethers[i].node(-1))
        system.pin(cable.node(-1), tethers[(i + 1) % p].node(-1))
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
                       "exponent": exponent, "remote_units": remote_units,
                       "auxiliary": auxiliary, "auxiliary_tension": auxiliary_tension,
                       "auxiliary_length": auxiliary_length},
                      ring)


def _spin_stretch(cfg, s, auxiliary, length):
    """Radius and stretch of a tether at the reference arc lengths ``s`` in the windless
    steady spin (``rotating_cable_stretch``): with a ring of auxiliary tethers of
    reference length ``length``, the tip mass is ``ring_tip_mass``'s at the tip radius,
    iterated to round-off."""
    sec = cfg.section
    mass, tip = cfg.remote_mass, cfg.hub_radius + cfg.tether_length
    for _ in range(50):
        if auxiliary is not None:
            tension = ring_tension(auxiliary, length, cfg.n_tethers, tip)
            mass = ring_tip_mass(cfg.remote_mass, auxiliary, length, tension, cfg.n_tethers,
                                 tip, cfg.spin_rate)
        r, lam = rotating_cable_stretch(s, cfg.hub_radius, cfg.tether_length, sec.EA,
                                        sec.mass_per_length, mass, cfg.spin_rate)
        done = abs(r[-1] - tip) <= 1e-14 * tip
        tip = r[-1]
        if done or auxiliary is None:
            break
    return r, lam


def _ring_design(cfg, alpha_deg, n_elements, kind, formulation, auxiliary, tension):
    """The auxiliary tethers' reference length that holds them at ``tension`` in the
    sail's steady spin under the wind (``steady_facing``: the tethers coned, the tips
    nearer the axis than in the windless spin), and that equilibrium without the ring.

    There the ring pulls each unit towards the axis in the plane of the tips, a change of
    its centrifugal force: the sail without the ring, its units of ``ring_tip_mass``, has
    the same equilibrium but for the axial inertia of that change of mass (the ring's
    pull is 3.1 % of a unit's centrifugal force in ``FULL_RIG``, on the sail's
    acceleration of about 1e-4 m/s^2).  The tips' distance from the axis is iterated
    (two passes hold it to 1e-12: the mass depends on it only through the pull).  Returns
    the length and the ringless sail with its equilibrium (``steady_facing``'s)."""
    p = cfg.n_tethers
    radius = cfg.hub_radius + cfg.tether_length
    for _ in range(3):
        length = ring_length(auxiliary, tension, p, radius)
        mass = ring_tip_mass(cfg.remote_mass, auxiliary, length, tension, p, radius,
                             cfg.spin_rate)
        free = _build(replace(cfg, remote_mass=mass), alpha_deg, n_elements, kind,
                      formulation)
        steady = steady_facing(free)
        radius = tip_spacing(free, steady[0].q).mean() / (2 * np.sin(np.pi / p))
    return ring_length(auxiliary, tension, p, radius), free, steady


def _facing_start(scene, free, steady):
    """The start of ``steady_facing`` for the ringed ``scene``: the ringless ``free``
    sail's equilibrium ``steady`` (``_ring_design``), each auxiliary tether's nodes on
    the tips it joins."""
    state, _ = steady
    system = scene.system
    q, v = np.zeros(system.n_dofs), np.zeros(system.n_dofs)
    for mine, theirs in zip([scene.hub, *scene.tethers], [free.hub, *free.tethers]):
        q[system.dofs(mine)] = state.q[free.system.dofs(theirs)]
        v[system.dofs(mine)] = state.v[free.system.dofs(theirs)]
    p = len(scene.tethers)
    for i, cable in enumerate(scene.auxiliary):
        ends = [free.system.dofs(free.tethers[k].node(-1))[:3] for k in (i, (i + 1) % p)]
        q[system.dofs(cable)] = state.q[np.concatenate(ends)]
        v[system.dofs(cable)] = state.v[np.concatenate(ends)]
    return State(system, q, v=v)


#: ``settled``'s relaxation: steps of this share of a spin period (4 deg of spin) ...
SETTLE_STEP = 1.0 / 90.0
#: ... over this many spin periods (4.4 h for ``FULL_SIZE``).  Measured on ``FULL_SIZE``
#: (the start in modified Newton, then a day of adaptive steps with the local error held
#: to 1e-5, two threads): 5.5 periods of 1/180 took 6.2 s, then 3933 steps; these 5.4 s,
#: then 3466 steps (3 of 1/180: 3.9 s, then 4001 steps; 5.5 of 1/45: 9.3 s, then 3262;
#: longer relaxation steps need more Newton iterations).  Now (full Newton, ``settle``'s
#: default; ``MISSION_RTOL``): 4.4 s, then 3284 steps.
SETTLE_SPINS = 3.0


def steady_facing(scene):
    """The relative equilibrium of ``scene`` (I fixed) turned to face the wind: its spin
    axis turned by ``R`` onto the wind line, where the wind is constant in the spinning
    frame (``solve_steady``: the tethers coned, the sail accelerating along the axis).
    Starts from ``scene.facing`` if it has one (a ringed sail's), else from its initial
    state turned.  Returns the steady state (in the turned frame) and ``R``."""
    system, initial = scene.system, scene.initial
    axis = scene.hub.rotation(initial.q[system.dofs(scene.hub)])[:, 0]
    R = _facing(axis, scene.R0 / np.linalg.norm(scene.R0))  # the wind blows from the Sun
    turned = scene.facing if scene.facing is not None else \
        State(system, system.rotate(initial.q, R), v=system.rotate(initial.v, R))
    return solve_steady(system, scene.config.spin_rate * (R @ axis), initial=turned), R


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
    system = scene.system
    # on an orbit the Sun line turns and the Sun's tides act: the equilibrium is that of
    # the sail fixed at the orbit's start, the rest is left to the relaxation
    fixed = scene if scene.orbit is None else _build(
        replace(scene.config, R0=tuple(scene.R0)), np.degrees(scene.alpha), **scene.options)
    steady, R = steady_facing(fixed)
    start = State(system, system.rotate(steady.q, R.T), v=system.rotate(steady.v, R.T))
    period = scene.config.spin_period
    duration = spins * period
    state = settle(system, duration, SETTLE_STEP * period, initial=start, t_start=-duration)
    return replace(scene, initial=State(system, state.q, state.lam, v=state.v, t=0.0))
