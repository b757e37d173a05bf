"""Spectra, figures and the coning animation of an E-sail run."""

import numpy as np

from ...loads.coulomb import SolarWindForce


def psd(t, x, segments=4):
    """Welch power spectral density of samples ``x`` (leading axis time) at uniform times
    ``t``: returns frequencies (Hz) and densities.  The package's one spectrum
    (``spectra.spectrum``, also drawn by ``plot.psd``): Hann window, ``segments``
    half-overlapping segments (1: the whole run), mean removed."""
    from ...analysis.spectra import spectrum

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
    from ... import plot

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
    from ... import plot

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

    from ... import plot

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
