"""Renders (off-screen OpenGL) and matplotlib figures."""

import numpy as np
import pytest
from PIL import Image

import skfem_cable as sc
from skfem_cable import plot
from skfem_cable.bodies.rigid import RigidBody
from skfem_cable.scenes import classics, esail


@pytest.fixture(scope="module")
def needs_opengl():
    ok, reason = plot.rendering_available()
    if not ok:
        pytest.skip(reason)


def test_render_shows_hub_tether_and_tension_colours(needs_opengl, tmp_path):
    """A hub with a stretched tether: the PNG is not blank, shows the grey hub and a tube
    whose colours span the colour map (the tension grows along the tether)."""
    hub = RigidBody.cylinder(radius=0.5, height=1.0, density=884.0)
    sec = sc.Section.circular(radius=0.01, E=7e10, rho=7800.0)
    tether = sc.Cable.straight([0, 0.5, 0], [0, 3.5, 0], 6, sec)
    system = sc.System([hub, tether]).pin(tether.node(0), hub.point([0, 0.5, 0]))
    system.add_point_mass(tether.node(-1), 1.0)
    q = system.q0.copy()
    nodes = q[system.dofs(tether)].reshape(-1, 2, 3)
    x = np.linspace(0.0, 1.0, len(nodes))
    nodes[:, 0, 1] = 0.5 + 3 * (x + 0.05 * x**2)  # strain growing along the tether
    nodes[:, 1, 1] = 1 + 0.1 * x
    q[system.dofs(tether)] = nodes.ravel()
    path = tmp_path / "scene.png"
    img = plot.render(system, sc.State(system, q), path, window_size=(400, 300))
    back = np.asarray(Image.open(path).convert("RGB"))
    assert back.shape == (300, 400, 3) and np.array_equal(back, img)
    background = (back == 255).all(axis=-1)
    assert 0.01 < 1 - background.mean() < 0.9
    colours = np.unique(back[~background].reshape(-1, 3) // 16, axis=0)
    assert len(colours) > 20
    grey = (np.abs(back.astype(int) - back.mean(axis=-1, keepdims=True)).max(axis=-1) < 12)
    assert (grey & ~background).mean() > 0.005  # the hub


def test_animation_gif_has_one_frame_per_selected_step(needs_opengl, tmp_path):
    scene = classics.pendulum(n_elements=3)
    result = sc.simulate(scene.system, t_end=0.1, dt=5e-3)
    path = tmp_path / "run.gif"
    n = plot.animate(result, path, max_frames=6, window_size=(160, 120))
    assert n == 6  # 21 saved steps, stride 4 -> 0, 4, ..., 20
    gif = Image.open(path)
    assert gif.n_frames == n
    first = np.asarray(gif.convert("RGB"))
    gif.seek(n - 1)
    assert not np.array_equal(first, np.asarray(gif.convert("RGB")))  # it moved


def test_animation_rejects_unknown_format(tmp_path):
    with pytest.raises(ValueError, match=r"\.gif or \.mp4"):
        plot.animate(None, tmp_path / "run.avi")


def test_spectrum_peak_at_signal_frequency():
    t = np.arange(4000) * 1e-3
    f, p = plot.spectrum(t, 2.0 + np.sin(2 * np.pi * 12.5 * t) + 0.1 * np.sin(2 * np.pi * 70 * t))
    assert f[np.argmax(p)] == pytest.approx(12.5, abs=f[1])
    with pytest.raises(ValueError, match="uniformly spaced"):
        plot.spectrum(np.sort(np.random.default_rng(0).uniform(size=50)), np.zeros(50))


def test_figures_are_written(tmp_path):
    scene = classics.pendulum(n_elements=3, gamma_axial=1e-4)
    result = sc.simulate(scene.system, t_end=0.1, dt=2e-3)
    fig = plot.energies(result, tmp_path / "energies.png")
    terms, balance, drift = fig.axes
    assert drift.get_yscale() == "log" and balance.get_yscale() == "linear"
    assert np.array_equal(balance.lines[0].get_ydata(), result.energy["balance"])
    scale = plot.energy_scale(result.energy)
    assert scale >= result.energy["kinetic"].max() > 0
    assert np.allclose(drift.lines[0].get_ydata()[1:],
                       np.abs(result.energy["balance"][1:]) / scale)
    assert len(terms.lines) == 5  # external work is zero to rounding: named in the legend title
    assert "external work" in terms.get_legend().get_title().get_text()
    plot.cable_histories(result, tmp_path / "cables.png")
    plot.psd(result.t, {"tip x": result.position(scene.cable, 1.2)[:, 0]},
             tmp_path / "psd.svg", markers={"pendulum": 0.47})
    rows = [{"elements": n, "wall": w, "error": e}
            for n, w, e in ((4, 0.1, 1e-2), (4, 0.2, 3e-3), (8, 0.3, 1e-3), (8, 0.6, 2e-4))]
    fig = plot.speed_error(rows, tmp_path / "speed.pdf")
    assert [line.get_label() for line in fig.axes[0].lines] == ["elements = 4", "elements = 8"]
    for name in ("energies.png", "cables.png", "psd.svg", "speed.pdf"):
        assert (tmp_path / name).stat().st_size > 1000


# --- cameras ------------------------------------------------------------------------------
def test_camera_with_gravity_has_up_against_gravity():
    """Up is -g; the eye looks horizontally across the cable's main extent, which runs
    left to right towards +x."""
    scene = classics.pendulum(n_elements=3)  # along +x, g along -y
    cam = plot.scene_camera(scene.system, scene.system.q0)
    assert cam.up == pytest.approx([0, 1, 0])
    assert cam.eye == pytest.approx([0, 0, 1])
    assert np.cross(cam.up, cam.eye) == pytest.approx([1, 0, 0])  # screen right
    g = np.array([1.0, -2.0, 0.5])
    cable = sc.Cable.straight([0, 0, 0], [0, 0, 1], 2, scene.cable.section)
    system = sc.System([cable]).pin(cable.node(0)).add_gravity(g)
    cam = plot.scene_camera(system, system.q0)
    assert cam.up == pytest.approx(-g / np.linalg.norm(g))
    assert cam.eye @ cam.up == pytest.approx(0, abs=1e-12)


def test_camera_of_a_spinning_scene_looks_along_or_across_the_spin_axis():
    scene = classics.spinning_tether(n_elements=2)  # spins about +z, no gravity
    q, v = scene.initial.q, scene.initial.v
    assert plot.spin_axis(scene.system, q, v) == pytest.approx([0, 0, 1])
    assert plot.spin_axis(scene.system, q, 0 * v) is None
    assert plot.scene_camera(scene.system, q, v).eye == pytest.approx([0, 0, 1])
    side = plot.scene_camera(scene.system, q, v, view="side", sun=[-1, 1, 0])
    assert side.up == pytest.approx([0, 0, 1])
    assert side.eye @ [-1, 1, 0] == pytest.approx(0, abs=1e-12)  # the Sun in the picture
    assert np.cross(side.up, side.eye) @ [-1, 1, 0] < 0  # ... on the left
    assert plot.scene_camera(scene.system, q).eye == pytest.approx(np.ones(3) / np.sqrt(3))
    with pytest.raises(ValueError, match="needs a scene with gravity"):
        plot.scene_camera(scene.system, q, v, view="gravity")


def test_colour_bar_labels_of_a_narrow_range_are_distinct():
    for lo, hi in ((213.0001, 213.0009), (0.0383, 0.0794), (0.0, 1e6), (1e-7, 1.3e-7),
                   (-5.0, 5.0)):
        fmt = plot.colorbar_format(lo, hi)
        values = np.linspace(lo, hi, 5)
        labels = [fmt % x for x in values]
        assert len(set(labels)) == 5, (lo, hi, labels)
        assert np.abs(np.array([float(s) for s in labels]) - values).max() <= (hi - lo) / 40
    assert [plot.nice_length(x) for x in (0.36, 7.3e3, 1.0)] == [0.2, 5e3, 1.0]
    assert plot.format_length(5e3) == "5 km" and plot.format_length(0.5) == "0.5 m"


def test_render_of_a_hanging_cable_is_upright(needs_opengl, tmp_path):
    """A cable pinned at both ends sags downwards on the picture (up is -g), the tension
    colours and a scale bar are drawn."""
    sec = sc.Section.circular(radius=5e-4, E=2e11, rho=7800.0)
    cable = sc.Cable.straight([0, 0, 0], [2, 0, 0], 8, sec)
    system = sc.System([cable]).pin(cable.node(0), [0, 0, 0]).pin(cable.node(-1), [2, 0, 0])
    system.add_gravity([0, -9.81, 0])
    q = system.q0.copy()
    nodes = q[system.dofs(cable)].reshape(-1, 2, 3)
    x = nodes[:, 0, 0]
    nodes[:, 0, 1] = -0.3 * np.sin(np.pi * x / 2)  # sagging along -y
    nodes[:, 1, 1] = -0.15 * np.pi * np.cos(np.pi * x / 2)
    q[system.dofs(cable)] = nodes.ravel()
    img = plot.render(system, sc.State(system, q), tmp_path / "hang.png",
                      window_size=(400, 300))[:240, :330]  # above the triad, left of the bar
    coloured = np.ptp(img.astype(int), axis=-1) > 60
    rows, cols = np.nonzero(coloured)
    middle = rows[np.abs(cols - cols.mean()) < 10].mean()
    ends = rows[np.abs(cols - cols.mean()) > 0.4 * np.ptp(cols)].mean()
    assert middle > ends + 20  # the sag is below the ends (image rows grow downwards)
    black = (img < 40).all(axis=-1)
    assert black[rows.max() + 1:].sum() > 50  # the scale bar below the cable


def test_side_view_animation_draws_the_sun_arrow(needs_opengl, tmp_path):
    scene = classics.spinning_tether(n_elements=2)
    result = sc.simulate(scene.system, t_end=0.2, dt=0.02, initial=scene.initial)
    n = plot.animate(result, tmp_path / "side.gif", max_frames=3, window_size=(240, 180),
                     view="side", sun=[-1, 0, 0], up_scale=5.0)
    assert n == 4  # 11 saved steps, stride 4 -> 0, 4, 8, 10
    frame = np.asarray(Image.open(tmp_path / "side.gif").convert("RGB")).astype(int)
    orange = (frame[..., 0] > 180) & (frame[..., 1] > 80) & (frame[..., 1] < 170) & (
        frame[..., 2] < 80)
    assert orange.sum() > 20


# --- spectra --------------------------------------------------------------------------------
def test_psd_window_resolves_the_spin_frequency():
    """Bins narrower than a quarter of f_min, whatever the run length: zero-padded for a
    short run, averaged segments for a long one; the peak lands on the spin."""
    f_spin, dt = 6.37e-4, 5.0
    for periods, segments in ((1.5, 1), (20, 9)):
        t = np.arange(0.0, periods / f_spin, dt)
        x = np.sin(2 * np.pi * f_spin * t) + 0.1 * np.sin(2 * np.pi * 7 * f_spin * t)
        nperseg, nfft = plot.welch_plan(len(t), dt, f_min=f_spin)
        assert 1 + (len(t) - nperseg) // (nperseg - nperseg // 2) == segments
        f, p = plot.spectrum(t, x, f_min=f_spin)
        assert f[1] <= f_spin / 4
        assert f[np.argmax(p)] == pytest.approx(f_spin, abs=f[1])


def test_esail_psd_is_the_one_spectrum():
    """``esail.psd`` is ``plot.spectrum`` (``skfem_cable.analysis.spectra``): the same numbers,
    several signals at once with time along the first axis, and a run's shortened last
    step left out; one segment is the whole run (the E-sail tests' peaks)."""
    from skfem_cable.analysis import spectra

    assert plot.spectrum is spectra.spectrum and plot.welch_plan is spectra.welch_plan
    t = np.append(np.arange(0.0, 400.0, 1.0), 399.4)  # a shortened last step
    x = np.column_stack([np.sin(2 * np.pi * 0.05 * t), 1.0 + np.cos(2 * np.pi * 0.125 * t)])
    f, p = esail.psd(t, x, segments=1)
    assert p.shape == (len(f), 2) and len(f) == 201  # 400 samples, one segment
    for k in range(2):
        fk, pk = plot.spectrum(t, x[:, k], segments=1)
        np.testing.assert_array_equal(fk, f)
        np.testing.assert_allclose(pk, p[:, k], rtol=1e-12, atol=1e-12 * pk.max())
    assert f[np.argmax(p, axis=0)] == pytest.approx([0.05, 0.125])


def test_psd_figure_marks_frequencies_and_units(tmp_path):
    t = np.arange(0.0, 5000.0, 5.0)
    fig = plot.psd(t, {"a": np.sin(2e-3 * t), "b": np.cos(3e-3 * t), "r": 1e-3 * np.sin(t / 50)},
                   tmp_path / "psd.png", units={"a": "deg", "b": "deg", "r": ""},
                   markers={"spin": 6.37e-4, "modes": [4.5e-3, 2e-2, 1.0]}, f_min=6.37e-4)
    top, bottom = fig.axes
    assert top.get_ylabel() == "PSD [deg$^2$/Hz]" and bottom.get_ylabel() == "PSD [1/Hz]"
    assert bottom.get_xlabel() == "frequency [Hz]"
    marks = sorted(line.get_xdata()[0] for line in top.lines[2:])
    assert marks == pytest.approx([6.37e-4, 4.5e-3, 2e-2])  # 1 Hz is beyond Nyquist
    (secondary,) = top.child_axes
    assert [label.get_text() for label in secondary.get_xticklabels()] == ["spin"]


def test_esail_figures_with_marks_and_coning_animation(needs_opengl, tmp_path):
    """A few seconds of a one-element sail: the figures, the PSD marked at the spin,
    Table 2 and given modes, and the side-view coning animation."""
    scene = esail.build(esail.BaselineConfig(), 10.0, 1)
    result = sc.simulate(scene.system, t_end=5.0, dt=0.5, rho_inf=0.25, initial=scene.initial)
    out = esail.outputs(scene, result)
    assert esail.distinct_frequencies([0.0, 1e-3, 1.01e-3, 4.5e-3, 4.51e-3]) == \
        pytest.approx([1e-3, 4.5e-3])
    paths = esail.figures(out, tmp_path, modes=[4.47e-3, 4.51e-3, 2.18e-2],
                          animation=result)
    assert [p.name for p in paths][-2:] == ["esail_psd.png", "esail_coning.gif"]
    assert all(p.stat().st_size > 10_000 for p in paths)
    fig = esail.psd_figure(out, None, modes=[4.47e-3, 2.18e-2])
    marks = sorted({line.get_xdata()[0] for line in fig.axes[0].lines[2:]})
    assert marks == pytest.approx([6.366e-4, 4.47e-3, 7.34e-3, 2.17e-2, 2.18e-2], rel=1e-3)
