"""Pictures of configurations and runs: 3-D renders (pyvista, off-screen) and figures of
time histories, spectra and speed-vs-error tables (matplotlib, no display needed).

Renders show the cables as tubes coloured by tension, rigid bodies as solids and point
masses as spheres, from the same mesh as ``export.system_mesh``, with an axes triad, a
scale bar and a colour bar whose labels carry enough digits for the range, in parallel
projection from a camera chosen from the scene (``scene_camera``: up against gravity;
along or across the spin axis of a spinning scene; face on for a planar scene).  They
need an OpenGL context but no display: on Linux without ``DISPLAY`` VTK is pointed at EGL (Mesa's
``libegl1``, ``libegl-mesa0``, ``libgl1-mesa-dri``; ``scripts/install_system_deps.sh``
installs them), and ``rendering_available`` tells whether a context can be created.
"""

import os
import subprocess
import sys
from collections import namedtuple
from functools import lru_cache
from itertools import cycle
from pathlib import Path

import numpy as np

from . import export
from .loads import Gravity

#: Colour map of the tension along the tubes.
TENSION_CMAP = "viridis"

#: Views of ``render`` and ``animate`` (see ``view_camera``).
VIEWS = ("auto", "isometric", "xy", "xz", "yz", "orbital", "gravity", "axial", "side")

#: A camera: unit vectors from the focal point towards the eye, and up on the screen.
Camera = namedtuple("Camera", "eye up")


# --- 3-D renders ------------------------------------------------------------------------
def use_egl_without_display():
    """On Linux without an X display, make VTK open EGL render windows (no X warning,
    no Xvfb needed); an explicit ``VTK_DEFAULT_OPENGL_WINDOW`` is respected."""
    if sys.platform.startswith("linux") and not os.environ.get("DISPLAY"):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")


_PROBE = """
import skfem_cable.plot as p
p.use_egl_without_display()
import pyvista as pv
pl = pv.Plotter(off_screen=True, window_size=(32, 32))
pl.add_mesh(pv.Sphere(), color="white")
img = pl.screenshot(return_img=True)
pl.close()
raise SystemExit(0 if img.std() > 0 else 3)
"""


@lru_cache(maxsize=1)
def rendering_available():
    """``(ok, reason)``: whether an off-screen OpenGL context can be created here.

    The probe renders a sphere in a child process, since a failing OpenGL set-up can abort
    the process rather than raise.
    """
    try:
        proc = subprocess.run([sys.executable, "-c", _PROBE], capture_output=True, text=True,
                              timeout=120)
    except subprocess.TimeoutExpired:
        return False, "the OpenGL probe timed out"
    if proc.returncode == 0:
        return True, "off-screen rendering works"
    tail = (proc.stderr.strip().splitlines() or ["no message"])[-1]
    return False, (f"no OpenGL context for off-screen rendering (probe exit code "
                   f"{proc.returncode}: {tail}); run scripts/install_system_deps.sh as root, "
                   f"or use xvfb-run")


def _grids(system, frames, points_per_element):
    """pyvista grids of the configurations ``frames`` (triples ``(q, v, t)``)."""
    use_egl_without_display()
    import pyvista as pv

    return [pv.from_meshio(export.system_mesh(system, q, v, points_per_element, t=t))
            for q, v, t in frames]


# --- cameras ------------------------------------------------------------------------------
def gravity_vector(system):
    """Sum of the ``loads.Gravity`` loads of ``system`` (m/s^2); zeros without gravity."""
    return sum((load.g for load in system.loads if isinstance(load, Gravity)), np.zeros(3))


def spin_axis(system, q, v, share=0.5):
    """Unit vector along the angular momentum about the centroid of the positions when
    the motion is a spin, else None.

    It is a spin when the angular momenta of the coordinate blocks (position or slope
    times momentum) add up to at least ``share`` of the sum of their norms: a rigid
    rotation (the E-sail) passes, a state at rest or without a common axis does not.
    """
    if v is None:
        return None
    pos = system.vector_is_position
    blocks = np.asarray(q, dtype=float)[system.vectors]
    rel = np.where(pos[:, None], blocks - blocks[pos].mean(axis=0), blocks)
    momenta = np.cross(rel, (system.layout.mass @ np.asarray(v, dtype=float))[system.vectors])
    total = momenta.sum(axis=0)
    size = np.linalg.norm(total)
    if size == 0 or size < share * np.linalg.norm(momenta, axis=1).sum():
        return None
    return total / size


def scene_camera(system, q, v=None, view=None, sun=None, points=None):
    """The camera of ``view_camera`` for configurations of ``system``: its gravity
    (``gravity_vector``) and spin axis (``spin_axis`` of ``q``, ``v``; the first row when
    they are 2-D, e.g. a run's) decide the automatic view.

    Parameters
    ----------
    system : System
    q, v : ndarray (n_dofs,) or (n_frames, n_dofs)
        Coordinates and velocities (``v`` None: at rest).
    view, sun
        As in ``view_camera``.
    points : ndarray (..., 3), optional
        The points to frame (default: the position coordinates of ``q``).

    Returns
    -------
    Camera
    """
    q = np.atleast_2d(q)
    if points is None:
        points = q[:, system.vectors[system.vector_is_position]]
    g = gravity_vector(system)
    axis = spin_axis(system, q[0], None if v is None else np.atleast_2d(v)[0])
    return view_camera(view, points, gravity=g if np.any(g) else None, spin=axis, sun=sun,
                       plane=plane_normal(points))


def plane_normal(points, rtol=1e-6):
    """Unit normal of the plane ``points`` (..., 3) lie in, or None when they do not lie
    in one plane or lie on a line (their thickness across it, or their width, is more,
    or not more, than ``rtol`` times their extent)."""
    points = np.reshape(points, (-1, 3))
    rel = points - points.mean(axis=0)
    if len(rel) < 3:
        return None
    _, sizes, axes = np.linalg.svd(rel, full_matrices=False)
    if not sizes[0] > 0 or sizes[2] > rtol * sizes[0] or sizes[1] <= rtol * sizes[0]:
        return None
    return axes[2] * np.sign(axes[2][np.argmax(np.abs(axes[2]))])


def view_camera(view, points, gravity=None, spin=None, sun=None, plane=None):
    """Camera of a named view of ``points``.

    Parameters
    ----------
    view : str or None
        One of ``VIEWS``.  ``None`` or ``"auto"``: ``"gravity"`` with gravity, else
        ``"axial"`` with a spin axis, else looking along the normal ``plane`` of planar
        points (``plane_camera``), else ``"isometric"``.  ``"gravity"``: up is
        ``-gravity``, looking horizontally across the points' main horizontal extent,
        which runs left to right.  ``"axial"``: looking down the spin axis (the spin turns
        anticlockwise on the screen), the Sun's direction (else a coordinate axis)
        up.  ``"side"``: the spin axis up, looking perpendicular to it and to the Sun's
        direction (the Sun on the left).  ``"isometric"`` (z up) and ``"xy"``, ``"xz"``,
        ``"yz"`` (looking along the third axis) are pyvista's.  ``"orbital"``: the
        orbiting frame's view, ``x`` (radial) up, ``y`` (along-track) to the right,
        looking along ``z`` (the orbit normal).
    points : ndarray (..., 3)
    gravity, spin, sun : array_like (3,), optional
        Gravity (m/s^2), the unit spin axis and the direction towards the Sun.
    plane : array_like (3,), optional
        Unit normal of the plane of planar points (``plane_normal``).

    Returns
    -------
    Camera
        Its ``up`` is perpendicular to its ``eye``.
    """
    view = "auto" if view is None else view
    if view not in VIEWS:
        raise ValueError(f"view must be one of {VIEWS}, got {view!r}")
    if view == "auto" and gravity is None and spin is None and plane is not None:
        return plane_camera(plane)
    if view == "auto":
        view = "gravity" if gravity is not None else "axial" if spin is not None else "isometric"
    if view == "gravity":
        if gravity is None:
            raise ValueError("the 'gravity' view needs a scene with gravity")
        return _gravity_camera(np.reshape(points, (-1, 3)), -_unit(gravity))
    if view in ("axial", "side"):
        if spin is None:
            raise ValueError(f"the {view!r} view needs a spinning scene")
        axis = _unit(spin)
        across = _perpendicular(axis, sun)
        if view == "axial":
            return Camera(axis, across)
        return Camera(np.cross(axis, across), axis)
    eye, up = _FIXED_VIEWS[view]
    return Camera(_unit(eye), _perpendicular(_unit(eye), up))


def plane_camera(normal):
    """Looking along the unit ``normal`` of a planar scene, with up the in-plane part of
    ``z`` (of ``y`` when the plane is nearly horizontal: an ``xy`` scene is drawn as
    ``"xy"`` draws it)."""
    normal = _unit(normal)
    hint = (0.0, 1.0, 0.0) if abs(normal[2]) > 0.9 else (0.0, 0.0, 1.0)
    return Camera(normal, _perpendicular(normal, hint))


#: ``(eye, up)`` of pyvista's fixed views.
_FIXED_VIEWS = {"isometric": ((1, 1, 1), (0, 0, 1)), "xy": ((0, 0, 1), (0, 1, 0)),
                "xz": ((0, -1, 0), (0, 0, 1)), "yz": ((1, 0, 0), (0, 0, 1)),
                "orbital": ((0, 0, -1), (1, 0, 0))}


def _unit(x):
    x = np.asarray(x, dtype=float)
    return x / np.linalg.norm(x)


def _perpendicular(a, hint=None):
    """Unit vector perpendicular to the unit vector ``a``: the part of ``hint`` normal to
    ``a`` when there is one, else that of the coordinate axis least aligned with ``a``."""
    candidates = [] if hint is None else [_unit(hint)]
    for h in candidates + [np.eye(3)[np.argmin(np.abs(a))]]:
        normal = h - (h @ a) * a
        if np.linalg.norm(normal) > 1e-6:
            return _unit(normal)
    raise AssertionError("unreachable: a coordinate axis is never parallel to all of a")


def _gravity_camera(points, up):
    """Up ``up``, looking horizontally with the main horizontal extent of ``points`` (its
    first principal direction) running left to right, towards its positive side."""
    rel = points - points.mean(axis=0)
    horizontal = rel - np.outer(rel @ up, up)
    right = np.linalg.svd(horizontal, full_matrices=False)[2][0]
    right -= (right @ up) * up
    if np.linalg.norm(right) < 1e-6 or not np.any(horizontal):  # a vertical line
        right = _perpendicular(up)
    right = _unit(right)
    right *= np.sign(right[np.argmax(np.abs(right))])
    return Camera(np.cross(right, up), up)


# --- renders ------------------------------------------------------------------------------
def colorbar_format(lo, hi, n_labels=5):
    """printf format of ``n_labels`` evenly spaced colour-bar labels from ``lo`` to ``hi``
    with one digit more than their spacing needs, so that narrow ranges (213.0001 to
    213.0009) do not print as repeated values; exponent notation beyond ``[1e-3, 1e5)``."""
    step = (hi - lo) / (n_labels - 1)
    big = max(abs(lo), abs(hi))
    if not np.isfinite(step) or step <= 0 or big == 0:
        return "%.3g"
    decimals = int(np.ceil(-np.log10(step))) + 1
    if 1e-3 <= big < 1e5 and decimals <= 6:
        return f"%.{max(decimals, 0)}f"
    significant = int(np.floor(np.log10(big))) + decimals + 1
    return f"%.{min(max(significant, 2), 15) - 1}e"


def nice_length(x):
    """The largest ``1, 2 or 5 times 10^k`` not above ``x`` (> 0)."""
    k = np.floor(np.log10(x))
    return max(m * 10**k for m in (1, 2, 5) if m * 10**k <= x)


def format_length(x):
    """A length in m as text, in km or mm when that reads better."""
    if x >= 1e3:
        return f"{x / 1e3:g} km"
    if x < 1e-2:
        return f"{x * 1e3:g} mm"
    return f"{x:g} m"


def colour_limits(values, n_labels=5):
    """Colour range ``(lo, hi)`` of the finite ``values``, a limit that its colour-bar
    label (``colorbar_format``) would print as zero made exactly zero, so that a
    round-off compression does not read ``-0.00``."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    lo, hi = (values.min(), values.max()) if values.size else (0.0, 1.0)
    if hi <= lo:
        return lo - 0.5, lo + 0.5
    fmt = colorbar_format(lo, hi, n_labels)
    return tuple(0.0 if float(fmt % x) == 0 else float(x) for x in (lo, hi))


def _colour_range(grids):
    return colour_limits(np.concatenate([g.point_data["tension"] for g in grids]))


def _stretch(grids, camera, factor):
    """Scale the offsets of the grids' points along ``camera.up`` from their centre by
    ``factor`` (in place)."""
    centre = np.vstack([g.points for g in grids]).mean(axis=0)
    for g in grids:
        g.points = g.points + (factor - 1) * np.outer((g.points - centre) @ camera.up,
                                                      camera.up)


#: Part of the window width the scene is fitted into (left of the colour bar); the
#: height below the title is set by the number of its lines.
_SCENE_WIDTH = (0.03, 0.78)


class _Renderer:
    """An off-screen plotter drawing configurations (grids of ``_grids``) with fixed
    colour limits, tube radius and camera, an axes triad, a scale bar and an optional
    arrow towards the Sun, so that the frames of an animation match."""

    def __init__(self, grids, window_size, clim, tube_radius, camera, sun=None,
                 horizontal_only=False, text_lines=2):
        import pyvista as pv

        self.pv = pv
        points = np.vstack([g.points for g in grids])
        diag = float(np.linalg.norm(np.ptp(points, axis=0))) or 1.0
        self.radius = 0.004 * diag if tube_radius is None else tube_radius
        self.clim = _colour_range(grids) if clim is None else tuple(clim)
        self.window_size = tuple(window_size)
        self.camera = camera
        self.right = np.cross(camera.up, camera.eye)
        self.plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
        self.plotter.set_background("white")
        self.plotter.enable_parallel_projection()
        self.plotter.add_axes(color="black", line_width=3, viewport=(0.0, 0.0, 0.17, 0.17))
        if sun is not None:
            points = np.vstack([points, self._sun_arrow(points, _unit(sun))])
        points = np.vstack([points, self._scale_bar(points, horizontal_only)])
        self._aim(points, top=1 - (17 * text_lines + 12) / window_size[1])
        self.text = self.plotter.add_text("", position="upper_left", font_size=10,
                                          color="black", render=False)
        self.frame_actors = []

    def _screen(self, points):
        """Coordinates of points along the screen's right and up directions."""
        return points @ self.right, points @ self.camera.up

    def _scale_bar(self, points, horizontal_only):
        """A black bar of a round length (a quarter of the scene's width or so) with end
        ticks and its length below, under the scene; returns its corner points."""
        x, y = self._screen(points)
        width, height = np.ptp(x), np.ptp(y)
        length = nice_length(max(0.3 * width, 0.3 * height, 1e-300))
        tick = 0.04 * max(width, height)
        depth = points.mean(axis=0) @ self.camera.eye
        start = ((x.min() + x.max() - length) / 2, y.min() - 2 * tick)
        corners = np.array([[start[0] + dx, start[1] + dy] for dx in (0, length)
                            for dy in (0, tick)])
        world = (corners[:, :1] * self.right + corners[:, 1:] * self.camera.up
                 + depth * self.camera.eye)
        bar = self.pv.PolyData(world, lines=[2, 0, 2, 2, 0, 1, 2, 2, 3])
        self.plotter.add_mesh(bar, color="black", line_width=3, render=False)
        text = format_length(length) + (" (horizontal)" if horizontal_only else "")
        self.plotter.add_point_labels(world[[0, 2]].mean(axis=0, keepdims=True), [text],
                                      font_size=18, text_color="black", shape=None,
                                      show_points=False, always_visible=True, bold=False,
                                      justification_horizontal="center",
                                      justification_vertical="top", render=False)
        return world - 1.5 * tick * self.camera.up  # room for the label

    def _sun_arrow(self, points, sun):
        """An orange arrow pointing at the Sun, just outside the scene on the Sun's side,
        a quarter of the scene's size long; returns its ends."""
        centre = (points.min(axis=0) + points.max(axis=0)) / 2
        size = max(np.ptp(self._screen(points), axis=1))
        start = centre + (np.max((points - centre) @ sun) + 0.08 * size) * sun
        arrow = self.pv.Arrow(start=start, direction=sun, scale=0.25 * size, tip_length=0.3,
                              tip_radius=0.08, shaft_radius=0.025)
        self.plotter.add_mesh(arrow, color="darkorange", render=False)
        tip = start + 0.28 * size * sun
        sx, sy = self._screen(sun)
        self.plotter.add_point_labels(
            tip[None], ["Sun"], font_size=18, text_color="black", shape=None,
            show_points=False, always_visible=True, bold=False, render=False,
            justification_horizontal="left" if sx > 0.3 else "right" if sx < -0.3 else "center",
            justification_vertical="top" if sy < -0.3 else "bottom" if sy > 0.3 else "center")
        return np.array([start, tip + 0.05 * size * sun])

    def _aim(self, points, top):
        """Point the camera and zoom (parallel projection) so that ``points`` (widened by
        the point masses' spheres) fill ``_SCENE_WIDTH`` of the window's width and the
        height from 0.04 to ``top``."""
        x, y = np.asarray(self._screen(points))
        pad = 3 * self.radius
        x0, x1 = _SCENE_WIDTH
        y0, y1 = 0.04, top
        aspect = self.window_size[0] / self.window_size[1]
        half = max((np.ptp(x) + 2 * pad) / (2 * (x1 - x0) * aspect),
                   (np.ptp(y) + 2 * pad) / (2 * (y1 - y0)), 1e-300)
        # screen centre in the scene's coordinates, shifted to put the box's centre there
        cx = (x.min() + x.max()) / 2 - ((x0 + x1) / 2 - 0.5) * 2 * half * aspect
        cy = (y.min() + y.max()) / 2 - ((y0 + y1) / 2 - 0.5) * 2 * half
        depth = points.mean(axis=0) @ self.camera.eye
        focal = cx * self.right + cy * self.camera.up + depth * self.camera.eye
        size = float(np.linalg.norm(np.ptp(points, axis=0))) + 2 * pad or 1.0
        cam = self.plotter.camera
        cam.focal_point = tuple(focal)
        cam.position = tuple(focal + 4 * size * self.camera.eye)
        cam.up = tuple(self.camera.up)
        cam.parallel_scale = half
        cam.clipping_range = (2 * size, 6 * size)  # every frame, not only what is drawn now

    def draw(self, grid, title=None):
        """Replace the drawn configuration by ``grid`` (one of ``_grids``)."""
        pl = self.plotter
        for actor in self.frame_actors:
            pl.remove_actor(actor, render=False)
        for bar in list(pl.scalar_bars.keys()):
            pl.remove_scalar_bar(bar, render=False)
        self.frame_actors = [pl.add_mesh(mesh, render=False, **style)
                             for mesh, style in self._pieces(grid)]
        self.text.set_text("upper_left",
                           "\n".join(filter(None, [title, "colour: axial tension [N]"])))

    def _pieces(self, grid):
        """``(mesh, add_mesh keywords)`` of the cables (tubes coloured by tension), rigid
        bodies and point masses of ``grid``."""
        part = grid.cell_data["part"]
        for value in (export.PART_CABLE, export.PART_RIGID, export.PART_POINT_MASS):
            if not np.any(part == value):
                continue
            piece = grid.extract_cells(part == value).extract_surface(algorithm=None)
            if value == export.PART_CABLE:
                yield piece.tube(radius=self.radius, n_sides=16), {
                    "scalars": "tension", "cmap": TENSION_CMAP, "clim": self.clim,
                    "smooth_shading": True, "scalar_bar_args": {
                        "title": "tension [N]", "color": "black", "vertical": True,
                        "position_x": 0.84, "position_y": 0.1, "height": 0.75,
                        "width": 0.05, "n_labels": 5, "fmt": colorbar_format(*self.clim)}}
            elif value == export.PART_RIGID:
                yield piece.compute_normals(split_vertices=True, feature_angle=30.0), {
                    "color": "lightsteelblue", "smooth_shading": True}
            else:
                yield piece.glyph(geom=self.pv.Sphere(radius=3 * self.radius), scale=False,
                                  orient=False), {"color": "firebrick", "smooth_shading": True}

    def image(self):
        """The drawn frame (rendered now: drawing does not render)."""
        self.plotter.render()
        return self.plotter.screenshot(return_img=True)

    def close(self):
        self.plotter.close()


def _render_grid(grid, path, window_size, clim, tube_radius, title, camera, sun=None):
    r = _Renderer([grid], window_size, clim, tube_radius, camera, sun,
                  text_lines=1 + (title or "").count("\n") + bool(title))
    try:
        r.draw(grid, title)
        img = r.image()
    finally:
        r.close()
    _save_png(path, img)
    return img


def render(system, state, path, points_per_element=8, window_size=(1024, 768), clim=None,
           tube_radius=None, title=None, view=None, sun=None, frame="inertial"):
    """Render one configuration to a PNG: tubes coloured by tension (a colour bar with
    tick labels precise enough for the range), rigid bodies, point masses, an axes triad
    and a scale bar, in parallel projection from a camera chosen from the scene
    (``scene_camera``: with gravity, up is up).

    Parameters
    ----------
    system : System
    state : State
        Configuration; its velocities (if any) only decide whether it spins.
    path : path
        Output ``.png``.
    points_per_element : int
        Samples of the Hermite interpolant per cable element.
    window_size : (int, int)
        Image size in pixels.
    clim : (float, float), optional
        Tension colour range (N); default: the range of the configuration.
    tube_radius : float, optional
        Radius of the tubes (m); default 0.4 % of the scene's diagonal (real tethers are
        far too thin to see).
    title : str, optional
        Text in the upper left corner, above the name of the colour field.
    view : str, optional
        One of ``VIEWS`` (``view_camera``); default the frame's (``"orbital"`` in the
        orbiting frame), else automatic.
    sun : array_like (3,), optional
        Direction towards the Sun: drawn as an arrow (and used by the spin views).
    frame : str
        The frame drawn (``export.FRAMES``): ``"inertial"``, or ``"lvlh"`` for the
        orbiting frame of a system in orbit (the camera is chosen there too).

    Returns
    -------
    ndarray (height, width, 3)
        The image.
    """
    moved = export.output_frame(system, frame)
    q, v = moved.configuration(state.t, state.q, state.v)
    (grid,) = _grids(system, [(q, v, state.t)], points_per_element)
    camera = scene_camera(system, q, v, view or moved.view, sun, points=grid.points)
    return _render_grid(grid, path, window_size, clim, tube_radius, title, camera, sun)


def render_mesh(mesh, path, window_size=(1024, 768), clim=None, tube_radius=None,
                title=None, view="isometric"):
    """Render a ``meshio.Mesh`` of lines (e.g. ``rodchain.chain_mesh``) as ``render``
    draws cables: tubes coloured by ``tension`` (point data, or cell data averaged to the
    points) with its colour bar, an axes triad and a scale bar.  Cells without the cell
    data ``part`` are drawn as cables.  ``view``: ``"isometric"``, or ``"xy"``, ``"xz"``,
    ``"yz"`` (looking along the third axis, for planar motions).  Other arguments and the
    return value as ``render``."""
    if view not in _FIXED_VIEWS:
        raise ValueError(f"view must be one of {tuple(_FIXED_VIEWS)}, got {view!r}")
    use_egl_without_display()
    import pyvista as pv

    grid = pv.from_meshio(mesh)
    if "tension" not in grid.point_data:
        grid = grid.cell_data_to_point_data(pass_cell_data=True)
    if "part" not in grid.cell_data:
        grid.cell_data["part"] = np.full(grid.n_cells, export.PART_CABLE, dtype=np.int32)
    camera = view_camera(view, grid.points)
    return _render_grid(grid, path, window_size, clim, tube_radius, title, camera)


def _save_png(path, img):
    from PIL import Image

    Image.fromarray(img).save(Path(path))


def animate(result, path, every=None, max_frames=150, fps=15, points_per_element=8,
            window_size=(800, 600), clim=None, tube_radius=None, view=None, sun=None,
            up_scale=1.0, title=None, frame="inertial"):
    """Animate a run: a GIF (Pillow) or an MP4 (needs ``imageio-ffmpeg``: the ``video``
    extra) of its saved steps, with fixed camera, scale bar and tension colour range.

    Parameters
    ----------
    result : Result
    path : path
        ``.gif`` or ``.mp4``.
    every : int, optional
        Use every ``every``-th saved step (and the last); default: the smallest stride
        giving at most ``max_frames`` frames.
    fps : float
        Frames per second.
    points_per_element, window_size, clim, tube_radius, view, sun
        As in ``render`` (``clim`` defaults to the tension range over all frames; the
        camera is chosen from all frames and the velocities of the first).
    up_scale : float
        Offsets along the screen's up direction (from the centre of the frames) are
        drawn this many times larger, e.g. to show a small coning in a ``"side"`` view;
        the title says so and the scale bar is then horizontal only.
    title : str, optional
        First line of every frame's text, above the time.
    frame : str
        The frame drawn, as in ``render``.

    Returns
    -------
    int
        Number of frames written.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise ValueError(f"animation path must end in .gif or .mp4, got {str(path)!r}")
    n = len(result)
    every = max(1, int(np.ceil(n / max_frames))) if every is None else int(every)
    idx = list(range(0, n, every))
    if idx[-1] != n - 1:
        idx.append(n - 1)
    moved = export.output_frame(result.system, frame)
    shown = [moved.configuration(result.t[i], result.q[i], result.v[i]) for i in idx]
    grids = _grids(result.system, [(q, v, result.t[i]) for i, (q, v) in zip(idx, shown)],
                   points_per_element)
    camera = scene_camera(result.system, np.array([q for q, _ in shown]),
                          np.array([v for _, v in shown]), view or moved.view, sun,
                          points=np.vstack([g.points for g in grids]))
    lines = [title] if title else []
    if up_scale != 1:
        _stretch(grids, camera, up_scale)
        lines.append(f"vertical offsets drawn {up_scale:g} times larger")
    r = _Renderer(grids, window_size, clim, tube_radius, camera, sun,
                  horizontal_only=up_scale != 1, text_lines=len(lines) + 2)
    try:
        frames = []
        for i, grid in zip(idx, grids):
            r.draw(grid, "\n".join(filter(None, lines + [f"t = {result.t[i]:.4g} s"])))
            frames.append(r.image())
    finally:
        r.close()
    if suffix == ".gif":
        from PIL import Image

        images = [Image.fromarray(f) for f in frames]
        images[0].save(path, save_all=True, append_images=images[1:],
                       duration=int(round(1000 / fps)), loop=0)
    else:
        _write_mp4(path, frames, fps)
    return len(frames)


def _write_mp4(path, frames, fps):
    try:
        import imageio_ffmpeg
    except ImportError:
        raise ImportError("MP4 output needs imageio-ffmpeg: pip install "
                          "'skfem_cable[video]' (or write a .gif)") from None
    h, w = frames[0].shape[:2]
    h2, w2 = h - h % 2, w - w % 2  # yuv420p needs even sizes
    writer = imageio_ffmpeg.write_frames(str(path), (w2, h2), fps=fps, macro_block_size=1)
    writer.send(None)
    for f in frames:
        writer.send(np.ascontiguousarray(f[:h2, :w2]))
    writer.close()


# --- figures ------------------------------------------------------------------------------
def _figure(n_panels, width=7.0, height_per_panel=2.2):
    from matplotlib.figure import Figure  # imported on first use: a second off every import

    fig = Figure(figsize=(width, max(2.5, height_per_panel * n_panels)), layout="constrained")
    axes = fig.subplots(n_panels, 1, sharex=True, squeeze=False)[:, 0]
    return fig, axes


def _finish(fig, path):
    if path is not None:
        fig.savefig(Path(path), dpi=120)
    return fig


#: Most curves of a panel told apart by the default colour cycle and named in a legend;
#: more are coloured from ``CURVE_CMAP`` and named on a colour bar (``curve_colours``).
MAX_LEGEND = 10

#: Colour map of panels with more than ``MAX_LEGEND`` curves (one hue per curve, in order).
CURVE_CMAP = "turbo"


def curve_colours(n):
    """Colours of ``n`` curves of a panel: the default cycle up to ``MAX_LEGEND`` curves,
    else ``n`` samples of ``CURVE_CMAP`` (its darkest ends left out), all distinct."""
    if n <= MAX_LEGEND:
        return [f"C{i}" for i in range(n)]
    from matplotlib import colormaps

    return [tuple(c) for c in colormaps[CURVE_CMAP](np.linspace(0.08, 0.92, n))]


def _curve_key(axes, labels, colours, **legend):
    """Name the curves ``labels`` drawn in ``colours`` on the panels ``axes``: a legend
    on the first panel (keywords ``legend``) up to ``MAX_LEGEND`` curves, else one colour
    bar beside all the panels with a tick per curve, the first at the top."""
    if len(labels) <= MAX_LEGEND:
        axes[0].legend(fontsize="small", **legend)
        return
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import BoundaryNorm, ListedColormap

    n = len(labels)
    mappable = ScalarMappable(BoundaryNorm(np.arange(n + 1) - 0.5, n), ListedColormap(colours))
    bar = axes[0].figure.colorbar(mappable, ax=list(axes), ticks=np.arange(n), pad=0.01,
                                  aspect=12 * len(axes), fraction=0.04)
    bar.ax.set_yticklabels(labels, fontsize="x-small")
    bar.ax.invert_yaxis()
    for ax in axes:  # other named lines (frequency marks) keep a legend
        others = [line for line in ax.get_lines()
                  if line.get_label() not in labels and not line.get_label().startswith("_")]
        if others:
            ax.legend(handles=others, fontsize="small", **legend)


def _plain_numbers(ax):
    """Tick labels of ``ax``'s linear y axis as plain numbers (no ``1e-5 + 1.0008``)."""
    if ax.get_yscale() == "linear":
        ax.ticklabel_format(axis="y", useOffset=False)


def histories(t, panels, path=None, title=None, xlabel="t [s]"):
    """Time histories, one panel per entry (as the E-sail paper's figures of coning and
    lagging angles, hub rates, thrust and reactions), with plain tick labels (no offset).

    Parameters
    ----------
    t : ndarray (nt,)
    panels : dict
        ``{panel label: {curve label: ndarray (nt,)}}``, or ``{panel label: ndarray}`` for
        a single curve; the panel label is the y-axis label.  Named curves get a legend,
        or beyond ``MAX_LEGEND`` distinct colours named on a colour bar (``_curve_key``).
    path : path, optional
        Save the figure there (``.png``, ``.pdf``, ``.svg``).
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, axes = _figure(len(panels))
    for ax, (ylabel, curves) in zip(axes, panels.items()):
        if not isinstance(curves, dict):
            curves = {None: curves}
        colours = curve_colours(len(curves))
        for (label, y), colour in zip(curves.items(), colours):
            ax.plot(t, np.asarray(y), label=label, lw=1.0, color=colour)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        _plain_numbers(ax)
        if any(label is not None for label in curves):
            _curve_key([ax], list(curves), colours, loc="best")
    axes[-1].set_xlabel(xlabel)
    if title:
        fig.suptitle(title)
    return _finish(fig, path)


def _uniform_samples(t, x):
    """``t``, ``x`` and the step, without a shortened last step; raises ``ValueError``
    unless uniformly spaced."""
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    dt = np.diff(t)
    if len(dt) > 1 and abs(dt[-1] - dt[0]) > 1e-6 * dt[0]:
        # a run's last saved step may follow a shortened final step: leave it out
        t, x, dt = t[:-1], x[:-1], dt[:-1]
    if len(t) < 8 or np.ptp(dt) > 1e-6 * dt.mean():
        raise ValueError("the PSD needs at least 8 uniformly spaced samples "
                         "(save steps with a constant stride)")
    return t, x, float(dt.mean())


def welch_plan(n, dt, segments=4, f_min=None, cycles=4):
    """Segment and FFT lengths (samples) of ``spectrum`` for ``n`` samples ``dt`` apart.

    With ``f_min`` (Hz, the lowest frequency to resolve, e.g. a spin frequency): segments
    of ``cycles`` periods of ``f_min`` (bins ``f_min / cycles`` wide), half-overlapping
    and averaged as often as the run allows; a shorter run is one segment zero-padded to
    that length (the bins are as fine, but peaks closer than about ``2 / (n dt)``, the
    Hann window's main lobe, merge).  Otherwise ``segments`` half-overlapping segments.

    Returns
    -------
    nperseg, nfft : int
    """
    if f_min is not None:
        nfft = int(np.ceil(cycles / (f_min * dt)))
        return min(n, nfft), nfft
    nperseg = min(n, max(8, 2 * n // (segments + 1)))
    return nperseg, nperseg


def spectrum(t, x, segments=4, f_min=None, cycles=4):
    """One-sided power spectral density of a uniformly sampled signal (Welch's method,
    Hann window, half-overlapping segments of ``welch_plan``, mean removed).

    Returns ``f`` (Hz) and ``psd`` (units^2 / Hz).
    """
    from scipy.signal import welch

    t, x, dt = _uniform_samples(t, x)
    nperseg, nfft = welch_plan(len(t), dt, segments, f_min, cycles)
    return welch(x, fs=1.0 / dt, nperseg=nperseg, nfft=nfft, detrend="constant")


def _psd_unit(unit):
    """Unit of the PSD of a signal in ``unit`` (``""``, "1" or None: dimensionless)."""
    return "1/Hz" if unit in (None, "", "1") else f"{unit}$^2$/Hz"


def psd(t, signals, path=None, title=None, markers=None, units=None, f_min=None):
    """Power spectral densities of several signals on log axes (the paper's PSD figures),
    one panel per unit, with vertical marks at known frequencies.

    Parameters
    ----------
    t : ndarray (nt,)
        Uniform sample times.
    signals : dict
        ``{label: ndarray (nt,)}``.
    markers : dict, optional
        ``{label: frequency in Hz}`` (a dashed line named on the top axis, e.g. the spin
        or a tabulated mode), or ``{label: sequence of frequencies}`` (dotted lines with
        one legend entry, e.g. computed modes).  Frequencies outside the plotted band are
        left out.
    units : str or dict, optional
        Unit of every signal, or ``{label: unit}`` (``""``: dimensionless); the y label
        is ``PSD [unit^2/Hz]``.  Default: ``"unit"``.
    f_min : float, optional
        Lowest frequency to resolve (Hz), which sets the segments (``welch_plan``);
        default: 4 half-overlapping segments.  The segments and bin width are printed
        on the figure.
    """
    units = units if isinstance(units, dict) else dict.fromkeys(signals, units or "unit")
    panels = {}
    for label, x in signals.items():
        panels.setdefault(units[label], {})[label] = x
    fig, axes = _figure(len(panels), height_per_panel=3.0 if len(panels) > 1 else 3.5)
    for ax, (unit, group) in zip(axes, panels.items()):
        for (label, x), colour in zip(group.items(), curve_colours(len(group))):
            f, p = spectrum(t, x, f_min=f_min)
            ax.loglog(f[1:], p[1:], label=label, lw=1.0, color=colour)
        ax.set_xlim(f[1], f[-1])
        ax.set_ylim(bottom=max(ax.get_ylim()[0], 1e-12 * ax.get_ylim()[1]))
        ax.set_ylabel(f"PSD [{_psd_unit(unit)}]")
        ax.grid(True, which="both", alpha=0.3)
    _frequency_marks(axes, markers or {}, (f[1], f[-1]))
    for ax, group in zip(axes, panels.values()):
        _curve_key([ax], list(group), curve_colours(len(group)), loc="lower left")
    axes[-1].set_xlabel("frequency [Hz]")
    fig.supxlabel(_welch_note(t, next(iter(signals.values())), f_min), fontsize="x-small",
                  color="dimgray")
    if title:
        fig.suptitle(title)
    return _finish(fig, path)


def _welch_note(t, x, f_min):
    """What ``spectrum`` averaged: segments, their length, the bin width and, for a
    zero-padded segment, the resolution the run allows."""
    t, _, dt = _uniform_samples(t, x)
    nperseg, nfft = welch_plan(len(t), dt, f_min=f_min)
    count = 1 + (len(t) - nperseg) // (nperseg - nperseg // 2)
    note = (f"Welch, Hann window: {count} segment{'s' if count > 1 else ''} of "
            f"{nperseg * dt:.4g} s; bins {1 / (nfft * dt):.3g} Hz")
    if nfft > nperseg:
        note += f"\nzero-padded: peaks closer than ~{2 / (nperseg * dt):.2g} Hz merge"
    return note


#: Colours of the dotted frequency marks (``psd``).
_MARK_COLOURS = ("tab:red", "tab:purple", "tab:brown", "tab:olive")


def _frequency_marks(axes, markers, band):
    """Dashed lines at single frequencies (named on a top axis) and dotted ones at
    sequences (one legend entry each), inside ``band``."""
    named, groups = {}, {}
    for label, value in markers.items():
        fs = np.atleast_1d(np.asarray(value, dtype=float))
        fs = fs[(fs >= band[0]) & (fs <= band[1])]
        if fs.size:
            (named if np.ndim(value) == 0 else groups)[label] = fs
    for ax in axes:
        for (f0,) in named.values():
            ax.axvline(f0, color="dimgray", ls="--", lw=0.9)
        for (label, fs), colour in zip(groups.items(), cycle(_MARK_COLOURS)):
            for i, f0 in enumerate(fs):
                ax.axvline(f0, color=colour, ls=":", lw=1.0, alpha=0.7,
                           label=None if i else label)
    if named:
        top = axes[0].secondary_xaxis("top")
        top.set_xticks([f0 for (f0,) in named.values()], list(named), fontsize="small")
        top.minorticks_off()
        top.tick_params(colors="dimgray")


#: Energy terms of ``energies``' first panel.
ENERGY_TERMS = ("kinetic", "axial", "bending", "potential", "dissipated", "external_work")


def energy_scale(E):
    """Energy in play in a run (J): the largest ``kinetic + axial + bending +
    |potential change| + dissipated + |external work|`` over its saved steps."""
    content = (np.abs(E["kinetic"]) + np.abs(E["axial"]) + np.abs(E["bending"])
               + np.abs(E["potential"] - E["potential"][0]) + np.abs(E["dissipated"])
               + np.abs(E["external_work"]))
    return float(content.max())


def energy_figure(t, E, path=None, title="Energy"):
    """``energies`` from the times and the energy dict (``Result.energy``'s keys)."""
    fig, (terms, balance, drift) = _figure(3, width=8.5)
    constant = [k for k in ENERGY_TERMS if not np.any(E[k] - E[k][0])]
    for k in ENERGY_TERMS:
        if k not in constant:
            change = E[k] - E[k][0]
            terms.plot(t, change, **_energy_style(k),
                       label=f"{k.replace('_', ' ')}\n(max |Δ| {np.abs(change).max():.2g} J)")
    terms.set_ylabel("change since\nfirst step [J]")
    terms.legend(fontsize="small", loc="center left", bbox_to_anchor=(1.01, 0.5),
                 title=_constant_note(constant), title_fontsize="small")
    balance.plot(t, E["balance"], color="k", lw=1.0)
    balance.set_ylabel("balance\nresidual [J]")
    scale = energy_scale(E)
    rel = np.abs(E["balance"]) / scale if scale > 0 else np.zeros_like(t)
    drift.semilogy(t, np.where(rel > 0, rel, np.nan), color="tab:red", lw=1.0)
    if not np.any(rel > 0):
        drift.text(0.5, 0.5, "balance exactly zero", transform=drift.transAxes, ha="center")
    drift.set_ylabel("|balance| / E_scale")
    drift.set_title(f"E_scale = max(K + V_axial + V_bending + |ΔV_pot| + D + |W|) = "
                    f"{scale:.4g} J", fontsize="small", loc="left")
    for ax in (terms, balance, drift):
        ax.grid(True, which="both", alpha=0.3)
    _plain_numbers(balance)
    drift.set_xlabel("t [s]")
    if title:
        fig.suptitle(title)
    return _finish(fig, path)


def _energy_style(term):
    """Line style of an energy term: the works (dissipated energy, external work) wide,
    pale and dashed under the energies they feed, which stay visible on top."""
    colour = f"C{ENERGY_TERMS.index(term)}"
    if term in ("dissipated", "external_work"):
        return {"color": colour, "lw": 3.0, "ls": "--", "alpha": 0.5, "zorder": 1}
    return {"color": colour, "lw": 1.0, "zorder": 3}


def _constant_note(constant):
    """Legend title naming the energy terms left out because they never change."""
    if not constant:
        return None
    names = ", ".join(k.replace("_", " ") for k in constant)
    return f"constant over the run\n(not drawn): {names}"


def energies(result, path=None, title="Energy"):
    """Energy books of a run in three panels: the terms (kinetic, axial, bending,
    potential energy; dissipated energy and external work) as changes since the first
    saved step, the balance residual (J), and the relative drift ``|balance| / E_scale``
    (``energy_scale``) on a log axis."""
    return energy_figure(result.t, result.energy, path, title)


def speed_error(rows, path=None, group="elements", cost="wall", error="error", title=None):
    """Speed against error of a benchmark: one log-log curve per value of ``group``.

    Parameters
    ----------
    rows : iterable of dict
        Each with the keys ``group``, ``cost`` (e.g. wall time in s) and ``error``.
    """
    rows = list(rows)
    fig, (ax,) = _figure(1, height_per_panel=3.5)
    for g in sorted({r[group] for r in rows}):
        sel = sorted((r for r in rows if r[group] == g), key=lambda r: r[cost])
        ax.loglog([r[cost] for r in sel], [r[error] for r in sel], "o-", label=f"{group} = {g}")
    ax.set_xlabel(cost)
    ax.set_ylabel(error)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    if title:
        fig.suptitle(title)
    return _finish(fig, path)


def rigid_fit(points):
    """Rigid motions that best carry the first row of ``points`` (nt, m, 3) onto each
    row (least squares, Kabsch): rotations ``R`` (nt, 3, 3) and centroids ``c`` (nt, 3)
    with ``points[k] ~ c[k] + (points[0] - c[0]) @ R[k].T``."""
    points = np.asarray(points, dtype=float)
    c = points.mean(axis=1)
    rel = points - c[:, None]
    U, _, Vt = np.linalg.svd(np.einsum("mi,tmj->tij", rel[0], rel))
    V = np.swapaxes(Vt, -1, -2)
    d = np.sign(np.linalg.det(V @ np.swapaxes(U, -1, -2)))
    D = np.broadcast_to(np.eye(3), V.shape).copy()
    D[:, 2, 2] = d
    return V @ D @ np.swapaxes(U, -1, -2), c


def corotated(result, x):
    """Points ``x`` (nt, ..., 3) of a run carried back by the rigid motion fitted to all
    its positions (``rigid_fit``) into where they would be at the first saved step: their
    motion relative to the frame that moves (spins) with the system as a whole."""
    system = result.system
    R, c = rigid_fit(result.q[:, system.vectors[system.vector_is_position]])
    rel = np.asarray(x, dtype=float) - c.reshape((len(c),) + (1,) * (np.ndim(x) - 2) + (3,))
    back = np.einsum("tji,t...j->t...i", R, rel)
    return back + c[0]


def cable_histories(result, path=None, title=None):
    """Tip displacement, root tension and peak tension of every cable of a run, one colour
    per cable (``curve_colours``; a colour bar names them beyond ``MAX_LEGEND``).  In a
    spinning run (``spin_axis`` of the first saved step) the tip displacement is measured
    in the frame spinning with the system (``corotated``), so that it shows the tethers'
    motion rather than the rotation's chord."""
    system = result.system
    cables = system.cables()
    tips = np.stack([result.position(c, c.length) for c in cables], axis=1)
    spinning = spin_axis(system, result.q[0], result.v[0]) is not None
    if spinning:
        tips = corotated(result, tips)
    panels = {"tip displacement\nin the spinning frame [m]" if spinning else
              "tip displacement [m]": np.linalg.norm(tips - tips[0], axis=-1),
              "root tension [N]": np.stack([result.tension(c, 0.0) for c in cables], axis=1),
              "peak tension [N]": np.stack([result.tension(c, c.mesh.p[0]).max(axis=-1)
                                            for c in cables], axis=1)}
    fig, axes = _figure(len(panels))
    colours = curve_colours(len(cables))
    for ax, (ylabel, values) in zip(axes, panels.items()):
        for k, (cable, colour) in enumerate(zip(cables, colours)):
            ax.plot(result.t, values[:, k], lw=1.0, color=colour, label=cable.name)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        _plain_numbers(ax)
    if len(cables) > 1:
        _curve_key(axes, [c.name for c in cables], colours, loc="best")
    axes[-1].set_xlabel("t [s]")
    if title:
        fig.suptitle(title)
    return _finish(fig, path)
