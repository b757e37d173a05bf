"""VTU/PVD export: files read back with meshio and pyvista carry the solver's fields."""

import meshio
import numpy as np
import pytest
import pyvista as pv
from interrupting import Interrupt, InterruptingLoad

import skfem_cable as sc
from skfem_cable.bodies.rigid import RigidBody
from skfem_cable.io import export
from skfem_cable.scenes import classics


@pytest.fixture(scope="module")
def pendulum_run():
    scene = classics.pendulum(n_elements=4)
    return scene, sc.simulate(scene.system, t_end=0.06, dt=2e-3, every=10)


def hub_system():
    """A spinning hub with one tether pinned to its rim and a tip mass."""
    hub = RigidBody.cylinder(radius=0.5, height=1.0, density=884.0)
    sec = sc.Section.circular(radius=5e-4, E=7e10, rho=2700.0)
    tether = sc.Cable.straight([0, 0.5, 0], [0, 4.5, 0], 3, sec, name="tether")
    system = sc.System([hub, tether]).pin(tether.node(0), hub.point([0, 0.5, 0]))
    system.add_point_mass(tether.node(-1), 0.5)
    return system, hub, tether


def test_series_read_back_with_meshio_and_pyvista(pendulum_run, tmp_path):
    """Times in the .pvd, point counts, positions and field ranges of every step equal
    what the solver computes at the sampled arc lengths."""
    scene, result = pendulum_run
    cable, ppe = scene.cable, 5
    pvd = export.write_series(result, tmp_path, points_per_element=ppe)
    s = cable.mesh.p[0][0] + np.linspace(0.0, cable.length, cable.n_elements * ppe + 1)
    reader = pv.get_reader(str(pvd))
    assert np.allclose(reader.time_values, result.t, rtol=0, atol=1e-15)
    assert len(reader.time_values) == len(result) == 4
    for i, (t, file) in enumerate(export.read_pvd(pvd)):
        assert t == result.t[i]
        m = meshio.read(tmp_path / file)
        assert len(m.points) == cable.n_elements * ppe + 1
        assert np.allclose(m.point_data["arc_length"], s, atol=1e-14)
        assert np.allclose(m.points, result.position(cable, s)[i], atol=1e-14)
        assert np.allclose(m.point_data["velocity"], result.velocity(cable, s)[i], atol=1e-12)
        assert np.allclose(m.point_data["curvature"], result.curvature(cable, s)[i])
        assert m.cells_dict["line"].shape == (cable.n_elements * ppe, 2)
        reader.set_active_time_point(i)
        grid = reader.read()[0]
        assert grid.n_points == len(s)
        T = result.tension(cable, s)[i]
        assert np.allclose(grid.get_data_range("tension"), (T.min(), T.max()), rtol=1e-12)
        assert np.array_equal(np.unique(grid.point_data["element_id"]), np.arange(4))
    assert result.tension(cable, s).max() > 1.0  # the pendulum is loaded: ranges not trivial


def test_hub_is_a_closed_cylinder_following_the_motion(tmp_path):
    system, hub, tether = hub_system()
    # the whole system turned by 30 degrees about x, spinning about x
    c, s_ = np.cos(np.pi / 6), np.sin(np.pi / 6)
    R = np.array([[1, 0, 0], [0, c, -s_], [0, s_, c]])
    q = (system.q0.reshape(-1, 3) @ R.T).ravel()
    omega = np.array([2.0, 0.0, 0.0])
    v = system.rigid_motion_velocity(q, omega)
    path = export.write_vtu(tmp_path / "hub.vtu", system, sc.State(system, q, v=v))
    grid = pv.read(path)
    part = grid.cell_data["part"]
    rigid = part == sc.core.contract.PART_RIGID
    surface = grid.extract_cells(rigid).extract_surface(algorithm=None)
    assert surface.n_open_edges == 0
    n = 32
    assert surface.volume == pytest.approx(0.5 * n * np.sin(2 * np.pi / n) * 0.25 * 1.0,
                                           rel=1e-12)
    rim = hub.positions(q[system.dofs(hub)], [[0.5, 0.5, 0.0]])[0]
    assert np.allclose(rim, R @ [0.5, 0.5, 0.0])
    assert np.min(np.linalg.norm(surface.points - rim, axis=1)) < 1e-12
    hub_pts = grid.point_data["body_id"] == 0
    assert np.allclose(grid.point_data["velocity"][hub_pts],
                       np.cross(omega, grid.points[hub_pts]), atol=1e-12)
    assert np.all(np.isnan(grid.point_data["tension"][hub_pts]))
    mass = grid.extract_cells(part == sc.core.contract.PART_POINT_MASS)
    assert mass.n_points == 1
    assert np.allclose(mass.points[0], R @ [0, 4.5, 0])
    assert np.all(grid.cell_data["body_id"][part == sc.core.contract.PART_CABLE] == 1)


def test_series_writer_appends_after_a_restart(tmp_path):
    system, _, _ = hub_system()
    writer = export.SeriesWriter(tmp_path, system, points_per_element=2)
    for t in (0.0, 1.0, 2.0):
        writer.write(t, system.q0)
    again = export.SeriesWriter(tmp_path, system, points_per_element=2, append=True)
    again.write(1.5, system.q0)
    assert [t for t, _ in export.read_pvd(again.pvd)] == [0.0, 1.0, 1.5]
    fresh = export.SeriesWriter(tmp_path, system)
    fresh.write(7.0, system.q0)
    assert export.read_pvd(fresh.pvd) == [(7.0, "vtu/series_000000.vtu")]


def test_a_series_formats_each_frame_of_its_pvd_once(tmp_path, monkeypatch):
    """Adding a frame rewrites the ``.pvd`` from the kept lines of the others: one
    ``pvd_line`` a frame (it rebuilt and indented the whole XML tree at every frame, which
    is quadratic: 3.1 of 13 s of a 271-frame run), and the file still lists every frame,
    with a name that needs escaping, as ``read_pvd`` and ParaView's reader see it."""
    formatted = []
    real = export.pvd_line
    monkeypatch.setattr(export, "pvd_line", lambda *e: formatted.append(e) or real(*e))
    series = export.VtuSeries(tmp_path, name="a&b")
    mesh = meshio.Mesh(np.zeros((2, 3)), [("line", np.array([[0, 1]]))])
    for t in range(30):
        series.add(0.5 * t, mesh)
    series.add(2.0, mesh)
    assert len(formatted) == 31
    want = [(0.5 * t, f"vtu/a&b_{t:06d}.vtu") for t in range(4)] + [
        (2.0, "vtu/a&b_000004.vtu")]
    assert export.read_pvd(series.pvd) == want
    reader = pv.get_reader(str(series.pvd))
    assert list(reader.time_values) == [t for t, _ in want]


def test_bad_sampling_is_named():
    _, _, tether = hub_system()
    with pytest.raises(ValueError, match="points_per_element"):
        tether.sample(tether.q0, points_per_element=0)
    with pytest.raises(ValueError, match="resolution"):
        sc.bodies.rigid.cylinder_surface(1.0, 1.0, resolution=2)


def _sine(t):
    return [0.0, 0.0, np.sin(20 * t)]


def test_simulate_writes_the_series_and_a_restart_continues_it(tmp_path):
    """The run directory of an interrupted and restarted run holds one .vtu per saved
    step, listed in series.pvd with exactly the saved times."""

    def scene(stop_at=None):
        s = classics.pendulum(n_elements=3)
        s.system.add_point_load(s.cable.node(-1), InterruptingLoad(_sine, stop_at))
        return s

    kw = dict(t_end=0.1, dt=2e-3, every=5)
    with pytest.raises(Interrupt):
        sc.simulate(scene(stop_at=0.071).system,
                    observers=sc.io.run_observers(tmp_path, progress=False, chunk=3), **kw)
    s = scene()
    result = sc.simulate(s.system, resume=sc.io.resume(tmp_path),
                         observers=sc.io.run_observers(tmp_path, progress=False, chunk=3,
                                                       restart=True), **kw)
    assert (tmp_path / "series.pvd").exists(), "no series.pvd in the run directory"
    entries = export.read_pvd(tmp_path / "series.pvd")
    assert [t for t, _ in entries] == list(result.t)
    for i, (_, file) in enumerate(entries):
        points = meshio.read(tmp_path / file).points
        assert np.allclose(points[0::8], result.position(s.cable, s.cable.mesh.p[0])[i])


def test_series_observer_thins_the_steps_and_keeps_the_last(tmp_path):
    """``every=2`` writes saved steps 0, 2, 4, ... and the last one (t_end, and the step
    at which an observer stopped the run)."""
    scene = classics.pendulum(n_elements=3)
    kw = dict(t_end=0.011, dt=1e-3, every=2)
    result = sc.simulate(scene.system, observers=[sc.io.SeriesObserver(tmp_path, every=2,
                                                                       points_per_element=3)],
                         **kw)
    assert len(result) == 7  # steps 0, 2, ..., 10 and 11
    times = [t for t, _ in export.read_pvd(tmp_path / "series.pvd")]
    assert times == [result.t[k] for k in (0, 2, 4, 6)]
    assert len(meshio.read(tmp_path / "vtu" / "series_000000.vtu").points) == 3 * 3 + 1

    class StopAtSix(sc.Observer):
        def saved(self, run, step):
            return step.index == 6 and "enough"

    stopped = sc.simulate(scene.system, observers=[sc.io.SeriesObserver(tmp_path, every=2),
                                                   StopAtSix()], **kw)
    assert stopped.stats["stopped"] == "enough" and len(stopped) == 4
    times = [t for t, _ in export.read_pvd(tmp_path / "series.pvd")]
    assert times == [result.t[k] for k in (0, 2, 3)]  # a fresh series, ending at the stop
