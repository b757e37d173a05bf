"""Pictures of configurations and runs, one module per job:

* ``plot.renders``: 3-D renders (pyvista, off-screen) of configurations (``render``,
  ``render_mesh``) and runs (``animate``): cables as tubes coloured by tension, rigid
  bodies as solids, point masses as spheres, with an axes triad, a scale bar and a colour
  bar; ``rendering_available`` tells whether an OpenGL context can be created here;
* ``plot.cameras``: the camera a scene chooses for itself (``scene_camera``: up against
  gravity; along or across the spin axis of a spinning scene; face on for a planar
  scene) and the named views (``VIEWS``, ``view_camera``);
* ``plot.figures``: figures (matplotlib, no display needed) of time histories (a long one
  drawn from the points its pixels show, ``thinned``), power spectral densities, the
  energy books and speed-against-error tables;
* the spectrum itself (``spectrum``, ``welch_plan``) is ``skfem_cable.analysis.spectra``'s, which
  needs no matplotlib.

Every public name of these modules is importable from ``skfem_cable.plot`` (``from
skfem_cable import plot; plot.render(...)``).  Importing the package imports neither
matplotlib nor pyvista: each is imported on first use.
"""

from ..analysis.spectra import spectrum, welch_plan
from .cameras import (
    VIEWS,
    Camera,
    gravity_vector,
    plane_camera,
    plane_normal,
    scene_camera,
    spin_axis,
    view_camera,
)
from .figures import (
    CURVE_CMAP,
    ENERGY_TERMS,
    MAX_LEGEND,
    cable_histories,
    corotated,
    curve_colours,
    energies,
    energy_figure,
    energy_scale,
    histories,
    psd,
    rigid_fit,
    speed_error,
    thinned,
)
from .renders import (
    TENSION_CMAP,
    animate,
    colorbar_format,
    colour_limits,
    format_length,
    nice_length,
    render,
    render_mesh,
    rendering_available,
    use_egl_without_display,
)

__all__ = [
    # renders
    "TENSION_CMAP", "animate", "colorbar_format", "colour_limits", "format_length",
    "nice_length", "render", "render_mesh", "rendering_available", "use_egl_without_display",
    # cameras
    "VIEWS", "Camera", "gravity_vector", "plane_camera", "plane_normal", "scene_camera",
    "spin_axis", "view_camera",
    # figures
    "CURVE_CMAP", "ENERGY_TERMS", "MAX_LEGEND", "cable_histories", "corotated",
    "curve_colours", "energies", "energy_figure", "energy_scale", "histories", "psd",
    "rigid_fit", "speed_error", "thinned",
    # spectra
    "spectrum", "welch_plan",
]
