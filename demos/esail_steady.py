"""Steady coning of the E-sail under a constant solar wind, without pre-simulation.

Physics
-------
The baseline sail of Pacheco-Ramos et al. (Table 1: a 2 m hub, twelve 10 km aluminium
tethers with 1.5 kg remote units, 20 kV, spin 4e-3 rad/s) faces the Sun (sailing angle
0): the solar wind blows along the spin axis, so in the frame spinning with the sail it is
constant.  The sail then has a relative equilibrium: every tether cones out of the spin
plane by the angle at which the centrifugal stiffness balances the Coulomb drag (0.49 deg),
while the whole sail accelerates along the axis under the thrust (54 mN on 5.6 t).

``sc.solve_steady`` finds that state directly: statics in the rotating frame (elastic,
centrifugal and Coulomb forces), with two gauge conditions for the free-floating sail
(the axial position of the centre of mass, whose multiplier is the thrust, and the phase
of the rotation, whose multiplier, a torque about the axis, vanishes).  A dynamic run
started from it (generalized-alpha, rho_inf = 0.8) must stay there: its coning angle
averages to the steady one and deviates from it only by the integrator's noise, and its
centre of mass accelerates at the steady state's frame acceleration.  A run from the
usual start (tethers in the spin plane, ``esail.build``'s initial state) swings about the
same angle with the full coning amplitude instead.

Run ``python demos/esail_steady.py [--periods P] [--figure PNG]``.
"""

import argparse

import numpy as np

import skfem_cable as sc
from skfem_cable.scenes import esail


def steady_state(elements=5, alpha=0.0):
    """The sail of ``esail.build`` and its relative equilibrium (``solve_steady`` about the
    hub's axis through the hub centre, from the built state)."""
    cfg = esail.BaselineConfig()
    scene = esail.build(cfg, alpha_deg=alpha, n_elements=elements, kind="cable")
    system = scene.system
    C_I_B = scene.hub.rotation(system.q0[system.dofs(scene.hub)])
    omega = C_I_B @ np.array([cfg.spin_rate, 0.0, 0.0])
    return scene, sc.solve_steady(system, omega, center=np.zeros(3), initial=scene.initial)


def axial_acceleration(scene, result, axis):
    """Mean acceleration (m/s^2) of the centre of mass along ``axis`` over the run: the
    least-squares slope of its velocity ``U^T M v / m``."""
    system = scene.system
    U = system.rigid_motion_velocity(system.q0, (0, 0, 0), velocity=axis)
    MU = system.mass_matrix() @ U
    speed = result.v @ MU / (U @ MU)
    return float(np.polyfit(result.t, speed, 1)[0])


def main(elements=5, periods=2.0, dt=2.0, figure=None):
    """Solve the steady state, run ``periods`` spin periods from it and from the usual
    start; returns the key numbers (angles in degrees) as a dict."""
    scene, steady = steady_state(elements)
    cfg = scene.config
    runs = {}
    for name, initial in (("steady", steady), ("usual", scene.initial)):
        result = sc.simulate(scene.system, t_end=periods * cfg.spin_period, dt=dt,
                             rho_inf=0.8, initial=initial, every=5)
        runs[name] = (result, np.rad2deg(esail.outputs(scene, result)["coning"]))
    result, coning = runs["steady"]
    steady_coning = float(coning[0].mean())
    a = steady.stats["frame_acceleration"]
    out = {"steady_coning": steady_coning,
           "run_mean_coning": float(coning.mean()),
           "run_deviation": float(np.abs(coning - coning[0]).max()),
           "usual_deviation": float(np.abs(runs["usual"][1] - steady_coning).max()),
           "frame_acceleration": float(np.linalg.norm(a)),
           "run_acceleration": axial_acceleration(scene, result, a / np.linalg.norm(a)),
           "phase_torque": steady.stats["phase_torque"],
           "newton_iterations": int(sum(steady.stats["iterations"]))}
    if figure:
        plot_coning(runs, steady_coning, cfg.spin_period, figure)
    return out


def plot_coning(runs, steady_coning, period, path):
    """Mean coning angle of the tethers over time, from the steady state and from the usual
    start, with the steady value."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 3.4), constrained_layout=True)
    for name, label in (("usual", "from the usual start (tethers in the spin plane)"),
                        ("steady", "from the steady state (solve_steady)")):
        result, coning = runs[name]
        ax.plot(result.t / period, coning.mean(axis=1), label=label)
    ax.axhline(steady_coning, color="k", ls=":", lw=1, label="steady coning angle")
    ax.set_xlabel("t / spin period")
    ax.set_ylabel("coning angle (deg)")
    ax.set_ylim(top=1.45 * ax.get_ylim()[1])
    ax.legend(fontsize=8, loc="upper center")
    fig.savefig(path, dpi=120)
    plt.close(fig)


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the coning angle over
    two spin periods from the steady state and from the usual start (``main``'s
    figure)."""
    main(figure=path)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--periods", type=float, default=2.0, help="spin periods to run")
    parser.add_argument("--figure", default=None, help="PNG of the coning angle")
    args = parser.parse_args()
    for key, value in main(periods=args.periods, figure=args.figure).items():
        print(f"{key:>20s}: {value:.10g}")
