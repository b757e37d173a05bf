"""Parameter studies on Dask distributed (``skfem_cable.study``, ``skfem-cable sweep``):
grids and run names, one point's task (reuse, continue, failures), the command line against
a scheduler and two workers started as separate processes, one of which is killed
mid-sweep, and sweeps on a ``LocalCluster`` of one worker process, the convergence study
and the E-sail demo as sweeps.

The command-line test comes before the cluster's tests: the module's cluster is started at
its first test and stopped at the module's end, and would otherwise idle (and tick) through
the command-line test's processes."""

import io
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from demo_modules import load_demo

import skfem_cable as sc
from skfem_cable.io import open_dataset
from skfem_cable.io.progress import Progress
from skfem_cable.runner import RunOptions
from skfem_cable.scenes import catalog, classics
from skfem_cable.scenes.catalog import pendulum_scene
from skfem_cable.study import open_run, open_study, parse_param, points, run_name, run_point


@pytest.fixture(scope="module")
def client():
    """One worker process with one thread (the cluster of the sweep tests: the tasks run
    in another process than the test's, as on any cluster; two workers at once are the
    command-line test's).  A second worker imports the package and loads the kernels of
    every scene again: each of two spent 6.3 CPU s on these four tests, almost all of it
    so."""
    from dask.distributed import Client, LocalCluster

    with LocalCluster(n_workers=1, processes=True, threads_per_worker=1,
                      dashboard_address=None) as cluster, Client(cluster) as c:
        yield c


def alone(scene, out):
    """``scene`` run by itself into ``out``; returns the stored coordinates."""
    scene.run(RunOptions(out=out, progress=False, plots=False))
    return open_dataset(out).q.values


def failing_pendulum(elements=2, t_fail=0.15):
    """A pendulum whose tip load raises at ``t > t_fail`` (a run failing half-way)."""
    scene = pendulum_scene(elements, t_end=0.3, dt=0.01, every=1)

    def force(t):
        if t > t_fail:
            raise RuntimeError(f"load undefined after t = {t_fail}")
        return [0.0, 0.0, 0.0]

    scene.system.add_point_load(scene.system.cables()[0].node(-1), force)
    return scene


# --- grids, names, parameters -------------------------------------------------------------
def test_points_outer_product_list_and_errors():
    dims, pts, coords = points({"alpha": [0, 10, 20], "voltage": [1e4, 2e4]})
    assert list(dims) == ["alpha", "voltage"] and len(pts) == 6
    assert pts[3] == ((1, 1), {"alpha": 10, "voltage": 2e4})
    dims, pts, coords = points([{"a": 1, "b": 2}, {"a": 3, "b": 4}])
    assert list(dims) == ["run"] and coords["b"] == (("run",), [2, 4])
    with pytest.raises(ValueError, match="'alpha' of the grid repeats a value"):
        points({"alpha": [10, 10.0]})
    with pytest.raises(ValueError, match="point 1 has the parameters"):
        points([{"a": 1}, {"b": 2}])
    with pytest.raises(ValueError, match="repeats a point"):
        points([{"a": 1}, {"a": 1.0}])


def test_parse_param_and_run_names():
    assert parse_param("alpha=0,10,22.5") == ("alpha", [0.0, 10.0, 22.5])
    assert parse_param("elements=3,5") == ("elements", [3, 5])
    assert parse_param("locking_free=false,True") == ("locking_free", [False, True])
    with pytest.raises(ValueError, match="expected NAME=V1,V2"):
        parse_param("alpha")
    a = run_name(pendulum_scene, {"elements": 3, "dt": 0.01})
    assert a == run_name(pendulum_scene, {"dt": 0.01, "elements": 3.0})
    assert a != run_name(pendulum_scene, {"elements": 4, "dt": 0.01})
    assert a != run_name(catalog.spinning_tether_scene, {"elements": 3, "dt": 0.01})
    assert a.startswith("dt=0.01_elements=3-0x")


def test_progress_over_tasks_is_labelled():
    stream = io.StringIO()
    bar = Progress(0, 4, True, stream=stream, label="runs")
    bar.update(2, "1 failed")
    assert " 50.0%  runs=2 " in stream.getvalue() and "1 failed" in stream.getvalue()


def test_sweep_rejects_unknown_and_clashing_parameters(tmp_path):
    with pytest.raises(ValueError, match="does not take the parameter 'elementz'.*elements"):
        sc.sweep(pendulum_scene, {"elementz": [2]}, store=tmp_path)
    with pytest.raises(ValueError, match="'t_end' is both fixed and swept"):
        sc.sweep(pendulum_scene, {"t_end": [1.0]}, fixed={"t_end": 2.0}, store=tmp_path)
    with pytest.raises(ValueError, match="without client"):
        sc.sweep(pendulum_scene, {"elements": [2]}, client=object(), workers=2,
                 store=tmp_path)
    assert not (tmp_path / "study.zarr").exists()


def test_cli_sweep_refuses_bad_parameters_before_running(tmp_path, capsys):
    from skfem_cable.cli.command import main

    out = str(tmp_path / "s")
    assert main(["sweep", "cantilever", "--param", "elements=2", "--out", out]) == 2
    assert "scene 'cantilever' cannot be swept" in capsys.readouterr().err
    assert main(["sweep", "pendulum", "--param", "dt=0.1", "--param", "dt=0.2",
                 "--out", out]) == 2
    assert "--param dt is given twice" in capsys.readouterr().err
    assert main(["sweep", "pendulum", "--param", "volts=1", "--out", out]) == 2
    assert "does not take the parameter 'volts'" in capsys.readouterr().err
    assert not (tmp_path / "s").exists()


# --- one point's task -----------------------------------------------------------------------
def test_run_point_continues_reuses_and_refuses_another_scene(tmp_path):
    params = {"elements": 2, "dt": 0.01, "t_end": 0.2}
    run_dir = tmp_path / "point"
    # an interrupted start (stored to t = 0.1, no study record) is continued bit for bit
    pendulum_scene(2, t_end=0.1, dt=0.01).run(RunOptions(out=run_dir, progress=False,
                                                         plots=False))
    first = run_point(pendulum_scene, params, run_dir)
    assert first["status"] == "complete" and not first["reused"]
    assert first["t_last"] == pytest.approx(0.2)
    reference = alone(pendulum_scene(**params), tmp_path / "alone")
    assert np.array_equal(open_dataset(run_dir).q.values, reference)
    # the same point again: reused, same numbers
    again = run_point(pendulum_scene, params, run_dir)
    assert again["reused"] and again["numbers"] == first["numbers"]
    # a finished run of another scene under these parameters: an error naming overwrite
    summary = json.loads((run_dir / "summary.json").read_text())
    summary["sweep"]["fingerprint"]["system"] = "0" * 64
    (run_dir / "summary.json").write_text(json.dumps(summary))
    other = run_point(pendulum_scene, params, run_dir)
    assert other["status"] == "failed" and "overwrite" in other["error"]
    replaced = run_point(pendulum_scene, params, run_dir, overwrite=True)
    assert replaced["status"] == "complete"
    assert np.array_equal(open_dataset(run_dir).q.values, reference)


def test_run_point_records_a_failure_and_keeps_the_partial_run(tmp_path):
    record = run_point(failing_pendulum, {"t_fail": 0.15}, tmp_path / "fail")
    assert record["status"] == "failed"
    assert "RuntimeError: load undefined after t = 0.15" in record["error"]
    assert record["numbers"] == {}
    stored = open_dataset(tmp_path / "fail")
    assert stored.attrs["manifest"]["status"] == "failed"
    assert 0.1 < record["t_last"] <= 0.15 and stored.time.values[-1] == record["t_last"]


# --- the command line on a scheduler and workers of their own ---------------------------------
def _wait_for(condition, timeout, what):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = condition()
        if value:
            return value
        time.sleep(0.05)
    raise TimeoutError(f"no {what} within {timeout} s")


@pytest.mark.slow
def test_cli_sweep_on_a_scheduler_survives_a_killed_worker(tmp_path):
    from dask.distributed import Client

    dask = str(Path(sys.executable).with_name("dask"))
    file = tmp_path / "scheduler.json"
    procs = [subprocess.Popen([dask, "scheduler", "--port", "0", "--no-dashboard",
                               "--scheduler-file", str(file)], stderr=subprocess.DEVNULL)]
    try:
        _wait_for(file.is_file, 30, "scheduler file")
        address = json.loads(file.read_text())["address"]
        procs += [subprocess.Popen([dask, "worker", address, "--nthreads", "1", "--no-nanny",
                                    "--no-dashboard"], stderr=subprocess.DEVNULL)
                  for _ in range(2)]
        out = tmp_path / "study"
        with Client(address, timeout="20s") as client:
            client.wait_for_workers(2, timeout=60)
            pids = client.run(os.getpid)
            cli = subprocess.Popen([sys.executable, "-m", "skfem_cable.cli", "sweep",
                                    "pendulum", "--param", "elements=4,5,6,7", "--t-end",
                                    "0.5", "--scheduler", address, "--out", str(out),
                                    "--no-progress"], stdout=subprocess.PIPE, text=True)

            def busy_worker():  # a worker whose task has started writing its run
                for worker, keys in client.processing().items():
                    name = keys[0].split("-", 4)[-1] if keys else None
                    if name and (out / "runs" / name).is_dir():
                        return worker, name
                return None

            victim, name = _wait_for(busy_worker, 60, "running task")
            os.kill(pids[victim], signal.SIGKILL)
            stdout, _ = cli.communicate(timeout=180)
        assert cli.returncode == 0, stdout
        ds = open_study(out)
        assert ds.status.dims == ("elements",) and (ds.status == "complete").all()
        killed = ds.elements.values[list(ds.run_dir.values).index(f"runs/{name}")].item()
        reference = alone(pendulum_scene(killed, t_end=0.5), tmp_path / "alone")
        assert np.array_equal(open_run(ds, elements=killed).q.values, reference)
    finally:
        for proc in procs[::-1]:
            proc.kill()
            proc.wait()


# --- sweeps on a local cluster --------------------------------------------------------------
def test_sweep_on_a_local_cluster_equals_runs_alone_and_resumes(client, tmp_path):
    grid = {"elements": [2, 3], "dt": [0.01, -0.01]}
    ds = sc.sweep(pendulum_scene, grid, client=client, store=tmp_path / "s",
                  fixed={"t_end": 0.2})
    assert ds.status.dims == ("elements", "dt")
    assert list(ds.status.sel(dt=0.01).values) == ["complete", "complete"]
    assert all("dt must be > 0" in e for e in ds.error.sel(dt=-0.01).values)
    assert np.isnan(ds.steps.sel(dt=-0.01)).all() and (ds.steps.sel(dt=0.01) == 20).all()
    # bit for bit the run alone, and its summary's numbers
    point = {"elements": 3, "dt": 0.01, "t_end": 0.2}
    reference = alone(pendulum_scene(**point), tmp_path / "alone")
    run = open_run(ds, elements=3, dt=0.01)
    assert np.array_equal(run.q.values, reference)
    summary = json.loads((tmp_path / "alone" / "summary.json").read_text())
    assert ds.cables_cable_max_tension_run.sel(elements=3, dt=0.01) == \
        summary["outputs"]["cables"]["cable"]["max_tension_run"]
    # the study on disk is the one returned; a second call reuses the finished runs
    stored = open_study(tmp_path / "s")
    assert stored.steps.equals(ds.steps) and stored.error.equals(ds.error)
    again = sc.sweep(pendulum_scene, grid, client=client, store=tmp_path / "s",
                     fixed={"t_end": 0.2})
    assert again.reused.sel(dt=0.01).all() and not again.reused.sel(dt=-0.01).any()
    assert again.cables_cable_max_tension_run.equals(ds.cables_cable_max_tension_run)


def test_sweep_of_a_list_grid_keeps_failed_runs_partial(client, tmp_path):
    ds = sc.sweep(failing_pendulum, [{"t_fail": 0.15}, {"t_fail": 1.0}], client=client,
                  store=tmp_path / "s")
    assert ds.status.dims == ("run",) and list(ds.t_fail.values) == [0.15, 1.0]
    assert list(ds.status.values) == ["failed", "complete"]
    assert 0.1 < ds.t_last.values[0] <= 0.15 and ds.t_last.values[1] == pytest.approx(0.3)
    assert open_run(ds, run=0).time.values[-1] == ds.t_last.values[0]


def test_convergence_study_as_a_sweep(client, tmp_path):
    ds = sc.sweep(catalog.cantilever_point, {"elements": [2, 4], "k": [1.0, 5.0]},
                  run=catalog.run_cantilever_point, client=client, store=tmp_path / "c")
    error = ds.rel_error
    assert (error.sel(elements=4) < error.sel(elements=2)).all()
    scene = classics.cantilever(4, 5.0)
    direct = catalog.elastica_row(scene.cable, 5.0, sc.solve_static(scene.system,
                                                                    load_steps=20))
    assert error.sel(elements=4, k=5.0) == direct["rel_error"]


def test_demo_esail_sweep(client, tmp_path):
    demo = load_demo("esail_sweep")
    ds = demo.main(alphas=(0, 30), voltages=(20e3,), periods=0.005, elements=1,
                   out=tmp_path / "e", client=client)
    assert (tmp_path / "e" / "esail_sweep.png").is_file()
    cfg = sc.esail.BaselineConfig()
    sun_facing = cfg.n_tethers * cfg.tether_length * sc.SolarWind().force_per_length(20e3)
    assert ds.thrust_mean_N.sel(alpha=0, voltage=20e3) == pytest.approx(sun_facing, rel=1e-3)
