"""Pitch and roll librations of a tethered satellite system in a circular Earth orbit.

Physics
-------
Two 100 kg satellites on a stiff, nearly massless 20 km tether fly a circular 400 km
orbit (mean motion ``n = 1.1316e-3 rad/s``, period 92.6 min); the scene is
``skfem-cable run tss`` (``skfem_cable.scenes.tss``).  In the orbiting (LVLH) frame the
central body's gravity gradient and the centrifugal force hold the tether along the local
vertical, under a tension of ``3 n^2 L m1 m2 / (m1 + m2) = 3.84 N``.  Turned out of the
vertical, it librates like a rigid dumbbell (Beletsky & Levin, *Dynamics of Space Tether
Systems*, 1993):

* pitch (in the orbit plane): ``theta'' + 3 n^2 sin(theta) cos(theta) = 0``, at
  ``sqrt(3) n`` for small angles (period 53.4 min), and
* roll (out of the plane): ``phi'' + 4 n^2 sin(phi) cos(phi) = 0``, at ``2 n`` (46.3 min).

Both are pendulums in the doubled angle, so an amplitude ``a`` lowers the frequency by
``(2 a)^2 / 16``: 6.25e-4 for the 0.05 rad pitch offset the run starts from, together
with a 0.03 rad roll offset, at rest in the orbiting frame (the steady state of
``solve_steady`` at the orbit's rate, turned).  The ANCF model, 8 elements and 200 time
steps per pitch period, finds the pitch frequency within 3e-4 of ``sqrt(3) n`` so
corrected, measured from the zero crossings over three pitch periods.  The roll comes out
within 1e-5 of ``2 n``: its own amplitude correction (-2.3e-4) is offset by its
second-order coupling to the pitch (with no pitch offset the run finds 1.99952 n against
the corrected 1.99955 n).  The render is drawn in the orbiting frame
(``frame="lvlh"``, as ``skfem-cable run tss --frame lvlh`` writes its ParaView series):
there the librating tether swings about the fixed local vertical instead of turning once
per orbit.

Run ``python demos/tss_libration.py [--periods P] [--figure PNG] [--render PNG]``.
"""

import argparse

import numpy as np

import skfem_cable as sc
from skfem_cable import plot
from skfem_cable.scenes import tss


def expected_frequency(rate, amplitude):
    """Frequency (over ``n``) of the libration ``x'' + rate^2 sin(x) cos(x) = 0`` of
    amplitude ``amplitude`` (rad), to second order: ``rate (1 - (2 amplitude)^2 / 16)``."""
    return rate * (1 - (2 * amplitude) ** 2 / 16)


def main(elements=8, periods=3.0, steps_per_period=200, figure=None, render=None):
    """Run ``periods`` pitch periods of the ``tss`` scene; returns the measured pitch and
    roll frequencies over ``n`` with their expected values (and the run)."""
    scene = tss.scene(elements=elements, periods=periods, steps_per_period=steps_per_period,
                      every=1)
    settings = {k: v for k, v in scene.settings.items() if k != "series_every"}
    result = sc.simulate(scene.system, initial=scene.initial, **settings)
    orbit, cable = scene.system.orbit, scene.system.cables()[0]
    pitch, roll = tss.attitude(orbit, cable, result.t, result.q)
    n = orbit.mean_motion
    out = {"pitch_frequency": tss.crossing_frequency(result.t, pitch) / n,
           "pitch_expected": expected_frequency(np.sqrt(3.0), tss.PITCH),
           "roll_frequency": tss.crossing_frequency(result.t, roll) / n,
           "roll_expected": 2.0,
           "pitch_max": np.abs(pitch).max(), "roll_max": np.abs(roll).max()}
    if figure:
        plot_librations(result.t * n / (2 * np.pi), pitch, roll, out, figure)
    if render:
        last = len(result) - steps_per_period + np.argmax(np.abs(pitch[-steps_per_period:]))
        plot.render(scene.system, result.state(last), render, frame="lvlh",
                       window_size=(640, 640),
                       title=f"orbiting frame, t = {result.t[last] / 60:.1f} min, "
                             f"pitch {np.degrees(pitch[last]):+.2f} deg")
    return {**out, "result": result}


def plot_librations(orbits, pitch, roll, out, path):
    """Pitch and roll (deg) against time (orbits), each with the rigid dumbbell's
    small-amplitude libration (dashed) and ticks at its periods."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 1, figsize=(7.0, 4.4), sharex=True, layout="constrained")
    rows = ((axes[0], pitch, "pitch", np.sqrt(3.0), "sqrt(3) n", "C0"),
            (axes[1], roll, "roll", 2.0, "2 n", "C1"))
    for ax, angle, name, rate, label, colour in rows:
        rigid = np.degrees(angle[0]) * np.cos(rate * 2 * np.pi * orbits)
        ax.plot(orbits, np.degrees(angle), colour, lw=1.6, label="ANCF cable")
        ax.plot(orbits, rigid, "k--", lw=0.8, label=f"rigid dumbbell, {label}")
        for k in range(1, int(orbits[-1] * rate) + 1):
            ax.axvline(k / rate, color="0.6", lw=0.6, ls=":")
        ax.set_ylabel(f"{name} [deg]")
        ax.set_title(f"{name}: {out[name + '_frequency']:.5f} n measured, "
                     f"{out[name + '_expected']:.5f} n expected; dotted: periods "
                     f"2 pi / ({label})", fontsize=9)
        ax.legend(fontsize=8, loc="upper right", ncol=2)
        ax.set_ylim(np.array(ax.get_ylim()) * 1.6)
    axes[1].set_xlabel("t [orbits]")
    fig.savefig(path, dpi=90)
    plt.close(fig)


def gallery_figure(path, render=None):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: pitch and roll over
    three pitch periods (``main``'s figure); with ``render``, the render of the largest
    pitch of the last period in the orbiting frame there too."""
    main(figure=path, render=render)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--periods", type=float, default=3.0, help="pitch periods to run")
    parser.add_argument("--figure", default=None, help="PNG of pitch and roll")
    parser.add_argument("--render", default=None, help="PNG of the tether, orbiting frame")
    args = parser.parse_args()
    numbers = main(periods=args.periods, figure=args.figure, render=args.render)
    for key, value in numbers.items():
        if key != "result":
            print(f"{key:>16s}: {value:.8g}")
