"""The rod chain's run store: ``io.RunStore`` stores a ``RodChain.simulate`` run as it
stores a ``System`` run (labelled Zarr arrays, checkpoint, manifest), and ``resume``
continues an interrupted one bit for bit, from the API and from ``skfem-cable run
hanging-chain --resume``.  Before: a rod-chain run had no store and refused ``--resume``."""

import json

import numpy as np
import pytest
import xarray as xr

import skfem_cable as sc
from skfem_cable import io
from skfem_cable.cli import command as cli
from skfem_cable.io import RunStore, StoreMismatch
from skfem_cable.io.manifest import read_manifest
from skfem_cable.scenes import hanging_chain

G = hanging_chain.GRAVITY


class _Interrupt(sc.Observer):
    """Ctrl-C right after the first saved step at or after ``t``."""

    def __init__(self, t):
        self.t = t

    def saved(self, run, step):
        if step.t >= self.t:
            raise KeyboardInterrupt


def _drag(t, r, v):
    return -0.5 * v


#: (method, step, saved every, line load): compiled RK4, RK4 in Python (a callable line
#: load, whose work enters the energy books) and scipy's DOP853 (its stepper's state is
#: in the checkpoint).
CASES = {"rk4": ("rk4", 2.5e-5, 40, None), "rk4-python": ("rk4", 2.5e-5, 40, _drag),
         "DOP853": ("DOP853", 1e-3, 1, None)}


@pytest.mark.parametrize("case", sorted(CASES))
def test_interrupted_chain_run_resumes_bit_for_bit(tmp_path, case):
    method, dt, every, line_load = CASES[case]
    chain = hanging_chain.steel_chain(4)
    q0, v0 = hanging_chain.release_state(chain)
    kw = {"gravity": G, "method": method, "output_every": every, "line_load": line_load}
    full = chain.simulate(q0, v0, 0.06, dt, **kw)
    with pytest.raises(KeyboardInterrupt) as info:
        chain.simulate(q0, v0, 0.06, dt, observers=[RunStore(tmp_path, chunk=7),
                                                     _Interrupt(0.0305)], **kw)
    assert len(info.value.result) >= 32  # what was computed (a compiled block: all of it)
    manifest = read_manifest(tmp_path)
    assert manifest["status"] == "interrupted" and manifest["saved"] == 32
    resumed = chain.simulate(q0, v0, 0.06, dt, resume=io.resume(tmp_path),
                             observers=[RunStore(tmp_path, chunk=7)], **kw)
    for name in ("t", "q", "v"):
        np.testing.assert_array_equal(getattr(resumed, name), getattr(full, name))
    work = full.energy["external_work"]
    np.testing.assert_array_equal(resumed.energy["external_work"], work)
    assert (work[-1] < -1e-4) == (line_load is not None)  # the drag's work is booked
    # the store holds the whole run, labelled for plain xarray
    ds = xr.open_zarr(tmp_path / "results.zarr")
    np.testing.assert_array_equal(ds["q"].values, full.q)
    np.testing.assert_array_equal(ds["kinetic"].values, full.energy["kinetic"])
    assert list(ds["dof_component"].values[:4]) == ["dx", "dy", "dz", "dx"]
    assert ds["dof_label"].values[4] == "rod 1 y" and "r" not in ds
    assert read_manifest(tmp_path)["status"] == "complete"


def test_a_chain_store_continues_only_the_run_that_wrote_it(tmp_path):
    chain = hanging_chain.steel_chain(3)
    q0, v0 = hanging_chain.release_state(chain)
    chain.simulate(q0, v0, 0.01, 2.5e-5, gravity=G, output_every=40,
                   observers=[RunStore(tmp_path)])
    stored = io.resume(tmp_path)
    with pytest.raises(StoreMismatch, match="another system"):  # other loads
        chain.simulate(q0, v0, 0.02, 2.5e-5, gravity=(0.0, -9.0, 0.0), output_every=40,
                       resume=stored)
    with pytest.raises(StoreMismatch, match="another system"):  # another chain
        other = hanging_chain.steel_chain(3)
        other.simulate(q0, v0, 0.02, 2.5e-5, gravity=G, output_every=40, tip_force=(1, 0, 0),
                       resume=stored)
    with pytest.raises(StoreMismatch, match="other solver settings.*dt"):
        chain.simulate(q0, v0, 0.02, 2e-5, gravity=G, output_every=50, resume=stored)


def test_hanging_chain_command_continues_its_run(tmp_path, capsys):
    """``skfem-cable run hanging-chain --resume --t-end`` extends a finished run: its
    store equals that of the longer run made at once."""
    def run(out, *extra):
        return cli.main(["run", "hanging-chain", "--elements", "3", "--no-progress",
                         "--no-plots", "--out", str(out), *extra])

    assert run(tmp_path / "once", "--t-end", "0.04") == 0
    assert run(tmp_path / "twice", "--t-end", "0.02") == 0
    assert run(tmp_path / "twice", "--t-end", "0.04", "--resume") == 0
    once, twice = (xr.open_zarr(tmp_path / d / "results.zarr") for d in ("once", "twice"))
    assert twice.sizes["time"] == 401
    for name in ("time", "q", "v", "kinetic"):
        np.testing.assert_array_equal(twice[name].values, once[name].values)
    summary = json.loads((tmp_path / "twice" / "summary.json").read_text())
    assert summary["store"]["saved_steps"] == 401 and summary["store"]["status"] == "complete"
    assert summary["saved_steps"] == 401 and summary["files"]["store"] == "results.zarr"
    assert len(io.reader.run_info(tmp_path / "twice")) and (tmp_path / "twice" / "series.pvd")
    # another chain is refused before any file is touched
    capsys.readouterr()
    assert run(tmp_path / "twice", "--t-end", "0.06", "--resume", "--elements", "4") == 2
    assert "n_rods: stored 3, given 4" in capsys.readouterr().err
