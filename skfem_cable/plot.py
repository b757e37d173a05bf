"""Pictures of configurations and runs: 3-D renders (pyvista, off-screen) and figures of
time histories, spectra and speed-vs-error tables (matplotlib, no display needed).

Renders show the cables as tubes coloured by tension, rigid bodies as solids and point
masses as spheres, from the same mesh as ``export.system_mesh``.  They need an OpenGL
context but no display: on Linux without ``DISPLAY`` VTK is pointed at EGL (Mesa's
``libegl1``, ``libegl-mesa0``, ``libgl1-mesa-dri``; ``scripts/install_system_deps.sh``
installs them), and ``rendering_available`` tells whether a context can be created.
"""

import os
import subprocess
import sys
from functools import lru_cache
from pathlib import Path

import numpy as np

from . import export

#: Colour map of the tension along the tubes.
TENSION_CMAP = "viridis"


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
    """pyvista grids of the configurations ``frames`` (pairs ``(q, v)``)."""
    use_egl_without_display()
    import pyvista as pv

    return [pv.from_meshio(export.system_mesh(system, q, v, points_per_element))
            for q, v in frames]


class _Renderer:
    """An off-screen plotter drawing configurations (grids of ``_grids``) with fixed
    colour limits, tube radius and camera, so that the frames of an animation match."""

    def __init__(self, grids, window_size, clim, tube_radius):
        import pyvista as pv

        self.pv = pv
        points = np.vstack([g.points for g in grids])
        lo, hi = points.min(axis=0), points.max(axis=0)
        diag = float(np.linalg.norm(hi - lo)) or 1.0
        self.radius = 0.004 * diag if tube_radius is None else tube_radius
        if clim is None:
            tension = np.concatenate([g.point_data["tension"] for g in grids])
            tension = tension[np.isfinite(tension)]
            clim = (tension.min(), tension.max()) if tension.size else (0.0, 1.0)
            if clim[1] <= clim[0]:
                clim = (clim[0] - 0.5, clim[0] + 0.5)
        self.clim = clim
        self.plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
        self.plotter.set_background("white")
        self.plotter.view_isometric()
        self.plotter.reset_camera(bounds=(lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]))

    def draw(self, grid, title=None):
        """Replace the drawn configuration by ``grid`` (one of ``_grids``)."""
        pl = self.plotter
        pl.clear_actors()
        for bar in list(pl.scalar_bars.keys()):
            pl.remove_scalar_bar(bar)
        part = grid.cell_data["part"]
        for value, style in ((export.PART_CABLE, "tube"), (export.PART_RIGID, "solid"),
                             (export.PART_POINT_MASS, "sphere")):
            if not np.any(part == value):
                continue
            piece = grid.extract_cells(part == value).extract_surface(algorithm=None)
            if style == "tube":
                tube = piece.tube(radius=self.radius, n_sides=16)
                pl.add_mesh(tube, scalars="tension", cmap=TENSION_CMAP, clim=self.clim,
                            smooth_shading=True,
                            scalar_bar_args={"title": "tension [N]", "color": "black",
                                             "vertical": True, "position_x": 0.83,
                                             "position_y": 0.1, "height": 0.8,
                                             "width": 0.06, "fmt": "%.3g"})
            elif style == "solid":
                solid = piece.compute_normals(split_vertices=True, feature_angle=30.0)
                pl.add_mesh(solid, color="lightsteelblue", smooth_shading=True)
            else:
                spheres = piece.glyph(geom=self.pv.Sphere(radius=3 * self.radius),
                                      scale=False, orient=False)
                pl.add_mesh(spheres, color="firebrick", smooth_shading=True)
        if title:
            pl.add_text(title, position="upper_left", font_size=10, color="black")

    def image(self):
        return self.plotter.screenshot(return_img=True)

    def close(self):
        self.plotter.close()


def render(system, state, path, points_per_element=8, window_size=(1024, 768), clim=None,
           tube_radius=None, title=None):
    """Render one configuration to a PNG.

    Parameters
    ----------
    system : System
    state : State
        Configuration (its velocities, if any, are not drawn).
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
        Text in the upper left corner.

    Returns
    -------
    ndarray (height, width, 3)
        The image.
    """
    grids = _grids(system, [(state.q, state.v)], points_per_element)
    r = _Renderer(grids, window_size, clim, tube_radius)
    try:
        r.draw(grids[0], title)
        img = r.image()
    finally:
        r.close()
    _save_png(path, img)
    return img


def render_mesh(mesh, path, window_size=(1024, 768), clim=None, tube_radius=None,
                title=None, view="isometric"):
    """Render a ``meshio.Mesh`` of lines (e.g. ``rodchain.chain_mesh``) as ``render``
    draws cables: tubes coloured by ``tension`` (point data, or cell data averaged to the
    points) with its colour bar.  Cells without the cell data ``part`` are drawn as
    cables.  ``view``: ``"isometric"`` (the camera of ``render``), or ``"xy"``, ``"xz"``,
    ``"yz"`` (looking along the third axis, for planar motions).  Other arguments and the
    return value as ``render``."""
    views = ("isometric", "xy", "xz", "yz")
    if view not in views:
        raise ValueError(f"view must be one of {views}, got {view!r}")
    use_egl_without_display()
    import pyvista as pv

    grid = pv.from_meshio(mesh)
    if "tension" not in grid.point_data:
        grid = grid.cell_data_to_point_data(pass_cell_data=True)
    if "part" not in grid.cell_data:
        grid.cell_data["part"] = np.full(grid.n_cells, export.PART_CABLE, dtype=np.int32)
    r = _Renderer([grid], window_size, clim, tube_radius)
    try:
        if view != "isometric":
            getattr(r.plotter, f"view_{view}")()
            _fit_left_of_colour_bar(r.plotter, grid.bounds)
        r.draw(grid, title)
        img = r.image()
    finally:
        r.close()
    _save_png(path, img)
    return img


def _fit_left_of_colour_bar(plotter, bounds, room=0.3):
    """Fit the camera (direction kept) to ``bounds`` widened by ``room`` times their
    on-screen width to the right, so that the colour bar at the right edge covers
    nothing, with a margin all round."""
    cam = plotter.camera
    d = np.subtract(cam.focal_point, cam.position)
    right = np.cross(d / np.linalg.norm(d), cam.up)
    lo, hi = np.array(bounds[::2]), np.array(bounds[1::2])
    shift = room * float(np.abs(right) @ (hi - lo)) * right
    lo, hi = np.minimum(lo, lo + shift), np.maximum(hi, hi + shift)
    plotter.reset_camera(bounds=(lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]))
    cam.zoom(0.9)


def _save_png(path, img):
    from PIL import Image

    Image.fromarray(img).save(Path(path))


def animate(result, path, every=None, max_frames=150, fps=15, points_per_element=8,
            window_size=(800, 600), clim=None, tube_radius=None):
    """Animate a run: a GIF (Pillow) or an MP4 (needs ``imageio-ffmpeg``: the ``video``
    extra) of its saved steps, with fixed camera and tension colour range.

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
    points_per_element, window_size, clim, tube_radius
        As in ``render`` (``clim`` defaults to the tension range over all frames).

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
    grids = _grids(result.system, [(result.q[i], result.v[i]) for i in idx],
                   points_per_element)
    r = _Renderer(grids, window_size, clim, tube_radius)
    try:
        frames = []
        for i, grid in zip(idx, grids):
            r.draw(grid, f"t = {result.t[i]:.4g} s")
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


def histories(t, panels, path=None, title=None, xlabel="t [s]"):
    """Time histories, one panel per entry (as the E-sail paper's figures of coning and
    lagging angles, hub rates, thrust and reactions).

    Parameters
    ----------
    t : ndarray (nt,)
    panels : dict
        ``{panel label: {curve label: ndarray (nt,)}}``, or ``{panel label: ndarray}`` for
        a single curve; the panel label is the y-axis label.
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
        for label, y in curves.items():
            ax.plot(t, np.asarray(y), label=label, lw=1.0)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        if any(label is not None for label in curves) and len(curves) <= 8:
            ax.legend(fontsize="small", loc="best")  # (no room for more: unlabelled)
    axes[-1].set_xlabel(xlabel)
    if title:
        fig.suptitle(title)
    return _finish(fig, path)


def spectrum(t, x, segments=4):
    """One-sided power spectral density of a uniformly sampled signal (Welch's method,
    Hann window, ``segments`` half-overlapping segments, mean removed).

    Returns ``f`` (Hz) and ``psd`` (units^2 / Hz).
    """
    from scipy.signal import welch

    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    dt = np.diff(t)
    if len(dt) > 1 and abs(dt[-1] - dt[0]) > 1e-6 * dt[0]:
        # a run's last saved step may follow a shortened final step: leave it out
        t, x, dt = t[:-1], x[:-1], dt[:-1]
    if len(t) < 8 or np.ptp(dt) > 1e-6 * dt.mean():
        raise ValueError("the PSD needs at least 8 uniformly spaced samples "
                         "(save steps with a constant stride)")
    nperseg = min(len(t), max(8, 2 * len(t) // (segments + 1)))
    return welch(x, fs=1.0 / dt.mean(), nperseg=nperseg,
                 detrend="constant")


def psd(t, signals, path=None, title=None, markers=None):
    """Power spectral densities of several signals on log axes (the paper's PSD figures),
    with optional vertical markers at known frequencies.

    Parameters
    ----------
    t : ndarray (nt,)
        Uniform sample times.
    signals : dict
        ``{label: ndarray (nt,)}``.
    markers : dict, optional
        ``{label: frequency in Hz}``, e.g. the spin rate or natural frequencies.
    """
    fig, (ax,) = _figure(1, height_per_panel=3.5)
    for label, x in signals.items():
        f, p = spectrum(t, x)
        ax.loglog(f[1:], p[1:], label=label, lw=1.0)
    for label, f0 in (markers or {}).items():
        ax.axvline(f0, color="gray", ls="--", lw=0.8)
        ax.text(f0, 1.0, f" {label}", transform=ax.get_xaxis_transform(), rotation=90,
                va="top", fontsize="small", color="gray")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("PSD [unit$^2$/Hz]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    if title:
        fig.suptitle(title)
    return _finish(fig, path)


def energies(result, path=None, title="Energy"):
    """Energy histories of a run: total and balance; kinetic, elastic and potential;
    dissipated and external work (the paper's Fig. 8)."""
    E = result.energy
    panels = {"total, balance [J]": {"total": E["total"], "balance": E["balance"]},
              "energy [J]": {k: E[k] for k in ("kinetic", "axial", "bending", "potential")},
              "work [J]": {k: E[k] for k in ("dissipated", "external_work")}}
    return histories(result.t, panels, path, title)


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


def cable_histories(result, path=None, title=None):
    """Tip displacement and root/peak tension of every cable of a run."""
    system = result.system
    tips, tension = {}, {}
    for cable in system.cables():
        tip = result.position(cable, cable.length)
        tips[cable.name] = np.linalg.norm(tip - tip[0], axis=-1)
        tension[f"{cable.name} root"] = result.tension(cable, 0.0)
        s = cable.mesh.p[0]
        tension[f"{cable.name} max"] = result.tension(cable, s).max(axis=-1)
    panels = {"tip displacement [m]": tips, "tension [N]": tension}
    return histories(result.t, panels, path, title)
