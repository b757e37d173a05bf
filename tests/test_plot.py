"""Renders (off-screen OpenGL) and matplotlib figures."""

import numpy as np
import pytest
from PIL import Image

import skfem_cable as sc
from skfem_cable import plot
from skfem_cable.rigid import RigidBody
from skfem_cable.scenes import classics


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
    assert len(fig.axes) == 3
    assert len(fig.axes[1].lines) == 4
    plot.cable_histories(result, tmp_path / "cables.png")
    plot.psd(result.t, {"tip x": result.position(scene.cable, 1.2)[:, 0]},
             tmp_path / "psd.svg", markers={"pendulum": 0.47})
    rows = [{"elements": n, "wall": w, "error": e}
            for n, w, e in ((4, 0.1, 1e-2), (4, 0.2, 3e-3), (8, 0.3, 1e-3), (8, 0.6, 2e-4))]
    fig = plot.speed_error(rows, tmp_path / "speed.pdf")
    assert [line.get_label() for line in fig.axes[0].lines] == ["elements = 4", "elements = 8"]
    for name in ("energies.png", "cables.png", "psd.svg", "speed.pdf"):
        assert (tmp_path / name).stat().st_size > 1000
