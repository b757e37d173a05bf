"""Figures and renders of a rod-chain run, the counterparts of those of cable runs
(``skfem_cable.plot``): energies, free-end and tension histories, the root-tension
spectrum and a render of the polyline of the joints."""

from pathlib import Path

import numpy as np

from .. import plot
from .export import state_mesh


def histories(result, path=None, title=None):
    """Free-end position and speed, root and peak rod tension of a run."""
    tip = result.free_end - result.joints[:, 0]
    speed = np.linalg.norm(result.joint_velocities[:, -1], axis=-1)
    panels = {"free end - anchor [m]": {"x": tip[:, 0], "y": tip[:, 1], "z": tip[:, 2]},
              "free-end speed [m/s]": speed,
              "tension [N]": {"root rod": result.tension[:, 0],
                              "max over rods": result.tension.max(axis=1),
                              "min over rods": result.tension.min(axis=1)}}
    return plot.histories(result.t, panels, path, title)


def tension_psd(result, path=None, title="root tension"):
    """Power spectral density of the tension of the root rod (needs at least 8 uniformly
    spaced saved steps)."""
    return plot.psd(result.t, {"root rod": result.tension[:, 0]}, path, title=title)


def planar_view(points, rtol=1e-9):
    """``"xy"``, ``"xz"`` or ``"yz"`` when the points (..., 3) lie in a plane normal to a
    coordinate axis (extent below ``rtol`` times the largest), else ``"isometric"``."""
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    extent = np.ptp(points, axis=0)
    axis = int(np.argmin(extent))
    if extent[axis] <= rtol * max(extent.max(), 1e-300):
        return ("yz", "xz", "xy")[axis]
    return "isometric"


def render(state, path, title=None, clim=None, tube_radius=None, window_size=(1024, 768),
           view=None):
    """Render a ``ChainState`` (``result.state(i)``) as a tube coloured by tension
    (``plot.render_mesh``; needs off-screen OpenGL, see ``plot.rendering_available``).
    ``view``: default ``planar_view`` of the joints and the anchor."""
    mesh = state_mesh(state)
    if view is None:
        view = planar_view(mesh.points)
    return plot.render_mesh(mesh, path, window_size, clim, tube_radius, title, view)


def run_figures(out, result, render_final=True):
    """The standard figures of a rod-chain run in ``out/plots``: ``energies.png``
    (``plot.energies``), ``chain.png`` (``histories``), ``tension_psd.png`` (with at least
    16 saved steps) and, when off-screen rendering works, ``final.png``.  Returns the
    paths written and the reason the render was skipped (or None)."""
    plots = Path(out) / "plots"
    plots.mkdir(parents=True, exist_ok=True)
    paths = [plots / "energies.png", plots / "chain.png"]
    plot.energies(result, paths[0], title="Energy (rod chain)")
    histories(result, paths[1])
    if len(result) >= 16:
        try:
            tension_psd(result, plots / "tension_psd.png")
            paths.append(plots / "tension_psd.png")
        except ValueError:  # saved steps not uniformly spaced (a stopped adaptive run)
            pass
    skipped = None
    if render_final:
        ok, reason = plot.rendering_available()
        if ok:
            paths.append(plots / "final.png")
            render(result.state(len(result) - 1), paths[-1], title=f"t = {result.t[-1]:.4g} s",
                   view=planar_view(result.joints))
        else:
            skipped = reason
    return paths, skipped
