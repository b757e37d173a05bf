"""The E-sail thrust laws side by side (``loads.thrust_laws``): force per unit length on a
tether across the wind against voltage (10-40 kV at 1 AU), density (at 20 kV, 1 AU) and
heliocentric distance (0.5-2 AU at 20 kV, the wind's data at 1 AU).  matplotlib is
imported on first use."""

import numpy as np

from ..loads.coulomb import SolarWind
from ..loads.thrust_laws import thrust_law
from ..space.constants import AU

#: The laws drawn by default.
LAWS = ("paper", "janhunen2009", "shielded")


def law_curves(laws=LAWS, wind=None, points=61):
    """The curves of ``laws_figure``: a dict ``{"voltage" | "density" | "distance":
    (x, {law: f (N/m)})}`` with x in kV, cm^-3 and AU."""
    wind = wind or SolarWind()
    objs = {name: thrust_law(name) for name in laws}
    V = np.linspace(10e3, 40e3, points)
    n = np.geomspace(1e6, 30e6, points)
    r = np.linspace(0.5, 2.0, points) * AU
    return {
        "voltage": (V / 1e3, {k: [law.force_per_length(v, wind, AU) for v in V]
                              for k, law in objs.items()}),
        "density": (n / 1e6, {k: [law.force_per_length(20e3, SolarWind(
            wind.speed, d, wind.V1, wind.proton_mass, wind.eps0), AU) for d in n]
                              for k, law in objs.items()}),
        "distance": (r / AU, {k: [law.force_per_length(20e3, wind, x) for x in r]
                              for k, law in objs.items()}),
    }


def laws_figure(path=None, laws=LAWS, wind=None):
    """Three panels of ``law_curves`` (nN/m, log scales for density and distance); saved
    to ``path`` when given.  Returns the figure."""
    from matplotlib.figure import Figure

    curves = law_curves(laws, wind)
    fig = Figure(figsize=(11, 3.6), layout="constrained")
    axes = fig.subplots(1, 3, sharey=False)
    labels = {"voltage": "tether voltage $V_0$ (kV), 1 AU",
              "density": "density $n$ (cm$^{-3}$), 20 kV, 1 AU",
              "distance": "distance $r$ (AU), 20 kV"}
    for ax, (key, (x, ys)) in zip(axes, curves.items()):
        for name, y in ys.items():
            ax.plot(x, np.asarray(y) * 1e9, label=name)
        ax.set_xlabel(labels[key])
        ax.grid(True, which="both", alpha=0.3)
        if key != "voltage":
            ax.set_xscale("log")
            ax.set_yscale("log")
    axes[0].set_ylabel("force per length (nN/m)")
    axes[0].axhline(500.0, color="0.5", lw=0.8, ls=":", label="1 N / 2000 km")
    axes[0].legend(title="law")
    fig.suptitle("E-sail thrust laws (wind 400 km/s, 7.3 cm$^{-3}$ at 1 AU)")
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig
