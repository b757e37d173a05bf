"""A gallery of cable laws, each a few lines, each checked by one number.

* ``laws.green`` (built-in): the paper's Green strain and squared curvature, with the
  Kelvin-Voigt damping of Eqs. 36-38 (``skfem_cable/laws/builtin.py``);
* ``biot``: the engineering strain ``e = |r_x| - 1``: a bar pulled by ``P`` stretches by
  exactly ``P L / EA`` (``demos/custom_element.py``);
* ``laws.truss`` (built-in): no bending;
* ``polymer``: a tension-only, stiffening polymer tether (Dyneema-like):
  ``N(e) = EA e0 (exp(e / e0) - 1)`` for ``e > 0`` and no force when slack, so a bar pulled
  by ``P`` stretches by ``e0 ln(1 + P / (EA e0))`` and a compressed one pushes back with
  nothing;
* ``power_law``: nonlinear viscous damping of the strain rate, ``D = c |e_dot|^(n+1) /
  (n+1)`` (force ``c |e_dot|^n sign(e_dot)``), with the energy balance of a free
  oscillation closing to the integrator's accuracy.

Run ``python demos/law_gallery.py``.
"""

import sys
from pathlib import Path

import numpy as np

import skfem_cable as sc
from skfem_cable import laws

sys.path.insert(0, str(Path(__file__).resolve().parent))
from custom_element import biot, pulled_bar  # noqa: E402 (the demo next to this one)

SECTION = sc.Section(E=1e9, A=1e-4, I=1e-10, rho=7850.0)


# --8<-- [start:polymer]
@sc.cable_law
def polymer(a, b, EA, EI, e0=0.01):
    """Tension-only, exponentially stiffening: ``N = EA e0 (exp(e/e0) - 1)`` for e > 0."""
    e = laws.ramp(laws.norm(a) - 1)
    return EA * e0**2 * (laws.exp(e / e0) - 1 - e / e0) + EI * laws.kappa2(a, b) / 2
# --8<-- [end:polymer]


# --8<-- [start:power_law]
def power_law(a, b, ad, bd, EA, c, n=2.0):
    """Viscous damping of the engineering strain rate: ``D = c EA |e_dot|^(n+1) / (n+1)``
    (``c`` in s^n)."""
    e_dot = laws.dot(a, ad) / laws.norm(a)
    return c * EA * laws.Abs(e_dot) ** (n + 1) / (n + 1)


damped_biot = biot.with_dissipation(power_law).with_parameters(c=1e-6)
# --8<-- [end:power_law]


def polymer_stretch(load=0.02):
    """Tip stretch of a bar of the polymer law pulled by ``P = load EA`` and the exact
    ``e0 ln(1 + P / (EA e0))``."""
    e0 = polymer.values["e0"]
    return pulled_bar(polymer, load), e0 * np.log1p(load / e0)


def slack_force(squeeze=0.9):
    """Largest internal force of a straight polymer bar compressed to ``squeeze`` of its
    length (zero: a slack tether carries nothing)."""
    bar = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, SECTION, law=polymer)
    f, _ = sc.System([bar]).assemble(bar.q0 * np.tile([squeeze] * 3 + [squeeze] * 3, bar.n_nodes))
    return float(np.abs(f).max())


def damped_oscillation(t_end=2e-3, dt=2e-6):
    """A bar clamped at one end, stretched by 1 % and released, with the power-law damping:
    the fraction of the initial energy dissipated, and the largest energy-balance error
    relative to the initial energy."""
    bar = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, SECTION, law=damped_biot)
    system = sc.System([bar]).clamp(bar.node(0))
    q0 = bar.q0.copy()
    q0[0::6] *= 1.01
    q0[3::6] = 1.01
    result = sc.simulate(system, t_end=t_end, dt=dt, initial=(q0, np.zeros_like(q0)))
    E = result.energy
    initial = E["total"][0]
    return E["dissipated"][-1] / initial, np.abs(E["balance"]).max() / initial


def main():
    stretch, exact = polymer_stretch()
    dissipated, balance = damped_oscillation()
    return {"biot_stretch": pulled_bar(biot), "biot_exact": 0.1,
            "polymer_stretch": stretch, "polymer_exact": exact,
            "polymer_slack_force": slack_force(),
            "power_law_dissipated": dissipated, "power_law_balance": balance}


def gallery_figure(path):
    """The gallery's picture (``scripts/gallery.py``) into ``path``: the polymer tether's
    stretch against the pull, computed and exact; the released bar's energy with the
    power-law damping and what it dissipated."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    e0 = polymer.values["e0"]
    loads = np.linspace(0.002, 0.03, 8)
    stretch = [pulled_bar(polymer, p) for p in loads]
    fine = np.linspace(0, 0.031, 100)
    bar = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, SECTION, law=damped_biot)
    system = sc.System([bar]).clamp(bar.node(0))
    q0 = bar.q0.copy()
    q0[0::6] *= 1.01
    q0[3::6] = 1.01
    r = sc.simulate(system, t_end=2e-3, dt=2e-6, initial=(q0, np.zeros_like(q0)))
    E = r.energy
    fig, (a, b) = plt.subplots(1, 2, figsize=(8.0, 3.0), layout="constrained")
    a.plot(fine, e0 * np.log1p(fine / e0), "k-", lw=0.8, label="e0 ln(1 + P/(EA e0))")
    a.plot(loads, stretch, "o", label="polymer law")
    a.set_xlabel("P / EA")
    a.set_ylabel("tip stretch u / L")
    a.legend(fontsize=8)
    a.set_title("tension-only polymer tether", fontsize=10)
    b.plot(r.t * 1e3, E["total"] / E["total"][0], label="energy")
    b.plot(r.t * 1e3, E["dissipated"] / E["total"][0], label="dissipated")
    b.plot(r.t * 1e3, (E["total"] + E["dissipated"]) / E["total"][0], "k--", lw=0.8,
           label="sum")
    b.set_xlabel("t [ms]")
    b.set_ylabel("/ initial energy")
    b.legend(fontsize=8)
    b.set_title("power-law damping", fontsize=10)
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.05)
    plt.close(fig)


if __name__ == "__main__":
    for key, value in main().items():
        print(f"{key:>22s}: {value:.10g}")
