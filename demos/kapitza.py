"""A driven constraint: Kapitza's pendulum, stable upside down on a shaking pivot.

A stiff steel rod (length ``l = 1 m``, radius 2 cm) is pinned at its lower end to a pivot
that oscillates vertically, ``y_p(t) = a cos(w t)`` (``System.pin(node, target=...)`` with
a callable target), under gravity ``g`` along ``-y``.  Started at rest, tilted by
``theta_0 = 0.1 rad`` from the upward vertical, it falls over unless the shaking is strong
enough.  For a rigid uniform rod (``k = m d / I = 3 / (2 l)``) the angle from the upward
vertical obeys, in the pivot's frame,

    theta'' = k (g - a w^2 cos(w t)) sin(theta),

and the inverted position is stable when the linear Mathieu equation
``theta'' = k (g - a w^2 cos w t) theta`` is: the monodromy matrix over one period has
``|trace| < 2``.  For fast shaking this is Kapitza's ``a^2 w^2 > 2 g / k = 4 g l / 3``;
``threshold`` computes the exact boundary by bisection on the trace (Floquet), the
independent reference.  The demo runs the ANCF rod at ``a`` a little above and a little
below that amplitude and returns the largest tilt.

Run ``python demos/kapitza.py``.
"""

import numpy as np
from scipy.integrate import solve_ivp

import skfem_cable as sc

G = 9.81
LENGTH = 1.0


def floquet_trace(a, omega, k=1.5 / LENGTH, g=G):
    """Trace of the monodromy matrix of ``theta'' = k (g - a w^2 cos w t) theta``."""

    def rhs(t, y):
        c = k * (g - a * omega**2 * np.cos(omega * t))
        return [y[1], c * y[0], y[3], c * y[2]]

    T = 2 * np.pi / omega
    y = solve_ivp(rhs, (0, T), [1.0, 0.0, 0.0, 1.0], method="DOP853", rtol=1e-12,
                  atol=1e-14).y[:, -1]
    return y[0] + y[3]


def threshold(omega, k=1.5 / LENGTH, g=G):
    """Smallest pivot amplitude ``a`` (m) that stabilises the inverted rod (Floquet)."""
    lo, hi = 0.0, 2.0 * np.sqrt(2 * g / k) / omega  # unstable at lo, stable at hi
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if abs(floquet_trace(mid, omega, k, g)) < 2 else (mid, hi)
    return hi


# --8<-- [start:tilt_history]
def tilt_history(amplitude, omega, t_end=4.0, steps_per_period=50, n_elements=3,
                 theta0=0.1):
    """Simulate the rod on the shaking pivot; returns times and the tilt from the upward
    vertical (rad)."""
    section = sc.Section.circular(radius=0.02, E=2e11, rho=7850.0)
    pivot = np.array([0.0, amplitude, 0.0])
    tip = pivot + LENGTH * np.array([np.sin(theta0), np.cos(theta0), 0.0])
    rod = sc.Cable.straight(pivot, tip, n_elements, section)

    def target(t):
        return np.array([0.0, amplitude * np.cos(omega * t), 0.0])

    def acceleration(t):
        return np.array([0.0, -amplitude * omega**2 * np.cos(omega * t), 0.0])

    system = sc.System([rod]).pin(rod.node(0), target, acceleration=acceleration)
    system.add_gravity([0, -G, 0])
    result = sc.simulate(system, t_end=t_end, dt=2 * np.pi / omega / steps_per_period,
                         rho_inf=0.8, every=5)
    rel = result.position(rod, LENGTH) - result.position(rod, 0.0)
    return result.t, np.arctan2(rel[:, 0], rel[:, 1])
# --8<-- [end:tilt_history]


def main(omega=2 * np.pi * 10, margin=0.1, t_end=4.0):
    """Largest tilt at ``(1 +- margin)`` times the threshold amplitude."""
    a_c = threshold(omega)
    out = {"threshold_amplitude": a_c, "kapitza_estimate": np.sqrt(4 * G * LENGTH / 3) / omega}
    for label, factor in (("above", 1 + margin), ("below", 1 - margin)):
        _, tilt = tilt_history(factor * a_c, omega, t_end)
        out[f"max_tilt_{label}"] = float(np.abs(tilt).max())
    return out


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the tilt from the
    upward vertical, 5 % above and 5 % below the threshold amplitude."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    omega = 2 * np.pi * 10
    a_c = threshold(omega)
    fig, ax = plt.subplots(1, 1, figsize=(6.0, 3.2), layout="constrained")
    for label, factor in (("5 % above", 1.05), ("5 % below", 0.95)):
        t, tilt = tilt_history(factor * a_c, omega, 5.0)
        ax.plot(t, np.unwrap(tilt), label=f"a = {factor:.2f} a_c ({label})")
    ax.axhspan(-0.15, 0.15, color="0.85", label="|tilt| < 0.15 rad")
    ax.set_ylim(-0.5, 3.5)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("tilt from upward vertical [rad]")
    ax.legend(fontsize=8)
    ax.set_title(f"Kapitza's pendulum, 10 Hz pivot, threshold a_c = {a_c * 1e3:.2f} mm",
                 fontsize=10)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


if __name__ == "__main__":
    for key, value in main().items():
        print(f"{key:>20s}: {value:.6g}")
