"""3-D renders of configurations and runs (pyvista, off-screen): ``render`` (one
configuration to a PNG), ``render_mesh`` (a ``meshio`` mesh of lines) and ``animate`` (a run
to a GIF or an MP4).

They show the cables as tubes coloured by tension, rigid bodies as solids and point masses
as spheres, from the same mesh as ``export.system_mesh``, with an axes triad, a scale bar
and a colour bar whose labels carry enough digits for the range, in parallel projection
from a camera chosen from the scene (``plot.cameras``).  They need an OpenGL context but no
display: on Linux without ``DISPLAY`` VTK is pointed at EGL (Mesa's ``libegl1``,
``libegl-mesa0``, ``libgl1-mesa-dri``; ``scripts/install_system_deps.sh`` installs them),
and ``rendering_available`` tells whether a context can be created.
"""

import os
import subprocess
import sys
from functools import lru_cache
from pathlib import Path

import numpy as np

from ..core.contract import PART_CABLE, PART_POINT_MASS, PART_RIGID
from ..io import export
from .cameras import _FIXED_VIEWS, _unit, scene_camera, view_camera

#: Colour map of the tension along the tubes.
TENSION_CMAP = "viridis"


def _window_environment():
    """This process's environment with, on Linux without an X display, VTK's EGL render
    windows chosen (no X warning, no Xvfb needed); an explicit
    ``VTK_DEFAULT_OPENGL_WINDOW`` is respected."""
    env = dict(os.environ)
    if sys.platform.startswith("linux") and not env.get("DISPLAY"):
        env.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    return env


def use_egl_without_display():
    """Make this process's VTK open the render windows of ``_window_environment``."""
    os.environ.update(_window_environment())


_PROBE = """
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
    the process rather than raise; the child opens the windows of
    ``use_egl_without_display`` (this process's environment is left as it is) and imports
    pyvista alone (not this package: 2 s less).
    """
    try:
        proc = subprocess.run([sys.executable, "-c", _PROBE], capture_output=True, text=True,
                              timeout=120, env=_window_environment())
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
        for value in (PART_CABLE, PART_RIGID, PART_POINT_MASS):
            if not np.any(part == value):
                continue
            piece = grid.extract_cells(part == value).extract_surface(algorithm=None)
            if value == PART_CABLE:
                yield piece.tube(radius=self.radius, n_sides=16), {
                    "scalars": "tension", "cmap": TENSION_CMAP, "clim": self.clim,
                    "smooth_shading": True, "scalar_bar_args": {
                        "title": "tension [N]", "color": "black", "vertical": True,
                        "position_x": 0.84, "position_y": 0.1, "height": 0.75,
                        "width": 0.05, "n_labels": 5, "fmt": colorbar_format(*self.clim)}}
            elif value == PART_RIGID:
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
        grid.cell_data["part"] = np.full(grid.n_cells, PART_CABLE, dtype=np.int32)
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
    moved = export.output_frame(result.system, frame, result.reference)
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
