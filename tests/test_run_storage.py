"""Incremental storage of long runs (``io.RunStore``: a Zarr store read with xarray, a
checkpoint and a manifest), bit-for-bit restart, progress bar.  The store's fault tests
(signals, full disk, damaged files, other systems) are in ``test_faults.py``."""

import io
import json

import numpy as np
import pytest
from interrupting import Interrupt, InterruptingLoad

import skfem_cable as sc
from skfem_cable.core.records import ENERGIES, FIELDS
from skfem_cable.io import Progress, ProgressBar, RunStore, open_dataset, resume, run_observers
from skfem_cable.io.schema import DEFAULT_FIELDS, STORE
from skfem_cable.scenes import classics


def tip_force(t):
    return [0.0, 0.0, 2.0 * np.sin(20 * t)]


def scene_with_load(stop_at=None):
    """Pendulum with a time-dependent tip load; raises ``Interrupt`` past ``stop_at``."""
    scene = classics.pendulum(n_elements=6, gamma_axial=1e-4)
    scene.system.add_point_load(scene.cable.node(-1), InterruptingLoad(tip_force, stop_at))
    return scene


@pytest.mark.parametrize("newton", ["full", "modified"])
def test_interrupted_run_keeps_its_steps_and_restarts_bit_for_bit(tmp_path, newton):
    kw = dict(t_end=0.2, dt=2e-3, rho_inf=0.7, every=2, newton=newton)
    ref = sc.simulate(scene_with_load().system, **kw)
    scene = scene_with_load(stop_at=0.1234)
    with pytest.raises(Interrupt):  # every field stored, the accelerations too
        sc.simulate(scene.system, observers=[RunStore(tmp_path / "run", chunk=7, fields=FIELDS)],
                    **kw)
    kept = sc.Result.load(tmp_path / "run", scene.system)
    assert 0.11 < kept.t[-1] <= 0.1234
    n = len(kept.t)
    for name in FIELDS:
        assert np.array_equal(getattr(kept, name), getattr(ref, name)[:n]), name
    resumed = sc.simulate(scene_with_load().system, resume=RunStore.resume(tmp_path / "run"),
                          observers=[RunStore(tmp_path / "run", chunk=7)], **kw)
    for name in FIELDS:
        assert np.array_equal(getattr(resumed, name), getattr(ref, name)), name
    again = sc.Result.load(tmp_path / "run", scene.system)
    assert np.array_equal(again.q, ref.q)


def test_output_directory_matches_memory_and_checks_settings(tmp_path):
    scene = classics.pendulum(n_elements=4)
    res = sc.simulate(scene.system, t_end=0.05, dt=1e-3,
                      observers=run_observers(tmp_path / "r", progress=False, chunk=10))
    back = sc.Result.load(tmp_path / "r", scene.system)
    assert np.array_equal(back.q, res.q) and np.array_equal(back.t, res.t)
    assert len(list((tmp_path / "r" / STORE / "q" / "c").iterdir())) == 6  # 51 steps
    manifest = json.loads((tmp_path / "r" / "manifest.json").read_text())
    assert manifest["commits"] == 6 and manifest["saved"] == 51
    assert manifest["status"] == "complete"
    assert (tmp_path / "r" / "series.pvd").exists()
    with pytest.raises(ValueError, match="must match"):
        sc.simulate(scene.system, t_end=0.1, dt=2e-3, resume=resume(tmp_path / "r"))
    with pytest.raises(FileNotFoundError, match="not a run directory"):
        sc.Result.load(tmp_path, scene.system)


def test_the_store_is_an_xarray_dataset(tmp_path):
    """``xarray.open_zarr(run / "results.zarr")``: ``time`` is the dimension and a
    coordinate, the fields and the solver counters are variables, the attributes hold
    the scene parameters, the layout of the coordinates and the settings."""
    xr = pytest.importorskip("xarray")
    scene = classics.pendulum(n_elements=4)
    res = sc.simulate(scene.system, t_end=0.05, dt=1e-3, every=5,
                      observers=run_observers(tmp_path, progress=False, chunk=4,
                                              attrs={"scene": "pendulum",
                                                     "parameters": {"elements": 4}}))
    ds = xr.open_zarr(tmp_path / STORE)
    assert dict(ds.sizes) == {"time": 11, "dof": scene.system.n_dofs, "multiplier": 3,
                              "body": 1, "node": 5, "component": 3}  # r: the positions
    assert np.array_equal(ds.time.values, res.t) and ds.time.attrs["units"] == "s"
    assert np.array_equal(ds.q.values, res.q) and ds.q.dims == ("time", "dof")
    assert np.array_equal(ds.lam.values, res.lam)
    assert np.array_equal(ds.iterations.values, res.iterations)
    for name in ENERGIES:
        assert np.array_equal(ds[name].values, getattr(res, name)), name
    assert ds.stat_steps.values[-1] == res.stats["steps"] == 50
    assert "a" not in ds and set(DEFAULT_FIELDS) - {"t"} <= set(ds.data_vars)
    assert ds.attrs["scene"] == "pendulum" and ds.attrs["parameters"] == {"elements": 4}
    assert ds.attrs["bodies"][0]["n_dofs"] == scene.system.n_dofs
    assert ds.attrs["settings"]["dt"] == 1e-3
    assert ds.q.encoding["compressors"]  # compressed
    same = open_dataset(tmp_path)  # the committed steps, with the manifest
    assert same.attrs["manifest"]["saved"] == 11 and np.array_equal(same.v.values, res.v)


def test_progress_bar_reports_percentage_and_eta():
    stream = io.StringIO()
    bar = Progress(0.0, 2.0, enabled=True, stream=stream)
    bar.update(1.0)
    bar.update(2.0)
    bar.close()
    out = stream.getvalue()
    assert "50.0%" in out and "100.0%" in out and "ETA" in out
    quiet = io.StringIO()
    Progress(0.0, 1.0, enabled=None, stream=quiet).update(1.0)
    assert quiet.getvalue() == ""  # not a terminal


def test_progress_bar_observer_reaches_the_end():
    scene = classics.pendulum(n_elements=3)
    stream = io.StringIO()
    sc.simulate(scene.system, t_end=0.02, dt=1e-3, every=5,
                observers=[ProgressBar(True, stream=stream)])
    out = stream.getvalue()
    assert "100.0%" in out and "t=0.02" in out and out.endswith("\n")
    quiet = io.StringIO()
    sc.simulate(scene.system, t_end=0.02, dt=1e-3, observers=[ProgressBar(stream=quiet)])
    assert quiet.getvalue() == ""
