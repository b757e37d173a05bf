"""An E-sail deploys its tethers under the solar wind: its spin follows the angular momentum.

Physics
-------
The hub of the paper's baseline sail (a cylinder of 1 m radius and 2 m height, density
884: 5.6 t) spins about its axis and pays out four of its aluminium tethers (4.28e-9 m^2,
E = 70 GPa, density 7653: 33 mg/m) with their 1.5 kg remote units, from 300 m to 1 km
along a smooth (quintic) length profile in 2000 s (``System.deploy`` with a prescribed
length), then holds them for 1600 s.  Each tether leaves through an exit guide that turns
with the hub (``direction`` in the hub's body frame: ``constraints.BodySlope``), and the
tether still on the reel rides with the hub (``capacity``, 1200 m per reel).  The
tethers are at 20 kV and the solar wind blows along the spin axis (sailing angle
``alpha = 0``; the Sun at ``-R0`` as in ``esail.build``): the Coulomb drag
(``SolarWindForce``, 0.45 mN/km, per unit of deployed material) pushes every tether along
the axis, and the sail cones by the angle at which the centrifugal stiffness balances it.
Gravity is off.

Nothing acts about the spin axis (the wind is axial), so the angular momentum ``H`` about
it is conserved while the moment of inertia grows 11 times: the spin drops from
0.044 rad/s (a 142 s period) to 4.0e-3 rad/s, the paper's.  The start is chosen for that
end: the tethers must stay taut, and the margin is smallest at the end (the centrifugal
pull ``m omega^2 r`` on a remote unit falls as ``1 / l^3`` while the drag ``f l`` on its
tether grows as ``l``): at 1 km the pull, 24 mN, is 54 times the drag.  The remote units
carry 99 % of the inertia and each keeps its own angular momentum, so the fan of tethers
lags the exit guides by 0.7 degrees at most.

The reference is independent of the finite elements: ``H`` at the start divided by the
moment of inertia of the deployed sail turning steadily at the rate sought -- the hub,
the reels' content at the rim, and four radial tethers stretched by the rotating string
(``esail.rotating_cable_stretch``) with their remote units, coned by the rigid-tether
estimate ``gamma = f l^2 / (2 omega^2 (m l (R + l) + mu (R l^2 / 2 + l^3 / 3)))`` (0.53
degrees: 8e-5 of the inertia) -- solved for the rate by secant iterations.  The run's
rate is the angle the remote units turn through in the last turn of the hold, over its
time: the coning oscillates about its steady angle (0.33 to 0.66 degrees) with the
period of the spin, and the hub librates against the fan through the exit guides
(+-3.5e-4 of its rate), so an average over one turn measures the mean spin.  The thrust
at the end is checked against that of four straight radial tethers of 1 km
(``straight_thrust``: ``4 f l`` along the axis at ``alpha = 0``).

The run starts in the steady rotating state of the 300 m tethers without wind (nodes on
the rotating string's radii, slopes stretched by its strain, 0.3 % at 0.89 N; rigid
rotation): only the wind's coning starts as a transient, of 0.008 degrees.  Steps are
``omega_0 dt = 0.05`` (1.13 s).  Generalized-alpha (``rho_inf = 0.8``) does not conserve
``H`` exactly: the deploying tethers make it grow by 6.4e-4, 96 % of it in the first
1000 s where the spin is fast and the tethers pay out fast (second order in the step:
1.6e-4 at half the step).  This drift is most of the difference between the measured and
the predicted rate, 6.6e-4; with ``H`` at the end the two agree to 2e-5.

The tethers are undamped, unlike the paper's (Kelvin-Voigt, 1 s): a damped law on a
deploying cable is refused, because on the stretching mesh its damping would take the
mesh's stretching ``l' / l`` for a strain rate (``docs/deploy.md``).

``main`` returns the measured and predicted spin rates and their relative differences,
the drift of ``H``, the thrust and its reference, the taut margin, the tension at
mid-tether and the coning at the end, and the run.  Run ``python
demos/esail_deployment.py [ANIMATION.gif] [FIGURE.png]`` (about 35 s, a minute with the
pictures).
"""

from dataclasses import replace

import numpy as np
from scipy.optimize import root_scalar

import skfem_cable as sc
from skfem_cable.constraints.deploy import smooth_profile
from skfem_cable.scenes import esail
from skfem_cable.space.frames import dcm_321, orbit_frame

CONFIG = esail.BaselineConfig()                  # the paper's Table 1
HUB_RADIUS, REMOTE_MASS = CONFIG.hub_radius, CONFIG.remote_mass
F_WIND = CONFIG.wind.force_per_length(20e3)     # 4.49e-7 N/m across the wind at 20 kV


def section():
    """The paper's tether section, undamped (deploying cables take no damping)."""
    return replace(CONFIG.section, gamma_axial=0.0, gamma_bending=0.0)


def sail_rotation(alpha):
    """``C_I_B`` of the hub at the sailing angle ``alpha`` (deg), as ``esail.build``: the
    spin axis ``X_B`` at ``alpha`` from the Sun line."""
    C_B_O = dcm_321(0.0, np.deg2rad(alpha) - np.pi / 2, 0.0)
    return orbit_frame(np.asarray(CONFIG.R0)) @ C_B_O.T


def coning_estimate(length, omega, force=F_WIND):
    """Coning angle (rad) of a rigid tether of ``length`` (m) with its remote unit at the
    hub rim, spinning at ``omega`` (rad/s) under the drag ``force`` (N/m) along the axis:
    the drag's moment about the root over the centrifugal one per radian."""
    mu, R, m = CONFIG.section.mass_per_length, HUB_RADIUS, REMOTE_MASS
    stiffness = omega**2 * (m * length * (R + length) + mu * (R * length**2 / 2 + length**3 / 3))
    return force * length**2 / (2 * stiffness)


def spin_inertia(length, omega, n_tethers, capacity, hub_inertia, coning=0.0, points=64):
    """Moment of inertia (kg m^2) about the spin axis of the hub, the reels' content at
    the rim and ``n_tethers`` tethers of free ``length`` (m) with their remote units in
    the steady rotating state at ``omega`` (rad/s; 0: unstretched), coned by ``coning``
    (rad): Gauss-Legendre rule on ``points`` points along the rotating string."""
    sec = section()
    mu, R = sec.mass_per_length, HUB_RADIUS
    x, w = np.polynomial.legendre.leggauss(points)
    s = np.append(0.5 * length * (x + 1), length)
    r = R + s if omega == 0 else \
        esail.rotating_cable_stretch(s, R, length, sec.EA, mu, REMOTE_MASS, omega)[0]
    r = R + (r - R) * np.cos(coning)                  # distance from the axis
    tether = 0.5 * length * mu * (w @ r[:-1] ** 2) + REMOTE_MASS * r[-1] ** 2
    return hub_inertia + n_tethers * (tether + mu * (capacity - length) * R**2)


def predicted_rate(H, length, n_tethers, capacity, hub_inertia, guess, force=F_WIND):
    """The rate (rad/s) at which the deployed sail of ``spin_inertia`` (coned by
    ``coning_estimate`` under ``force``) has the angular momentum ``H``: secant
    iterations to 1e-13 relative."""
    def excess(w):
        coning = coning_estimate(length, w, force)
        return spin_inertia(length, w, n_tethers, capacity, hub_inertia, coning) * w - H

    return root_scalar(excess, x0=guess, x1=guess * (1 + 1e-4), method="secant", xtol=1e-300,
                       rtol=1e-13).root


def build(l0=300.0, l1=1000.0, duration=2000.0, n_elements=6, n_tethers=4,
          final_spin=4e-3, capacity=1200.0, voltage=20e3, alpha=0.0):
    """The hub and its tethers deploying from ``l0`` to ``l1`` (m) in ``duration`` s,
    spinning at the rate ``omega0`` that leaves the unstretched radial sail at
    ``final_spin`` (rad/s), in its steady rotating state at ``l0``.

    Returns
    -------
    dict
        ``system``, ``hub``, ``tethers``, ``wind`` (the ``SolarWindForce``), ``axis``
        (the spin axis in I), ``omega0``, ``initial`` (the ``State``), ``length`` (the
        profile ``(l, l', l'')``).
    """
    C_I_B = sail_rotation(alpha)
    hub = sc.RigidBody.cylinder(HUB_RADIUS, CONFIG.hub_height, CONFIG.hub_density,
                                rotation=C_I_B, name="hub")
    I_hub = hub.inertia[0, 0]
    omega0 = final_spin * (spin_inertia(l1, 0.0, n_tethers, capacity, I_hub)
                           / spin_inertia(l0, 0.0, n_tethers, capacity, I_hub))
    sec = section()
    s = np.linspace(0.0, l0, n_elements + 1)
    r, lam = esail.rotating_cable_stretch(s, HUB_RADIUS, l0, sec.EA, sec.mass_per_length,
                                          REMOTE_MASS, omega0)
    length = smooth_profile(l0, l1, duration)
    mesh = sc.Cable.straight([0, 0, 0], [l0, 0, 0], n_elements, sec).mesh
    zeta = 2 * np.pi * np.arange(n_tethers) / n_tethers
    radial_B = np.column_stack([np.zeros(n_tethers), np.cos(zeta), np.sin(zeta)])
    tethers = [sc.Cable(mesh, sec, r[:, None] * (C_I_B @ e), lam[:, None] * (C_I_B @ e),
                        name=f"tether{i + 1}") for i, e in enumerate(radial_B)]
    system = sc.System([hub, *tethers])
    for tether, e in zip(tethers, radial_B):
        system.deploy(tether, hub.point(HUB_RADIUS * e), *length, capacity=capacity,
                      direction=e)
        system.add_point_mass(tether.node(-1), REMOTE_MASS)
    wind = sc.SolarWindForce(tethers, voltage, CONFIG.wind, sun_position=-np.asarray(CONFIG.R0))
    system.add_load(wind)
    axis = C_I_B[:, 0]
    v = system.rigid_motion_velocity(system.q0, omega0 * axis)
    return {"system": system, "hub": hub, "tethers": tethers, "wind": wind, "axis": axis,
            "omega0": omega0, "initial": sc.State(system, system.q0, v=v), "length": length}


def wind_force(system, wind, q, t):
    """Resultant (N) of the Coulomb drag on the tethers at coordinates ``q`` and time
    ``t``: ``int f (iR - (t . iR) t) ds`` over the deployed material (``ds = lam dx``)."""
    total = np.zeros(3)
    coef = wind.coefficients(t)
    for k, cable in enumerate(wind.cables):
        qe = q[system.dofs(cable)][cable.element_dofs].reshape(-1, 4, 3)
        r = np.einsum("egA,eAi->egi", cable.S, qe)
        a = np.einsum("egA,eAi->egi", cable.Sx, qe)
        iR = r - wind.sun
        iR /= np.linalg.norm(iR, axis=-1, keepdims=True)
        a /= np.linalg.norm(a, axis=-1, keepdims=True)
        f = iR - np.einsum("egi,egi->eg", a, iR)[..., None] * a
        weight = coef[k] * cable.weights * system.stretch(cable, t)
        total += np.einsum("eg,egi->i", weight, f)
    return total


def straight_thrust(wind, centre, axis, n_tethers, length, voltage):
    """Thrust (N) of ``n_tethers >= 3`` straight radial tethers of ``length`` (m), evenly
    spaced in the spin plane of ``axis`` at ``centre``: each pushed by ``f (iR - (t . iR)
    t)``, whose sum over the tethers is ``n f l (iR_a + iR_p / 2)`` with ``iR_a``, ``iR_p``
    the parts of the wind direction ``iR`` along and across the axis (the sum of
    ``cos^2`` of the azimuths is ``n / 2``)."""
    iR = (centre - wind.sun) / np.linalg.norm(centre - wind.sun)
    along = (iR @ axis) * axis
    return n_tethers * wind.wind.force_per_length(voltage) * length * (along + (iR - along) / 2)


def azimuth(points, centre, axis, reference):
    """Unwrapped rotation angle (rad) about ``axis`` through ``centre`` (nt, 3) of each of
    the ``points`` (nt, k, 3) of a run's saved steps, from the direction ``reference`` (normal to
    ``axis``): the saved steps must be less than half a turn apart."""
    e1 = reference / np.linalg.norm(reference)
    e2 = np.cross(axis, e1)
    rel = points - centre[:, None]
    return np.unwrap(np.arctan2(rel @ e2, rel @ e1), axis=0)


def main(l0=300.0, l1=1000.0, duration=2000.0, hold=1600.0, average=None, n_elements=6,
         n_tethers=4, final_spin=4e-3, spin_step=0.05, capacity=1200.0, voltage=20e3,
         alpha=0.0, every=5):
    """Deploy from ``l0`` to ``l1`` (m) in ``duration`` s and hold ``hold`` s, in steps
    ``dt = spin_step / omega0``; rates are averaged over the last ``average`` s (default:
    one turn at ``final_spin``, the period of the coning oscillation).

    Returns
    -------
    dict
        ``measured``: the sail's spin rate over the last ``average`` s, the angle the
        remote units turned through over the time (rad/s); ``hub_measured``: the same of
        the hub; ``predicted``: the rate of the deployed sail with the initial angular
        momentum (``predicted_rate``); ``difference``: the relative difference of
        ``measured`` and ``predicted``, ``hub_difference`` that of the hub, and
        ``residual`` that of ``measured`` and the rate predicted from the angular momentum
        at the end (the model's part, without the integrator's drift);
        ``momentum_drift``: the largest relative change of the angular momentum about the
        spin axis; ``thrust``, ``thrust_expected`` (3-vectors, N): the drag's resultant
        at the end and that of straight tethers (``straight_thrust``), and the norm of
        their difference relative to the latter, ``thrust_difference``; ``taut_margin``:
        the centrifugal pull on a remote unit over the drag on its tether at the end;
        ``tension``, ``tension_expected`` (N): at mid-tether at the end and on the
        rotating string; ``coning_deg``: the remote units' mean coning at the end and
        ``coning_estimate_deg``; ``omega0``, ``dt``, ``wall_time`` (s); ``t``,
        ``hub_rate``, ``fan_rate`` (rad/s), ``fan_angle`` (rad), ``H``, ``result``,
        ``system``, ``tethers``, ``wind``, ``hub``.
    """
    scene = build(l0, l1, duration, n_elements, n_tethers, final_spin, capacity, voltage,
                  alpha)
    system, hub, tethers, axis = scene["system"], scene["hub"], scene["tethers"], scene["axis"]
    dt = spin_step / scene["omega0"]
    average = 2 * np.pi / final_spin if average is None else average
    r = sc.simulate(system, t_end=duration + hold, dt=dt, rho_inf=0.8,
                    initial=scene["initial"], every=every)
    H = np.array([system.angular_momentum(q, v, t=t) @ axis
                  for q, v, t in zip(r.q, r.v, r.t)])
    d = system.dofs(hub)
    centre = hub.positions(r.q[:, d], np.zeros(3))
    tips = np.stack([r.q[:, system.dofs(c)[-6:-3]] for c in tethers], axis=1)
    reference = hub.rotation(r.q[0, d])[:, 1]
    fan = azimuth(tips, centre, axis, reference).mean(axis=1)
    rim = azimuth(hub.positions(r.q[:, d], np.array([[0.0, 1.0, 0.0]])), centre, axis,
                  reference)[:, 0]
    start = int(np.searchsorted(r.t, r.t[-1] - average))
    span = r.t[-1] - r.t[start]
    measured = float((fan[-1] - fan[start]) / span)
    hub_measured = float((rim[-1] - rim[start]) / span)
    force = F_WIND * np.cos(np.deg2rad(alpha))
    predicted, settled = (predicted_rate(h, l1, n_tethers, capacity, hub.inertia[0, 0],
                                         measured, force) for h in (H[0], H[-1]))
    history = np.array([wind_force(system, scene["wind"], q, t) for q, t in zip(r.q, r.t)])
    thrust = history[-1]
    lengths = scene["length"][0](r.t)
    quasi_steady = H[0] / np.array([spin_inertia(ell, 0.0, n_tethers, capacity,
                                                 hub.inertia[0, 0]) for ell in lengths])
    expected = straight_thrust(scene["wind"], centre[-1], axis, n_tethers, l1, voltage)
    tips_B = (tips[-1] - centre[-1]) @ hub.rotation(r.q[-1, d])
    coning = np.rad2deg(np.arctan2(tips_B[:, 0], np.hypot(tips_B[:, 1], tips_B[:, 2])))
    sec = section()
    _, lam = esail.rotating_cable_stretch(np.array([0.5 * l1]), HUB_RADIUS, l1, sec.EA,
                                          sec.mass_per_length, REMOTE_MASS, predicted)
    return {"measured": measured, "hub_measured": hub_measured, "predicted": predicted,
            "difference": abs(measured / predicted - 1),
            "hub_difference": abs(hub_measured / predicted - 1),
            "residual": abs(measured / settled - 1),
            "momentum_drift": float(np.abs(H / H[0] - 1).max()),
            "thrust": thrust, "thrust_expected": expected,
            "thrust_difference": float(np.linalg.norm(thrust - expected)
                                       / np.linalg.norm(expected)),
            "taut_margin": REMOTE_MASS * measured**2 * (HUB_RADIUS + l1)
            / (CONFIG.wind.force_per_length(voltage) * l1),
            "tension": float(np.mean([r.tension(c, 0.5 * c.length)[-1] for c in tethers])),
            "tension_expected": float(sec.EA * (lam[0] ** 2 - 1) * lam[0] / 2),
            "coning_deg": float(coning.mean()),
            "coning_estimate_deg": float(np.rad2deg(coning_estimate(l1, predicted, force))),
            "omega0": scene["omega0"], "dt": dt, "wall_time": r.stats["wall_time"],
            "thrust_history": history, "thrust_straight": np.outer(
                lengths / l1, expected), "quasi_steady": quasi_steady, "lengths": lengths,
            "t": r.t, "hub_rate": hub.angular_velocity(r.q[:, d], r.v[:, d])[:, 0],
            "fan_rate": np.gradient(fan, r.t), "fan_angle": fan, "H": H, "result": r,
            "system": system, "tethers": tethers, "wind": scene["wind"], "hub": hub}


def figure(out, path):
    """The spin rates of the hub and of the remote units against ``H0 / I(l)`` (the
    unstretched radial sail), and the thrust against that of straight tethers, over the
    run: a PNG at ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = out["t"]
    fig, (left, right) = plt.subplots(1, 2, figsize=(7.5, 3.0), layout="constrained")
    left.semilogy(t, out["hub_rate"], label="hub")
    left.semilogy(t, out["fan_rate"], "--", label="remote units")
    left.semilogy(t, out["quasi_steady"], "k:", label="$H_0 / I(l)$")
    left.set(xlabel="t [s]", ylabel="spin rate [rad/s]")
    left.set_title(f"spin: {out['measured']:.5e} rad/s at the end,\n"
                   f"predicted {out['predicted']:.5e} (H drift {out['momentum_drift']:.0e})",
                   fontsize=9)
    left.legend(fontsize=8)
    right.plot(t, 1e3 * np.linalg.norm(out["thrust_history"], axis=1), label="run")
    right.plot(t, 1e3 * np.linalg.norm(out["thrust_straight"], axis=1), "k:",
               label="straight tethers")
    right.set(xlabel="t [s]", ylabel="thrust [mN]")
    right.set_title(f"thrust at the end: {1e3 * np.linalg.norm(out['thrust']):.4f} mN\n"
                    f"(straight tethers: {1e3 * np.linalg.norm(out['thrust_expected']):.4f})",
                    fontsize=9)
    right.legend(fontsize=8)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


def animation(out, path, degrees=30.0, window_size=(640, 480)):
    """Animate the run seen along the spin axis (``plot.animate``, view ``"axial"``), one
    frame each time the remote units have turned ``degrees`` further: the fast turns at
    the start are not aliased by the four-fold symmetry of the sail, and the slow ones
    at the end are not drawn many times.  Returns the number of frames."""
    from skfem_cable import plot
    from skfem_cable.core.records import FIELDS

    r = out["result"]
    turned = out["fan_angle"] - out["fan_angle"][0]
    targets = np.arange(0.0, turned[-1], np.deg2rad(degrees))
    idx = np.unique(np.append(np.abs(turned[None] - targets[:, None]).argmin(axis=1),
                              len(r) - 1))
    frames = sc.Result(r.system, {name: getattr(r, name)[idx] for name in FIELDS})
    return plot.animate(frames, path, every=1, max_frames=len(idx), view="axial",
                        window_size=window_size,
                        title=f"E-sail deploying {len(out['tethers'])} tethers "
                              f"({out['lengths'][0]:.0f} m -> {out['lengths'][-1]:.0f} m), "
                              f"a frame every {degrees:g} deg")


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: ``figure`` of a run
    of ``main``."""
    figure(main(), path)


if __name__ == "__main__":
    import sys

    out = main()
    print(f"spin after deployment {out['measured']:.6e} rad/s, predicted from H "
          f"{out['predicted']:.6e} rad/s (relative difference {out['difference']:.1e}, "
          f"{out['residual']:.0e} from the final H); angular momentum drift "
          f"{out['momentum_drift']:.1e}; thrust {1e3 * np.linalg.norm(out['thrust']):.4f} mN "
          f"(straight tethers {1e3 * np.linalg.norm(out['thrust_expected']):.4f} mN); "
          f"taut margin {out['taut_margin']:.0f}; {out['wall_time']:.0f} s")
    for path in sys.argv[1:]:
        if path.endswith(".png"):
            figure(out, path)
        else:
            animation(out, path)
