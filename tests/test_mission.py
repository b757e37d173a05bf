"""Mission-length runs (issue 31): durations with suffixes, the progress bar's simulated
time per wall second, and the full-size E-sail preset."""

import io
import time
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve

import skfem_cable as sc
from skfem_cable import simulate
from skfem_cable.cli import command as cli
from skfem_cable.core.linalg import THREADS, PatternSolver, thread_count
from skfem_cable.io.progress import Progress
from skfem_cable.scene_file import loads_text
from skfem_cable.scenes import catalog, esail
from skfem_cable.util import durations

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("text, seconds", [("30d", 2592000.0), ("12h", 43200.0),
                                           ("90min", 5400.0), ("0.5s", 0.5), ("2.5", 2.5),
                                           (" 1e3 s ", 1000.0), (4, 4.0)])
def test_durations_take_the_suffixes(text, seconds):
    assert durations.parse(text) == seconds


@pytest.mark.parametrize("text", ["30 days", "h", "1.2.3h", "inf", "nan", None, "5y"])
def test_a_bad_duration_names_the_accepted_forms(text):
    with pytest.raises(ValueError, match="t_end must be a finite number of seconds or a "
                                         "number with a suffix s, min, h or d"):
        durations.parse(text, "t_end")


def test_the_cli_and_scene_files_read_durations():
    args = cli.build_parser().parse_args(["run", "esail-full", "--t-end", "30d", "--dt", "2min"])
    assert (args.t_end, args.dt) == (2592000.0, 120.0)
    with pytest.raises(SystemExit):
        cli.build_parser().parse_args(["run", "esail-full", "--t-end", "-1d"])
    text = (ROOT / "demos" / "reel_brake.toml").read_text()
    spec = loads_text(text.replace("t_end = 1.0 ", 't_end = "1s"').replace(
        "dt = 1e-3 ", 'dt = "0.001s"'), "reel_brake.toml")
    assert (spec.solver["t_end"], spec.solver["dt"]) == (1.0, 1e-3)


def test_the_progress_bar_shows_simulated_time_per_wall_second():
    stream = io.StringIO()
    bar = Progress(0.0, 30 * 86400.0, enabled=True, stream=stream)
    time.sleep(0.05)
    bar.update(2.5 * 86400.0)
    line = stream.getvalue()
    assert "t=2.5 d, " in line and " d/s" in line and "ETA" in line


def test_the_full_size_sail_meets_the_spin_criterion():
    """Janhunen and Toivanen's criterion: centrifugal tension at the root at least 5 times
    the Coulomb force on the tether (the paper's baseline has 59)."""
    cfg = esail.FULL_SIZE
    assert (cfg.n_tethers, cfg.tether_length) == (100, 20e3)
    assert 5.0 <= cfg.centrifugal_ratio < 6.0
    tether = cfg.tether_density * cfg.tether_area * cfg.tether_length
    force = cfg.wind.force_per_length(cfg.voltage) * cfg.tether_length
    assert cfg.centrifugal_ratio == pytest.approx(
        cfg.spin_rate**2 * cfg.tether_length * (cfg.remote_mass + tether / 2) / force)
    assert esail.BaselineConfig().centrifugal_ratio == pytest.approx(59.2, abs=0.1)


def test_the_esail_full_scene_runs_with_adaptive_steps():
    scene = catalog.esail_full_scene(elements=2, t_end=5.0)
    assert scene.settings["rtol"] == esail.MISSION_RTOL
    assert len(scene.system.cables()) == 100
    settings = {k: v for k, v in scene.settings.items() if k != "series_every"}
    result = simulate(scene.system, initial=scene.initial, **settings)
    assert result.t[-1] == 5.0 and result.stats["path"] == "compiled"
    assert scene.outputs(result)["thrust_mean_N"] == pytest.approx(0.89, rel=0.02)  # 1 AU


def baseline_matrix():
    """The 12-tether sail's iteration matrix at its initial state, its layout and a
    right-hand side."""
    scene = esail.build(esail.BaselineConfig(), 10.0, 3)
    system = scene.system
    lay = system.current_layout()
    data = lay.mass_data + lay.linear_data
    system.evaluate(scene.initial.q, scene.initial.v, 0.0, np.zeros(lay.n_c), cK=1e-3,
                    data=data)
    return scene, lay, data, np.random.default_rng(0).standard_normal(lay.N)


def test_the_bordered_lu_factors_each_tether_as_a_block_on_any_number_of_threads():
    """Each tether (with its pin's multipliers) is a block of the band, coupled to the
    hub through its three pin rows; factors and solves agree bit for bit on one and on
    two threads, and with SuperLU to round-off."""
    _, lay, data, rhs = baseline_matrix()
    A = sp.csr_matrix((data, lay.indices, lay.indptr), shape=(lay.N, lay.N))
    solutions = []
    for threads in (1, 2):
        solver = PatternSolver(lay.indptr, lay.indices, border=lay.border, threads=threads)
        starts, rows_ptr = solver.lu[0][0][6], solver.lu[0][0][7]
        assert starts.size - 1 == 12 and np.all(np.diff(rows_ptr) == 3)
        solver.factor(data)
        solutions.append(solver.solve(rhs))
    assert np.array_equal(solutions[0], solutions[1])
    exact = spsolve(A.tocsc(), rhs)
    assert np.abs(solutions[0] - exact).max() < 1e-10 * np.abs(exact).max()


def test_a_run_is_the_same_on_one_and_on_two_threads(monkeypatch):
    """The 12-tether sail (6 elements per tether: the element loops' chunks of 64 cut
    inside a tether) built and run on one and on two threads: the laws' and the solar
    wind's element loops (``kernels.chunks``) and the bordered LU on threads give the
    same steps, bit for bit."""
    runs = []
    for threads in ("1", "2"):
        monkeypatch.setenv(THREADS, threads)
        scene = esail.build(esail.BaselineConfig(), 10.0, 6)
        (tethers,), (wind,) = ([t for t, _ in scene.system.current_layout().body_terms
                                if t.kernels], [t for t, _ in scene.system.current_layout()
                                                .load_terms if t.name == "solar wind"])
        threaded = tethers.kernels[0][0].__name__ == "kernel_parallel"
        assert threaded == (threads == "2") and wind.kernels[0][0].__name__ == (
            "kernel_parallel" if threaded else "kernel")
        runs.append(simulate(scene.system, 1.0, 0.1, initial=scene.initial, rho_inf=0.25))
    assert np.array_equal(runs[0].q, runs[1].q) and np.array_equal(runs[0].v, runs[1].v)


def test_a_cable_longer_than_a_chunk_is_the_same_on_one_and_on_two_threads(monkeypatch):
    """One damped cable of 140 elements (chunk boundaries inside it, where two chunks'
    elements share a node): forces, tangent and energies bit for bit on both threads."""
    out = []
    for threads in ("1", "2"):
        monkeypatch.setenv(THREADS, threads)
        section = sc.Section.circular(0.01, 2e9, 1000.0, gamma_axial=1e-3, gamma_bending=1e-3)
        cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 140, section)
        q = cable.q0 + 1e-3 * np.random.default_rng(2).standard_normal(cable.n_dofs)
        f, K = sc.System([cable]).assemble(q, q - cable.q0, cC=0.5)
        _, info = sc.System([cable]).evaluate(q, q - cable.q0, 0.0, np.zeros(0))
        out.append((f, K.toarray(), info["energy"]))
    assert all(np.array_equal(a, b) for a, b in zip(*out))


@pytest.mark.parametrize("value", ["0", "two", "1.5"])
def test_a_bad_thread_count_is_named(monkeypatch, value):
    monkeypatch.setenv(THREADS, value)
    with pytest.raises(ValueError, match=f"SKFEM_CABLE_THREADS must be an integer >= 1, "
                                         f"got '{value}'"):
        thread_count()


def _small_sail():
    return esail.build(esail.BaselineConfig(n_tethers=4), 10.0, 3)


def test_modified_newton_takes_fresh_tangents_where_its_stale_one_fails(monkeypatch):
    """At 10 s steps the sail's tangent turns within a step: modified Newton factors the
    tangent at the start of each step for a while.  It factors 1.2 times per step where
    full Newton factors 3.1 times, for 3.6 corrections against 3.1 (measured); kept on
    the stale tangent it needs 4.6."""
    from skfem_cable.solvers.galpha import GeneralizedAlpha

    scene = _small_sail()

    def per_step(newton="modified"):
        r = sc.simulate(scene.system, 400.0, 10.0, initial=scene.initial, rho_inf=0.25,
                        newton=newton, every=1000)
        return r.stats["newton"] / r.stats["steps"], r.stats["factorizations"] / r.stats["steps"]

    (switching, factored), (full, _) = per_step(), per_step("full")
    monkeypatch.setattr(GeneralizedAlpha, "FRESH_STEPS_MAX", 0)  # never a fresh start
    kept, _ = per_step()
    assert switching < 1.3 * full and factored < 0.5 * full and switching < 0.85 * kept


def test_a_run_continues_bit_for_bit_within_fresh_tangent_steps():
    """A checkpoint taken while modified Newton starts its steps from fresh tangents holds
    that choice and its tangent's age: the continuation is bit for bit the same."""
    from skfem_cable.solvers.galpha import GeneralizedAlpha

    scene = _small_sail()
    whole = GeneralizedAlpha(scene.system, rho_inf=0.25)
    whole.initialize(scene.initial.q, scene.initial.v, 0.0)
    while not whole.fresh_steps:
        assert whole.step(10.0)[0] and whole.t < 200.0
    snap = whole.snapshot()
    for _ in range(6):
        whole.step(10.0)
    again = GeneralizedAlpha(scene.system, rho_inf=0.25)
    again.restore(snap)
    assert [again.fresh_steps, again.strikes, again.tangent_age] == list(snap["newton_choice"])
    for _ in range(6):
        again.step(10.0)
    assert np.array_equal(whole.q, again.q) and whole.stats["newton"] > 0
