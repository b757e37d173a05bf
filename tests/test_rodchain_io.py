"""The rod chain in the family: the ``Result``-style API of ``RodChainResult``, observers
of ``RodChain.simulate`` (``contract.Observer``), the VTU/PVD series, figures, TOML scenes
and the ``hanging-chain`` scene of the command line built from the package."""

import json
from pathlib import Path

import meshio
import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable import plot, scene_file
from skfem_cable.cli import command as cli
from skfem_cable.io import export
from skfem_cable.rodchain import (
    RodChain,
    RodChainDivergence,
    chain_mesh,
    integrate,
    plots,
    write_series,
    write_vtu,
)
from skfem_cable.runner import RunOptions
from skfem_cable.scenes import catalog, hanging_chain
from skfem_cable.scenes.rodchain_studies import paper_chain, paper_state

G = np.array([0.0, -9.81, 0.0])
ROOT = Path(__file__).resolve().parents[1]


def small_run(**kwargs):
    chain = hanging_chain.steel_chain(4)
    return hanging_chain.simulate_release(4, t_end=0.05, output_dt=1e-3, **kwargs), chain


# --- the result ---------------------------------------------------------------------------
def test_result_has_the_api_of_the_cable_result():
    res, chain = small_run()
    assert len(res) == 51 and res.system is res.chain
    assert res.q.shape == (51, 12) and res.v.shape == (51, 12)
    np.testing.assert_array_equal(res.q[7], res.rods[7].ravel())
    np.testing.assert_array_equal(res.positions, res.joints)
    assert set(res.stats) >= {"method", "dt", "steps", "nfev", "saved", "wall_time", "stopped"}
    every = round(1e-3 / res.stats["dt"])
    assert res.stats["steps"] == every * (len(res) - 1) == res.stats["nfev"] / 4
    assert res.stats["saved"] == len(res) and res.stats["stopped"] is None
    # material points: the joints at their arc lengths, linear along each rod
    S = np.concatenate([[0.0], np.cumsum(chain.lengths)])
    np.testing.assert_allclose(res.position(S), res.joints, rtol=0, atol=1e-15)
    mid = res.position(0.5 * (S[1:] + S[:-1]))
    np.testing.assert_allclose(mid, 0.5 * (res.joints[:, 1:] + res.joints[:, :-1]), atol=1e-15)
    assert res.position(np.zeros((2, 3))).shape == (51, 2, 3, 3)
    np.testing.assert_allclose(res.velocity(S[-1]), res.joint_velocities[:, -1], atol=1e-15)
    with pytest.raises(ValueError, match="reference arc length"):
        res.position(2.0)
    state = res.state(-1)
    assert state.t == res.t[-1] and state.q.shape == (12,)
    np.testing.assert_array_equal(state.joints, res.joints[-1])
    np.testing.assert_allclose(state.tension, res.tension[-1])
    np.testing.assert_allclose(res.strain * chain.EA, res.tension, rtol=1e-12)


# --- observers ----------------------------------------------------------------------------
class Recorder(sc.Observer):
    """Keeps every step; stops once the free end is below ``floor``."""

    def __init__(self, floor=-np.inf):
        self.floor, self.steps, self.calls = floor, [], []

    def start(self, run):
        self.calls.append("start")
        self.run = run

    def saved(self, run, step):
        self.steps.append((step.index, step.t, step.q.copy(), step.a.copy(),
                           dict(step.energies)))
        tip = np.sum(step.q.reshape(-1, 3), axis=0)
        if tip[1] < self.floor:
            return f"free end below {self.floor} m"

    def finish(self, run, error):
        self.calls.append(("finish", error))


@pytest.mark.parametrize("method", ["rk4", "rk4-python", "DOP853"])
def test_observer_sees_saved_steps_and_stops_the_run(method):
    chain = RodChain.uniform(4, mass=0.05, length=0.25, E=1e8, A=1e-6)  # strain ~ 0.2 %
    q0, v0 = hanging_chain.release_state(chain)
    kwargs = {"gravity": G}
    if method == "rk4-python":  # a callable load runs the RK4 loop in Python
        kwargs["line_load"] = lambda t, r, u: np.zeros_like(r)
    if method == "DOP853":
        kwargs.update(method="DOP853", rtol=1e-8, atol=1e-10)
        dt, every = 1e-2, 1
    else:
        dt, every = 2e-3, 5
    full = Recorder()
    ref = chain.simulate(q0, v0, 0.3, dt, output_every=every, observers=[full], **kwargs)
    assert [s[0] for s in full.steps] == [k * every for k in range(len(ref))]
    np.testing.assert_array_equal(np.array([s[1] for s in full.steps]), ref.t)
    np.testing.assert_array_equal(np.array([s[2] for s in full.steps]), ref.q)
    k = len(ref) // 2
    np.testing.assert_allclose(full.steps[k][3],
                               chain.acceleration(ref.rods[k], ref.rod_velocities[k],
                                                  gravity=G).ravel(), rtol=1e-12, atol=1e-9)
    assert set(full.steps[k][4]) == {"kinetic", "axial", "bending", "potential", "dissipated",
                                     "external_work"}
    assert full.steps[k][4]["kinetic"] == pytest.approx(ref.energy["kinetic"][k], rel=1e-14)
    assert full.calls == ["start", ("finish", None)]
    assert full.run.system.chain is chain and full.run.settings["every"] == every
    # a stop at the first saved step with the free end below -0.2 m ends the result there
    stopper = Recorder(floor=-0.2)
    res = chain.simulate(q0, v0, 0.3, dt, output_every=every, observers=[stopper], **kwargs)
    first = int(np.argmax(ref.free_end[:, 1] < -0.2))
    assert 0 < first < len(ref) - 1
    assert len(res) == first + 1 and res.stats["stopped"] == "free end below -0.2 m"
    np.testing.assert_array_equal(res.rods, ref.rods[: first + 1])
    assert res.energy["balance"].shape == (first + 1,)
    assert stopper.calls[-1] == ("finish", None) and len(stopper.steps) == first + 1


def test_compiled_blocks_do_not_change_the_result(monkeypatch):
    """Observers hear of a compiled block when it is done; the block size changes nothing."""
    res, _ = small_run()
    monkeypatch.setattr(integrate, "_BLOCK_WORK", 4 * 4 * 5)  # 4 saved steps per block
    seen = Recorder()
    again, _ = small_run(observers=[seen])
    np.testing.assert_array_equal(again.rods, res.rods)
    assert len(seen.steps) == len(res)


def test_progress_bar_and_divergence_with_observers(capsys):
    chain = hanging_chain.steel_chain(11)
    q0, v0 = hanging_chain.release_state(chain)
    dt = 1.3 * chain.stable_dt()
    rec = Recorder()
    bar = sc.io.ProgressBar(enabled=True)
    with pytest.raises(RodChainDivergence) as info:
        chain.simulate(q0, v0, 2000 * dt, dt, gravity=G, check_stability=False,
                       output_every=5, observers=[rec, bar])
    err = info.value
    assert rec.calls[-1] == ("finish", err)
    saved = err.result  # the saved steps before the failure travel with the error
    assert 1 < len(saved) == len(rec.steps) and saved.t[-1] < err.t
    assert np.all(np.isfinite(saved.rods))
    assert "%" in capsys.readouterr().err
    with pytest.raises(TypeError, match="not an Observer"):
        chain.simulate(q0, v0, 10 * dt, dt, gravity=G, check_stability=False,
                       observers=[object()])


# --- VTU ----------------------------------------------------------------------------------
def test_vtu_series_round_trips_positions(tmp_path):
    chain = RodChain(np.array([0.1, 0.2, 0.3]), np.array([1.0, 0.5, 0.8]), np.full(3, 1e3))
    q0 = chain.static_equilibrium(G) + 0.1
    res = chain.simulate(q0, np.zeros_like(q0), 0.2, 1e-3, gravity=G, output_every=10,
                         anchor=lambda t: (np.outer(t, [1.0, 0, 0]),
                                           np.tile([1.0, 0, 0], (t.size, 1)),
                                           np.zeros((t.size, 3))))
    pvd = write_series(res, tmp_path, every=3)
    entries = export.read_pvd(pvd)
    indices = [0, 3, 6, 9, 12, 15, 18, 20]
    assert [t for t, _ in entries] == pytest.approx(res.t[indices].tolist(), abs=0)
    for i, (_, file) in zip(indices, entries):
        mesh = meshio.read(tmp_path / file)
        np.testing.assert_array_equal(mesh.points, res.joints[i])
        np.testing.assert_array_equal(mesh.point_data["position"], res.joints[i])
        np.testing.assert_allclose(mesh.point_data["velocity"], res.joint_velocities[i])
        assert mesh.cells_dict["line"].tolist() == [[0, 1], [1, 2], [2, 3]]
        np.testing.assert_allclose(mesh.cell_data["tension"][0], res.tension[i])
        np.testing.assert_allclose(mesh.cell_data["strain"][0], res.strain[i])
        assert mesh.cell_data["rod_id"][0].tolist() == [0, 1, 2]
    path = write_vtu(tmp_path / "one.vtu", res.state(4))
    np.testing.assert_array_equal(meshio.read(path).points, res.joints[4])
    assert chain_mesh(chain, q0).point_data["arc_length"].tolist() == [0.0, 1.0, 1.5, 2.3]


def test_series_observer_writes_during_the_run(tmp_path):
    """The one series observer of every model (``io.SeriesObserver``) writes a rod chain's
    series through its integration's writer; a frame other than the inertial one is
    refused before any file is written."""
    res, _ = small_run(observers=[sc.io.SeriesObserver(tmp_path, every=20)])
    entries = export.read_pvd(tmp_path / "series.pvd")
    assert [t for t, _ in entries] == pytest.approx([0.0, 0.02, 0.04, 0.05])
    np.testing.assert_array_equal(meshio.read(tmp_path / entries[-1][1]).points, res.joints[-1])
    with pytest.raises(ValueError, match="inertial frame, not 'lvlh'"):
        small_run(observers=[sc.io.SeriesObserver(tmp_path / "lvlh", frame="lvlh")])
    assert not (tmp_path / "lvlh" / "series.pvd").exists()


# --- figures ------------------------------------------------------------------------------
def test_figures_of_a_run(tmp_path):
    res, _ = small_run()
    paths, _ = plots.run_figures(tmp_path, res, render_final=False)
    assert [p.name for p in paths] == ["energies.png", "chain.png", "tension_psd.png"]
    for p in paths:
        assert p.stat().st_size > 10_000
    assert plots.planar_view(res.joints) == "xy"
    assert plots.planar_view(np.random.default_rng(0).random((5, 3))) == "isometric"


def test_render_of_the_polyline(tmp_path):
    ok, reason = plot.rendering_available()
    if not ok:
        pytest.skip(reason)
    res, _ = small_run()
    img = plots.render(res.state(-1), tmp_path / "chain.png", title="t = 0.05 s")
    assert img.std() > 0 and (tmp_path / "chain.png").stat().st_size > 5_000


# --- the command line and TOML scenes -----------------------------------------------------
def test_hanging_chain_scene_runs_from_the_package(tmp_path, capsys):
    assert catalog.SCENES["hanging-chain"].target == "skfem_cable.scenes.hanging_chain:run"
    out = tmp_path / "run"
    rc = cli.main(["run", "hanging-chain", "--elements", "3", "--t-end", "0.05",
                   "--out", str(out), "--no-progress", "--no-plots"])
    assert rc == 0
    assert "max_dev_rigid_rel" in capsys.readouterr().out
    summary = json.loads((out / "summary.json").read_text())
    assert summary["scene"] == "hanging-chain" and summary["parameters"]["n_rods"] == 3
    assert summary["saved_steps"] == 501 and summary["integration"]["method"] == "rk4"
    assert summary["outputs"]["reference"]["max_dev_rigid_rel"] < 1e-5
    assert summary["outputs"]["energy"]["max_abs_balance_relative"] < 1e-8
    entries = export.read_pvd(out / summary["files"]["series"])
    assert [t for t, _ in entries] == pytest.approx([0.0, 0.01, 0.02, 0.03, 0.04, 0.05])
    mesh = meshio.read(out / entries[-1][1])
    assert mesh.points.shape == (4, 3) and "tension" in mesh.cell_data
    tip = summary["outputs"]["chain"]["free_end"]
    np.testing.assert_allclose(mesh.points[-1], tip, rtol=1e-12)
    # the directory holds a run now: refused, then replaced with --overwrite
    assert cli.main(["run", "hanging-chain", "--out", str(out)]) == 2
    assert cli.main(["run", "hanging-chain", "--elements", "2", "--t-end", "0.01",
                     "--out", str(out), "--overwrite", "--no-progress", "--no-plots"]) == 0
    assert len(export.read_pvd(out / "series.pvd")) == 2
    assert cli.main(["run", "hanging-chain", "--every", "2"]) == 2
    assert "does not take --every" in capsys.readouterr().err
    # before: --frame lvlh was ignored, the series written in the inertial frame
    assert cli.main(["run", "hanging-chain", "--frame", "lvlh", "--t-end", "0.01"]) == 2
    assert "written in the inertial frame: --frame lvlh" in capsys.readouterr().err


CHAIN_SCENE = """
title = "falling chain"
[rod_chain]
rods = 5
length = 5.0
mass = 0.5
E = 1e9
A = 1e-6
[loads]
gravity = [0, -9.81, 0]
[initial]
direction = [0, -1, 0]
angular_velocity = [0, 0, 1.0]
[solver]
t_end = 0.5
dt = 1e-2
step = 1e-3
[output]
series_every = 10
"""


def test_rod_chain_toml_scene_runs(tmp_path):
    path = tmp_path / "chain.toml"
    path.write_text(CHAIN_SCENE)
    spec = scene_file.load(path)
    assert isinstance(spec, scene_file.ChainSceneSpec) and spec.chain.n == 5
    np.testing.assert_allclose(spec.initial[1], np.tile([1.0, 0, 0], (5, 1)))
    summary = catalog.run_scene(str(path), RunOptions(out=tmp_path / "run", plots=False,
                                                      progress=False))
    assert summary["scene"] == "chain" and summary["saved_steps"] == 51
    assert summary["outputs"]["energy"]["max_abs_balance_relative"] < 1e-8
    assert len(export.read_pvd(tmp_path / "run" / "series.pvd")) == 6
    assert summary["outputs"]["chain"]["rods"] == 5
    # --elements refines at fixed length and mass; a steel preset and a moving anchor
    steel = scene_file.loads_text(
        '[rod_chain]\npreset = "steel"\nrods = 11\n'
        'anchor = { motion = "circular", radius = 0.5, omega = 2.0 }\n'
        '[loads]\ngravity = [0, -9.81, 0]\n[initial]\nshape = "equilibrium"\n'
        '[solver]\nt_end = 0.01\ndt = 1e-3\n', "steel.toml", elements=22)
    ref = hanging_chain.steel_chain(22)
    assert steel.chain.n == 22
    np.testing.assert_allclose(steel.chain.masses, ref.masses, rtol=1e-14)
    np.testing.assert_allclose(steel.chain.EA, ref.EA, rtol=1e-14)
    assert callable(steel.loads["anchor"])
    res = steel.chain.simulate(*steel.initial, 0.01, 5e-6, output_every=20, **steel.loads)
    assert np.abs(res.energy["balance"]).max() < 1e-6 * np.abs(res.energy["external_work"]).max()


def test_example_scene_file_is_the_papers_energy_experiment():
    spec = scene_file.load(ROOT / "demos" / "falling_chain.toml")
    chain = paper_chain()
    for name in ("masses", "lengths", "EA"):
        np.testing.assert_allclose(getattr(spec.chain, name), getattr(chain, name), rtol=1e-15)
    for got, want in zip(spec.initial, paper_state()):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-15)
    res = spec.chain.simulate(*spec.initial, 0.1, spec.solver["step"], output_every=10,
                              **spec.loads)
    assert res.energy["total"][0] == pytest.approx(-62.87, abs=0.01)  # Sect. 5.2
    assert spec.series_every == 20 and spec.solver["dt"] == 1e-3


@pytest.mark.parametrize("change, message", [
    (("rods = 5", "rods = 0"), "rod_chain.rods must be an integer >= 1, got 0"),
    (("mass = 0.5", "density = 7800.0\nmass = 0.5"),
     "rod_chain.density excludes rod_chain.mass (give one of them)"),
    (("mass = 0.5", ""), "rod_chain.mass is required"),
    (("A = 1e-6", ""), "rod_chain.E needs the section: A or radius"),
    (("E = 1e9", "E = 1e9\ncolour = 1"), "rod_chain.colour is not a known key"),
    (("[loads]", "[rod_chain.anchor]\nmotion = \"spiral\"\n[loads]"),
     "rod_chain.anchor.motion must be one of 'circular'"),
    (("step = 1e-3", "step = 3e-3"), "solver.step must divide dt = 0.01 s"),
    (("step = 1e-3", "step = 1e-3\nrtol = 1e-6"),
     "solver.rtol applies to method = 'RK45' or 'DOP853' only"),
    (("t_end = 0.5", "t_end = 0.505"), "solver.t_end must be a multiple of dt"),
    (("direction = [0, -1, 0]", "direction = [0, 0, 0]"),
     "initial.direction must be a non-zero vector"),
    (("direction = [0, -1, 0]", "shape = \"equilibrium\""), None),
    (("gravity = [0, -9.81, 0]\n[initial]\ndirection = [0, -1, 0]",
      "gravity = [0, 0, 0]\n[initial]\nshape = \"equilibrium\""),
     "initial.shape needs gravity or a tip force that tensions every rod"),
    (("[output]", "[[cables]]\n[output]"), "cables is not a known key"),
])
def test_rod_chain_scene_errors_name_the_key(change, message):
    text = CHAIN_SCENE.replace(*change)
    if message is None:
        assert scene_file.loads_text(text, "ok.toml").initial[0][0, 1] < -1.0
        return
    with pytest.raises(scene_file.SceneFileError) as err:
        scene_file.loads_text(text, "bad.toml")
    assert str(err.value).startswith("bad.toml: ") and message in str(err.value)
