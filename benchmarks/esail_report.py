"""Reproduce the E-sail paper (Sects. 4.2-4.3), its tethers in the paper's formulation
(``formulation="paper"``), and measure speed.

Prints markdown tables: the baseline runs (thrust, thrust angle, energy, frequencies, the
rigid coning equation), the convergence study of Fig. 4 (elements per tether, cable and
truss), and the speed figures (baseline wall time, growth with tethers and elements).
Run ``python benchmarks/esail_report.py [--quick]`` (``--quick``: one spin period, fewer
cases and 100 steps per speed case, a few minutes).
"""

import time

import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import arguments
from skfem_cable.loads.coulomb import SolarWind
from skfem_cable.scenes import esail


def run(alpha, n_elements=5, kind="cable", periods=3.0, every=10, **config):
    cfg = esail.BaselineConfig(**config)
    scene = esail.build(cfg, alpha_deg=alpha, n_elements=n_elements, kind=kind,
                        formulation="paper")
    start = time.perf_counter()
    result = sc.simulate(scene.system, t_end=periods * cfg.spin_period, dt=0.1, rho_inf=0.25,
                         initial=scene.initial, every=every)
    wall = time.perf_counter() - start
    return cfg, scene, result, esail.outputs(scene, result), wall


def max_strain(scene, result, tether=0):
    cable = scene.tethers[tether]
    qc = result.q[:, scene.system.dofs(cable)]
    s = np.linspace(0, cable.length, 101)
    return float(cable.strain(qc, s).max())


def table2_modes(cfg, n_elements=5):
    """Modes of one spinning tether with its remote unit in the rotating frame."""
    system = esail.spinning_tether(cfg, n_elements, formulation="paper")
    spin = [cfg.spin_rate, 0, 0]
    return sc.modes(system, sc.solve_static(system), k=12, spin=spin)[0]


def psd_peaks(t, x, n=3):
    f, P = esail.psd(t, x, segments=1)
    i = [k for k in range(1, len(P) - 1) if P[k] > P[k - 1] and P[k] >= P[k + 1]]
    return f[sorted(i, key=lambda k: -P[k])[:n]]


def baseline(periods):
    """Print the baseline tables; returns one row per run (``alpha``, ``voltage``,
    ``wall_s``, ``stats``, mean ``thrust_N`` and ``thrust_angle_deg``, ``energy_drift``)."""
    print(f"## Baseline, 12 tethers x 5 cable elements, dt = 0.1 s, rho_inf = 0.25, "
          f"{periods:g} T_s\n")
    print("| case | wall [s] | steps | Newton | factorizations | rejected | |F_c| [N] "
          "| thrust angle [deg] | max |E - E0|/E0 | balance/E0 |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    runs, rows = {}, []
    for alpha, V in ((0.0, 20e3), (10.0, 20e3), (10.0, 0.0)):
        cfg, scene, res, out, wall = run(alpha, periods=periods, voltage=V)
        runs[(alpha, V)] = (cfg, scene, res, out)
        E = out["total"]
        st = res.stats
        rows.append({"alpha": alpha, "voltage": V, "wall_s": wall, "stats": dict(st),
                     "thrust_N": np.linalg.norm(out["thrust"], axis=1).mean(),
                     "thrust_angle_deg": np.rad2deg(out["thrust_angle"]).mean(),
                     "energy_drift": np.abs(E / E[0] - 1).max()})
        print(f"| alpha={alpha:g}, V0={V / 1e3:g} kV | {wall:.1f} | {st['steps']} | "
              f"{st['newton']} | {st['factorizations']} | {st['rejected']} | "
              f"{np.linalg.norm(out['thrust'], axis=1).mean():.5e} | "
              f"{np.rad2deg(out['thrust_angle']).mean():.3f} | "
              f"{np.abs(E / E[0] - 1).max():.2e} | {np.abs(out['balance']).max() / E[0]:.2e} |")
    cfg, scene, res, out = runs[(0.0, 20e3)]
    F0 = cfg.n_tethers * cfg.tether_length * SolarWind().force_per_length(20e3)
    proj = F0 * np.mean(np.cos(out["coning"]) ** 2, axis=1)
    ratio = np.linalg.norm(out["thrust"], axis=1) / proj
    print(f"\nSun-facing thrust / (12 x 10 km x {F0 / 120e3:.4e} N/m x <cos^2 coning>): "
          f"{ratio.min():.6f} ... {ratio.max():.6f}")
    _, _, _, out10 = runs[(10.0, 20e3)]
    a = np.deg2rad(10)
    drop = np.linalg.norm(out10["thrust"], axis=1).mean() / np.linalg.norm(
        out["thrust"], axis=1).mean()
    flat = 0.5 * np.hypot(1 + np.cos(a) ** 2, np.sin(a) * np.cos(a))
    angle = np.rad2deg(out10["thrust_angle"])
    print(f"alpha = 10 deg: |F| / |F(alpha=0)| = {drop:.5f} (flat-sail spin average "
          f"{flat:.5f}); thrust angle {angle.min():.3f} ... {angle.max():.3f} deg (alpha/2 = 5)")
    rigid = esail.rigid_coning(cfg, out10, 0)
    gamma = out10["coning"][:, 0]
    amp = np.abs(gamma).max()
    diff = np.abs(rigid - gamma).max()
    print(f"Eq. 83 (rigid coning) vs tether 1: max difference {np.rad2deg(diff):.4f} deg = "
          f"{diff / amp:.3f} of the amplitude {np.rad2deg(amp):.4f} deg\n")
    f = table2_modes(cfg)
    t = out10["t"]

    def peaks(name):
        return ", ".join(f"{x:.3e}" for x in psd_peaks(t, out10[name][:, 0]))

    axial = f[np.argmin(np.abs(f - 2.17e-2))]
    print("| mode | Table 2 [Hz] | modes() [Hz] | PSD peaks, alpha = 10 [Hz] |")
    print("|---|---|---|---|")
    print(f"| spin (coning) | 6.37e-4 | {f[1]:.4e} | coning: {peaks('coning')} |")
    print(f"| 1st bending | 7.34e-3 | {f[2]:.4e} (in-plane), {f[3]:.4e} (out) | "
          f"lagging: {peaks('lagging')} |")
    print(f"| 1st axial | 2.17e-2 | {axial:.4e} | length ratio: {peaks('length_ratio')} |")
    print(f"\nPSD resolution 1/T = {1 / (t[-1] - t[0]):.2e} Hz\n")
    return rows


def convergence(periods, elements=(1, 3, 5, 7, 9)):
    """Print the convergence table; returns its rows (``kind``, ``elements`` and the
    normalised thrust, thrust angle, max strain and wall time)."""
    print(f"## Convergence (Fig. 4), alpha = 10 deg, {periods:g} T_s, normalised by one cable "
          "element\n")
    print("| kind | elements | |F_c| | thrust angle | max strain | wall [s] | wall / 1 cable |")
    print("|---|---|---|---|---|---|---|")
    ref, rows = None, []
    for kind in ("cable", "truss"):
        for n in elements:
            cfg, scene, res, out, wall = run(10.0, n, kind, periods=periods)
            F = np.linalg.norm(out["thrust"][-1])
            ang = out["thrust_angle"][-1]
            eps = max_strain(scene, res)
            if ref is None:
                ref = (F, ang, eps, wall)
            rows.append({"kind": kind, "elements": n, "thrust": F / ref[0],
                         "thrust_angle": ang / ref[1], "max_strain": eps / ref[2],
                         "wall_s": wall, "wall_ratio": wall / ref[3]})
            print(f"| {kind} | {n} | {F / ref[0]:.5f} | {ang / ref[1]:.5f} | {eps / ref[2]:.4f} "
                  f"| {wall:.1f} | {wall / ref[3]:.2f} |")
    print()
    return rows


def speed(steps=300):
    """Print the cost table; returns its rows (``tethers``, ``elements``, ``ms_per_step``,
    ``newton_per_step``)."""
    print(f"## Cost per step ({steps} steps of 0.1 s)\n")
    print("| tethers | elements/tether | ms/step | Newton/step |")
    print("|---|---|---|---|")
    rows = []
    for p, n in [(4, 5), (12, 5), (24, 5), (48, 5), (12, 1), (12, 10), (12, 20), (12, 50)]:
        cfg = esail.BaselineConfig(n_tethers=p)
        scene = esail.build(cfg, 10.0, n)
        sc.simulate(scene.system, t_end=1.0, dt=0.1, initial=scene.initial, rho_inf=0.25)
        start = time.perf_counter()
        r = sc.simulate(scene.system, t_end=steps * 0.1, dt=0.1, rho_inf=0.25,
                        initial=scene.initial, every=steps)
        wall = time.perf_counter() - start
        rows.append({"tethers": p, "elements": n, "ms_per_step": 1e3 * wall / steps,
                     "newton_per_step": r.stats["newton"] / steps})
        print(f"| {p} | {n} | {1e3 * wall / steps:.3f} | {r.stats['newton'] / steps:.2f} |")
    print()
    return rows


def main(argv=None):
    """Parse the arguments (``--quick``), print the tables and return their rows."""
    quick = arguments(__doc__, "one spin period, fewer cases and steps", argv).quick
    periods = 1.0 if quick else 3.0
    return {"baseline": baseline(periods),
            "convergence": convergence(periods, elements=(1, 3, 5) if quick else (1, 3, 5, 7, 9)),
            "speed": speed(100 if quick else 300)}


if __name__ == "__main__":
    main()
