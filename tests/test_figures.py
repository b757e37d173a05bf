"""Figures and summaries of a run, as a new user first sees them (``docs/figures.md``):
every figure listed, curves told apart, plain tick labels, the scene's title shown."""

from pathlib import Path

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable import plot, runner
from skfem_cable.bodies.rigid import RigidBody
from skfem_cable.scenes import classics, esail

ROOT = Path(__file__).resolve().parents[1]


def _offset_texts(fig):
    fig.draw_without_rendering()
    return [ax.yaxis.get_offset_text().get_text() for ax in fig.axes]


def test_summary_lists_every_figure_of_the_plots_folder(tmp_path):
    """A scene's own figures (the E-sail's, written by its outputs) are listed too, after
    the standard ones; temporary files are not."""
    plots = tmp_path / "plots"
    plots.mkdir()
    for name in ("energies.png", "esail_tether.png", "esail_psd.png", "final.png"):
        (plots / name).write_bytes(b"png")
    (plots / "cables.png.tmp").write_bytes(b"half")
    written = [plots / "energies.png", plots / "final.png", tmp_path / "animation.gif"]
    assert runner.plot_files(tmp_path, written) == [
        "plots/energies.png", "plots/final.png", "animation.gif", "plots/esail_psd.png",
        "plots/esail_tether.png"]


def test_esail_figures_leave_the_duplicate_energy_figure_out(tmp_path):
    """``plots/energies.png`` is the E-sail's Fig. 10: ``esail.figures`` does not draw it
    again, and the tether's stretch is a strain in ppm (no offset notation)."""
    nt = 40
    t = np.arange(nt) * 5.0
    wave = np.sin(2 * np.pi * t / 100.0)
    out = {"t": t, "coning": 1e-2 * wave[:, None], "root_coning": 2e-2 * wave[:, None],
           "lagging": 1e-3 * wave[:, None], "root_lagging": 2e-3 * wave[:, None],
           "length_ratio": 1.00086 + 3e-6 * wave[:, None],
           "omega_B": np.tile([4e-3, 1e-6, 1e-6], (nt, 1)), "euler_B": np.zeros((nt, 3)),
           "euler_E": np.zeros((nt, 3)), "thrust_O": np.ones((nt, 3)),
           "reaction_force_O": np.ones((nt, 3)), "thrust_angle": 0.1 + 0 * t,
           "reaction_angle": 0.1 + 0 * t}
    paths = esail.figures(out, tmp_path)
    assert [p.name for p in paths] == ["esail_tether.png", "esail_hub.png",
                                       "esail_forces.png", "esail_psd.png"]
    assert "plots/esail_energy.png" not in runner.DESCRIPTIONS


def test_histories_tick_labels_have_no_offset():
    t = np.linspace(0.0, 10.0, 50)
    fig = plot.histories(t, {"L / L0": 1.0008 + 1e-6 * np.sin(t), "x": 213.0 + 1e-4 * t})
    assert _offset_texts(fig) == ["", ""]


def test_long_history_is_drawn_from_each_columns_first_last_and_extremes():
    """A noisy 47,000-step history with a one-step spike is drawn from at most four points
    in each of ``COLUMNS`` equal spans of time: the span's first, last, lowest and highest
    (the spike kept), in order; a short history, or one with a gap (NaN), as it is."""
    from skfem_cable.plot.figures import COLUMNS

    rng = np.random.default_rng(0)
    t = np.linspace(0.0, 100.0, 47_000)
    y = np.sin(t) + 0.1 * rng.normal(size=t.size)
    y[12_345] = 5.0
    (line,) = plot.histories(t, {"y": y}).axes[0].lines
    drawn = np.searchsorted(t, line.get_xdata())
    assert np.array_equal(t[drawn], line.get_xdata()) and np.array_equal(y[drawn], line.get_ydata())
    assert np.all(np.diff(drawn) > 0) and len(drawn) <= 4 * COLUMNS and 12_345 in drawn
    column = np.minimum((t * (COLUMNS / 100.0)).astype(int), COLUMNS - 1)
    first = np.flatnonzero(np.diff(column, prepend=-1))
    kept = np.flatnonzero(np.diff(column[drawn], prepend=-1))
    assert np.array_equal(drawn[kept], first)  # every column, from its first point
    assert np.array_equal(drawn[np.append(kept[1:], len(drawn)) - 1],
                          np.append(first[1:], len(t)) - 1)  # ... to its last
    for extreme in (np.minimum, np.maximum):
        assert np.array_equal(extreme.reduceat(y[drawn], kept), extreme.reduceat(y, first))
    for short in (t[:4 * COLUMNS], np.where(t < 50.0, t, np.nan)):
        assert np.array_equal(plot.thinned(short, short)[1], short, equal_nan=True)


def test_many_curves_get_distinct_colours_and_a_colour_bar_key():
    """12 root tensions: 12 distinct colours (no repeated cycle: tether 11 is not tether
    1's colour), named on a colour bar beside the panel rather than by a legend over it."""
    t = np.arange(256) * 0.1
    signals = {f"tether{i + 1}": np.sin((1 + 0.1 * i) * t) for i in range(12)}
    fig = plot.psd(t, signals, title="root tension", units="N")
    panel = fig.axes[0]
    colours = {tuple(np.round(plot_colour(line), 6)) for line in panel.get_lines()}
    assert len(colours) == 12
    assert panel.get_legend() is None
    bar = fig.axes[-1]
    assert [label.get_text() for label in bar.get_yticklabels()] == list(signals)
    assert len(set(plot.curve_colours(3))) == 3


def plot_colour(line):
    from matplotlib.colors import to_rgba

    return to_rgba(line.get_color())


def test_spinning_run_cable_histories_show_motion_in_the_spinning_frame():
    """A tether spinning rigidly: its tip's chord grows to a metre within a sixth of a
    turn, but relative to the spinning frame it moves by millimetres."""
    scene = classics.spinning_tether(n_elements=2, length=1.0)
    result = sc.simulate(scene.system, initial=scene.initial, t_end=0.5, dt=5e-3, every=10)
    chord = np.linalg.norm(result.position(scene.cable, 1.0)
                           - result.position(scene.cable, 1.0)[0], axis=-1)
    assert chord.max() > 0.9
    fig = plot.cable_histories(result)
    tip = fig.axes[0]
    assert "spinning frame" in tip.get_ylabel()
    assert np.abs(tip.get_lines()[0].get_ydata()).max() < 0.01 * chord.max()


def test_rigid_fit_recovers_a_rotation():
    rng = np.random.default_rng(1)
    points = rng.normal(size=(6, 3))
    angle = np.linspace(0.0, 3.0, 5)
    c, s = np.cos(angle), np.sin(angle)
    R = np.zeros((5, 3, 3))
    R[:, 0, 0], R[:, 0, 1], R[:, 1, 0], R[:, 1, 1], R[:, 2, 2] = c, -s, s, c, 1.0
    moved = np.einsum("tij,mj->tmi", R, points) + [1.0, 2.0, 3.0]
    fitted, centre = plot.rigid_fit(moved)
    assert np.allclose(fitted, R) and np.allclose(centre, moved.mean(axis=1))


def test_energy_figure_names_constant_terms_and_keeps_kinetic_on_top():
    """A spin-up by external work: kinetic energy and external work are the same curve;
    the work is drawn under it.  A constant term is named as such, not as 'zero'."""
    t = np.linspace(0.0, 1.0, 20)
    work = t**2
    E = {"kinetic": 10.0 + work, "axial": 1e-3 * t, "bending": 0 * t, "potential": 5 + 0 * t,
         "dissipated": 0 * t, "external_work": work}
    E["balance"] = 0 * t
    fig = plot.energy_figure(t, E)
    terms = fig.axes[0]
    lines = {line.get_label().split("\n")[0]: line for line in terms.get_lines()}
    assert lines["kinetic"].get_zorder() > lines["external work"].get_zorder()
    title = terms.get_legend().get_title().get_text()
    assert "constant" in title and "potential" in title and "zero" not in title


def test_colour_bar_labels_never_read_minus_zero():
    """A round-off compression at a pendulum's free end does not print as ``-0.00``."""
    for values in ([-3e-7, 0.7, 1.53], [-2e-4, 50.0], [0.0, 1e-3], [-1.0, 1.0]):
        lo, hi = plot.colour_limits(values)
        fmt = plot.colorbar_format(lo, hi)
        labels = [fmt % x for x in np.linspace(lo, hi, 5)]
        assert not any(label.startswith("-") and float(label) == 0 for label in labels)
    assert plot.colour_limits([-1.0, 1.0]) == (-1.0, 1.0)


def test_planar_scene_is_viewed_face_on():
    """The cantilever bends in the xy plane: looked at along z with y up (not
    obliquely); a fixed view's up is perpendicular to its eye, as the screen's."""
    scene = classics.cantilever(4, 5.0)
    state = sc.solve_static(scene.system, load_steps=5)
    cam = plot.scene_camera(scene.system, state.q)
    assert cam.eye == pytest.approx([0, 0, 1]) and cam.up == pytest.approx([0, 1, 0])
    iso = plot.view_camera("isometric", np.eye(3))
    assert iso.eye @ iso.up == pytest.approx(0, abs=1e-12)
    assert np.linalg.norm(iso.up) == pytest.approx(1)


def test_scene_file_title_is_shown_on_the_snapshot_of_a_dynamic_run(tmp_path, monkeypatch):
    """The TOML ``title`` of a dynamic scene heads its snapshot, above the time."""
    from skfem_cable.cli import command as cli

    titles = []
    monkeypatch.setattr(plot, "rendering_available", lambda: (True, "stub"))
    monkeypatch.setattr(plot, "render", lambda *args, title=None, **kw: titles.append(title))
    rc = cli.main(["run", str(ROOT / "demos" / "spinning_hub.toml"), "--t-end", "0.02",
                   "--elements", "2", "--out", str(tmp_path), "--no-progress"])
    assert rc == 0
    assert titles == ["Spinning hub with two tethers\nt = 0.02 s"]


def test_energy_balance_of_a_steady_spin_has_no_jump_at_the_ends():
    """A free hub spinning steadily (``omega h = 0.1``): the balance residual moves by no
    more at the first step, and at the last (half) step, than at the steps between, where
    it is the algorithmic dissipation of ``rho_inf = 0.25`` (third order in ``h``).
    Starting with ``abar_0 = a_0`` it dropped by 2.6e-3 of the energy at the first step,
    65 times a middle step's change, and jumped again at the shortened last step."""
    hub = RigidBody.cylinder(radius=1.0, height=2.0, density=884.0)
    system = sc.System([hub])
    v0 = system.rigid_motion_velocity(system.q0, np.array([1.0, 0.0, 0.0]))
    result = sc.simulate(system, initial=sc.State(system, system.q0, v=v0), t_end=1.05,
                         dt=0.1, rho_inf=0.25)
    E = result.energy
    change = np.abs(np.diff(E["balance"] / E["kinetic"][0]))
    middle = np.median(change[1:-1])
    assert change[0] < 2 * middle and change[-1] < 2 * middle
